"""The grammar operators: load/save a grammar, add its axiom, place a rule at the 3D
cursor, grow by derivation steps; compared with the CLI and with ggg.derive."""

import json
import math
import subprocess

import bpy
import numpy as np
import pytest

from conftest import REPO, edge_attribute, import_roads, snapshot, write_osm
from road_grammar.core.names import NAME, SOURCE_KEY, SURFACE_EDGE
from road_grammar.core.polylines import segment_polylines
from road_grammar.data import mesh as mesh_build
from road_grammar.data import roads, texts
from road_grammar.display import frames
from road_grammar.operators import grammar as grammar_ops

SIERPINSKI = REPO / "samples" / "sierpinski.grammar.json"
CLI = REPO / "build" / "bin" / "ggg"

# A rule T with an embedding point: vertex 0 at the nonterminal connects to the vertex one
# unit behind it (-1, 0); vertex 1 is one unit ahead, joined by a primary road.
T_GRAMMAR = {
    "format": "ggg-grammar",
    "version": 1,
    "name": "spur",
    "origin_latlon": [0, 0],
    "symbols": ["T"],
    "rules": [{
        "symbol": "T",
        "vertices": [
            {"position": [0, 0], "embedding": [{"offset": [-1, 0], "highway": "tertiary"}]},
            {"position": [1, 0]},
        ],
        "edges": [[0, 1, "primary"]],
    }],
    "axiom": {"vertices": [{"position": [0, 0], "symbol": "T", "frame": {"scale": 50}}], "edges": []},
}


@pytest.fixture
def op_results(monkeypatch):
    """What each grammar operator's execute() returned (bpy.ops raises on ERROR reports)."""
    results = []

    def recorder(original):
        def recording_execute(self, context):
            result = original(self, context)
            results.append(result)
            return result
        return recording_execute

    for cls in (grammar_ops.ROADS_OT_load_grammar, grammar_ops.ROADS_OT_add_axiom, grammar_ops.ROADS_OT_place_rule,
                grammar_ops.ROADS_OT_grow, grammar_ops.ROADS_OT_save_grammar):
        monkeypatch.setattr(cls, "execute", recorder(cls.execute))
    return results


@pytest.fixture
def reports(capsys):
    """A function returning the (type, message) reports printed so far (Blender prints an
    operator's reports on the console in background mode)."""
    kinds = {"Info": 'INFO', "Warning": 'WARNING', "Error": 'ERROR'}
    seen = []

    def read():
        for line in capsys.readouterr().out.splitlines():
            kind, _, message = line.partition(": ")
            if kind in kinds:
                seen.append((kinds[kind], message))
        return seen

    return read


def load(path=SIERPINSKI):
    return bpy.ops.roads.load_grammar(filepath=str(path))


def write_grammar(tmp_path, data, name="g.grammar.json"):
    path = tmp_path / name
    path.write_text(json.dumps(data) if not isinstance(data, str) else data, encoding="utf-8")
    return path


def graph_arrays(obj):
    """(positions (N, 2), edges (M, 2), symbols (N,), frames a, b (N, 2)) of a graph object."""
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int64)
    mesh.edges.foreach_get("vertices", edges)

    def point(name, dtype):
        values = np.empty(len(mesh.vertices), dtype=dtype)
        mesh.attributes[name].data.foreach_get("value", values)
        return values

    return (co.reshape(-1, 3)[:, :2], edges.reshape(-1, 2), point("symbol", np.int64),
            np.column_stack((point("frame_a", np.float64), point("frame_b", np.float64))))


def canonical(positions, edges, decimals=2):
    """Vertices as sorted rounded points, edges as a sorted list of rounded point pairs."""
    points = [tuple(p) for p in np.round(np.asarray(positions, dtype=np.float64), decimals) + 0.0]
    pairs = sorted(tuple(sorted((points[u], points[v]))) for u, v in np.asarray(edges))
    return sorted(points), pairs


def cli_derive(steps, tmp_path):
    if not CLI.is_file():
        pytest.skip("the CLI {} is missing: build it (cmake --build build)".format(CLI))
    out = tmp_path / "derived.geojson"
    completed = subprocess.run([str(CLI), "derive", str(SIERPINSKI), "--steps", str(steps), "-o", str(out)],
                               capture_output=True, text=True, timeout=120)
    assert completed.returncode == 0, completed.stderr
    return json.loads(completed.stdout.strip().splitlines()[-1])


