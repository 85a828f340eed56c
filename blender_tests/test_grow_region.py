"""Grow into Region (roads.grow_region): the sample town's learned grammar grows streets into
a rectangle east of the town, given as a mesh plane, a cyclic poly curve or a Bezier circle,
picked by name, in the panel or by selection; the result is the one of ggg.grow_region on the
graph's streets, in place in the graph object; seeds; a moved and turned graph; the rules
placed by hand; bad input; the panel; undo (in a windowed Blender under Xvfb); and
ggg.compare of the grown town with the town."""

import math
import re

import bpy
import numpy as np
import pytest

from conftest import PanelLayout, activate, import_roads, record_executes, snapshot
from road_grammar.core.growth import fitted
from road_grammar.core.names import SURFACE_EDGE
from road_grammar.core.polygons import closed_loops, contains, signed_area
from road_grammar.data import graph_edit, region, roads, texts
from road_grammar.data import mesh as mesh_build
from road_grammar.operators import region as region_ops

# The region, in the graph's frame (metres): east of the sample town, which spans x -747..747.
X0, X1, Y0, Y1 = 700.0, 1500.0, -600.0, 600.0
RECTANGLE = np.array([[X0, Y0], [X1, Y0], [X1, Y1], [X0, Y1]])


@pytest.fixture
def town(town):
    """The imported sample town (conftest's town, active) with its grammar learned (the
    scene's grammar)."""
    assert bpy.ops.roads.learn() == {'FINISHED'}
    assert bpy.context.scene.road_grammar.text is not None
    activate(town)
    return town


@pytest.fixture
def op_results(monkeypatch):
    """What roads.grow_region's execute() returned (bpy.ops raises on ERROR reports)."""
    return record_executes(monkeypatch, region_ops.ROADS_OT_grow_region)


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def mesh_region(name="Region", corners=RECTANGLE, z=0.0, faces=True):
    """A mesh object: one face on ``corners`` (faces=False: a closed loop of edges)."""
    mesh = bpy.data.meshes.new(name)
    n = len(corners)
    vertices = [(float(x), float(y), z) for x, y in corners]
    if faces:
        mesh.from_pydata(vertices, [], [tuple(range(n))])
    else:
        mesh.from_pydata(vertices, [(i, (i + 1) % n) for i in range(n)], [])
    return link(bpy.data.objects.new(name, mesh))


def poly_curve(name="Region Curve", corners=RECTANGLE, cyclic=True):
    curve = bpy.data.curves.new(name, 'CURVE')
    curve.dimensions = '3D'
    spline = curve.splines.new('POLY')
    spline.points.add(len(corners) - 1)
    for point, (x, y) in zip(spline.points, corners):
        point.co = (float(x), float(y), 0.0, 1.0)
    spline.use_cyclic_u = cyclic
    return link(bpy.data.objects.new(name, curve))


def mesh_state(obj):
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    return (len(mesh.vertices), len(mesh.edges), co.tobytes(), mesh_build.edge_vertices(mesh).tobytes(),
            sorted(a.name for a in mesh.attributes))


def arrays(obj):
    mesh = obj.data
    return mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh)


def expected(ggg, obj, corners, **options):
    """ggg.grow_region on the streets of ``obj`` (as the mesh holds them) with the scene's
    grammar: (grown graph, report)."""
    old = graph_edit.MeshGraph(obj)
    streets, _ids, _edges = ggg.induced_subgraph(old.graph(ggg), old.symbols == 0)
    _text, parsed = texts.active(bpy.context)
    return ggg.grow_region(streets, parsed, np.asarray(corners, dtype=np.float64), **options)


def counts_reported(message):
    """(rules, vertices, streets) of a Grow into Region report."""
    found = re.search(r"([\d,]+) rules?, ([\d,]+) vert(?:ex|ices), ([\d,]+) streets?", message)
    assert found, message
    return tuple(int(group.replace(",", "")) for group in found.groups())


def inside_rectangle(points, margin=1e-3):
    points = np.asarray(points)
    return (points[:, 0] > X0 - margin) & (points[:, 0] < X1 + margin) & \
        (points[:, 1] > Y0 - margin) & (points[:, 1] < Y1 + margin)


