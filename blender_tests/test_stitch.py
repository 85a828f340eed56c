"""Stitch Cities (roads.stitch_cities, paper Fig. 18): the sample town imported twice, the
second moved 1.8 km east by its object location, each with its own learned grammar, and a
plane over the gap between them. The second town is joined into the first (its vertices
moved by the offset, its attributes kept), the gap grows with the first town's grammar and
then the second's (as ggg.grow_region twice), and the second object is removed; the same
seed gives the same mesh; bad input cancels and changes nothing; undo (a windowed Blender
under Xvfb) brings both towns back; Place Rule places a rule of the second town's grammar."""

import json
import os
import re
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import bpy
import numpy as np
import pytest

import road_grammar
from conftest import PanelLayout, import_roads, snapshot
from road_grammar.core.columns import joined
from road_grammar.core.grammar import rule_of
from road_grammar.core.names import GRAPH_KEY, RULE_GRAMMAR, RULE_GRAMMARS_KEY, SURFACE_EDGE
from road_grammar.data import graph_edit, roads, texts
from road_grammar.data import mesh as mesh_build
from road_grammar.operators import stitch as stitch_ops

HERE = Path(__file__).resolve().parent
OFFSET = 1800.0  # the second town, east of the first (the town spans x -747..747)
X0, X1, Y0, Y1 = 650.0, 1150.0, -700.0, 700.0  # the gap, in world metres
GAP = np.array([[X0, Y0], [X1, Y0], [X1, Y1], [X0, Y1]])


# --- helpers ---------------------------------------------------------------------------------

@pytest.fixture
def op_results(monkeypatch):
    """What roads.stitch_cities' execute() returned (bpy.ops raises on ERROR reports)."""
    results = []
    original = stitch_ops.ROADS_OT_stitch_cities.execute

    def recording_execute(self, context):
        result = original(self, context)
        results.append(result)
        return result

    monkeypatch.setattr(stitch_ops.ROADS_OT_stitch_cities, "execute", recording_execute)
    return results


def activate(obj, *others):
    for o in bpy.context.view_layer.objects:
        o.select_set(o == obj or o in others)
    bpy.context.view_layer.objects.active = obj


def import_town(path, offset=0.0, learn=True):
    assert import_roads(path) == {'FINISHED'}
    obj = bpy.context.active_object
    obj.location = (offset, 0.0, 0.0)
    bpy.context.view_layer.update()
    if learn:
        assert bpy.ops.roads.learn() == {'FINISHED'}
        assert obj.road_learning.text is not None
    return obj


def gap_region(name="Gap", corners=GAP):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(float(x), float(y), 0.0) for x, y in corners], [], [tuple(range(len(corners)))])
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


@pytest.fixture
def towns(sample_city, ggg):
    """(first town, second town 1.8 km east), each with its own learned grammar, and the gap."""
    first = import_town(sample_city)
    second = import_town(sample_city, OFFSET)
    region_obj = gap_region()
    activate(first, second)
    return first, second, region_obj


def arrays(obj):
    mesh = obj.data
    return mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh)


def mesh_state(obj):
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    return (len(mesh.vertices), len(mesh.edges), co.tobytes(), mesh_build.edge_vertices(mesh).tobytes(),
            sorted(a.name for a in mesh.attributes))


def scene_state(*objs):
    return [mesh_state(o) for o in objs] + [mesh_state(roads.surface_object(o)) for o in objs] + [snapshot()]


REPORT = re.compile(r"Stitched (\S+) and (\S+) in (\S+): ([\d,]+) rules? of \1, ([\d,]+) rules? of \2, ([\d,]+) "
                    r"vert(?:ex|ices), ([\d,]+) new streets, ([\d,]+) from \1's streets, ([\d,]+) from \2's")


def counts_reported(message):
    """(rules of A, rules of B, vertices, streets, from A, from B) of the report."""
    found = REPORT.search(message)
    assert found, message
    return tuple(int(group.replace(",", "")) for group in found.groups()[3:])


