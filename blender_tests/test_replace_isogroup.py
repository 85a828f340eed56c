"""Replace (roads.replace_isogroup, paper Fig. 1) and Store as Piece (roads.store_replacement):
a ring stored as the piece (from an object, or selected in Edit Mode), the square blocks of a
street grid replaced by it as ggg.replace_isogroup replaces them (each ring inside its square,
the corners where other streets meet kept and joined to it), the analysis cleared; the
analysis run again when its isogroups are no longer in memory; bad input; the panel; the
sample town; undo (in a windowed Blender under Xvfb)."""

import json
import math
import re

import bpy
import numpy as np
import pytest
from mathutils import Vector

from conftest import SIZE, SPACING, activate, draw_panel, record_executes, snapshot, write_grid
from test_analysis import grid_cells, select_only
from road_grammar.core.names import SURFACE_EDGE
from road_grammar.data import analysis, graph_edit, replacement, roads
from road_grammar.data import mesh as mesh_build
from road_grammar.display import patterns as pattern_display
from road_grammar.operators import replacement as replacement_ops

RING = 8  # vertices of the ring piece


@pytest.fixture
def op_results(monkeypatch):
    """What the two operators' execute() returned (bpy.ops raises on ERROR reports)."""
    return record_executes(monkeypatch, replacement_ops.ROADS_OT_store_replacement,
                           replacement_ops.ROADS_OT_replace_isogroup)


def ring_object(name="Piece", radius=10.0, location=(3000.0, 0.0, 0.0), count=RING, centre=False):
    """A mesh object: a ring of ``count`` vertices turned by half a step (none on the axes
    or diagonals) and its edges; ``centre``: with a middle vertex joined to every third ring
    vertex (12 + 1 vertices, 12 + 4 streets: a round plaza)."""
    angles = [math.pi / count + k * 2.0 * math.pi / count for k in range(count)]
    vertices = [(radius * math.cos(a), radius * math.sin(a), 0.0) for a in angles]
    edges = [(k, (k + 1) % count) for k in range(count)]
    if centre:
        vertices.append((0.0, 0.0, 0.0))
        edges += [(count, k) for k in range(0, count, 3)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, edges, [])
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    return obj


def in_graph_frame(piece_obj, graph_obj):
    """(positions (N, 2), edges (M, 2)) of ``piece_obj`` in ``graph_obj``'s local frame."""
    to_local = graph_obj.matrix_world.inverted() @ piece_obj.matrix_world
    positions = np.array([tuple((to_local @ v.co).xy) for v in piece_obj.data.vertices])
    return positions, mesh_build.edge_vertices(piece_obj.data)


def square_index(obj):
    return next(i for i, item in enumerate(obj.road_analysis.isogroups) if item.order == 4 and item.edge_count == 4)


def analysed(obj):
    """Analyse ``obj`` (max order 4) and choose the isogroup of the squares; its index."""
    activate(obj)
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    index = square_index(obj)
    obj.road_analysis.active_index = index
    return index


def arrays(obj):
    mesh = obj.data
    return mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh)


def state(obj):
    """What Replace may change: the mesh, its attributes and selection, the analysis, the
    colours, the stored piece."""
    mesh = obj.data
    positions, edges = arrays(obj)
    attributes = {a.name: mesh_build.read_attribute(mesh, a.name).tolist() for a in mesh.attributes
                  if a.data_type in ('INT', 'FLOAT') and not a.name.startswith(".")}
    selected = np.zeros(len(mesh.vertices), dtype=bool)
    mesh.vertices.foreach_get("select", selected)
    result = obj.road_analysis
    stored = {key: list(result[key]) for key in (analysis.OCCURRENCES, analysis.NON_OVERLAPPING,
                                                 analysis.PATTERN_EDGES) if key in result}
    child = pattern_display.patterns_object(obj)
    return (positions.tobytes(), edges.tobytes(), attributes, selected.tolist(), obj.mode,
            [(i.order, i.frequency) for i in result.isogroups], result.topology, result.options, stored,
            result.active_index, child and child.name, bpy.context.scene.road_replacement.piece)