# --- growing -------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["mesh", "edge loop", "poly curve"])
def test_grow_into_a_rectangle(town, ggg, reports, op_results, kind):
    region_obj = {"mesh": lambda: mesh_region(), "edge loop": lambda: mesh_region(faces=False),
                  "poly curve": lambda: poly_curve()}[kind]()
    activate(town)
    positions, edges = arrays(town)
    mesh, surface_obj = town.data, roads.surface_object(town)
    grown, report = expected(ggg, town, RECTANGLE, seed=1)
    assert report["added_vertices"] > 20 and report["added_edges"] > 20  # the town's grammar grows here

    assert bpy.ops.roads.grow_region(region=region_obj.name, seed=1) == {'FINISHED'}
    assert op_results == [{'FINISHED'}]
    kind_, message = reports()[-1]
    assert kind_ == 'INFO' and message.startswith("Grew sample_city into {}:".format(region_obj.name)), message
    rules, vertices, streets = counts_reported(message)
    assert (rules, vertices, streets) == (report["placements"], report["added_vertices"], report["added_edges"])
    assert "{} from the border".format(report["border_connections"]) in message and "seed 1" in message
    # The town's roundabout makes roundabouts of some grown junctions, and the summary says so.
    assert report["roundabouts"] >= 1
    assert "; {} roundabout{};".format(report["roundabouts"], "" if report["roundabouts"] == 1 else "s") in message, message
    # So do the dead-end streets the town's blocks of their size hold.
    assert report["cul_de_sacs"] >= 1
    assert "; {} dead-end street{}".format(report["cul_de_sacs"], "" if report["cul_de_sacs"] == 1 else "s") in message, message

    # In place: same object, name and mesh datablock; the base first, then the grown streets.
    assert town.name == "sample_city" and town.data == mesh and roads.surface_object(town) == surface_obj
    new_positions, new_edges = arrays(town)
    assert len(new_positions) == len(positions) + report["added_vertices"]
    assert len(new_edges) == len(edges) + report["added_edges"]
    np.testing.assert_array_equal(new_positions[:len(positions)], positions)
    np.testing.assert_array_equal(new_edges[:len(edges)], edges)
    np.testing.assert_allclose(new_positions, grown.positions, atol=1e-3)
    np.testing.assert_array_equal(new_edges, grown.edges)
    assert inside_rectangle(new_positions[len(positions):]).all()
    # The new streets have their rule's classes and the class widths; the surface follows.
    classes = list(ggg.highway_classes())
    highway = mesh_build.read_attribute(mesh, "highway", np.int64)
    np.testing.assert_array_equal(highway[len(edges):], grown.edge_highway[len(edges):])
    defaults = ggg.default_widths()
    width = mesh_build.read_attribute(mesh, "width", np.float64)
    np.testing.assert_allclose(width[len(edges):], [defaults[classes[c]] for c in highway[len(edges):]], rtol=1e-6)
    owner = mesh_build.read_attribute(surface_obj.data, SURFACE_EDGE, np.int64)
    assert set(owner.tolist()) == set(range(len(new_edges)))
    assert surface_obj.modifiers and surface_obj.modifiers[0].node_group is not None
    assert town["total_length_m"] == pytest.approx(grown.total_length_m, rel=1e-5)
    # No nonterminal: no arrows added, and the graph still does not render.
    assert not town.modifiers and town.hide_render


def test_the_same_seed_grows_the_same_streets(sample_city, town, ggg):
    """Three copies of the town: seed 1 twice gives the same mesh, seed 2 another one."""
    copies = [town]
    for _ in range(2):
        assert import_roads(sample_city) == {'FINISHED'}
        copies.append(bpy.context.active_object)
    region_obj = mesh_region()
    grown = []
    for obj, seed in zip(copies, (1, 1, 2)):
        activate(obj)
        assert bpy.ops.roads.grow_region(region=region_obj.name, seed=seed) == {'FINISHED'}
        grown.append(mesh_state(obj))
    assert grown[0] == grown[1]
    assert grown[0][0] > 190 and grown[2][0] > 190  # (both grew)
    assert grown[0][:4] != grown[2][:4]