def inside_gap(points, margin=1e-3):
    points = np.asarray(points)
    return (points[:, 0] > X0 - margin) & (points[:, 0] < X1 + margin) & \
        (points[:, 1] > Y0 - margin) & (points[:, 1] < Y1 + margin)


def expected(ggg, first, second, seed=1, share=0.5, **options):
    """What Stitch Cities should make, computed with ggg directly: the two towns' streets
    one after the other (the second moved by the offset), grown into the gap with the first
    town's grammar (its share of what it would place alone) and then the second's."""
    old = joined(ggg, graph_edit.MeshGraph(first), graph_edit.MeshGraph(second),
                 np.array(first.matrix_world.inverted() @ second.matrix_world))
    base = old.graph(ggg)
    _ta, parsed_a = texts.of_text(first.road_learning.text)
    _tb, parsed_b = texts.of_text(second.road_learning.text)
    options["continue_hierarchy"] = False  # (once, after both)
    # First the streets of both towns that reach the gap, traced on into it; then the rules.
    traced, report_traced = ggg.grow_region(base, parsed_a, GAP, seed=seed, patience=0, continue_hierarchy=False)
    options["trace_streets"] = False
    alone, report_a = ggg.grow_region(traced, parsed_a, GAP, seed=seed, **options)
    placed_alone = report_a["placements"]
    limit = int(round(share * placed_alone))
    if share < 1.0 and limit == 0:  # (its share is nothing: the second grammar grows it all)
        alone, report_a = traced, {key: (False if isinstance(value, bool) else 0) for key, value in report_a.items()}
    elif share < 1.0 and limit < placed_alone:
        alone, report_a = ggg.grow_region(traced, parsed_a, GAP, seed=seed, max_placements=limit, **options)
    report_a["alone"] = placed_alone
    grown, report_b = ggg.grow_region(alone, parsed_b, GAP, seed=seed + 1, **options)
    grown, hierarchy = ggg.continue_hierarchy(grown, base.edge_count, region=GAP)
    report_b["hierarchy"] = hierarchy
    report_b["traced"] = report_traced
    return base, grown, report_a, report_b


# --- stitching ---------------------------------------------------------------------------------

def test_stitch_two_towns(towns, ggg, reports, op_results):
    first, second, region_obj = towns
    positions_a, edges_a = arrays(first)
    positions_b, edges_b = arrays(second)
    highway = np.concatenate([mesh_build.read_attribute(o.data, "highway", np.int64) for o in (first, second)])
    width = np.concatenate([mesh_build.read_attribute(o.data, "width", np.float64) for o in (first, second)])
    names = [n for o in (first, second) for n in mesh_build.read_strings(o.data, "name", 'EDGE') or []]
    n_a, n_b, e_a, e_b = len(positions_a), len(positions_b), len(edges_a), len(edges_b)
    mesh, surface_obj = first.data, roads.surface_object(first)
    second_name, second_surface = second.name, roads.surface_object(second).name
    second_rules = [child.name for child in second.children]
    assert len(second_rules) >= 2  # its surface and its Rules display (Learn)

    assert bpy.ops.roads.stitch_cities(region=region_obj.name, seed=1) == {'FINISHED'}
    assert op_results == [{'FINISHED'}]
    kind, message = reports()[-1]
    assert kind == 'INFO' and message.startswith("Stitched sample_city and sample_city.001 in Gap:"), message
    rules_a, rules_b, added, streets, from_a, from_b = counts_reported(message)
    # The streets of both towns that reach the gap go on into it, and meet there.
    assert from_a > 0 and from_b > 0 and added > 0
    assert re.search(r"[\d,]+ streets traced on into it from [\d,]+ streets of both", message), message
    assert "seed 1 and 2" in message

    # One object now: the first, same name and mesh; the second is gone with its children.
    assert first.name == "sample_city" and first.data == mesh and roads.surface_object(first) == surface_obj
    assert second_name not in bpy.data.objects and second_surface not in bpy.data.objects
    assert not any(name in bpy.data.objects for name in second_rules)
    assert [o.name for o in bpy.context.scene.objects if o.get(GRAPH_KEY)] == ["sample_city"]
    assert bpy.context.view_layer.objects.active == first

    # Both towns' vertices, in their places (the second moved by its object's offset), then the new ones.
    positions, edges = arrays(first)
    assert len(positions) == n_a + n_b + added
    assert len(edges) == e_a + e_b + streets
    np.testing.assert_allclose(positions[:n_a], positions_a, atol=1e-3)
    np.testing.assert_allclose(positions[n_a:n_a + n_b], positions_b + [OFFSET, 0.0], atol=1e-3)
    np.testing.assert_array_equal(edges[:e_a], edges_a)
    np.testing.assert_array_equal(edges[e_a:e_a + e_b], edges_b + n_a)
    assert inside_gap(positions[n_a + n_b:]).all()
    # The towns' edges keep their attributes.
    np.testing.assert_array_equal(mesh_build.read_attribute(mesh, "highway", np.int64)[:e_a + e_b], highway)
    np.testing.assert_allclose(mesh_build.read_attribute(mesh, "width", np.float64)[:e_a + e_b], width, rtol=1e-6)
    if names:
        assert mesh_build.read_strings(mesh, "name", 'EDGE')[:e_a + e_b] == names
    # Some new streets end on vertices of each town, as many as reported.
    new = edges[e_a + e_b:]
    on_a = ((new >= 0) & (new < n_a)).any(axis=1)
    on_b = ((new >= n_a) & (new < n_a + n_b)).any(axis=1)
    assert int(on_a.sum()) == from_a > 0 and int(on_b.sum()) == from_b > 0
    # The surface has every street, the second town's polylines moved with it.
    owner = mesh_build.read_attribute(surface_obj.data, SURFACE_EDGE, np.int64)
    assert set(owner.tolist()) == set(range(len(edges)))
    surface_points = mesh_build.positions_xy(surface_obj.data)
    assert surface_points[:, 0].max() > OFFSET + 700.0