def mesh_state(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    return len(obj.data.vertices), len(obj.data.edges), co.tobytes(), sorted(a.name for a in obj.data.attributes)


# --- loading and saving ---------------------------------------------------------------

def test_load_grammar_keeps_it_in_a_text(ggg, op_results):
    assert load() == {'FINISHED'}
    settings = bpy.context.scene.road_grammar
    text = settings.text
    assert text is not None and text.name == "sierpinski.grammar.json"
    assert text.as_string() == SIERPINSKI.read_text(encoding="utf-8")
    assert text.use_fake_user  # saved in the .blend even when no scene uses it
    assert text[SOURCE_KEY] == str(SIERPINSKI)
    _, parsed = texts.active(bpy.context)
    assert parsed.name == "sierpinski" and [r["name"] for r in parsed.rules] == ["P"]
    # Loading the same file again refreshes that text, it makes no copy.
    assert load() == {'FINISHED'}
    assert len(bpy.data.texts) == 1 and settings.text == text
    assert op_results == [{'FINISHED'}, {'FINISHED'}]


@pytest.mark.parametrize("content, expected", [
    ("{not json", "not valid JSON"),
    ("", "empty"),
    ('{"format": "ggg-grammar", "version": 1, "rules": []}', 'missing "axiom"'),
    (json.dumps({**T_GRAMMAR, "rules": [{**T_GRAMMAR["rules"][0], "edges": [[0, 7]]}]}), "rules[0].edges[0]"),
])
def test_bad_grammar_file_creates_nothing(tmp_path, ggg, op_results, content, expected):
    path = write_grammar(tmp_path, content, "bad.grammar.json")
    before = snapshot()
    with pytest.raises(RuntimeError) as error:
        load(path)
    message = str(error.value)
    assert message.startswith("Error:") and expected in message and "bad.grammar.json" in message, message
    assert op_results == [{'CANCELLED'}]
    assert snapshot() == before and len(bpy.data.texts) == 0
    assert bpy.context.scene.road_grammar.text is None


def test_missing_grammar_file(tmp_path, ggg, op_results):
    with pytest.raises(RuntimeError, match="no such file"):
        load(tmp_path / "nothing.json")
    assert op_results == [{'CANCELLED'}] and len(bpy.data.texts) == 0


def test_save_grammar_round_trip(tmp_path, ggg):
    assert load() == {'FINISHED'}
    out = tmp_path / "copy.grammar.json"
    assert bpy.ops.roads.save_grammar(filepath=str(out)) == {'FINISHED'}
    assert ggg.read_grammar(str(out)).to_json() == ggg.read_grammar(str(SIERPINSKI)).to_json()


def test_edited_text_is_used_and_a_broken_edit_is_reported(tmp_path, ggg, op_results):
    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    text = bpy.context.scene.road_grammar.text
    edited = json.loads(text.as_string())
    edited["name"] = "renamed"
    text.from_string(json.dumps(edited))
    assert texts.active(bpy.context)[1].name == "renamed"
    text.from_string("{oops")
    before = snapshot()
    with pytest.raises(RuntimeError, match="not a valid grammar"):
        bpy.ops.roads.add_axiom()
    assert snapshot() == before
    assert op_results[-1] == {'CANCELLED'}


def test_operators_without_grammar_report(ggg, op_results):
    for call in (bpy.ops.roads.add_axiom, bpy.ops.roads.place_rule):
        with pytest.raises(RuntimeError, match="No grammar"):
            call()
    assert op_results == [{'CANCELLED'}, {'CANCELLED'}]
    assert len(bpy.data.objects) == 0


# --- the axiom and growing it -------------------------------------------------------------

def test_add_axiom(ggg):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    axiom = ggg.read_grammar(str(SIERPINSKI)).axiom_graph()
    positions, edges, symbols, ab = graph_arrays(obj)
    np.testing.assert_allclose(positions, axiom.positions, atol=1e-3)
    np.testing.assert_array_equal(edges, axiom.edges)
    np.testing.assert_array_equal(symbols, axiom.vertex_symbols)
    np.testing.assert_allclose(ab, axiom.vertex_frames[:, :2], rtol=1e-6, atol=1e-3)
    assert obj["road_graph"] == 1 and obj["grammar"] == "sierpinski"
    assert obj.name == "sierpinski" and roads.surface_object(obj) is not None
    # The grammar's origin becomes the scene's georeference.
    scene = bpy.context.scene
    assert (scene["lat"], scene["lon"]) == pytest.approx((46.0, 8.95))
    assert scene["SRID"] == axiom.crs
    # Arrows: the Rule Frames modifier, and the object renders.
    assert frames.find_modifier(obj) is not None and not obj.hide_render


@pytest.mark.parametrize("steps", [1, 2, 3, 4])
def test_grow_matches_the_cli(steps, tmp_path, ggg, op_results):
    expected = cli_derive(steps, tmp_path)
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    assert bpy.ops.roads.grow(steps=steps) == {'FINISHED'}
    # 3^(n+1) triangle corners, two to each place the triangles share: one vertex per place.
    assert len(obj.data.vertices) == expected["vertices"] == (3 ** (steps + 1) + 3) // 2
    assert len(obj.data.edges) == expected["edges"] == 3 ** (steps + 1)
    # The surface is rebuilt: one segment per (straight) edge.
    surface_obj = roads.surface_object(obj)
    assert len(surface_obj.data.edges) == expected["edges"]
    assert op_results[-1] == {'FINISHED'}


def test_grow_matches_derive_in_python(ggg):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    assert bpy.ops.roads.grow(steps=3) == {'FINISHED'}
    derived, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=3)
    positions, edges, symbols, ab = graph_arrays(obj)
    np.testing.assert_allclose(positions, derived.positions, atol=1e-3)
    np.testing.assert_array_equal(edges, derived.edges)
    np.testing.assert_array_equal(symbols, derived.vertex_symbols)
    np.testing.assert_allclose(ab, derived.vertex_frames[:, :2], atol=1e-4)
    # Frames are anchored at their vertices.
    np.testing.assert_allclose(derived.vertex_frames[:, 2:], derived.positions, atol=1e-9)