def test_region_picked_in_the_panel_or_selected(town, ggg, reports):
    plane = mesh_region("Plane")
    _grown, report = expected(ggg, town, RECTANGLE, seed=3)
    count = len(town.data.vertices)
    # Selected with the graph (the graph active).
    activate(town, plane)
    assert bpy.ops.roads.grow_region(seed=3) == {'FINISHED'}
    assert len(town.data.vertices) == count + report["added_vertices"]
    assert "into Plane" in reports()[-1][1]
    # The panel's picker wins over the selection.
    other = poly_curve("Elsewhere", RECTANGLE - [2200.0, 0.0])  # west of the town
    settings = bpy.context.scene.road_grammar
    settings.region = other
    activate(town, plane)
    assert bpy.ops.roads.grow_region(seed=3) == {'FINISHED'}
    assert "into Elsewhere" in reports()[-1][1]


def test_bezier_circle(town, ggg):
    """A Bezier curve is read at its resolution (the evaluated points)."""
    bpy.ops.curve.primitive_bezier_circle_add(radius=400.0, location=(1100.0, 0.0, 0.0))
    circle = bpy.context.active_object
    corners, loops = region.polygon(circle, bpy.context.evaluated_depsgraph_get(), town)
    assert loops == 1 and len(corners) == 4 * (circle.data.resolution_u)
    np.testing.assert_allclose(np.hypot(corners[:, 0] - 1100.0, corners[:, 1]), 400.0, rtol=1e-3)
    count = len(town.data.vertices)
    _grown, report = expected(ggg, town, corners, seed=1)
    activate(town)
    assert bpy.ops.roads.grow_region(region=circle.name, seed=1) == {'FINISHED'}
    positions, _edges = arrays(town)
    assert len(positions) == count + report["added_vertices"] > count
    assert (np.hypot(positions[count:, 0] - 1100.0, positions[count:, 1]) < 400.0).all()


def test_region_in_world_space_graph_moved_and_turned(town, ggg):
    """The region's world coordinates are brought into the graph's frame: the grown streets
    lie inside the region in the world, whatever the two objects' transforms."""
    town.location = (250.0, -100.0, 5.0)
    town.rotation_euler = (0.0, 0.0, math.radians(30.0))
    region_obj = mesh_region(corners=[[-400.0, -300.0], [400.0, -300.0], [400.0, 300.0], [-400.0, 300.0]])
    region_obj.location = (1400.0, 600.0, 0.0)
    region_obj.rotation_euler = (0.0, 0.0, math.radians(45.0))
    region_obj.scale = (1.0, 2.0, 1.0)
    bpy.context.view_layer.update()
    count = len(town.data.vertices)
    activate(town)
    assert bpy.ops.roads.grow_region(region=region_obj.name) == {'FINISHED'}
    positions, _edges = arrays(town)
    assert len(positions) > count
    world = np.array([tuple(town.matrix_world @ v.co) for v in town.data.vertices[count:]])
    in_region = np.array(region_obj.matrix_world.inverted()) @ np.column_stack((world, np.ones(len(world)))).T
    x, y = in_region[0], in_region[1]
    assert ((np.abs(x) < 400.0 + 1e-3) & (np.abs(y) < 300.0 + 1e-3)).all()


def test_grow_region_in_edit_mode(town, ggg):
    region_obj = mesh_region()
    count = len(town.data.vertices)
    activate(town)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.grow_region(region=region_obj.name) == {'FINISHED'}
    assert town.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    assert len(town.data.vertices) > count


# --- rules placed by hand ---------------------------------------------------------------------

def place(rule, x, y, angle_deg=0.0, scale=80.0):
    cursor = bpy.context.scene.cursor
    cursor.location = (x, y, 0.0)
    cursor.rotation_euler = (0.0, 0.0, math.radians(angle_deg))
    assert bpy.ops.roads.place_rule(rule=rule, scale=scale) == {'FINISHED'}


def nonterminals(obj):
    symbols = mesh_build.read_attribute(obj.data, "symbol", np.int64)
    positions = mesh_build.positions_xy(obj.data)
    return [(int(s), tuple(np.round(p, 3))) for s, p in zip(symbols, positions) if s > 0]