def expected_replacement(ggg, obj, index, positions, edges, highway=None):
    """ggg.replace_isogroup on the graph of ``obj`` as the mesh holds it, with the isogroup
    ``index`` of ggg.analyze (max order 4, as Analyze runs it), which must be the stored
    one: (graph, report, isogroup)."""
    graph = graph_edit.MeshGraph(obj).graph(ggg)
    direct = ggg.analyze(graph, max_order=4, tolerance=0.15).isogroups[index]
    occurrences, non_overlapping, _ = analysis.isogroup_arrays(obj, index)
    np.testing.assert_array_equal(direct.occurrences, occurrences)
    np.testing.assert_array_equal(direct.non_overlapping, non_overlapping)
    if highway is None:
        highway = np.full(len(edges), list(ggg.highway_classes()).index("residential"))
    out, report = ggg.replace_isogroup(graph, direct, np.asarray(positions, dtype=np.float64),
                                       np.asarray(edges, dtype=np.int64), edge_highway=highway)
    return out, report, direct


def counts_reported(message):
    """(occurrences, order, removed, added, joined, intersections) of a Replace report."""
    found = re.search(r"Replaced ([\d,]+) occurrences? of the (\d+)-vertex pattern in \S+: ([\d,]+) vert(?:ex|ices) "
                      r"removed, ([\d,]+) added, ([\d,]+) streets? joined(?:, ([\d,]+) intersections? made)?; "
                      r"the analysis is cleared", message)
    assert found, message
    return tuple(int((group or "0").replace(",", "")) for group in found.groups())


def area_centroid(corners):
    """The centroid of the area of the convex polygon with these corners (any order)."""
    corners = np.asarray(corners, dtype=np.float64)
    middle = corners.mean(axis=0)
    ring = corners[np.argsort(np.arctan2(*(corners - middle).T[::-1]))]
    following = np.roll(ring, -1, axis=0)
    cross = ring[:, 0] * following[:, 1] - following[:, 0] * ring[:, 1]
    return ((ring + following) * cross[:, None]).sum(axis=0) / (3.0 * cross.sum())


def hull_ratio(points, corners):
    """For each point, how far out it is in the convex polygon ``corners`` (any order), seen
    from the polygon's centroid: 0 at the centroid, 1 on a side, > 1 outside."""
    corners = np.asarray(corners, dtype=np.float64)
    centre = area_centroid(corners)
    ring = corners[np.argsort(np.arctan2(*(corners - centre).T[::-1]))]
    following = np.roll(ring, -1, axis=0)
    normals = np.column_stack((following[:, 1] - ring[:, 1], ring[:, 0] - following[:, 0]))  # outward
    room = np.einsum("ij,ij->i", normals, ring - centre)
    assert np.all(room > 0)
    return ((np.asarray(points) - centre) @ normals.T / room).max(axis=1)


# --- storing the piece ----------------------------------------------------------------------

def ring_around_the_middle(obj):
    """The 8 grid vertices around the middle one (2, 2): a ring of 8 streets, 200 m wide."""
    by_cell = {ij: v for v, ij in grid_cells(obj).items()}
    return [by_cell[(2 + di, 2 + dj)] for di in (-1, 0, 1) for dj in (-1, 0, 1) if (di, dj) != (0, 0)]


def test_store_the_selection_in_edit_mode(grid, ggg, reports, op_results):
    ring = ring_around_the_middle(grid)
    select_only(grid, ring)
    positions, edges = arrays(grid)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.store_replacement() == {'FINISHED'}
    assert grid.mode == 'EDIT'
    kind, message = reports()[-1]
    found = re.fullmatch(r"Stored a piece of 8 vertices and 8 streets from grid \(selection\) "
                         r"\(([\d.]+) x ([\d.]+) m\)", message)
    assert kind == 'INFO' and found, message
    # (The grid is 200 m across on the earth; the projection makes it a little more or less.)
    assert [float(size) for size in found.groups()] == [pytest.approx(200.0, abs=1.0)] * 2
    settings = bpy.context.scene.road_replacement
    assert (settings.vertex_count, settings.edge_count) == (8, 8)
    assert (settings.width_m, settings.height_m) == (pytest.approx(float(found.group(1)), abs=0.05),
                                                     pytest.approx(float(found.group(2)), abs=0.05))
    piece = replacement.stored(bpy.context.scene)
    # The selected vertices in the graph's metres, and exactly the streets between them (not
    # the four to the unselected middle vertex).
    np.testing.assert_allclose(piece.positions, positions[sorted(ring)], atol=1e-4)
    chosen = sorted(ring)
    stored_edges = {frozenset((chosen[a], chosen[b])) for a, b in piece.edges.tolist()}
    ring_edges = {frozenset(e) for e in edges.tolist() if set(e) <= set(ring)}
    assert len(ring_edges) == 8 and stored_edges == ring_edges
    assert piece.highway == ["residential"] * 8
    bpy.ops.object.mode_set(mode='OBJECT')
    assert arrays(grid)[0].tobytes() == positions.tobytes()  # the graph itself is unchanged
    assert op_results == [{'FINISHED'}]