def test_grow_step_by_step_equals_grow_at_once(ggg):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    for _ in range(3):
        assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    derived, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=3)
    positions, edges, _, _ = graph_arrays(obj)
    assert canonical(positions, edges) == canonical(derived.positions, derived.edges)


def test_place_rule_at_the_cursor_then_grow(ggg):
    assert load() == {'FINISHED'}
    cursor = bpy.context.scene.cursor
    cursor.location = (120.0, -40.0, 3.0)
    cursor.rotation_euler = (0.0, 0.0, math.radians(30.0))
    assert bpy.context.view_layer.objects.active is None
    assert bpy.ops.roads.place_rule(rule='P', scale=200.0) == {'FINISHED'}
    obj = bpy.context.active_object
    assert obj["road_graph"] == 1 and roads.surface_object(obj) is not None
    positions, edges, symbols, ab = graph_arrays(obj)
    np.testing.assert_allclose(positions, [[120.0, -40.0]])
    assert len(edges) == 0 and symbols.tolist() == [1]
    assert ab[0] == pytest.approx((200.0 * math.cos(math.radians(30)), 200.0 * math.sin(math.radians(30))),
                                  rel=1e-6)

    assert bpy.ops.roads.grow(steps=2) == {'FINISHED'}
    grammar_ = ggg.read_grammar(str(SIERPINSKI))
    start = ggg.Graph.from_arrays(np.array([[120.0, -40.0]]), np.zeros((0, 2), dtype=np.int64),
                                  origin_latlon=(46.0, 8.95), vertex_symbols=np.array([1]),
                                  vertex_frames=np.array([[ab[0, 0], ab[0, 1], 120.0, -40.0]]))
    derived, report = ggg.derive(grammar_, start, steps=2)
    positions, edges, symbols, _ = graph_arrays(obj)
    assert len(positions) == report["vertices"] == 6 and len(edges) == report["edges"] == 9
    np.testing.assert_allclose(positions, derived.positions, atol=1e-3)
    np.testing.assert_array_equal(edges, derived.edges)
    # The first placed triangle side runs along the cursor's 30 degrees.
    first = derived.positions[derived.edges[0]]
    direction = first[1] - first[0]
    assert math.degrees(math.atan2(direction[1], direction[0])) == pytest.approx(30.0, abs=1e-6)


def test_place_rule_in_a_moved_and_turned_graph(ggg):
    """Cursor in world space, vertex and frame in the object's local space."""
    assert load() == {'FINISHED'}
    bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)
    assert bpy.ops.roads.place_rule(rule='P', scale=100.0) == {'FINISHED'}
    obj = bpy.context.active_object
    obj.location = (1000.0, 500.0, 0.0)
    obj.rotation_euler = (0.0, 0.0, math.radians(90.0))
    bpy.context.view_layer.update()
    cursor = bpy.context.scene.cursor
    cursor.location = (1000.0, 600.0, 0.0)  # local (100, 0)
    cursor.rotation_euler = (0.0, 0.0, math.radians(120.0))  # local 30 degrees
    assert bpy.ops.roads.place_rule(rule='P', scale=50.0) == {'FINISHED'}
    assert bpy.context.active_object == obj
    positions, _, symbols, ab = graph_arrays(obj)
    assert len(positions) == 2 and symbols.tolist() == [1, 1]
    assert positions[1] == pytest.approx((100.0, 0.0), abs=1e-3)
    assert math.degrees(math.atan2(ab[1, 1], ab[1, 0])) == pytest.approx(30.0, abs=1e-3)
    assert math.hypot(*ab[1]) == pytest.approx(50.0, rel=1e-6)