def test_placed_rules_grow_first(town, ggg, reports):
    """With Use Placed Rules, a nonterminal in the region is grown first and becomes
    streets; one outside does not fit and stays as it was (a warning says so)."""
    _text, parsed = texts.active(bpy.context)
    rule = parsed.rules[0]
    place(rule["name"], 1100.0, 0.0, 20.0)
    place(rule["name"], -2000.0, 0.0)
    count = len(town.data.vertices)
    assert len(nonterminals(town)) == 2
    old = graph_edit.MeshGraph(town)
    streets, _ids, _edges = ggg.induced_subgraph(old.graph(ggg), old.symbols == 0)
    a, b = old.frames[count - 2, :2]
    placed = (rule["symbol"], 1100.0, 0.0, math.hypot(a, b), math.degrees(math.atan2(b, a)))
    assert placed[3] == pytest.approx(80.0) and placed[4] == pytest.approx(20.0)
    grown, report = ggg.grow_region(streets, parsed, RECTANGLE, seed=1, placements=[placed])
    alone, _ = ggg.grow_region(streets, parsed, RECTANGLE, seed=1)
    assert grown.vertex_count != alone.vertex_count or not np.array_equal(grown.positions, alone.positions)

    region_obj = mesh_region()
    activate(town)
    assert bpy.ops.roads.grow_region(region=region_obj.name, seed=1, use_placed_rules=True) == {'FINISHED'}
    seen = reports()
    assert ('WARNING', "1 placed rule did not fit into Region and is left as it was") in seen
    assert "1 placed rule grown" in seen[-1][1]
    # The placed rule in the region is streets now; the one outside is still there, after
    # the town's streets, then the grown streets.
    assert nonterminals(town) == [(rule["symbol"], (-2000.0, 0.0))]
    positions, edges = arrays(town)
    streets_count = count - 2
    assert len(positions) == streets_count + 1 + report["added_vertices"]
    np.testing.assert_allclose(positions[streets_count + 1:], grown.positions[streets_count:], atol=1e-3)
    assert len(edges) == grown.edge_count
    assert inside_rectangle(positions[streets_count + 1:]).all()
    assert town.modifiers  # the arrow of the one left


def test_placed_rules_left_alone(town, ggg, reports):
    """Without Use Placed Rules, the nonterminals stay as they are and growth leaves them out."""
    _text, parsed = texts.active(bpy.context)
    place(parsed.rules[0]["name"], 1100.0, 0.0)
    count = len(town.data.vertices)
    before = nonterminals(town)
    alone, report = expected(ggg, town, RECTANGLE, seed=1)
    region_obj = mesh_region()
    activate(town)
    assert bpy.ops.roads.grow_region(region=region_obj.name, seed=1, use_placed_rules=False) == {'FINISHED'}
    assert nonterminals(town) == before
    positions, edges = arrays(town)
    assert len(positions) == count + report["added_vertices"]
    np.testing.assert_allclose(positions[count:], alone.positions[count - 1:], atol=1e-3)
    assert len(edges) == alone.edge_count
    assert "placed rule" not in reports()[-1][1]


def test_placed_rule_without_a_frame_and_one_without_a_rule(town, ggg):
    """A nonterminal whose frame has no scale grows at its rule's learned size; one whose
    symbol has no rule in the grammar is left as it is."""
    _text, parsed = texts.active(bpy.context)
    rule = parsed.rules[0]
    place(rule["name"], 1100.0, 0.0)
    place(rule["name"], 900.0, 400.0)
    mesh = town.data
    count = len(mesh.vertices)
    mesh.attributes["frame_a"].data[count - 2].value = 0.0  # no scale: the unit frame for Grow
    mesh.attributes["frame_b"].data[count - 2].value = 0.0
    mesh.attributes["symbol"].data[count - 1].value = 99  # no such rule
    streets, _ids, _edges = ggg.induced_subgraph(graph_edit.MeshGraph(town).graph(ggg),
                                             np.arange(count) < count - 2)
    grown, report = ggg.grow_region(streets, parsed, RECTANGLE, seed=1,
                                    placements=[(rule["symbol"], 1100.0, 0.0, 0.0, 0.0)])
    region_obj = mesh_region()
    activate(town)
    assert bpy.ops.roads.grow_region(region=region_obj.name, seed=1) == {'FINISHED'}
    assert nonterminals(town) == [(99, (900.0, 400.0))]
    positions, _edges = arrays(town)
    assert len(positions) == count - 1 + report["added_vertices"]
    np.testing.assert_allclose(positions[count - 1:], grown.positions[count - 2:], atol=1e-3)