def test_store_an_object_in_the_graphs_frame(grid, ggg, reports):
    """A mesh object anywhere, turned and scaled, with road classes; the graph moved and
    turned too: the piece is in the graph's local metres. A curve works as well."""
    grid.location = (1000.0, -500.0, 3.0)
    grid.rotation_euler = (0.0, 0.0, 0.5)
    piece_obj = ring_object(location=(-200.0, 4000.0, 7.0))
    piece_obj.rotation_euler = (0.0, 0.0, -0.3)
    piece_obj.scale = (2.0, 3.0, 1.0)
    classes = list(ggg.highway_classes())
    codes = [classes.index("primary")] * 4 + [classes.index("footway")] * 4
    mesh_build.set_attribute(piece_obj.data, "highway", 'INT', 'EDGE', codes)
    bpy.context.view_layer.update()
    activate(grid)
    assert bpy.ops.roads.store_replacement(object=piece_obj.name) == {'FINISHED'}
    kind, message = reports()[-1]
    assert message.startswith("Stored a piece of 8 vertices and 8 streets from Piece"), message
    piece = replacement.stored(bpy.context.scene)
    positions, edges = in_graph_frame(piece_obj, grid)
    np.testing.assert_allclose(piece.positions, positions, atol=1e-3)
    np.testing.assert_array_equal(piece.edges, edges)
    assert piece.highway == ["primary"] * 4 + ["footway"] * 4
    # (Far from the graph's origin: the frame was applied, not the world coordinates.)
    assert np.linalg.norm(piece.positions.mean(axis=0) - np.array([-200.0, 4000.0])) > 100.0

    bpy.ops.curve.primitive_bezier_circle_add(radius=30.0, location=(0.0, 9000.0, 0.0))
    curve = bpy.context.active_object
    activate(grid)
    assert bpy.ops.roads.store_replacement(object=curve.name) == {'FINISHED'}
    piece = replacement.stored(bpy.context.scene)
    assert piece.vertex_count >= 8 and piece.edge_count == piece.vertex_count  # a closed polyline
    assert piece.highway == ["residential"] * piece.edge_count
    world = np.array([tuple((grid.matrix_world @ Vector((x, y, 0.0))).xy) for x, y in piece.positions])
    assert np.linalg.norm(world - (0.0, 9000.0), axis=1) == pytest.approx(np.full(len(world), 30.0), abs=0.5)


