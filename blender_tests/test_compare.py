"""Compare (roads.compare_graphs): the sample town's drivable streets (A) against all its
streets (B, imported a second time with every highway, 1.8 km east): the result kept on A is
ggg.compare of the same two graphs, the report line says it, the Compare panel shows it, and
every refused input cancels and changes nothing."""

import json
from types import SimpleNamespace

import bpy
import pytest

from conftest import PanelLayout, activate, draw_panel, import_roads, record_executes, snapshot
from road_grammar.core import comparison
from road_grammar.data import graph_edit, roads
from road_grammar.operators import comparison as compare_ops
from road_grammar.ui import comparison as compare_ui

OFFSET = 1800.0


@pytest.fixture
def towns(sample_city, ggg):
    """(the town's drivable streets, all its streets 1.8 km east), A active, both selected."""
    assert import_roads(sample_city) == {'FINISHED'}
    first = bpy.context.active_object
    assert import_roads(sample_city, highways='ALL') == {'FINISHED'}
    second = bpy.context.active_object
    second.location.x = OFFSET
    bpy.context.view_layer.update()
    assert len(second.data.edges) > len(first.data.edges)
    activate(first, second)
    return first, second


@pytest.fixture
def op_results(monkeypatch):
    return record_executes(monkeypatch, compare_ops.ROADS_OT_compare_graphs)


def direct_compare(ggg, a, b):
    """ggg.compare of the two road graph objects, read as the grammar operators read them."""
    return ggg.compare(graph_edit.MeshGraph(a).graph(ggg), graph_edit.MeshGraph(b).graph(ggg))


def test_compare_keeps_what_ggg_compare_says(towns, ggg, sample_city, reports, op_results):
    first, second = towns
    assert bpy.ops.roads.compare_graphs() == {'FINISHED'}
    kept = first.road_compare
    stored = json.loads(kept.result)
    expected = direct_compare(ggg, first, second)
    assert stored == expected
    assert kept.stored() == expected and kept.other == second.name and kept.topology
    assert not second.road_compare.result
    # The same numbers as the library on the files, up to the float32 coordinates of the mesh.
    from_files = ggg.compare(ggg.read_graph(str(sample_city)), ggg.read_graph(str(sample_city), highways="all"))
    for part in ("a", "b", "distances"):
        assert stored[part].keys() == from_files[part].keys()
        for key, value in from_files[part].items():
            assert stored[part][key] == pytest.approx(value, rel=1e-4, abs=1e-6), (part, key)
    assert stored["a"]["edges"] == 286 and stored["b"]["edges"] == 408
    assert stored["distances"]["mean"] > 0.0

    kind, line = reports()[-1]
    assert kind == 'INFO' and line == comparison.summary(first.name, second.name, expected)
    d, a, b = expected["distances"], expected["a"], expected["b"]
    assert line.startswith("Compared sample_city with sample_city.001: mean distance {:.2f} (degree {:.2f}, edge "
                           "length {:.2f}, orientation {:.2f}, block area {:.2f}); junction angles {:.2f}; "
                           "dead ends {:.1f}% / {:.1f}%".format(
                               d["mean"], d["degree"], d["edge_length"], d["orientation"], d["block_area"],
                               d["junction_angle"], 100 * a["dead_end_share"], 100 * b["dead_end_share"]))
    assert line.endswith("circuity {:.2f} / {:.2f}".format(a["circuity"], b["circuity"]))

    # The other way round, named: B is kept on the active graph, the other one untouched.
    activate(second)
    assert bpy.ops.roads.compare_graphs(other=first.name) == {'FINISHED'}
    assert json.loads(second.road_compare.result) == direct_compare(ggg, second, first)
    assert json.loads(first.road_compare.result) == expected
    assert op_results == [{'FINISHED'}, {'FINISHED'}]


def test_compare_in_edit_mode_reads_the_edited_mesh(towns, ggg):
    first, second = towns
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='DESELECT')
    bpy.ops.object.mode_set(mode='OBJECT')
    first.data.vertices[0].select = True
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.delete(type='VERT')
    assert bpy.ops.roads.compare_graphs() == {'FINISHED'}
    assert bpy.context.object.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    stored = json.loads(first.road_compare.result)
    assert stored["a"]["vertices"] == len(first.data.vertices) == 189
    assert stored == direct_compare(ggg, first, second)


