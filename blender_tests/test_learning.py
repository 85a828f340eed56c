"""Grammar learning in Blender: Learn on the sample town (paper and lossless mode) and its
grammar Text, the rule list, the level slider and its display object (compared with
ggg.encoded_graph), choosing a rule, persistence in the .blend, cancelling, bad input, the
panels; in a windowed Blender under Xvfb, the modal Learn (with its undo, and cancelled
with Esc). Undo of Learn run from a script is in test_undo.py."""

import json
from types import SimpleNamespace

import bpy
import numpy as np
import pytest

from conftest import (PanelLayout, cancel_at_first_progress, draw_panel, record_executes, run_analysis_session,
                      snapshot)
from road_grammar.core.names import LEARNED_FROM_KEY
from road_grammar.core.palette import DIMMED_SLOT
from road_grammar.core.text import plural
from road_grammar.data import analysis, texts
from road_grammar.data import mesh as mesh_build
from road_grammar.display import patterns as pattern_display
from road_grammar.display import rules as rule_display
from road_grammar.operators import learning as learning_ops
from road_grammar.ui import learning as learning_ui


@pytest.fixture
def op_results(monkeypatch):
    """What each learning operator's execute() returned (bpy.ops raises on ERROR reports)."""
    return record_executes(monkeypatch, learning_ops.ROADS_OT_learn, learning_ops.ROADS_OT_show_level)


def text_grammar(ggg, text):
    return ggg.parse_grammar(text.as_string(), text.name)


def display_arrays(obj):
    """What the rules object of ``obj`` holds: {attribute: values} and the vertex positions."""
    child = rule_display.rules_object(obj)
    assert child is not None
    mesh = child.data
    arrays = {name: mesh_build.read_attribute(mesh, name, np.int64)
              for name in (rule_display.EDGE_RULE, rule_display.EDGE_SLOT, rule_display.MARKER_RULE,
                           rule_display.MARKER_SLOT)}
    arrays["edges"] = mesh_build.edge_vertices(mesh)
    arrays["positions"] = mesh_build.positions_xy(mesh)
    return child, arrays


def expected_level(ggg, parsed, level):
    """Straight from the library: the decoded streets, {symbol: streets held at ``level``}
    and {symbol: nonterminal vertices of the level's graph}."""
    streets = ggg.decode(parsed)
    edges = np.asarray(streets.edges, dtype=np.int64)
    graph, image = ggg.encoded_graph(parsed, level)
    symbols = np.asarray(graph.vertex_symbols, dtype=np.int64)
    image = np.asarray(image, dtype=np.int64)
    held = {}
    for u, v in edges.tolist():
        a, b = image[u], image[v]
        if a == b and a >= 0 and symbols[a] > 0:
            held[int(symbols[a])] = held.get(int(symbols[a]), 0) + 1
    markers = {}
    for s in symbols[symbols > 0].tolist():
        markers[s] = markers.get(s, 0) + 1
    return streets, held, markers


def counts(values):
    values = np.asarray(values)
    return {int(k): int(n) for k, n in zip(*np.unique(values[values > 0], return_counts=True))}