def _only_vertices(obj):
    mesh = bpy.data.meshes.new("Dots")
    mesh.from_pydata([(0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (0.0, 10.0, 0.0)], [], [])
    dots = bpy.data.objects.new("Dots", mesh)
    bpy.context.scene.collection.objects.link(dots)
    return {"object": "Dots"}, "Dots has no edges"


def _one_place(obj):
    mesh = bpy.data.meshes.new("Point")
    mesh.from_pydata([(5.0, 5.0, 0.0)] * 3, [(0, 1), (1, 2)], [])
    point = bpy.data.objects.new("Point", mesh)
    bpy.context.scene.collection.objects.link(point)
    return {"object": "Point"}, "all at one place"


def _an_empty(obj):
    empty = bpy.data.objects.new("Marker", None)
    bpy.context.scene.collection.objects.link(empty)
    return {"object": "Marker"}, "Marker is not a mesh or a curve"


def _nothing_selected(obj):
    select_only(obj, [])
    return {}, "Nothing is selected in grid"


def _no_street_between(obj):
    by_cell = {ij: v for v, ij in grid_cells(obj).items()}
    select_only(obj, [by_cell[(0, 0)], by_cell[(1, 1)], by_cell[(3, 3)]])
    return {}, "No street joins the 3 selected vertices"


@pytest.mark.parametrize("make", [
    _nothing_selected,
    _no_street_between,
    lambda obj: ({"object": "Nowhere"}, "No object named 'Nowhere'"),
    _an_empty,
    lambda obj: ({"object": obj.name}, "is the road graph itself"),
    _only_vertices,
    _one_place,
], ids=["nothing selected", "no street between", "no such object", "an empty", "the graph itself",
        "no edges", "one place"])
def test_store_errors_keep_the_stored_piece(grid, op_results, make):
    activate(grid)
    assert bpy.ops.roads.store_replacement(object=ring_object().name) == {'FINISHED'}
    kwargs, message = make(grid)
    activate(grid)
    before = state(grid), snapshot()
    with pytest.raises(RuntimeError, match=re.escape(message)):
        bpy.ops.roads.store_replacement(**kwargs)
    assert op_results == [{'FINISHED'}, {'CANCELLED'}]
    assert (state(grid), snapshot()) == before  # the piece stored first is still there
    assert bpy.context.scene.road_replacement.vertex_count == RING


def test_store_needs_a_road_graph(grid, op_results):
    piece_obj = ring_object()
    activate(piece_obj)
    with pytest.raises(RuntimeError, match="not a road graph"):
        bpy.ops.roads.store_replacement(object=piece_obj.name)
    assert op_results == [{'CANCELLED'}]
    assert not bpy.context.scene.road_replacement.has_piece()


# --- replacing ----------------------------------------------------------------------------------

def test_replace_the_squares_by_a_ring(grid, ggg, reports, op_results):
    classes = list(ggg.highway_classes())
    cells = grid_cells(grid)
    by_cell = {ij: v for v, ij in cells.items()}
    positions, edges = arrays(grid)
    # One street of the south-west square made secondary: the junctions at its ends are
    # joined to the ring with that class, the others with the squares' residential.
    secondary = next(e for e, (a, b) in enumerate(edges.tolist())
                     if {cells.get(a), cells.get(b)} == {(1, 0), (1, 1)})
    old_highway = mesh_build.read_attribute(grid.data, "highway", np.int64)
    old_highway[secondary] = classes.index("secondary")
    mesh_build.set_attribute(grid.data, "highway", 'INT', 'EDGE', old_highway)
    index = analysed(grid)
    piece_obj = ring_object()
    activate(grid)
    assert bpy.ops.roads.store_replacement(object=piece_obj.name) == {'FINISHED'}
    mesh, surface_obj = grid.data, roads.surface_object(grid)
    piece_positions, piece_edges = in_graph_frame(piece_obj, grid)
    out, report, iso = expected_replacement(ggg, grid, index, piece_positions, piece_edges)
    occurrences, chosen, _ = analysis.isogroup_arrays(grid, index)
    squares = occurrences[chosen]
    assert len(squares) == 4 and report["replaced"] == 4  # the four corner blocks of the grid
    owner = np.full(len(positions), -1)
    for c, square in enumerate(squares):
        owner[square] = c
    own = (owner[edges[:, 0]] >= 0) & (owner[edges[:, 0]] == owner[edges[:, 1]])
    assert own.sum() == 16
    # The junctions: the squares' corners that a street from outside the square reaches (the
    # footway at the grid's corner (0, 0) too); the grid's other three corners are not.
    junction = np.zeros(len(positions), dtype=bool)
    junction[edges[~own].ravel()] = True
    junction &= owner >= 0
    corners = [by_cell[ij] for ij in ((4, 0), (0, 4), (4, 4))]
    assert sorted(np.flatnonzero((owner >= 0) & ~junction).tolist()) == sorted(corners)
    kept = np.flatnonzero((owner < 0) | junction)
    assert len(kept) == len(positions) - 3
    # What only Blender holds follows the vertices that stay: a point attribute, the selection
    # (the east spur's end, the middle of the grid, a junction and a corner that goes).
    elevation = 0.5 * np.arange(len(positions), dtype=np.float64)
    mesh_build.set_attribute(grid.data, "elevation", 'FLOAT', 'POINT', elevation)
    picked = [max((v for v in range(len(positions)) if v not in cells), key=lambda v: positions[v, 0]),
              by_cell[(2, 2)], by_cell[(1, 1)], by_cell[(4, 4)]]
    select_only(grid, picked)

    assert bpy.ops.roads.replace_isogroup() == {'FINISHED'}
    assert op_results[-1] == {'FINISHED'}
    kind, message = reports()[-1]
    assert kind == 'INFO'
    assert counts_reported(message) == (report["replaced"], 4, report["removed_vertices"], report["added_vertices"],
                                        report["joined_streets"], report["intersections"])
    # 3 corners removed; 8 vertices per ring; 13 junctions (4 of the south-west square, 3 of
    # each other one) joined; no new street crosses another.
    assert (report["removed_vertices"], report["added_vertices"]) == (3, 4 * RING)
    assert (report["joined_streets"], report["intersections"]) == (13, 0)
    assert "intersection" not in message

    # Exactly what ggg.replace_isogroup gives, in place (same object and mesh datablock).
    assert grid.data == mesh and roads.surface_object(grid) == surface_obj
    new_positions, new_edges = arrays(grid)
    assert (len(new_positions), len(new_edges)) == (out.vertex_count, out.edge_count)
    assert len(new_positions) == len(kept) + 4 * RING
    assert len(new_edges) == len(edges) - 16 + 4 * RING + 13
    np.testing.assert_allclose(new_positions, out.positions, atol=1e-3)
    np.testing.assert_array_equal(new_edges, out.edges)

    # The kept vertices come first, in their order, where they were (the junctions too); no
    # vertex is where a removed corner was.
    np.testing.assert_allclose(new_positions[:len(kept)], positions[kept], atol=1e-4)
    distance = np.linalg.norm(new_positions[:, None, :] - positions[None, corners, :], axis=2)
    assert distance.min() > 1.0
    carried = mesh_build.read_attribute(grid.data, "elevation", np.float64)
    np.testing.assert_allclose(carried[:len(kept)], elevation[kept])
    assert not carried[len(kept):].any()
    new_id = np.full(len(positions), -1)
    new_id[kept] = np.arange(len(kept))
    selected = np.zeros(len(new_positions), dtype=bool)
    grid.data.vertices.foreach_get("select", selected)
    assert set(np.flatnonzero(selected).tolist()) == {int(new_id[v]) for v in picked[:3]}
    # The streets outside the squares stay, in their order, with their classes (the footway
    # at the junction (0, 0) and the spur too), before everything the replacement made.
    outside = np.flatnonzero(~own)
    np.testing.assert_array_equal(new_edges[:len(outside)], new_id[edges[outside]])
    new_highway = mesh_build.read_attribute(grid.data, "highway", np.int64)
    np.testing.assert_array_equal(new_highway[:len(outside)], old_highway[outside])
    assert classes.index("footway") in new_highway[:len(outside)].tolist()

    # Each ring lies inside the square it replaced: centred on it, every vertex inside the
    # square shrunk to 0.8 about its centre and one of them on that boundary (the squares are
    # 100 m wide; the projection makes them a little uneven).
    added = np.asarray(out.positions)[len(kept):]
    centres = positions[squares].mean(axis=1)
    home = np.linalg.norm(added[:, None, :] - centres[None, :, :], axis=2).argmin(axis=1)
    assert np.bincount(home, minlength=4).tolist() == [RING] * 4
    for c, square in enumerate(squares):
        corner = positions[square]
        centre = centres[c]
        ring = added[home == c]
        np.testing.assert_allclose(ring.mean(axis=0), area_centroid(corner), atol=1e-3)
        np.testing.assert_allclose(area_centroid(corner), centre, atol=0.05)  # (near a parallelogram)
        ratio = hull_ratio(ring, corner)
        assert ratio.max() == pytest.approx(0.8, abs=1e-4) and np.all(ratio <= 0.8 + 1e-4)
        # So every ring vertex is at most 0.8 x 50 m from the centre along each street.
        assert np.all(np.abs(ring - centre) <= 0.8 * SPACING / 2 + 0.5)

    # Each junction is joined by one new street to the ring vertex nearest to it, with the
    # class of the square's most important street there; the outside streets are not touched.
    # (The ring is turned by half a step: two of its vertices are about as near to a corner;
    # the one joined is the nearer, to within the mesh's precision.)
    made = set()
    for x in np.flatnonzero(junction):
        ring_ids = len(kept) + np.flatnonzero(home == owner[x])
        to_ring = [(e, b if a == new_id[x] else a) for e, (a, b) in enumerate(new_edges.tolist())
                   if new_id[x] in (a, b) and (a >= len(kept) or b >= len(kept))]
        assert len(to_ring) == 1, cells[x]
        e, end = to_ring[0]
        assert end in ring_ids, cells[x]
        reach = np.linalg.norm(new_positions[ring_ids] - positions[x], axis=1)
        assert np.linalg.norm(new_positions[end] - positions[x]) <= reach.min() + 1e-3, cells[x]
        at_secondary = cells[x] in ((1, 0), (1, 1))
        assert new_highway[e] == classes.index("secondary" if at_secondary else "residential"), cells[x]
        made.add(e)
    assert len(made) == report["joined_streets"] == 13
    # The rings' own streets: 8 per square, residential (the piece has no classes); nothing
    # else was made.
    ring_streets = [i for i, (a, b) in enumerate(new_edges.tolist()) if a >= len(kept) and b >= len(kept)]
    assert len(ring_streets) == 4 * RING
    assert set(new_highway[ring_streets].tolist()) == {classes.index("residential")}
    assert len(outside) + len(ring_streets) + len(made) == len(new_edges)

    # The analysis no longer fits: cleared, with its colours; the surface has every street.
    result = grid.road_analysis
    assert not result.has_result() and len(result.isogroups) == 0 and analysis.OCCURRENCES not in result
    assert result.active_index == -1 and not result.options
    assert pattern_display.ATTRIBUTE not in grid.data.attributes and pattern_display.patterns_object(grid) is None
    surface_owner = mesh_build.read_attribute(surface_obj.data, SURFACE_EDGE, np.int64)
    assert set(surface_owner.tolist()) == set(range(len(new_edges)))
    assert grid["total_length_m"] == pytest.approx(out.total_length_m, rel=1e-5)


def test_replace_in_edit_mode_with_a_selected_ring(grid, ggg, reports):
    """The ring around the middle selected in Edit Mode is the piece; Replace runs in Edit
    Mode and comes back to it."""
    select_only(grid, ring_around_the_middle(grid))
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.store_replacement() == {'FINISHED'}
    piece = replacement.stored(bpy.context.scene)
    index = analysed(grid)  # (Analyze leaves Edit Mode)
    assert grid.mode == 'OBJECT'
    out, report, _iso = expected_replacement(ggg, grid, index, piece.positions, piece.edges)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.replace_isogroup() == {'FINISHED'}
    assert grid.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    new_positions, new_edges = arrays(grid)
    assert (len(new_positions), len(new_edges)) == (out.vertex_count, out.edge_count)
    # 3 corners of the grid removed, 8 vertices per square, its 13 junctions joined.
    assert (report["removed_vertices"], report["added_vertices"], report["joined_streets"]) == (3, 4 * 8, 13)
    assert report["intersections"] == 0
    np.testing.assert_allclose(new_positions, out.positions, atol=1e-3)
    np.testing.assert_array_equal(new_edges, out.edges)
    assert not grid.road_analysis.has_result()


def test_the_analysis_is_run_again_when_its_isogroups_are_gone(grid, ggg, monkeypatch, tmp_path):
    """Right after Analyze the isogroups are in memory; after reopening the file (in a new
    session, where they are gone) the same analysis runs again, once, and Replace gives what
    ggg.replace_isogroup gives."""
    calls = []
    original = ggg.analyze

    def counting(*args, **kwargs):
        calls.append(kwargs)
        return original(*args, **kwargs)

    index = analysed(grid)
    assert bpy.ops.roads.store_replacement(object=ring_object().name) == {'FINISHED'}
    monkeypatch.setattr(ggg, "analyze", counting)
    analysis.live_isogroup(ggg, grid, index)
    assert calls == []  # kept from Analyze

    path = tmp_path / "analysed.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    analysis.forget()  # as in a new session
    obj = bpy.data.objects["grid"]
    activate(obj)
    piece = replacement.stored(bpy.context.scene)
    out, report, _iso = expected_replacement(ggg, obj, index, piece.positions, piece.edges)
    calls.clear()
    assert bpy.ops.roads.replace_isogroup(index=index) == {'FINISHED'}
    assert len(calls) == 1 and calls[0]["max_order"] == 4
    new_positions, new_edges = arrays(obj)
    np.testing.assert_allclose(new_positions, out.positions, atol=1e-3)
    np.testing.assert_array_equal(new_edges, out.edges)


def test_moved_vertices(grid, ggg):
    """A vertex moved a little: the isogroups kept from Analyze have the old transforms, so
    the analysis runs again; it finds the same squares, and the ring of the moved square is
    centred on the square as it is now (on its area's centroid) and inside it."""
    index = analysed(grid)
    assert bpy.ops.roads.store_replacement(object=ring_object().name) == {'FINISHED'}
    occurrences, chosen, _ = analysis.isogroup_arrays(grid, index)
    square = occurrences[chosen[0]]
    centre_before = arrays(grid)[0][square].mean(axis=0)
    grid.data.vertices[int(square[0])].co.x += 2.0
    grid.data.update()
    positions = arrays(grid)[0]
    centre = positions[square].mean(axis=0)
    assert np.linalg.norm(centre - centre_before) == pytest.approx(0.5, abs=1e-3)
    piece = replacement.stored(bpy.context.scene)
    out, report, _iso = expected_replacement(ggg, grid, index, piece.positions, piece.edges)
    assert bpy.ops.roads.replace_isogroup() == {'FINISHED'}
    new_positions = arrays(grid)[0]
    np.testing.assert_allclose(new_positions, out.positions, atol=1e-3)
    assert report["removed_vertices"] == 3
    added = np.asarray(out.positions)[len(positions) - 3:]
    assert len(added) == report["added_vertices"] == 4 * RING
    ring = added[np.argsort(np.linalg.norm(added - centre, axis=1))[:RING]]
    # (The centroid of the area, not the mean of the corners, which is 0.5 m east.)
    middle = area_centroid(positions[square])
    assert np.linalg.norm(middle - centre) > 0.1
    assert np.linalg.norm(ring.mean(axis=0) - middle) < 1e-3
    ratio = hull_ratio(ring, positions[square])
    assert ratio.max() == pytest.approx(0.8, abs=1e-4)


def test_vertices_moved_far_are_refused(grid, ggg, op_results):
    index = analysed(grid)
    assert bpy.ops.roads.store_replacement(object=ring_object().name) == {'FINISHED'}
    occurrences, chosen, _ = analysis.isogroup_arrays(grid, index)
    corner = int(occurrences[chosen[0]][0])
    grid.data.vertices[corner].co.x += 45.0
    grid.data.vertices[corner].co.y -= 30.0
    before = state(grid), snapshot()
    with pytest.raises(RuntimeError, match="moved since it was analysed"):
        bpy.ops.roads.replace_isogroup()
    assert op_results[-1] == {'CANCELLED'}
    assert (state(grid), snapshot()) == before


# --- bad input --------------------------------------------------------------------------------------

def _not_analysed(obj):
    return {}, "grid has not been analysed"


def _no_isogroup_chosen(obj):
    analysed(obj)
    obj.road_analysis.active_index = -1
    return {}, "Choose an isogroup in the list first"


def _no_such_isogroup(obj):
    analysed(obj)
    return {"index": 999}, "there is no isogroup 999"


def _no_piece(obj):
    analysed(obj)
    bpy.context.scene.road_replacement.piece = ""
    return {}, "No piece is stored"


def _piece(**changes):
    data = {"version": 1, "source": "by hand", "positions": [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]],
            "edges": [[0, 1], [1, 2], [2, 0]], "highway": ["residential"] * 3}
    data.update(changes)
    return json.dumps(data)