def test_the_two_growths_are_those_of_ggg(sample_city, ggg, reports):
    """The mesh is ggg.grow_region with the first town's grammar (seed; its share of what it
    would place alone) and then with the second's (seed + 1) on the joined streets; with
    Share 1 the first grammar grows until the gap is full and the second fills what is left."""
    for share in (0.5, 1.0):
        bpy.ops.wm.read_homefile(use_empty=True)
        first, second, region_obj = _fresh_towns()
        base, grown, report_a, report_b = expected(ggg, first, second, seed=4, share=share)
        assert report_b["traced"]["traced_streets"] > 0
        assert bpy.ops.roads.stitch_cities(region=region_obj.name, seed=4, share=share) == {'FINISHED'}
        positions, edges = arrays(first)
        np.testing.assert_allclose(positions, grown.positions, atol=1e-3)
        np.testing.assert_array_equal(edges, grown.edges)
        # The road classes too: the towns' main roads continued across the gap.
        highway = mesh_build.read_attribute(first.data, "highway", np.int64)
        np.testing.assert_array_equal(highway, grown.edge_highway)
        message = reports()[-1][1]
        hierarchy = report_b["hierarchy"]
        if hierarchy["routes"] + hierarchy["connectors"]:
            assert "continued across the gap ({} raised".format(
                _plural_streets(hierarchy["raised_streets"] + hierarchy["connector_streets"])) in message, message
        else:
            assert "across the gap" not in message
        rules_a, rules_b, added, streets, _a, _b = counts_reported(message)
        assert (rules_a, rules_b) == (report_a["placements"], report_b["placements"])
        assert added == grown.vertex_count - base.vertex_count
        assert streets == grown.edge_count - base.edge_count
        assert "seed 4 and 5" in message
        if share < 1.0 and int(round(share * report_a["alone"])) < report_a["alone"]:
            assert "sample_city: its share ({} of".format(rules_a) in message
        elif share == 1.0:
            assert "its share" not in message and "sample_city: region full" in message


def _plural_streets(n):
    return "1 street" if n == 1 else "{:,} streets".format(n)