def test_abstract_grammar_does_not_georeference_the_scene(tmp_path, ggg):
    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    assert "SRID" not in bpy.context.scene and "lat" not in bpy.context.scene


def test_grow_without_nonterminals_changes_nothing(sample_city, ggg, op_results, reports):
    assert import_roads(sample_city) == {'FINISHED'}
    assert load() == {'FINISHED'}
    obj = bpy.context.active_object
    before = mesh_state(obj), snapshot()
    assert bpy.ops.roads.grow(steps=2) == {'CANCELLED'}
    assert (mesh_state(obj), snapshot()) == before
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "no nonterminal" in message and "unchanged" in message


def test_grow_nothing_selected(ggg, op_results):
    assert load() == {'FINISHED'}
    with pytest.raises(RuntimeError, match="Select a road graph"):
        bpy.ops.roads.grow()
    assert op_results[-1] == {'CANCELLED'}


def test_grow_budget(ggg, reports):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    assert bpy.ops.roads.grow(steps=10, max_vertices=100) == {'FINISHED'}
    assert len(obj.data.vertices) == 42
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "3 steps of 10" in message and "42 vertices" in message
    assert "stopped by budget" in message
    # A budget the first step already passes: nothing changes.
    before = mesh_state(obj)
    assert bpy.ops.roads.grow(steps=1, max_vertices=100) == {'CANCELLED'}
    assert mesh_state(obj) == before
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "budget" in message and "unchanged" in message


def test_grow_error_leaves_the_object(ggg, op_results, monkeypatch):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    before = mesh_state(obj), snapshot()

    def failing_derive(*args, **kwargs):
        raise ggg.Error("simulated derivation failure")

    monkeypatch.setattr(ggg, "derive", failing_derive)
    with pytest.raises(RuntimeError, match="simulated derivation failure"):
        bpy.ops.roads.grow(steps=2)
    assert op_results[-1] == {'CANCELLED'}
    assert (mesh_state(obj), snapshot()) == before


def test_grow_progress(ggg, capsys):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    assert bpy.ops.roads.grow(steps=2) == {'FINISHED'}
    assert "Growing roads: done (100%)" in capsys.readouterr().out


def test_arrows_follow_the_frames(ggg):
    """One arrow instance per nonterminal, turned and scaled by its frame, after each grow."""
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    for steps in (0, 1):
        if steps:
            assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
        depsgraph = bpy.context.evaluated_depsgraph_get()
        arrows = [inst.matrix_world.copy() for inst in depsgraph.object_instances
                  if inst.is_instance and inst.parent is not None and inst.parent.original == obj]
        positions, _, symbols, ab = graph_arrays(obj)
        assert len(arrows) == int(np.count_nonzero(symbols))
        size = 0.3  # the modifier's default Arrow Size
        found = sorted((round(m.translation.x, 2), round(m.translation.y, 2),
                        round(math.degrees(m.to_euler().z) % 360.0, 2), round(m.to_scale().x, 2)) for m in arrows)
        wanted = sorted((round(p[0], 2), round(p[1], 2), round(math.degrees(math.atan2(f[1], f[0])) % 360.0, 2),
                         round(size * math.hypot(*f), 2)) for p, f in zip(positions, ab))
        assert found == pytest.approx(wanted, abs=0.02)