def _piece_without_streets(obj):
    analysed(obj)
    bpy.context.scene.road_replacement.piece = _piece(edges=[], highway=[])
    return {}, "The piece has no streets"


def _unreadable_piece(obj):
    analysed(obj)
    bpy.context.scene.road_replacement.piece = "{not json"
    return {}, "The stored piece cannot be read"


def _edge_out_of_range(obj):
    """The library checks the piece's edges: its message comes through."""
    analysed(obj)
    bpy.context.scene.road_replacement.piece = _piece(edges=[[0, 1], [1, 7]], highway=["residential"] * 2)
    return {}, "Cannot replace the pattern in grid: a replacement edge joins vertices out of range"


def _unknown_class(obj):
    analysed(obj)
    bpy.context.scene.road_replacement.piece = _piece(highway=["residential", "boulevard", "residential"])
    return {}, "road classes the library does not know: boulevard"


def _changed_mesh(obj):
    analysed(obj)
    obj.data.vertices.add(1)
    obj.data.update()
    return {}, "changed since it was analysed"


def _older_analysis(obj):
    analysed(obj)
    obj.road_analysis.options = ""
    analysis.forget()
    return {}, "does not say how it was made"


@pytest.mark.parametrize("make", [_not_analysed, _no_isogroup_chosen, _no_such_isogroup, _no_piece,
                                  _piece_without_streets, _unreadable_piece, _edge_out_of_range, _unknown_class,
                                  _changed_mesh, _older_analysis])