def test_main_roads_continue_across_the_gap(towns, ggg, reports):
    """The first town's main roads that reach the gap meet the second town's through the
    grown streets: the grown streets on the way take the main road's class, and each such run
    of raised streets ends on main roads of the towns."""
    first, second, region_obj = towns
    n_edges = len(first.data.edges) + len(second.data.edges)
    positions_before_a = mesh_build.positions_xy(first.data)
    highway_before = np.concatenate([mesh_build.read_attribute(o.data, "highway", np.int64) for o in (first, second)])
    ranks = ggg.highway_ranks()
    unclassified = ranks[ggg.highway_classes().index("unclassified")]
    assert bpy.ops.roads.stitch_cities(region=region_obj.name, seed=1) == {'FINISHED'}
    message = reports()[-1][1]
    found = re.search(r"(\d+) main roads? continued across the gap \(([\d,]+) streets? raised", message)
    assert found, message
    routes, raised = int(found.group(1)), int(found.group(2).replace(",", ""))
    assert routes >= 1 and raised >= 2
    positions, edges = arrays(first)
    highway = mesh_build.read_attribute(first.data, "highway", np.int64)
    np.testing.assert_array_equal(highway[:n_edges], highway_before)  # the towns' own streets keep theirs
    main = np.array([ranks[int(c)] <= unclassified for c in highway])
    main_ends = set(edges[:n_edges][main[:n_edges]].ravel().tolist())
    new_main = np.flatnonzero(main[n_edges:]) + n_edges
    assert len(new_main) >= raised
    # Runs of grown main-road streets: each touches the towns' main roads at two ends or more.
    parent = {}

    def root(v):
        while parent.setdefault(v, v) != v:
            v = parent[v]
        return v

    for e in new_main:
        a, b = (int(x) for x in edges[e])
        parent[root(a)] = root(b)
    runs = {}
    for v in list(parent):
        runs.setdefault(root(v), set()).add(v)
    joined = [run for run in runs.values() if len(run & main_ends) >= 2]
    # (Two routes that cross make one run, with the four main roads of both.)
    assert joined and sum(len(run & main_ends) for run in joined) >= 2 * routes
    # A run joins a main road of the first town to one of the second.
    n_a = len(positions_before_a)
    assert any(any(v < n_a for v in run & main_ends) and any(v >= n_a for v in run & main_ends) for run in joined), \
        [sorted(positions[list(run), 0].round()) for run in joined]


def _fresh_towns():
    from conftest import SAMPLE_CITY

    first = import_town(SAMPLE_CITY)
    second = import_town(SAMPLE_CITY, OFFSET)
    region_obj = gap_region()
    activate(first, second)
    return first, second, region_obj


def test_the_same_seed_gives_the_same_mesh(towns, ggg):
    first, _second, region_obj = towns
    assert bpy.ops.roads.stitch_cities(region=region_obj.name, seed=1) == {'FINISHED'}
    once = mesh_state(first)
    states = [once]
    for seed in (1, 2):
        bpy.ops.wm.read_homefile(use_empty=True)
        first, _second, region_obj = _fresh_towns()
        assert bpy.ops.roads.stitch_cities(region=region_obj.name, seed=seed) == {'FINISHED'}
        states.append(mesh_state(first))
    assert states[0] == states[1]
    assert states[0][0] > 380 and states[2][0] > 380  # (both grew)
    assert states[0][:3] != states[2][:3]


def test_selected_region_and_a_turned_second_town(sample_city, ggg, reports):
    """The region selected with the two towns; the second town turned by 90 degrees about
    its origin: its vertices land where its object put them in the world."""
    first = import_town(sample_city)
    second = import_town(sample_city, OFFSET + 100.0)
    second.rotation_euler = (0.0, 0.0, np.pi / 2.0)
    bpy.context.view_layer.update()
    world_b = np.array([tuple(second.matrix_world @ v.co) for v in second.data.vertices])[:, :2]
    region_obj = gap_region()
    activate(first, second, region_obj)
    n_a = len(first.data.vertices)
    assert bpy.ops.roads.stitch_cities() == {'FINISHED'}
    assert "in Gap:" in reports()[-1][1]
    positions, _edges = arrays(first)
    np.testing.assert_allclose(positions[n_a:n_a + len(world_b)], world_b, atol=1e-2)