def test_grow_keeps_imported_roads(tmp_path, ggg, prefs):
    """Growing a rule placed next to an OSM network keeps each old edge's attributes and
    polyline; the embedding joins the new road to the network."""
    nodes = {1: (46.0, 8.95), 2: (46.0, 8.951), 3: (46.0003, 8.9515), 4: (46.0, 8.952), 5: (46.001, 8.951)}
    ways = [(10, [1, 2], {"highway": "residential", "width": "7.5", "oneway": "yes"}),
            (11, [2, 3, 4], {"highway": "secondary", "lanes": "3"}),  # node 3 is a shape node
            (12, [2, 5], {"highway": "service"})]
    path = write_osm(tmp_path / "streets.osm", nodes, ways)
    assert import_roads(path, highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    surface_obj = roads.surface_object(obj)
    old_surface = len(surface_obj.data.edges)
    positions = np.array([v.co[:2] for v in obj.data.vertices])
    anchor = positions[np.argmax(positions[:, 0])]  # the east end of the secondary road (node 4)
    old_width = edge_attribute(obj.data, "width")
    old_lanes = edge_attribute(obj.data, "lanes", np.int64)
    old_oneway = edge_attribute(obj.data, "oneway", np.int64)

    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    cursor = bpy.context.scene.cursor
    cursor.location = (anchor[0] + 40.0, anchor[1], 0.0)
    cursor.rotation_euler = (0.0, 0.0, 0.0)
    assert bpy.ops.roads.place_rule(rule='T', scale=40.0) == {'FINISHED'}
    assert bpy.context.active_object == obj
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}

    mesh = obj.data
    assert len(mesh.vertices) == len(positions) + 2 and len(mesh.edges) == len(old_width) + 2
    width = edge_attribute(mesh, "width")
    np.testing.assert_allclose(width[:len(old_width)], old_width)
    np.testing.assert_array_equal(edge_attribute(mesh, "lanes", np.int64)[:len(old_lanes)], old_lanes)
    np.testing.assert_array_equal(edge_attribute(mesh, "oneway", np.int64)[:len(old_oneway)], old_oneway)
    classes = list(ggg.highway_classes())
    highway = edge_attribute(mesh, "highway", np.int64)
    new = sorted(classes[c] for c in highway[len(old_width):])
    assert new == ["primary", "tertiary"]
    defaults = ggg.default_widths()
    assert sorted(width[len(old_width):].tolist()) == pytest.approx(
        sorted([defaults["primary"], defaults["tertiary"]]))
    ranks = ggg.highway_ranks()
    np.testing.assert_array_equal(edge_attribute(mesh, "rank", np.int64), [ranks[c] for c in highway])
    # The surface keeps the bent secondary road (2 segments) and adds 2 straight ones.
    assert len(surface_obj.data.edges) == old_surface + 2
    owner = edge_attribute(surface_obj.data, "graph_edge", np.int64)
    assert np.bincount(owner).max() == 2


def test_grow_in_edit_mode(ggg):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    assert obj.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    assert len(obj.data.vertices) == 6 and len(obj.data.edges) == 9


def test_moved_nonterminal_takes_its_frame_along(ggg):
    """A frame's origin is its vertex: moving the vertex (Edit Mode, G) moves its rule."""
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    obj.data.vertices[0].co.x += 10.0
    moved = tuple(obj.data.vertices[0].co[:2])
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    positions, _, _, _ = graph_arrays(obj)
    # The rule's vertex at [0, 0] lands where the rewritten vertex was.
    assert any(np.allclose(p, moved, atol=1e-3) for p in positions)


def test_import_derived_graph_file_keeps_nonterminals(tmp_path, ggg):
    """A .ggraph with nonterminals (e.g. written by `ggg derive`) imports with its frames
    and can be grown further."""
    derived, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=1)
    path = tmp_path / "sierpinski1.ggraph"
    derived.write(str(path))
    assert import_roads(path) == {'FINISHED'}
    obj = bpy.context.active_object
    _, _, symbols, ab = graph_arrays(obj)
    np.testing.assert_array_equal(symbols, derived.vertex_symbols)
    np.testing.assert_allclose(ab, derived.vertex_frames[:, :2], atol=1e-3)
    assert frames.find_modifier(obj) is not None and not obj.hide_render
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    # The corners the file's triangles share carried both rewrites into the mesh.
    assert (len(obj.data.vertices), len(obj.data.edges)) == (15, 27)


def test_grow_step_by_step_is_grow_at_once(ggg):
    """A corner two triangles share is one vertex that holds both triangles' rewrites (the
    point attributes symbol_2, frame_a_2, frame_b_2), so growing one step at a time gives what
    three steps at once give."""
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    obj = bpy.context.active_object
    for _ in range(3):
        assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    from road_grammar.data.graph_edit import MeshGraph

    # The slot is the graph's own column, not an attribute only Blender holds.
    assert "symbol_2" in obj.data.attributes and "symbol_2" not in MeshGraph(obj).point_attributes
    positions, edges, _, _ = graph_arrays(obj)
    direct, _ = ggg.derive(ggg.read_grammar(str(SIERPINSKI)), steps=3)
    assert len(positions) == direct.vertex_count == 42 and len(edges) == 81
    np.testing.assert_allclose(positions, direct.positions, atol=1e-3)
    np.testing.assert_array_equal(edges, direct.edges)