def test_the_report_says_which_placed_rules_fitted(town, ggg):
    _text, parsed = texts.active(bpy.context)
    old = graph_edit.MeshGraph(town)
    streets = old.graph(ggg)
    symbol = parsed.rules[0]["symbol"]
    inside, outside = (symbol, 1100.0, 0.0, 0.0, 0.0), (symbol, -3000.0, 0.0, 0.0, 0.0)

    def fits(region, placements):
        return fitted(ggg.grow_region(streets, parsed, region, patience=0, placements=placements)[1])

    assert fits(RECTANGLE, []) == []
    assert fits(RECTANGLE, [inside]) == [True]
    assert fits(RECTANGLE, [outside, inside, outside]) == [False, True, False]
    # The same rule twice at one place: the second crowds the first.
    assert fits(RECTANGLE, [inside, inside]) == [True, False]
    # A region no street reaches (growth would seed its middle): still only the placements count.
    far = RECTANGLE + [5000.0, 0.0]
    assert fits(far, [outside]) == [False]
    assert fits(far, [outside, (symbol, 6100.0, 0.0, 0.0, 0.0)]) == [False, True]


def test_roundabouts_turned_off(town, ggg, reports, op_results):
    # The sample town's old town has a roundabout (one-way, driven anticlockwise), so the
    # district grown east of it gets some (test_grow_into_a_rectangle); turned off (the Grammar
    # panel's Roundabouts), the same seed grows the same streets without them.
    region_obj = mesh_region()
    activate(town)
    _plain, without = expected(ggg, town, RECTANGLE, seed=1, roundabouts=False)
    assert without["roundabouts"] == 0 and without["added_vertices"] > 20
    assert bpy.context.scene.road_grammar.region_roundabouts  # on by default
    assert bpy.ops.roads.grow_region(region=region_obj.name, seed=1, roundabouts=False) == {'FINISHED'}
    kind_, message = reports()[-1]
    assert kind_ == 'INFO' and "roundabout" not in message, message
    assert counts_reported(message)[1:] == (without["added_vertices"], without["added_edges"])


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


BAD_REGIONS = {
    "two corners": (lambda: mesh_region("Bad", [[800.0, 0.0], [900.0, 0.0], [800.0, 0.0]]), 'ERROR',
                    "fewer than 3 corners"),
    "vertical": (lambda: _vertical_plane(), 'ERROR', "no area seen from above"),
    "open curve": (lambda: poly_curve("Bad", cyclic=False), 'ERROR', "not closed"),
    "no edges": (lambda: _loose_vertices(), 'ERROR', "has no edges"),
    "closed surface": (lambda: _cube(), 'ERROR', "closed surface"),
    "branching": (lambda: _branching(), 'ERROR', "branches"),
    # Native refusals, reported by the job: an outline that crosses itself (a bow tie, not
    # symmetric, so that it still has an area) and one 40 km east of the town.
    "bow tie": (lambda: mesh_region("Bad", [[800.0, 0.0], [1000.0, 300.0], [1000.0, 0.0], [800.0, 200.0]]), 'ERROR',
                "crosses itself (its sides from corners 1 and 3 meet)"),
    "far away": (lambda: mesh_region("Bad", RECTANGLE + np.array([40000.0, 0.0])), 'ERROR',
                 "km from the streets of the base (at most 20 km): check its coordinates"),
    "too small": (lambda: mesh_region("Bad", [[1000.0, 0.0], [1001.0, 0.0], [1001.0, 1.0]]), 'WARNING',
                  "Nothing grew in Bad from sample_city: no rule fits there"),
}


def _vertical_plane():
    obj = mesh_region("Bad")
    obj.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # seen from above: a line
    bpy.context.view_layer.update()
    return obj


def _loose_vertices():
    mesh = bpy.data.meshes.new("Bad")
    mesh.from_pydata([(800.0, 0.0, 0.0), (900.0, 0.0, 0.0), (900.0, 100.0, 0.0)], [], [])
    return link(bpy.data.objects.new("Bad", mesh))


def _cube():
    bpy.ops.mesh.primitive_cube_add(size=200.0, location=(1100.0, 0.0, 0.0))
    return bpy.context.active_object


def _branching():
    mesh = bpy.data.meshes.new("Bad")
    mesh.from_pydata([(800.0, 0.0, 0.0), (900.0, 0.0, 0.0), (900.0, 100.0, 0.0), (1000.0, 0.0, 0.0)],
                     [(0, 1), (1, 2), (2, 0), (1, 3), (3, 2)], [])
    return link(bpy.data.objects.new("Bad", mesh))