def test_second_town_without_grammar_and_the_scene_grammar(sample_city, ggg, reports):
    """The active town without a learned grammar uses the scene's; the other town without one
    lets the active town's grammar grow the whole gap, with a warning."""
    first = import_town(sample_city)
    second = import_town(sample_city, OFFSET, learn=False)
    scene_text = first.road_learning.text
    first.road_learning.text = None  # no learned grammar: the scene's (the same text) is used
    assert bpy.context.scene.road_grammar.text == scene_text
    region_obj = gap_region()
    activate(first, second)
    n = len(first.data.vertices) + len(second.data.vertices)
    assert bpy.ops.roads.stitch_cities(region=region_obj.name) == {'FINISHED'}
    seen = reports()
    assert ('WARNING', "sample_city.001 has no grammar (learn it first): the gap grew with sample_city's rules "
            "only") in seen
    rules_a, rules_b, added, *_rest = counts_reported(seen[-1][1])
    assert added > 0 and rules_b == 0 and len(first.data.vertices) == n + added
    assert "seed 1;" not in seen[-1][1] and seen[-1][1].endswith("seed 1")


# --- bad input ---------------------------------------------------------------------------------

def _cancelled_with(call, kind, expected_text, reports, op_results):
    if kind == 'ERROR':
        with pytest.raises(RuntimeError) as error:
            call()
        assert expected_text in str(error.value), str(error.value)
    else:
        assert call() == {'CANCELLED'}
        found = [m for k, m in reports() if k == kind]
        assert found and expected_text in found[-1], found
    assert op_results[-1] == {'CANCELLED'}


def test_bad_input_cancels_and_changes_nothing(sample_city, towns, ggg, reports, op_results):
    first, second, region_obj = towns
    before = scene_state(first, second)
    stitch = bpy.ops.roads.stitch_cities

    activate(first)
    _cancelled_with(lambda: stitch(region="Gap"), 'ERROR', "only sample_city is selected", reports, op_results)
    third = import_town(sample_city, -OFFSET, learn=False)
    before_three = scene_state(first, second, third)
    activate(first, second, third)
    _cancelled_with(lambda: stitch(region="Gap"), 'ERROR', "3 are selected (sample_city.001, sample_city.002)",
                    reports, op_results)
    activate(region_obj, first, second)
    _cancelled_with(lambda: stitch(region="Gap"), 'ERROR', "needs two road graphs", reports, op_results)
    activate(first, second)
    _cancelled_with(lambda: stitch(), 'ERROR', "No region", reports, op_results)
    _cancelled_with(lambda: stitch(region="Nowhere"), 'ERROR', "No object named 'Nowhere'", reports, op_results)
    _cancelled_with(lambda: stitch(other="Gap", region="Gap"), 'ERROR', "'Gap' is not another road graph",
                    reports, op_results)
    surface_name = roads.surface_object(second).name
    _cancelled_with(lambda: stitch(region=surface_name), 'ERROR', "is part of a road graph", reports, op_results)
    line = bpy.data.meshes.new("Line")
    line.from_pydata([(800.0, 0.0, 0.0), (900.0, 0.0, 0.0)], [(0, 1)], [])
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Line", line))
    activate(first, second)
    _cancelled_with(lambda: stitch(region="Line"), 'ERROR', "not closed", reports, op_results)
    gap_region("Tiny", [[900.0, 0.0], [901.0, 0.0], [901.0, 1.0]])
    activate(first, second)
    _cancelled_with(lambda: stitch(region="Tiny"), 'WARNING', "Nothing grew in Tiny between sample_city and "
                    "sample_city.001", reports, op_results)
    # A grammar text that does not parse.
    text = second.road_learning.text
    content = text.as_string()
    text.from_string("{ not a grammar")
    _cancelled_with(lambda: stitch(region="Gap"), 'ERROR', "is not a valid grammar", reports, op_results)
    text.from_string(content)
    bpy.data.objects.remove(bpy.data.objects["Line"])
    bpy.data.meshes.remove(line)
    for name in ("Tiny",):
        mesh = bpy.data.objects[name].data
        bpy.data.objects.remove(bpy.data.objects[name])
        bpy.data.meshes.remove(mesh)
    assert scene_state(first, second, third) == before_three
    assert scene_state(first, second)[:4] == before[:4]