def test_kept_edges_follow_source_vertices():
    from road_grammar.core.topology import kept_edges

    old_edges = np.array([[0, 3], [1, 2], [3, 4], [2, 1]])  # edge 3 runs beside edge 1
    # New vertices 0..3 are old 3, 0, 1, 2; vertex 4 was placed (old vertex 4 was rewritten).
    source = np.array([3, 0, 1, 2, -1])
    new_edges = np.array([[1, 0], [2, 3], [0, 4], [1, 2], [4, 2]])
    # Old edge 0 and old edge 1 (the first of the two between 1 and 2) are kept; edges at
    # the placed vertex and between vertices no old edge joined are new.
    np.testing.assert_array_equal(kept_edges(old_edges, source, new_edges), [0, 1, -1, -1, -1])
    assert kept_edges(np.zeros((0, 2)), source, new_edges).tolist() == [-1] * 5


def surface_lines(obj):
    """The polyline of each graph edge in the surface of ``obj``, as stored (float32)."""
    mesh = roads.surface_object(obj).data
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    offsets, points = segment_polylines(co.reshape(-1, 3)[:, :2], mesh_build.edge_vertices(mesh),
                                                   edge_attribute(mesh, SURFACE_EDGE, np.int64),
                                                   len(obj.data.edges))
    return [points[offsets[i]:offsets[i + 1]] for i in range(len(obj.data.edges))]


def edge_names(obj):
    return mesh_build.read_strings(obj.data, NAME, 'EDGE')


def test_grow_keeps_two_roads_that_end_at_one_place(tmp_path, ggg, prefs):
    """Two dead ends at the same position (two vertices, e.g. a road that stops where
    another begins without a junction): a grow keeps both roads' widths, names and
    polylines exactly, and the embedding edge joins one of the two vertices."""
    positions = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 0.0], [200.0, 0.0]])
    classes = list(ggg.highway_classes())
    graph = ggg.Graph.from_arrays(
        positions, np.array([[0, 1], [2, 3]]), origin_latlon=(46.0, 8.95),
        edge_highway=np.array([classes.index("secondary"), classes.index("residential")]),
        edge_width=np.array([7.3, 4.1]), edge_lanes=np.array([2, 0]), edge_oneway=np.array([0, 1]),
        edge_names=["Rue des Arts", "Chemin du Lac"],
        edge_geometry=(np.array([0, 3, 5]), np.array([[0.0, 0.0], [50.0, 20.0], [100.0, 0.0],
                                                      [100.0, 0.0], [200.0, 0.0]])))
    path = tmp_path / "two_dead_ends.ggraph"
    graph.write(str(path))
    assert import_roads(path, highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    assert edge_names(obj) == ["Rue des Arts", "Chemin du Lac"]
    before = {name: (width, lanes, oneway, line) for name, width, lanes, oneway, line in zip(
        edge_names(obj), edge_attribute(obj.data, "width", np.float32), edge_attribute(obj.data, "lanes", np.int64),
        edge_attribute(obj.data, "oneway", np.int64), surface_lines(obj))}
    assert before["Rue des Arts"][0] == np.float32(7.3) and before["Chemin du Lac"][0] == np.float32(4.1)
    assert len(before["Rue des Arts"][3]) == 3

    # A spur whose embedding point lands on the shared place (100, 0), 40 m south of it.
    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    cursor = bpy.context.scene.cursor
    cursor.location = (100.0, 40.0, 0.0)
    cursor.rotation_euler = (0.0, 0.0, math.radians(90.0))
    assert bpy.ops.roads.place_rule(rule='T', scale=40.0) == {'FINISHED'}
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}

    mesh = obj.data
    assert len(mesh.vertices) == 6 and len(mesh.edges) == 4
    names = edge_names(obj)
    assert sorted(names) == ["", "", "Chemin du Lac", "Rue des Arts"]
    width = edge_attribute(mesh, "width", np.float32)
    lanes = edge_attribute(mesh, "lanes", np.int64)
    oneway = edge_attribute(mesh, "oneway", np.int64)
    lines = surface_lines(obj)
    for i, name in enumerate(names):
        if name:
            old_width, old_lanes, old_oneway, old_line = before[name]
            assert (width[i], lanes[i], oneway[i]) == (old_width, old_lanes, old_oneway), name
            np.testing.assert_array_equal(lines[i], old_line)
    # The new edges: the rule's primary road and the tertiary embedding edge, class widths.
    defaults = ggg.default_widths()
    highway = edge_attribute(mesh, "highway", np.int64)
    new = {classes[highway[i]]: width[i] for i, name in enumerate(names) if not name}
    assert new == pytest.approx({"primary": defaults["primary"], "tertiary": defaults["tertiary"]})
    embedding = next(i for i, name in enumerate(names) if not name and classes[highway[i]] == "tertiary")
    ends = mesh_build.positions_xy(mesh)[mesh_build.edge_vertices(mesh)[embedding]]
    assert sorted(map(tuple, np.round(ends, 3))) == [(100.0, 0.0), (100.0, 40.0)]