@pytest.mark.parametrize("case", sorted(BAD_REGIONS))
def test_bad_region_changes_nothing(town, ggg, reports, op_results, case):
    make, kind, expected_text = BAD_REGIONS[case]
    region_obj = make()
    activate(town)
    before = mesh_state(town), mesh_state(roads.surface_object(town)), snapshot()
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=region_obj.name), kind, expected_text, reports,
                    op_results)
    assert (mesh_state(town), mesh_state(roads.surface_object(town)), snapshot()) == before


def test_no_region(town, ggg, reports, op_results):
    before = mesh_state(town), snapshot()
    activate(town)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(), 'ERROR', "No region", reports, op_results)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region="Nowhere"), 'ERROR', "No object named 'Nowhere'",
                    reports, op_results)
    # The graph's own surface is not a region.
    surface_obj = roads.surface_object(town)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=surface_obj.name), 'ERROR',
                    "is part of a road graph", reports, op_results)
    # A region picked, then deleted (the picker still holds it).
    gone = mesh_region("Gone")
    bpy.context.scene.road_grammar.region = gone
    bpy.context.scene.collection.objects.unlink(gone)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(), 'ERROR', "The region Gone is not in the view layer",
                    reports, op_results)
    bpy.context.scene.road_grammar.region = None
    # Two candidates selected: which one?
    one, two = mesh_region("One"), mesh_region("Two")
    activate(town, one, two)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(), 'ERROR', "Several curves or meshes are selected (One, Two)",
                    reports, op_results)
    assert mesh_state(town) == before[0]


def test_no_grammar_or_no_graph(sample_city, ggg, reports, op_results):
    assert import_roads(sample_city) == {'FINISHED'}
    obj = bpy.context.active_object
    region_obj = mesh_region()
    activate(obj)
    assert bpy.context.scene.road_grammar.text is None  # (reading the settings makes their ID property)
    before = mesh_state(obj), snapshot()
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=region_obj.name), 'ERROR', "No grammar", reports,
                    op_results)
    activate(region_obj)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=region_obj.name), 'ERROR', "Select a road graph",
                    reports, op_results)
    assert (mesh_state(obj), snapshot()) == before


def test_grammar_that_cannot_grow(sample_city, ggg, reports, op_results):
    """Sierpinski's rule places only nonterminals: nothing of it derives to streets."""
    from conftest import REPO

    assert import_roads(sample_city) == {'FINISHED'}
    obj = bpy.context.active_object
    assert bpy.ops.roads.load_grammar(filepath=str(REPO / "samples" / "sierpinski.grammar.json")) == {'FINISHED'}
    region_obj = mesh_region()
    activate(obj)
    before = mesh_state(obj), snapshot()
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=region_obj.name), 'ERROR',
                    "Cannot grow sample_city into Region: the grammar has no rule that derives to streets", reports,
                    op_results)
    assert (mesh_state(obj), snapshot()) == before


def test_vertex_budget(town, ggg, reports, op_results):
    region_obj = mesh_region()
    activate(town)
    before = mesh_state(town)
    _cancelled_with(lambda: bpy.ops.roads.grow_region(region=region_obj.name, max_vertices=100), 'WARNING',
                    "the graph has 190 vertices, the budget is 100", reports, op_results)
    assert mesh_state(town) == before
    count = len(town.data.vertices)
    # The budget is vertices: growth stops at it (tracing streets or placing rules).
    assert bpy.ops.roads.grow_region(region=region_obj.name, max_vertices=count + 20) == {'FINISHED'}
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "stopped by budget" in message
    assert count < len(town.data.vertices) <= count + 20 + 10  # (+ T-junctions made at the end)


# --- the panel, the region helpers, ggg.compare ---------------------------------------------------

def test_the_panel_button_takes_the_settings(town, ggg):
    from types import SimpleNamespace

    from road_grammar.ui import grammar as grammar_ui

    settings = bpy.context.scene.road_grammar
    region_obj = mesh_region()
    settings.region, settings.region_seed, settings.region_max_placements = region_obj, 7, 40
    settings.region_patience, settings.region_max_vertices, settings.region_use_placed = 60, 5000, False
    settings.region_roundabouts = False
    labels, buttons = [], []
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert "Grow into Region" in labels
    grow = next(properties for idname, properties in buttons if idname == "roads.grow_region")
    assert grow == {"region": "Region", "seed": 7, "max_placements": 40, "patience": 60, "max_vertices": 5000,
                    "use_placed_rules": False, "roundabouts": False}
    assert bpy.ops.roads.grow_region(**grow) == {'FINISHED'}
    # The picker lists curves and meshes that are not part of a road graph.
    assert region.is_candidate(region_obj) and not region.is_candidate(town)
    assert not region.is_candidate(roads.surface_object(town))
    settings.region = None
    labels.clear()
    grammar_ui.VIEW3D_PT_roads_grammar.draw(SimpleNamespace(layout=PanelLayout(labels, buttons)), bpy.context)
    assert "Or select a curve or mesh with the graph" in labels