def test_bad_input_cancels_and_changes_nothing(grid, op_results, make):
    activate(grid)
    bpy.context.scene.road_replacement.piece = _piece()
    kwargs, message = make(grid)
    activate(grid)
    before = state(grid), snapshot()
    with pytest.raises(RuntimeError, match=re.escape(message)):
        bpy.ops.roads.replace_isogroup(**kwargs)
    assert op_results == [{'CANCELLED'}]
    assert (state(grid), snapshot()) == before


def test_replace_needs_a_road_graph(grid, op_results):
    analysed(grid)
    bpy.context.scene.road_replacement.piece = _piece()
    piece_obj = ring_object()
    activate(piece_obj)
    before = state(grid), snapshot()
    with pytest.raises(RuntimeError, match="not a road graph"):
        bpy.ops.roads.replace_isogroup()
    assert op_results == [{'CANCELLED'}]
    assert (state(grid), snapshot()) == before


# --- the panel ---------------------------------------------------------------------------------------

def test_panel_draws(grid):
    from road_grammar.ui import patterns as patterns_ui

    text = draw_panel(patterns_ui.VIEW3D_PT_roads_replace)
    assert "No piece stored" in text and "Analyze first" in text
    index = analysed(grid)
    assert bpy.ops.roads.store_replacement(object=ring_object(radius=25.0).name) == {'FINISHED'}
    text = draw_panel(patterns_ui.VIEW3D_PT_roads_replace)
    assert "8 vertices, 8 streets" in text and "46.2 x 46.2 m as drawn" in text and "from Piece" in text
    assert "Isogroup {}: 4 vertices".format(index + 1) in text and "4 non-overlapping occurrences" in text
    grid.road_analysis.active_index = -1
    assert "Choose an isogroup in the list" in draw_panel(patterns_ui.VIEW3D_PT_roads_replace)