def ribbons(obj):
    """(material name, height above the graph, vertices) of every instance the rules
    object's modifier makes: street ribbons (quads), marker discs and their outlines."""
    child = rule_display.rules_object(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    found = []
    for instance in depsgraph.object_instances:
        if instance.is_instance and instance.parent is not None and instance.parent.original == child:
            names = [s.material.name for s in instance.object.material_slots if s.material is not None]
            height = max((instance.matrix_world @ v.co).z for v in instance.object.data.vertices)
            found.append((names[0] if names else None, round(height - obj.location.z, 4),
                          len(instance.object.data.vertices)))
    return found


# --- Learn -------------------------------------------------------------------------------

@pytest.mark.parametrize("mode", ['PAPER', 'LOSSLESS'])
def test_learn_the_sample_town(town, ggg, op_results, reports, mode):
    assert bpy.ops.roads.learn(mode=mode) == {'FINISHED'}
    assert op_results == [{'FINISHED'}]
    result = town.road_learning
    stats = json.loads(result.stats)
    assert stats["mode"] == mode.lower() and result.mode == mode.lower()
    assert stats["input"] == {"vertices": len(town.data.vertices), "edges": len(town.data.edges)}
    # The Text is the scene's grammar and parses to a learned grammar with the stats' numbers.
    text = bpy.context.scene.road_grammar.text
    assert text is not None and text == result.text and text.name == "sample_city.grammar.json"
    assert text.use_fake_user and text.get(LEARNED_FROM_KEY) == town.name
    parsed = text_grammar(ggg, text)
    assert parsed.learned and parsed.mode == stats["mode"]
    assert len(parsed.rules) == stats["rules"] > 0
    assert parsed.levels == stats["levels"] == result.levels > 0
    assert parsed.instance_count == stats["instances"]
    # The list has the rules, each used at least once, with their numbers.
    assert [item.name for item in result.rules] == [rule["name"] for rule in parsed.rules]
    for item, rule in zip(result.rules, parsed.rules):
        assert item.uses == rule["uses"] > 0
        assert (item.symbol, item.level, item.vertex_count, item.edge_count, item.embedding_points) == \
            (rule["symbol"], rule["level"], rule["vertices"], rule["edges"], rule["embedding_points"])
    assert sum(item.uses for item in result.rules) == stats["instances"]
    kind, message = next(r for r in reports() if r[1].startswith("Learned"))
    assert kind == 'INFO' and message.startswith("Learned a grammar of sample_city ({})".format(mode.lower()))
    assert "{}, {}".format(plural(stats["rules"], "rule"), plural(stats["levels"], "level")) \
        in message and "round trip" in message
    if mode == 'LOSSLESS':
        assert stats["roundtrip"]["edges_equal"] is True
        assert stats["roundtrip"]["max_displacement_m"] <= 0.7072 * 0.01  # the 1 cm quantum
    # The decoded streets have the town's edge count either way.
    assert ggg.decode(parsed).edge_count == len(town.data.edges)


def test_learn_matches_ggg_learn(town, ggg):
    options = dict(max_order=4, levels=3, angle_cells=8, distance_cells=6, cut=0.7)
    assert bpy.ops.roads.learn(**options) == {'FINISHED'}
    graph = analysis.MeshTopology(town, with_classes=True).graph(ggg)
    direct, stats = ggg.learn(graph, max_order=4, levels=3, grid=(8, 6), cut=0.7)
    parsed = text_grammar(ggg, town.road_learning.text)
    assert [(r["name"], r["vertices"], r["edges"], r["uses"]) for r in parsed.rules] == \
        [(r["name"], r["vertices"], r["edges"], r["uses"]) for r in direct.rules]
    assert parsed.levels == direct.levels <= 3
    assert all(r["vertices"] <= 4 for r in parsed.rules)
    stored = json.loads(town.road_learning.stats)
    assert (stored["rules"], stored["instances"], stored["axiom"]) == (stats["rules"], stats["instances"],
                                                                       stats["axiom"])
    assert "max order 4" in town.road_learning.parameters and "grid 8x6" in town.road_learning.parameters
    # The rules keep the streets' classes (the mesh's highway attribute goes in).
    assert stats["roundtrip"]["classes_equal"]
    assert set(np.asarray(ggg.decode(parsed).edge_highway).tolist()) == \
        set(mesh_build.read_attribute(town.data, "highway", np.int64).tolist())


def test_the_panel_button_takes_the_settings(town, ggg):
    settings = bpy.context.scene.road_learning
    settings.mode, settings.max_order, settings.levels = 'LOSSLESS', 4, 1
    buttons = []
    layout = PanelLayout([], buttons)
    learning_ui.VIEW3D_PT_roads_learn.draw(SimpleNamespace(layout=layout), bpy.context)
    learn = next(properties for idname, properties in buttons if idname == "roads.learn")
    assert learn == {name: getattr(settings, name) for name in learning_ops.ROADS_OT_learn._FROM_SETTINGS}
    assert bpy.ops.roads.learn(**learn) == {'FINISHED'}
    stats = json.loads(town.road_learning.stats)
    assert stats["mode"] == "lossless" and stats["levels"] == 1
    assert all(item.vertex_count <= 4 for item in town.road_learning.rules)
    assert "max order 4, 1 level, lossless" in town.road_learning.parameters


def test_learn_again_refreshes_the_text(town, ggg):
    assert bpy.ops.roads.learn(mode='PAPER') == {'FINISHED'}
    text = town.road_learning.text
    assert bpy.ops.roads.learn(mode='LOSSLESS') == {'FINISHED'}
    assert town.road_learning.text == text and len(bpy.data.texts) == 1
    assert text_grammar(ggg, text).mode == "lossless"
    # The scene's grammar follows even when another one was chosen in between.
    bpy.context.scene.road_grammar.text = bpy.data.texts.new("other.json")
    assert bpy.ops.roads.learn(mode='PAPER') == {'FINISHED'}
    assert bpy.context.scene.road_grammar.text == text and text_grammar(ggg, text).mode == "paper"


def test_learned_grammar_works_with_the_grammar_operators(town, ggg, tmp_path):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    parsed = text_grammar(ggg, town.road_learning.text)
    path = tmp_path / "learned.grammar.json"
    assert bpy.ops.roads.save_grammar(filepath=str(path)) == {'FINISHED'}
    written = ggg.read_grammar(str(path))
    assert written.learned and [r["name"] for r in written.rules] == [r["name"] for r in parsed.rules]
    assert [item[0] for item in texts.rule_items(None, bpy.context)] == [r["name"] for r in parsed.rules]
    vertices = len(town.data.vertices)
    rule = parsed.rules[0]["name"]
    assert bpy.ops.roads.place_rule(rule=rule, scale=50.0) == {'FINISHED'}
    assert len(town.data.vertices) == vertices + 1
    assert mesh_build.read_attribute(town.data, "symbol", np.int64)[-1] == parsed.rules[0]["symbol"]


def test_cancel_through_the_progress_callback_changes_nothing(town, monkeypatch, reports):
    before = snapshot()
    calls = cancel_at_first_progress(monkeypatch, learning_ops.LearningJob)
    assert bpy.ops.roads.learn() == {'CANCELLED'}
    assert len(calls) == 1
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "cancelled" in message and "nothing changed" in message
    assert snapshot() == before and len(bpy.data.texts) == 0
    assert bpy.context.scene.road_grammar.text is None and not town.road_learning.has_result()
    assert rule_display.rules_object(town) is None
    assert not learning_ops.running


def test_cancel_keeps_the_previous_grammar(town, monkeypatch, ggg):
    assert bpy.ops.roads.learn(mode='LOSSLESS') == {'FINISHED'}
    text = town.road_learning.text
    content, stats, level = text.as_string(), town.road_learning.stats, town.road_learning.level
    before = snapshot()

    def cancelling(self, fraction, message):
        self.cancel()
        return self.keep_going()

    monkeypatch.setattr(learning_ops.LearningJob, "__call__", cancelling)
    assert bpy.ops.roads.learn(mode='PAPER') == {'CANCELLED'}
    assert snapshot() == before
    assert (text.as_string(), town.road_learning.stats, town.road_learning.level) == (content, stats, level)


def test_learn_on_a_mesh_with_no_edges(ggg, op_results, reports):
    mesh = bpy.data.meshes.new("dots")
    mesh.vertices.add(3)
    mesh.vertices.foreach_set("co", [0.0, 0.0, 0.0, 100.0, 0.0, 0.0, 0.0, 100.0, 0.0])
    obj = bpy.data.objects.new("dots", mesh)
    obj["road_graph"] = 1
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    before = snapshot()
    with pytest.raises(RuntimeError, match="dots has no edges to learn from"):
        bpy.ops.roads.learn()
    assert op_results == [{'CANCELLED'}]
    assert snapshot() == before and not obj.road_learning.has_result()


def test_learn_without_a_road_graph(ggg, op_results):
    plain = bpy.data.objects.new("plain", bpy.data.meshes.new("plain"))
    bpy.context.scene.collection.objects.link(plain)
    bpy.context.view_layer.objects.active = plain
    before = snapshot()
    with pytest.raises(RuntimeError, match="not a road graph"):
        bpy.ops.roads.learn()
    bpy.context.view_layer.objects.active = None
    with pytest.raises(RuntimeError, match="the active object is none"):
        bpy.ops.roads.learn()
    assert op_results == [{'CANCELLED'}, {'CANCELLED'}]
    assert snapshot() == before


def test_learn_in_edit_mode(town, ggg):
    highway = mesh_build.read_attribute(town.data, "highway", np.int64)
    direct, _ = ggg.learn(analysis.MeshTopology(town, with_classes=True).graph(ggg))
    bpy.ops.object.mode_set(mode='EDIT')
    # The edit mesh's classes (Blender's attribute data is empty in Edit Mode).
    assert np.array_equal(analysis.MeshTopology(town, with_classes=True).highway, highway)
    assert bpy.ops.roads.learn() == {'FINISHED'}
    assert town.mode == 'OBJECT'  # the result is kept in Object Mode, one undo step
    assert town.road_learning.has_result() and rule_display.rules_object(town) is not None
    parsed = text_grammar(ggg, town.road_learning.text)
    assert [(r["vertices"], r["edges"], r["uses"]) for r in parsed.rules] == \
        [(r["vertices"], r["edges"], r["uses"]) for r in direct.rules]


# --- the level slider and the display ----------------------------------------------------

def test_top_level_shows_one_coloured_group_per_rule(town, ggg):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    result = town.road_learning
    parsed = text_grammar(ggg, result.text)
    top = parsed.levels
    result.level = 0
    result.level = top
    child, arrays = display_arrays(town)
    assert child.name == "sample_city Rules" and child.parent == town and child.hide_select
    assert child[rule_display.LEVEL_KEY] == top
    streets, held, markers = expected_level(ggg, parsed, top)
    assert held and len(held) <= len(parsed.rules)
    # One coloured group of streets per rule present at the top level, as the library says.
    assert counts(arrays[rule_display.EDGE_RULE]) == held
    slot_of = {item.symbol: item.color_slot for item in result.rules}
    rules = arrays[rule_display.EDGE_RULE]
    slots = arrays[rule_display.EDGE_SLOT]
    assert np.array_equal(slots, np.array([slot_of.get(r, 0) for r in rules.tolist()]))
    # The decoded streets, then one marker vertex per nonterminal of the level's graph.
    n = streets.vertex_count
    assert len(arrays["edges"]) == streets.edge_count
    np.testing.assert_allclose(arrays["positions"][:n], np.asarray(streets.positions), atol=1e-2)
    assert counts(arrays[rule_display.MARKER_RULE][n:]) == markers
    assert not arrays[rule_display.MARKER_RULE][:n].any() and (arrays[rule_display.MARKER_SLOT][n:] > 0).all()
    # Drawn: a ribbon per street in its colour's material, a disc (and an outline) per marker.
    drawn = ribbons(town)
    by_material = {}
    for name, _, _ in drawn:
        by_material[name] = by_material.get(name, 0) + 1
    marker_count = sum(markers.values())
    for slot in set(slots.tolist()) - {0}:
        quads = int(np.count_nonzero(slots == slot))
        discs = int(np.count_nonzero(arrays[rule_display.MARKER_SLOT] == slot))
        assert by_material[pattern_display.material(slot).name] == quads + discs
    assert by_material[rule_display.slot_material(0).name] == int(np.count_nonzero(slots == 0))
    outline = rule_display.outline_material().name
    assert by_material[outline] == marker_count
    assert len(drawn) == streets.edge_count + 2 * marker_count
    # Streets above the road surfaces, the markers above them, each disc above its outline.
    street_heights = [h for _, h, vertices in drawn if vertices == 4]
    outline_heights = [h for name, h, vertices in drawn if name == outline]
    disc_heights = [h for name, h, vertices in drawn if vertices > 4 and name != outline]
    assert len(street_heights) == streets.edge_count and len(disc_heights) == marker_count
    assert 0.25 < min(street_heights) and max(street_heights) < min(outline_heights)
    assert max(outline_heights) < min(disc_heights)


def test_level_zero_shows_the_plain_streets(town, ggg):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    result = town.road_learning
    assert result.level == result.levels  # Learn shows the top level
    result.level = 0
    parsed = text_grammar(ggg, result.text)
    streets = ggg.decode(parsed)
    child, arrays = display_arrays(town)
    assert child[rule_display.LEVEL_KEY] == 0
    assert len(arrays["edges"]) == streets.edge_count and len(arrays["positions"]) == streets.vertex_count
    assert not arrays[rule_display.EDGE_RULE].any() and not arrays[rule_display.EDGE_SLOT].any()
    drawn = ribbons(town)
    assert len(drawn) == streets.edge_count
    assert {name for name, _, _ in drawn} == {rule_display.slot_material(0).name}


def expect_every_level_as_the_library(town, ggg, parsed):
    """Shows each level of the learned grammar in turn and checks the display against the
    library; returns the top level's markers ({symbol: nonterminals})."""
    result = town.road_learning
    markers = {}
    for level in range(result.levels + 1):
        result.level = level
        _, arrays = display_arrays(town)
        _streets, held, markers = expected_level(ggg, parsed, level)
        assert counts(arrays[rule_display.EDGE_RULE]) == held
        assert counts(arrays[rule_display.MARKER_RULE]) == markers
    return markers


def test_every_level_matches_the_library(town, ggg):
    assert bpy.ops.roads.learn(mode='LOSSLESS') == {'FINISHED'}
    result = town.road_learning
    parsed = text_grammar(ggg, result.text)
    expect_every_level_as_the_library(town, ggg, parsed)
    # The slider stays within the grammar's levels.
    result.level = result.levels + 5
    assert result.level == result.levels
    result.level = -3
    assert result.level == 0


def test_complete_learning_shows_every_level_down_to_one_vertex(town, ggg, reports):
    """Learn with Complete on: the top level is the axiom's single nonterminal, and every level
    shows what the library says it holds."""
    assert bpy.ops.roads.learn(mode='LOSSLESS', complete=True) == {'FINISHED'}
    result = town.road_learning
    parsed = text_grammar(ggg, result.text)
    stats = json.loads(result.stats)
    assert stats["axiom"] == {"vertices": 1, "edges": 0}
    assert stats["roundtrip"]["edges_equal"]
    assert "complete" in result.parameters
    markers = expect_every_level_as_the_library(town, ggg, parsed)
    assert sum(markers.values()) == 1  # the top level: one nonterminal


def test_choosing_a_rule_highlights_its_instances(town, ggg, op_results, reports):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    result = town.road_learning
    top = result.levels
    _, all_rules = display_arrays(town)
    present = sorted(counts(all_rules[rule_display.EDGE_RULE]))
    index = next(i for i, item in enumerate(result.rules) if item.symbol == present[-1])
    item = result.rules[index]
    result.active_rule = index
    _, arrays = display_arrays(town)
    rules, slots = arrays[rule_display.EDGE_RULE], arrays[rule_display.EDGE_SLOT]
    assert np.array_equal(rules, all_rules[rule_display.EDGE_RULE])
    assert set(np.flatnonzero(slots).tolist()) == set(np.flatnonzero(rules == item.symbol).tolist())
    assert set(slots[slots > 0].tolist()) == {item.color_slot}
    marker_rules, marker_slots = arrays[rule_display.MARKER_RULE], arrays[rule_display.MARKER_SLOT]
    mine = marker_rules == item.symbol
    assert mine.any() and (marker_slots[mine] == item.color_slot).all()
    assert (marker_slots[(marker_rules > 0) & ~mine] == DIMMED_SLOT).all()
    # Another level keeps the highlight; All Rules shows every colour again.
    result.level = 0
    result.level = top
    assert np.array_equal(display_arrays(town)[1][rule_display.EDGE_SLOT], slots)
    assert bpy.ops.roads.show_level(rule=-1) == {'FINISHED'}
    assert result.active_rule == -1
    assert np.array_equal(display_arrays(town)[1][rule_display.EDGE_SLOT], all_rules[rule_display.EDGE_SLOT])
    kind, message = reports()[-1]
    assert kind == 'INFO' and message.startswith("sample_city: level {} of {},".format(top, top))


def test_show_level_errors(town, ggg, op_results):
    with pytest.raises(RuntimeError, match="has no learned grammar"):
        bpy.ops.roads.show_level(level=0)
    assert bpy.ops.roads.learn() == {'FINISHED'}
    result = town.road_learning
    with pytest.raises(RuntimeError, match="there is no level"):
        bpy.ops.roads.show_level(level=result.levels + 1)
    with pytest.raises(RuntimeError, match="there is no rule"):
        bpy.ops.roads.show_level(rule=len(result.rules))
    # A text that no longer parses: reported, the level and the display stay.
    _, before = display_arrays(town)
    level = result.level
    result.text.from_string("{ not a grammar")
    with pytest.raises(RuntimeError, match="is not a valid grammar"):
        bpy.ops.roads.show_level(level=0)
    assert result.level == level
    assert np.array_equal(display_arrays(town)[1][rule_display.EDGE_RULE], before[rule_display.EDGE_RULE])
    # The slider cannot report: the panel says why.
    result.level = 0
    assert "is not a valid grammar" in rule_display.display_problems[town.name]
    assert op_results[:1] == [{'CANCELLED'}] and op_results[-1] == {'CANCELLED'}


def test_display_survives_save_and_reload(town, ggg, tmp_path):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    result = town.road_learning
    result.active_rule = 0
    _, before = display_arrays(town)
    state = (result.level, result.active_rule, result.stats, [item.name for item in result.rules],
             result.text.as_string())
    name = town.name
    path = tmp_path / "learned.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert name not in bpy.data.objects
    rule_display.forget_cache()
    bpy.ops.wm.open_mainfile(filepath=str(path))
    obj = bpy.data.objects[name]
    result = obj.road_learning
    assert (result.level, result.active_rule, result.stats, [item.name for item in result.rules],
            result.text.as_string()) == state
    assert bpy.context.scene.road_grammar.text == result.text
    _, after = display_arrays(obj)
    for key in before:
        assert np.array_equal(after[key], before[key]), key
    assert len(ribbons(obj)) == len(before["edges"]) + 2 * int(np.count_nonzero(before[rule_display.MARKER_SLOT]))
    # The slider works on the reloaded file (from the stored grammar text).
    top = result.level
    result.level = 0
    assert not display_arrays(obj)[1][rule_display.EDGE_RULE].any()
    result.level = top
    assert np.array_equal(display_arrays(obj)[1][rule_display.EDGE_SLOT], before[rule_display.EDGE_SLOT])


def test_slider_is_fast_on_a_larger_graph(ggg):
    """A 40 x 40 street grid (1,600 vertices): learning it and moving the slider over every
    level stay quick (each level is one native call and bulk writes)."""
    import time

    n, spacing = 40, 80.0
    ij = np.array([(i, j) for j in range(n) for i in range(n)], dtype=np.float64)
    rng = np.random.default_rng(3)
    positions = ij * spacing + rng.normal(0.0, 1.0, ij.shape)
    edges = [(j * n + i, j * n + i + 1) for j in range(n) for i in range(n - 1)] + \
        [(j * n + i, (j + 1) * n + i) for j in range(n - 1) for i in range(n)]
    mesh = mesh_build.new_edge_mesh("grid", positions, np.array(edges))
    obj = bpy.data.objects.new("grid", mesh)
    obj["road_graph"] = 1
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.roads.learn(max_order=4) == {'FINISHED'}
    result = obj.road_learning
    assert result.levels >= 1 and len(result.rules) >= 1
    started = time.perf_counter()
    for level in list(range(result.levels, -1, -1)) + list(range(result.levels + 1)):
        result.level = level
    per_level = (time.perf_counter() - started) / (2 * result.levels + 2)
    assert per_level < 0.5, per_level
    assert len(display_arrays(obj)[1]["edges"]) == len(edges)


# --- the panels ---------------------------------------------------------------------------

def test_panels_draw(town, ggg):
    assert "Learn from sample_city" in draw_panel(learning_ui.VIEW3D_PT_roads_learn)
    assert "Nothing learned yet" in draw_panel(learning_ui.VIEW3D_PT_roads_learned_rules)
    assert bpy.ops.roads.learn(mode='LOSSLESS') == {'FINISHED'}
    result = town.road_learning
    stats = json.loads(result.stats)
    result.active_rule = 0
    text = draw_panel(learning_ui.VIEW3D_PT_roads_learned_rules)
    assert "{}, {}".format(plural(stats["rules"], "rule"), plural(stats["levels"], "level")) in text
    assert "Round trip: same edges" in text and "sample_city.grammar.json" in text
    # The sizes in both encodings, and what each pass saved.
    assert "JSON: {:,} \u2192 {:,} bytes".format(stats["bytes"]["original"], stats["bytes"]["encoded"]) in text
    assert "CBOR: {:,} \u2192".format(stats["bytes"]["original_cbor"]) in text
    assert "Graph CBOR: positions" in text and "Grammar CBOR: " in text
    assert "Pass 1: {}".format(plural(stats["per_level"][0]["rules"], "rule")) in text
    assert "of {}".format(stats["levels"]) in text and "Not the scene's grammar" not in text
    item = result.rules[0]
    assert "{} (symbol {}), level {}".format(item.name, item.symbol, item.level) in text
    labels = []
    ui_list = SimpleNamespace(layout_type='DEFAULT')
    learning_ui.ROADS_UL_learned_rules.draw_item(ui_list, bpy.context, PanelLayout(labels), None, item, 0, None, "")
    assert labels == [item.name, str(item.level), str(item.uses), str(item.vertex_count)]
    bpy.context.scene.road_grammar.text = None
    assert "Not the scene's grammar" in draw_panel(learning_ui.VIEW3D_PT_roads_learned_rules)


# --- the modal run, in a Blender with a window ---------------------------------------------

def test_modal_learn_takes_the_panel_settings_and_undoes(sample_city, ggg, tmp_path):
    result = run_analysis_session(ggg, tmp_path, sample_city, "learn")
    assert result["learn"] == ['RUNNING_MODAL'] and result["was_running"] and result["finished"]
    before, learned = result["before"], result["learned"]
    assert before["texts"] == [] and before["scene grammar"] is None and before["rules"] == 0
    # The panel's settings (lossless, max order 4), not the operator's defaults.
    assert learned["mode"] == "lossless" and 0 < learned["max rule vertices"] <= 4
    assert learned["texts"] == ["sample_city.grammar.json"] == [learned["scene grammar"]]
    assert "sample_city Rules" in learned["objects"]
    assert result["undo"] == ['FINISHED'] and result["undone"] == before
    assert result["redo"] == ['FINISHED'] and result["redone"] == learned


def test_modal_learn_cancelled_with_escape(sample_city, ggg, tmp_path):
    result = run_analysis_session(ggg, tmp_path, sample_city, "learn_escape", "--enable-event-simulate")
    assert result["learn"] == ['RUNNING_MODAL']
    assert result["was_running"] and result["progress_calls"] >= 1
    assert not result["still_running"]
    assert result["after"] == result["before"] and result["after"]["texts"] == []


def test_selection_as_first_rule(town, ggg):
    # One block of the town's grid, picked by the analyzer: its vertices are the selection.
    graph = analysis.MeshTopology(town, with_classes=True).graph(ggg)
    block = [iso for iso in ggg.analyze(graph, max_order=4).isogroups if iso.order == 4 and iso.edge_count == 4][0]
    selected = np.zeros(len(town.data.vertices), dtype=bool)
    selected[block.occurrences[0]] = True
    town.data.vertices.foreach_set("select", selected)
    town.data.update()
    assert bpy.ops.roads.learn(use_seed=True) == {'FINISHED'}
    parsed = text_grammar(ggg, town.road_learning.text)
    first = parsed.rules[0]
    assert (first["vertices"], first["edges"]) == (4, 4) and first["uses"] >= 2
    direct, _ = ggg.learn(graph, seed=block.occurrences[0])
    assert [(r["vertices"], r["edges"], r["uses"]) for r in parsed.rules] == \
        [(r["vertices"], r["edges"], r["uses"]) for r in direct.rules]
    # A selection that is not one connected piece is refused, nothing changes.
    text = town.road_learning.text
    selected[:] = False
    selected[[0, len(selected) - 1]] = True
    town.data.vertices.foreach_set("select", selected)
    town.data.update()
    with pytest.raises(RuntimeError, match="Selection as first rule: No street joins"):
        bpy.ops.roads.learn(use_seed=True)
    assert town.road_learning.text == text