def test_closed_loops_and_area():
    loops = closed_loops(np.array([[0, 1], [1, 2], [2, 0], [3, 4], [5, 3], [4, 5]]))
    assert [sorted(loop.tolist()) for loop in loops] == [[0, 1, 2], [3, 4, 5]]
    assert closed_loops(np.array([[2, 0], [0, 1], [1, 3], [3, 2]]))[0].tolist() == [0, 2, 3, 1]
    with pytest.raises(region.RegionError, match="2 open ends"):
        closed_loops(np.array([[0, 1], [1, 2]]))
    assert signed_area(RECTANGLE) == pytest.approx(800.0 * 1200.0)
    assert signed_area(RECTANGLE[::-1]) == pytest.approx(-800.0 * 1200.0)
    assert contains(RECTANGLE, [[1000.0, 0.0], [0.0, 0.0], [1499.0, 599.0]]).tolist() == [True, False, True]


def test_the_largest_outline_is_the_region(town, ggg, reports):
    """A mesh of two faces apart: the larger one is the region (a warning says so)."""
    mesh = bpy.data.meshes.new("Two Faces")
    small = [(-3000.0, 0.0, 0.0), (-2990.0, 0.0, 0.0), (-2990.0, 10.0, 0.0)]
    big = [(x, y, 0.0) for x, y in RECTANGLE]
    mesh.from_pydata(small + big, [], [(0, 1, 2), (3, 4, 5, 6)])
    obj = link(bpy.data.objects.new("Two Faces", mesh))
    corners, loops = region.polygon(obj, bpy.context.evaluated_depsgraph_get(), town)
    assert loops == 2 and sorted(map(tuple, corners)) == sorted(map(tuple, RECTANGLE))
    activate(town)
    assert bpy.ops.roads.grow_region(region=obj.name) == {'FINISHED'}
    assert ('WARNING', "Two Faces has 2 outlines: grew into the largest") in reports()


def test_compare_the_grown_town_with_the_town(town, ggg):
    base = graph_edit.MeshGraph(town).graph(ggg)
    region_obj = mesh_region()
    activate(town)
    assert bpy.ops.roads.grow_region(region=region_obj.name) == {'FINISHED'}
    grown = graph_edit.MeshGraph(town).graph(ggg)
    result = ggg.compare(grown, base)
    distances = result["distances"]
    assert set(distances) == {"degree", "edge_length", "orientation", "block_area", "mean", "junction_angle"}
    assert all(0.0 <= value <= 1.0 for value in distances.values()), distances
    assert distances["mean"] == pytest.approx(sum(distances[k] for k in ("degree", "edge_length", "orientation",
                                                                         "block_area")) / 4.0)
    assert distances["mean"] > 0.0  # the grown town is not the town
    assert result["a"]["vertices"] == grown.vertex_count and result["b"]["vertices"] == base.vertex_count
    assert result["a"]["blocks"] > result["b"]["blocks"]  # the new district has blocks
    same = ggg.compare(base, base)["distances"]
    assert all(value == 0.0 for value in same.values()), same


# --- undo (a windowed Blender under Xvfb) ------------------------------------------------------

def test_undo_of_grow_region_restores_the_mesh(sample_city, ggg, tmp_path):
    from test_undo import _session

    result = _session(ggg, tmp_path, sample_city, "grow_region")
    assert result["load"] == ['FINISHED'] and result["learn"] == ['FINISHED']
    assert result["grow_region"] == ['FINISHED']
    before, grown = result["before"], result["imported"]
    old, new = before["meshes held"]["sample_city"], grown["meshes held"]["sample_city"]
    assert new[0] > old[0] and new[1] > old[1] and new[2] != old[2]
    assert grown["meshes held"]["sample_city Surface"][1] > before["meshes held"]["sample_city Surface"][1]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == grown