def test_no_grammar_at_all_or_one_that_cannot_grow(sample_city, ggg, reports, op_results):
    from conftest import REPO

    first = import_town(sample_city, learn=False)
    second = import_town(sample_city, OFFSET, learn=False)
    gap_region()
    activate(first, second)
    assert bpy.context.scene.road_grammar.text is None  # (reading the settings makes their ID property)
    before = scene_state(first, second)
    _cancelled_with(lambda: bpy.ops.roads.stitch_cities(region="Gap"), 'ERROR', "No grammar for sample_city",
                    reports, op_results)
    assert scene_state(first, second) == before
    # The scene's grammar cannot grow streets (Sierpinski's rule places only nonterminals): the library refuses.
    assert bpy.ops.roads.load_grammar(filepath=str(REPO / "samples" / "sierpinski.grammar.json")) == {'FINISHED'}
    activate(first, second)
    before = scene_state(first, second)
    _cancelled_with(lambda: bpy.ops.roads.stitch_cities(region="Gap"), 'ERROR',
                    "Cannot stitch sample_city and sample_city.001 into Gap: the grammar has no rule that derives "
                    "to streets", reports, op_results)
    assert scene_state(first, second) == before


# --- Place Rule with another city's grammar ------------------------------------------------------

def _renamed(text, prefix):
    """Give the grammar of ``text`` other symbol names (prefix + name), so that its rules
    differ from those of the other town; the names, in order."""
    data = json.loads(text.as_string())
    if "symbols" not in data:
        # A learned grammar (version 6) leaves out the names R1, R2, ... it gives its rules:
        # naming them in "symbols" renames them.
        names = ["R{}".format(k + 1) for k in range(len(data["rules"][0]))]
        data["symbols"] = [prefix + name for name in names]
        text.from_string(json.dumps(data))
        return data["symbols"]
    names = list(data["symbols"])
    content = text.as_string()
    for name in names:
        content = content.replace('"{}"'.format(name), '"{}{}"'.format(prefix, name))
    text.from_string(content)
    return [prefix + name for name in names]


def test_place_rule_with_the_second_towns_grammar(towns, ggg, reports):
    from road_grammar.ui import grammar as grammar_ui

    first, second, region_obj = towns
    text_a, text_b = first.road_learning.text, second.road_learning.text
    names_b = _renamed(text_b, "B_")
    settings = bpy.context.scene.road_grammar
    settings.text = text_a  # the scene's grammar is the first town's
    rule = names_b[-1]
    symbol_b = rule_of(texts.of_text(text_b)[1], rule)["symbol"]
    assert rule_of(texts.of_text(text_a)[1], rule) is None
    cursor = bpy.context.scene.cursor
    cursor.location = (900.0, 0.0, 0.0)
    activate(first)
    count = len(first.data.vertices)
    assert bpy.ops.roads.place_rule(grammar=text_b.name, rule=rule, scale=60.0) == {'FINISHED'}
    assert "Placed {} ({}) of '{}' in sample_city".format(rule, symbol_b, text_b.name) in reports()[-1][1]
    mesh = first.data
    assert len(mesh.vertices) == count + 1
    assert mesh_build.read_attribute(mesh, "symbol", np.int64)[-1] == symbol_b
    note = mesh_build.read_attribute(mesh, RULE_GRAMMAR, np.int64)
    assert note[:-1].tolist() == [0] * count
    assert list(first[RULE_GRAMMARS_KEY])[note[-1] - 1] == text_b.name
    np.testing.assert_allclose(mesh.vertices[-1].co[:2], (900.0, 0.0), atol=1e-3)
    # Without the grammar named, the scene's (the first town's) has no such rule.
    with pytest.raises((TypeError, RuntimeError)):
        bpy.ops.roads.place_rule(rule=rule)

    # The panel: a picker of the grammar texts; the rule menu and the button follow it.
    plain = bpy.data.texts.new("notes.txt")
    plain.from_string("not a grammar")
    assert texts.looks_like_grammar(text_a) and texts.looks_like_grammar(text_b)
    assert not texts.looks_like_grammar(plain)
    settings.place_grammar = text_b
    assert [item[0] for item in texts.rule_items(settings, bpy.context)] == names_b
    settings.rule = rule
    labels, buttons = [], []
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    place = next(properties for idname, properties in buttons if idname == "roads.place_rule")
    assert place["grammar"] == text_b.name and place["rule"] == rule
    settings.place_grammar = None
    assert [item[0] for item in texts.rule_items(settings, bpy.context)][0] == "R1"

    # Stitching grows the placed rule with the second town's grammar (its note), before the rest.
    activate(first, second)
    assert bpy.ops.roads.stitch_cities(region=region_obj.name) == {'FINISHED'}
    assert "1 placed rule grown" in reports()[-1][1]
    assert not mesh_build.read_attribute(first.data, "symbol", np.int64).any()