def test_grow_keeps_a_curved_road_exactly(tmp_path, ggg):
    """An imported road with shape nodes keeps its exact polyline (and name) through grows."""
    lat, lon = 46.0, 8.95
    nodes = {i + 1: (lat + 0.0004 * math.sin(i / 3.0), lon + 0.0002 * i) for i in range(12)}
    nodes[20], nodes[21] = (lat - 0.001, lon), (lat - 0.001, lon + 0.001)
    ways = [(10, list(range(1, 13)), {"highway": "tertiary", "name": "Route du Col"}),
            (11, [20, 21], {"highway": "residential", "name": "Rue Basse", "width": "5.5"})]
    path = write_osm(tmp_path / "curve.osm", nodes, ways)
    assert import_roads(path, highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    lines = dict(zip(edge_names(obj), surface_lines(obj)))
    assert len(lines["Route du Col"]) == 12
    widths = dict(zip(edge_names(obj), edge_attribute(obj.data, "width", np.float32)))

    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    positions = mesh_build.positions_xy(obj.data)
    east = positions[np.argmax(positions[:, 0])]
    cursor = bpy.context.scene.cursor
    cursor.location = (east[0] + 30.0, east[1], 0.0)
    cursor.rotation_euler = (0.0, 0.0, 0.0)
    for _ in range(2):
        assert bpy.ops.roads.place_rule(rule='T', scale=30.0) == {'FINISHED'}
        assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
        cursor.location.x += 60.0

    names = edge_names(obj)
    assert len(names) == 2 + 4 and sorted(names)[-2:] == ["Route du Col", "Rue Basse"]
    after = surface_lines(obj)
    width = edge_attribute(obj.data, "width", np.float32)
    for name, line in lines.items():
        i = names.index(name)
        np.testing.assert_array_equal(after[i], line)
        assert width[i] == widths[name]
    assert widths["Rue Basse"] == np.float32(5.5)
    assert obj["total_length_m"] == pytest.approx(ggg_length(after), rel=1e-5)


def ggg_length(lines):
    return float(sum(np.linalg.norm(np.diff(line.astype(np.float64), axis=0), axis=1).sum() for line in lines))


def test_grow_carries_blender_data_by_source_vertex(tmp_path, ggg):
    """Attributes only Blender holds, selection and hiding follow their vertices and edges;
    a width set to 0 by hand (the library takes only > 0) stays on its edge."""
    nodes = {1: (46.0, 8.95), 2: (46.0, 8.951), 3: (46.0, 8.952)}
    ways = [(10, [1, 2], {"highway": "residential"}), (11, [2, 3], {"highway": "residential"})]
    assert import_roads(write_osm(tmp_path / "line.osm", nodes, ways), highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    mesh = obj.data
    positions = mesh_build.positions_xy(mesh)
    order = [int(i) for i in np.argsort(positions[:, 0])]  # west to east
    edge_west = [i for i, (u, v) in enumerate(mesh_build.edge_vertices(mesh)) if order[0] in (u, v)][0]
    mesh_build.set_attribute(mesh, "speed", 'FLOAT', 'EDGE', np.arange(len(mesh.edges)) + 30.0)
    mesh_build.set_attribute(mesh, "height", 'INT', 'POINT', np.arange(len(mesh.vertices)) + 7)
    mesh.attributes["width"].data[edge_west].value = 0.0
    for v in mesh.vertices:
        v.select = v.index == order[0]
    mesh.vertices[order[2]].hide = True
    for e in mesh.edges:
        e.select = e.index == edge_west
    old_speed = edge_attribute(mesh, "speed")
    old_height = {tuple(positions[i]): i + 7 for i in range(len(positions))}

    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    cursor = bpy.context.scene.cursor
    east = positions[order[2]]
    cursor.location = (east[0] + 50.0, east[1] + 50.0, 0.0)  # far from the roads: no embedding edge
    cursor.rotation_euler = (0.0, 0.0, 0.0)
    assert bpy.ops.roads.place_rule(rule='T', scale=20.0) == {'FINISHED'}
    obj.data.vertices[-1].select = False
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}

    mesh = obj.data
    assert len(mesh.vertices) == 5 and len(mesh.edges) == 3
    new_positions = mesh_build.positions_xy(mesh)
    height = np.empty(len(mesh.vertices), dtype=np.int64)
    mesh.attributes["height"].data.foreach_get("value", height)
    for i, p in enumerate(new_positions):
        assert height[i] == old_height.get(tuple(p), 0)
    select = [v.select for v in mesh.vertices]
    assert select == [tuple(p) == tuple(positions[order[0]]) for p in new_positions]
    assert [v.hide for v in mesh.vertices] == [tuple(p) == tuple(positions[order[2]]) for p in new_positions]
    speed = edge_attribute(mesh, "speed")
    np.testing.assert_array_equal(speed, [*old_speed, 0.0])
    assert [e.select for e in mesh.edges] == [i == edge_west for i in range(3)]
    width = edge_attribute(mesh, "width")
    assert width[edge_west] == 0.0 and width[1 - edge_west] > 0.0


def test_grow_in_edit_mode_keeps_the_selection(tmp_path, ggg):
    """In Edit Mode too, a kept vertex keeps its selection; the new geometry is not selected."""
    nodes = {1: (46.0, 8.95), 2: (46.0, 8.951), 3: (46.0003, 8.9515)}
    ways = [(10, [1, 2], {"highway": "residential", "name": "Rue \u00c9t\u00e9"}), (11, [2, 3], {"highway": "service"})]
    assert import_roads(write_osm(tmp_path / "streets.osm", nodes, ways), highways='ALL') == {'FINISHED'}
    obj = bpy.context.active_object
    assert load() == {'FINISHED'}
    bpy.context.scene.cursor.location = (500.0, 500.0, 0.0)
    assert bpy.ops.roads.place_rule(rule='P', scale=50.0) == {'FINISHED'}
    for element in (*obj.data.vertices, *obj.data.edges):
        element.select = False
    obj.data.vertices[0].select = True
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.grow(steps=2) == {'FINISHED'}
    assert obj.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    assert len(obj.data.vertices) == 3 + 6
    assert [v.select for v in obj.data.vertices] == [True] + [False] * 8
    assert not any(e.select for e in obj.data.edges)
    assert sorted(edge_names(obj))[-1] == "Rue \u00c9t\u00e9"


def test_grow_nonterminal_without_rule(ggg, reports):
    assert load() == {'FINISHED'}
    assert bpy.ops.roads.place_rule(rule='P', scale=100.0) == {'FINISHED'}
    obj = bpy.context.active_object
    obj.data.attributes["symbol"].data[0].value = 5  # a symbol the grammar has no rule for
    before = mesh_state(obj), snapshot()
    assert bpy.ops.roads.grow(steps=1) == {'CANCELLED'}
    assert (mesh_state(obj), snapshot()) == before
    kind, message = reports()[-1]
    assert kind == 'WARNING' and message == ("Nothing was rewritten in {}: none of its 1 nonterminal has a rule in "
                                             "the grammar 'sierpinski'. The graph is unchanged.".format(obj.name))


def test_grow_strict_refuses_every_rewrite(tmp_path, ggg, reports):
    assert load(write_grammar(tmp_path, T_GRAMMAR)) == {'FINISHED'}
    assert bpy.ops.roads.place_rule(rule='T', scale=50.0) == {'FINISHED'}
    obj = bpy.context.active_object
    before = mesh_state(obj)
    assert bpy.ops.roads.grow(steps=1, strict=True) == {'CANCELLED'}
    assert mesh_state(obj) == before
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "strict embedding refused all 1 rewrite" in message and "unchanged" in message
    # Relaxed, the same rule grows (its embedding point finds no vertex).
    assert bpy.ops.roads.grow(steps=1) == {'FINISHED'}
    assert len(obj.data.vertices) == 2 and len(obj.data.edges) == 1


class _Layout:
    """Stands in for a UILayout: records labels, accepts everything else."""

    def __init__(self, labels):
        self._labels = labels

    def label(self, text="", **_kwargs):
        self._labels.append(text)

    def __getattr__(self, name):
        return lambda *args, **kwargs: _Layout(self._labels)


@pytest.mark.parametrize("state", ["none", "broken", "loaded"])
def test_grammar_panel_draws(tmp_path, ggg, state):
    from types import SimpleNamespace

    from road_grammar.ui import grammar as grammar_ui
    from road_grammar.ui import roads as roads_ui

    if state != "none":
        assert load() == {'FINISHED'}
        assert bpy.ops.roads.add_axiom() == {'FINISHED'}
    if state == "broken":
        bpy.context.scene.road_grammar.text.from_string("[]")
    labels = []
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=_Layout(labels)), bpy.context)
    roads_ui.VIEW3D_PT_roads.draw(SimpleNamespace(layout=_Layout(labels)), bpy.context)
    text = "\n".join(labels)
    if state == "none":
        assert "No grammar loaded" in text
    elif state == "broken":
        assert "Not a valid grammar" in text
    else:
        assert "sierpinski: 1 rule" in text and "P (1)" in text and "3 v, 3 e, 0 emb, 0 uses" in text
        assert "Grow sierpinski" in text