def test_the_panel(towns, ggg):
    first, second = towns
    labels, buttons = [], []
    compare_ui.VIEW3D_PT_roads_compare.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert labels == ["sample_city with sample_city.001"]
    assert [idname for idname, _properties in buttons] == ["roads.compare_graphs"]

    bpy.ops.roads.compare_graphs(other=second.name)
    result = json.loads(first.road_compare.result)
    text = draw_panel(compare_ui.VIEW3D_PT_roads_compare)
    lines = text.splitlines()
    assert "A: sample_city" in lines and "B: sample_city.001" in lines
    assert "Distances (0: alike, 1: most unlike)" in lines
    # Each measure: its label, A's value, B's value, one cell a label.
    for key, label, a, b, _meaning in comparison.measure_rows(result):
        position = lines.index(label)
        assert lines[position + 1:position + 3] == [a, b], key
    assert lines[lines.index("Dead ends") + 1] == "{:.1f}%".format(100 * result["a"]["dead_end_share"])
    assert lines[lines.index("Circuity") + 2] == "{:.2f}".format(result["b"]["circuity"])
    for key, label, _text, _meaning in comparison.distance_rows(result):
        assert lines[lines.index(label) + 1] == "{:.3f}".format(result["distances"][key])
    assert "how regular the crossings are" not in text
    first.road_compare.show_meanings = True
    text = " ".join(draw_panel(compare_ui.VIEW3D_PT_roads_compare).split())  # the meanings are wrapped
    assert "how regular the crossings are" in text and "are the blocks as large: what can be built on them" in text
    assert "changed since" not in text

    # The graph changed: the table stays, with a note.
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='DESELECT')
    bpy.ops.object.mode_set(mode='OBJECT')
    first.data.vertices[0].select = True
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.delete(type='VERT')
    bpy.ops.object.mode_set(mode='OBJECT')
    text = draw_panel(compare_ui.VIEW3D_PT_roads_compare)
    assert "sample_city changed since" in text and "Dead ends" in text

    # Nothing to compare with; another object active; nothing selected.
    activate(first)
    assert draw_panel(compare_ui.VIEW3D_PT_roads_compare).splitlines()[0] == "Select one other road graph"
    bpy.context.view_layer.objects.active = None
    assert draw_panel(compare_ui.VIEW3D_PT_roads_compare) == "Select two road graphs (the one to compare active)"


def _cancelled_with(call, expected_text, op_results):
    with pytest.raises(RuntimeError) as error:
        call()
    assert expected_text in str(error.value), str(error.value)
    assert op_results[-1] == {'CANCELLED'}


def _state(*objs):
    return [(len(o.data.vertices), len(o.data.edges), o.road_compare.result, o.road_compare.other) for o in objs] + \
        [snapshot()]


def test_refused_input_changes_nothing(towns, sample_city, ggg, op_results):
    first, second = towns
    compare = bpy.ops.roads.compare_graphs
    before = _state(first, second)
    activate(first)
    _cancelled_with(compare, "only sample_city is selected", op_results)
    assert _state(first, second) == before
    assert import_roads(sample_city) == {'FINISHED'}
    third = bpy.context.active_object
    before_three = _state(first, second, third)
    activate(first, second, third)
    _cancelled_with(compare, "3 are selected (sample_city.001, sample_city.002)", op_results)
    assert not any(o.road_compare.result for o in (first, second, third))
    assert _state(first, second, third) == before_three
    roads.remove_graph_object(third)
    assert _state(first, second) == before
    bpy.context.view_layer.objects.active = None
    _cancelled_with(compare, "Compare needs two road graphs", op_results)
    activate(first, second)
    _cancelled_with(lambda: compare(other="Nowhere"), "'Nowhere' is not another road graph", op_results)
    _cancelled_with(lambda: compare(other=first.name), "'sample_city' is not another road graph", op_results)

    # A graph without streets.
    empty_mesh = bpy.data.meshes.new("Empty")
    empty = bpy.data.objects.new("Empty", empty_mesh)
    empty["road_graph"] = True
    bpy.context.scene.collection.objects.link(empty)
    activate(first, empty)
    _cancelled_with(compare, "Cannot compare sample_city with Empty: Empty has no streets", op_results)
    activate(empty, first)
    _cancelled_with(compare, "Cannot compare Empty with sample_city: Empty has no streets", op_results)
    assert not empty.road_compare.result
    bpy.data.objects.remove(empty)
    bpy.data.meshes.remove(empty_mesh)

    # A graph the library refuses (a vertex that is not a number): its error.
    co = second.data.vertices[3].co.copy()
    second.data.vertices[3].co.x = float("nan")
    activate(first, second)
    _cancelled_with(compare, "Cannot compare sample_city with sample_city.001: positions[3] is not finite",
                    op_results)
    second.data.vertices[3].co = co
    assert _state(first, second) == before

    # The library's error, whatever it is, is reported and nothing is kept.
    def failing(_a, _b):
        raise ggg.Error("simulated failure")

    original = ggg.compare
    ggg.compare = failing
    try:
        _cancelled_with(compare, "Cannot compare sample_city with sample_city.001: simulated failure", op_results)
    finally:
        ggg.compare = original
    assert _state(first, second) == before
    assert bpy.ops.roads.compare_graphs() == {'FINISHED'}