# --- the sample town -----------------------------------------------------------------------------------

def test_sample_town_blocks_become_plazas(town, ggg, reports):
    """The best isogroup of the sample town (default Analyze) replaced by a round plaza of 13
    vertices and 16 streets, as ggg.replace_isogroup replaces it."""
    assert bpy.ops.roads.analyze() == {'FINISHED'}
    town.road_analysis.active_index = 0
    item = town.road_analysis.isogroups[0]
    order, count = item.order, item.non_overlapping_count
    plaza = ring_object("Plaza", radius=40.0, count=12, centre=True)
    activate(town)
    assert bpy.ops.roads.store_replacement(object=plaza.name) == {'FINISHED'}
    assert reports()[-1][1].startswith("Stored a piece of 13 vertices and 16 streets from Plaza")
    positions, edges = in_graph_frame(plaza, town)
    graph = graph_edit.MeshGraph(town).graph(ggg)
    options = json.loads(town.road_analysis.options)
    direct = ggg.analyze(graph, grid=tuple(options.pop("grid")), **options).isogroups[0]
    assert direct.order == order and len(direct.non_overlapping) == count
    out, report = ggg.replace_isogroup(graph, direct, positions, edges)
    before = len(town.data.vertices)
    assert bpy.ops.roads.replace_isogroup() == {'FINISHED'}
    assert counts_reported(reports()[-1][1]) == (count, order, report["removed_vertices"], report["added_vertices"],
                                                 report["joined_streets"], report["intersections"])
    # The junctions stay (most of the blocks' corners), each joined to its plaza by one street;
    # 13 vertices per plaza and one per intersection made.
    assert 0 < report["removed_vertices"] < count * order
    assert report["joined_streets"] == count * order - report["removed_vertices"]
    assert report["added_vertices"] == count * 13 + report["intersections"]
    assert len(town.data.vertices) == out.vertex_count == before - report["removed_vertices"] + report["added_vertices"]
    assert len(town.data.edges) == out.edge_count
    np.testing.assert_allclose(arrays(town)[0], out.positions, atol=1e-3)
    np.testing.assert_array_equal(arrays(town)[1], out.edges)