def test_the_panel_box(towns, ggg):
    from road_grammar.ui import grammar as grammar_ui

    first, second, region_obj = towns
    settings = bpy.context.scene.road_grammar
    settings.region, settings.region_seed, settings.region_max_placements = region_obj, 5, 90
    settings.stitch_share = 0.25
    settings.region_roundabouts = False
    labels, buttons = [], []
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert "Stitch Cities" in labels
    assert "sample_city: sample_city.grammar.json" in labels
    assert "sample_city.001: sample_city.001.grammar.json" in labels
    assert "sample_city.001 is joined into sample_city" in labels
    stitch = next(properties for idname, properties in buttons if idname == "roads.stitch_cities")
    assert stitch["region"] == "Gap" and stitch["seed"] == 5 and stitch["max_placements"] == 90
    assert stitch["share"] == pytest.approx(0.25) and stitch["roundabouts"] is False
    assert bpy.ops.roads.stitch_cities(**stitch) == {'FINISHED'}
    labels.clear()
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert "Select two road graphs (the one to keep active)" in labels


# --- undo (a windowed Blender under Xvfb) ------------------------------------------------------

def test_undo_restores_both_towns(sample_city, ggg, tmp_path):
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        pytest.skip("xvfb-run is not installed (apt-get install xvfb xauth): undo needs a Blender window")
    output = tmp_path / "stitch.json"
    env = dict(os.environ)
    env["GGG_MODULE_DIR"] = str(Path(ggg.__file__).parent)
    command = [xvfb_run, "-a", bpy.app.binary_path, "--factory-startup", "--python-exit-code", "1",
               "--python", str(HERE / "stitch_session.py"), "--",
               str(Path(road_grammar.__file__).parent.parent), str(sample_city), str(output)]
    completed = subprocess.run(command, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=300)
    assert output.is_file(), "the windowed Blender wrote nothing:\n" + completed.stdout[-3000:] + \
        completed.stderr[-3000:]
    result = json.loads(output.read_text())
    assert "error" not in result, result.get("error")
    assert result["load"] == [['FINISHED']] * 2 and result["learn"] == [['FINISHED']] * 2
    assert result["stitch"] == ['FINISHED']
    before, stitched = result["before"], result["stitched"]
    assert "sample_city.001" in before["objects"] and "sample_city.001 Surface" in before["objects"]
    assert "sample_city.001" not in stitched["objects"] and "sample_city.001" not in stitched["scene objects"]
    old, new = before["meshes held"]["sample_city"], stitched["meshes held"]["sample_city"]
    assert new[0] > 2 * old[0] and new[1] > 2 * old[1]
    assert before["locations"]["sample_city.001"] == [1800.0, 0.0, 0.0]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == stitched