# --- undo, in a Blender with a window --------------------------------------------------------------

def test_undo_of_replace_restores_the_mesh(ggg, tmp_path):
    from test_undo import _session

    result = _session(ggg, tmp_path, write_grid(tmp_path / "grid.osm"), "replace")
    assert result["load"] == ['FINISHED'] and result["analyze"] == ['FINISHED'] and result["store"] == ['FINISHED']
    assert result["replace"] == ['FINISHED']
    before, replaced = result["before"], result["imported"]
    grid_before, grid_after = before["meshes held"]["grid"], replaced["meshes held"]["grid"]
    assert grid_before[:2] == [SIZE * SIZE + 2, 2 * SIZE * (SIZE - 1) + 2]
    # The grid's 3 corners that no other street reaches removed, 8 vertices per ring.
    assert grid_after[0] == SIZE * SIZE + 2 - 3 + 4 * RING and grid_after[1] > grid_before[1]
    assert before["analysis"]["grid"][0] and before["analysis"]["grid"][1] > 0
    assert replaced["analysis"]["grid"] == ["", 0, -1]
    assert "road_pattern" in grid_before[3] and "road_pattern" not in grid_after[3]
    assert result["undo"] == ['FINISHED']
    assert result["undone"] == before
    assert result["redo"] == ['FINISHED']
    assert result["redone"] == replaced
