"""The graph analyzer in Blender: Analyze (the isogroup list, the overview colours),
choosing an isogroup, Find Similar, bad seeds, cancelling, persistence in the .blend, and
(in a windowed Blender under Xvfb) undo and the modal run with Esc."""

from types import SimpleNamespace

import bmesh
import bpy
import numpy as np
import pytest

from conftest import (SIZE, SPACING, PanelLayout, cancel_at_first_progress, draw_panel, record_executes,
                      run_analysis_session, snapshot, write_grid)
from road_grammar.core.names import SURFACE_EDGE, SYMBOL
from road_grammar.core.palette import MATCH_SLOT, PALETTE_SIZE, SEED_SLOT, slot_color_linear
from road_grammar.core.topology import seed_problem
from road_grammar.data import analysis, roads
from road_grammar.data import mesh as mesh_build
from road_grammar.display import patterns as pattern_display
from road_grammar.operators import analysis as analysis_ops
from road_grammar.ui import patterns as patterns_ui

# The tests run on the street grid of conftest.write_grid (the fixture grid): SIZE x SIZE
# streets SPACING apart, and two dead-end spurs that belong to no square.


def grid_cells(obj):
    """{mesh vertex: (i, j)} of the grid vertices (not the spurs)."""
    positions = mesh_build.positions_xy(obj.data)
    # The vertex nearest the mean is the middle of the grid, (2, 2).
    centre = positions[np.argmin(np.linalg.norm(positions - positions.mean(axis=0), axis=1))]
    origin = centre - SPACING * (SIZE // 2)
    cells = {}
    for v, p in enumerate(positions - origin):
        ij = np.round(p / SPACING)
        if np.all(np.abs(p - ij * SPACING) < 5.0) and np.all((ij >= 0) & (ij < SIZE)):
            cells[v] = (int(ij[0]), int(ij[1]))
    assert len(cells) == SIZE * SIZE
    return cells


def grid_squares(obj):
    """Every block of the grid as a frozenset of its 4 mesh vertices."""
    by_cell = {ij: v for v, ij in grid_cells(obj).items()}
    return {frozenset(by_cell[(i + di, j + dj)] for di in (0, 1) for dj in (0, 1))
            for i in range(SIZE - 1) for j in range(SIZE - 1)}


def square_group(obj):
    """Index of the stored isogroup of the 4-cycle, else None."""
    return next((i for i, item in enumerate(obj.road_analysis.isogroups) if item.order == 4 and item.edge_count == 4),
                None)


def mesh_graph(obj, ggg):
    mesh = obj.data
    return ggg.Graph.from_arrays(mesh_build.positions_xy(mesh), mesh_build.edge_vertices(mesh),
                                 origin_latlon=(obj["origin_lat"], obj["origin_lon"]))


def selection(obj):
    """(selected vertex ids, selected edge ids) of the mesh (Object Mode)."""
    mesh = obj.data
    vertices = np.zeros(len(mesh.vertices), dtype=bool)
    mesh.vertices.foreach_get("select", vertices)
    edges = np.zeros(len(mesh.edges), dtype=bool)
    mesh.edges.foreach_get("select", edges)
    return set(np.flatnonzero(vertices).tolist()), set(np.flatnonzero(edges).tolist())


def induced_edges(obj, vertices):
    edges = mesh_build.edge_vertices(obj.data).tolist()
    return {i for i, (u, v) in enumerate(edges) if u in vertices and v in vertices}


def select_only(obj, vertices):
    """Select exactly ``vertices`` (and the edges between them), in Object Mode."""
    mesh = obj.data
    mask = np.zeros(len(mesh.vertices), dtype=bool)
    mask[list(vertices)] = True
    mesh.vertices.foreach_set("select", mask)
    edges = mesh_build.edge_vertices(mesh)
    mesh.edges.foreach_set("select", mask[edges[:, 0]] & mask[edges[:, 1]])


def mesh_state(obj):
    """What an operator may change on the graph: selection, attributes, modifiers, the
    patterns object, the stored analysis."""
    mesh = obj.data
    attributes = {}
    for attribute in mesh.attributes:
        if attribute.data_type in ('INT', 'FLOAT') and not attribute.name.startswith("."):
            attributes[attribute.name] = mesh_build.read_attribute(mesh, attribute.name).tolist()
    result = obj.road_analysis
    stored = {key: list(result[key]) for key in (analysis.OCCURRENCES, analysis.NON_OVERLAPPING,
                                                 analysis.PATTERN_EDGES) if key in result}
    child = pattern_display.patterns_object(obj)
    return (selection(obj), attributes, [m.name for m in obj.modifiers], obj.hide_render, child and child.name,
            [(i.order, i.frequency) for i in result.isogroups], result.topology, stored, result.active_index)


@pytest.fixture
def op_results(monkeypatch):
    """What each analysis operator's execute() returned (bpy.ops raises on ERROR reports)."""
    return record_executes(monkeypatch, analysis_ops.ROADS_OT_find_similar, analysis_ops.ROADS_OT_analyze,
                           analysis_ops.ROADS_OT_select_isogroup, analysis_ops.ROADS_OT_show_patterns)


# --- Analyze ------------------------------------------------------------------------------

def test_analyze_finds_every_square(grid, op_results, reports):
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    result = grid.road_analysis
    assert result.has_result() and len(result.isogroups) > 0
    index = square_group(grid)
    assert index is not None, [(i.order, i.edge_count) for i in result.isogroups]
    occurrences, non_overlapping, pattern_edges = analysis.isogroup_arrays(grid, index)
    assert {frozenset(o) for o in occurrences.tolist()} == grid_squares(grid)
    assert result.isogroups[index].frequency == (SIZE - 1) ** 2
    # Non-overlapping squares share no vertex: at most 2 x 2 in a 4 x 4 grid of blocks.
    chosen = occurrences[non_overlapping]
    assert len(chosen) == 4 and len(np.unique(chosen)) == chosen.size
    assert len(pattern_edges) == 4
    kind, message = reports()[-1]
    assert kind == 'INFO' and message.startswith("Analysed grid in") and "isogroups" in message
    assert op_results == [{'FINISHED'}]
    # The overview colours edges by isogroup, drawn by a child object that renders (the
    # graph itself still does not).
    slots = pattern_display.read_slots(grid)
    assert slots.max() >= 1 and slots.max() <= PALETTE_SIZE
    child = pattern_display.patterns_object(grid)
    assert child is not None and child.name == "grid Patterns" and child.parent == grid
    assert pattern_display.find_modifier(child) is not None and child.hide_select and not child.hide_render
    assert grid.hide_render


def test_list_matches_ggg_analyze(grid, ggg):
    assert bpy.ops.roads.analyze(max_order=5, min_count=3, max_stored=7) == {'FINISHED'}
    direct = ggg.analyze(mesh_graph(grid, ggg), max_order=5, min_count=3)
    result = grid.road_analysis
    assert len(direct.isogroups) > 7
    assert result.listed == len(direct.isogroups) and result.detected == direct.detected
    assert len(result.isogroups) == 7
    for rank, (item, iso) in enumerate(zip(result.isogroups, direct.isogroups)):
        assert (item.rank, item.order, item.edge_count, item.frequency, item.non_overlapping_count) == \
            (rank + 1, iso.order, iso.edge_count, iso.frequency, len(iso.non_overlapping))
        assert item.gain == pytest.approx(iso.gain) and item.score == pytest.approx(iso.score)
        occurrences, non_overlapping, pattern_edges = analysis.isogroup_arrays(grid, rank)
        np.testing.assert_array_equal(occurrences, iso.occurrences)
        np.testing.assert_array_equal(non_overlapping, iso.non_overlapping)
        np.testing.assert_array_equal(pattern_edges, iso.pattern_edges)
    assert "max order 5" in result.parameters and "min count 3" in result.parameters


def test_choosing_an_item_selects_its_occurrences(grid):
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    result = grid.road_analysis
    assert result.active_index == -1  # the overview is shown, no item chosen
    select_only(grid, [])
    for index in (square_group(grid), 0, len(result.isogroups) - 1):
        result.active_index = index
        occurrences, _, pattern_edges = analysis.isogroup_arrays(grid, index)
        expected = set(occurrences.ravel().tolist())
        vertices, edges = selection(grid)
        assert vertices == expected
        assert edges == induced_edges(grid, expected)
        # Colour: the occurrences' own edges in the item's colour, nothing else.
        slots = pattern_display.read_slots(grid)
        mesh_edges = {tuple(sorted(e)): i for i, e in enumerate(mesh_build.edge_vertices(grid.data).tolist())}
        own = {mesh_edges[tuple(sorted((o[a], o[b])))] for o in occurrences.tolist() for a, b in pattern_edges.tolist()}
        slot = result.isogroups[index].color_slot or MATCH_SLOT
        assert set(np.flatnonzero(slots).tolist()) == own and set(slots[list(own)].tolist()) == {slot}
    # In Edit Mode too.
    select_only(grid, [])
    bpy.ops.object.mode_set(mode='EDIT')
    result.active_index = square_group(grid)
    assert grid.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    assert selection(grid)[0] == set(grid_cells(grid))
    assert np.count_nonzero(pattern_display.read_slots(grid)) == 2 * SIZE * (SIZE - 1)


def test_select_isogroup_non_overlapping_and_overview(grid, op_results):
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    index = square_group(grid)
    assert bpy.ops.roads.select_isogroup(index=index, only_non_overlapping=True) == {'FINISHED'}
    occurrences, non_overlapping, _ = analysis.isogroup_arrays(grid, index)
    vertices, _ = selection(grid)
    assert vertices == set(occurrences[non_overlapping].ravel().tolist()) and len(vertices) == 16
    assert grid.road_analysis.active_index == index
    # Show Overview: each coloured occurrence is a non-overlapping occurrence of the
    # isogroup of its colour, and the colours do not overlap.
    assert bpy.ops.roads.show_patterns() == {'FINISHED'}
    assert grid.road_analysis.active_index == -1
    slots = pattern_display.read_slots(grid)
    edges = mesh_build.edge_vertices(grid.data)
    coloured = 0
    for i, item in enumerate(grid.road_analysis.isogroups):
        if item.color_slot == 0:
            continue
        occ, chosen, pattern_edges = analysis.isogroup_arrays(grid, i)
        for o in occ[chosen].tolist():
            ids = [int(np.flatnonzero(((edges[:, 0] == o[a]) & (edges[:, 1] == o[b])) |
                                      ((edges[:, 0] == o[b]) & (edges[:, 1] == o[a])))[0]) for a, b in pattern_edges]
            if all(slots[k] == item.color_slot for k in ids):
                coloured += len(ids)
    assert coloured == np.count_nonzero(slots) > 0
    with pytest.raises(RuntimeError, match="no isogroup"):
        bpy.ops.roads.select_isogroup(index=999)
    assert op_results[-1] == {'CANCELLED'}


def test_analyze_with_a_seed_in_edit_mode(grid, reports):
    square = sorted(next(iter(grid_squares(grid))))
    select_only(grid, square)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.analyze(max_order=6, use_seed=True) == {'FINISHED'}
    assert grid.mode == 'OBJECT'  # the results are kept in Object Mode
    result = grid.road_analysis
    assert result.seeded and "seed of 4 vertices" in result.parameters
    first = result.isogroups[0]
    assert (first.order, first.edge_count, first.frequency) == (4, 4, (SIZE - 1) ** 2)
    occurrences, _, _ = analysis.isogroup_arrays(grid, 0)
    assert sorted(occurrences[0].tolist()) == square  # the seed itself is occurrence 0
    assert all(item.order >= 4 for item in result.isogroups)


def test_analyze_in_edit_mode_reads_the_edit_mesh_symbols(grid, ggg):
    """Blender's attribute data is empty in Edit Mode: the vertex symbols come from the edit
    mesh (a graph with a nonterminal attribute was refused before)."""
    mesh_build.set_attribute(grid.data, SYMBOL, 'INT', 'POINT', np.zeros(len(grid.data.vertices)))
    bpy.ops.object.mode_set(mode='EDIT')
    topology = analysis.MeshTopology(grid)
    assert topology.symbols is not None and len(topology.symbols) == len(grid.data.vertices)
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    assert square_group(grid) is not None


def test_analyze_errors_change_nothing(grid, op_results, ggg):
    select_only(grid, [])
    before = mesh_state(grid), snapshot()
    with pytest.raises(RuntimeError, match="Selection as seed: Select the vertices"):
        bpy.ops.roads.analyze(use_seed=True)
    plain = bpy.data.objects.new("plain", bpy.data.meshes.new("plain"))
    bpy.context.scene.collection.objects.link(plain)
    bpy.context.view_layer.objects.active = plain
    with pytest.raises(RuntimeError, match="not a road graph"):
        bpy.ops.roads.analyze()
    bpy.data.objects.remove(plain)
    bpy.data.meshes.remove(bpy.data.meshes["plain"])
    bpy.context.view_layer.objects.active = grid
    assert op_results == [{'CANCELLED'}, {'CANCELLED'}]
    assert (mesh_state(grid), snapshot()) == before


def test_cancel_through_the_progress_callback_changes_nothing(grid, monkeypatch, reports):
    # A first analysis, kept; then a second one that the user cancels.
    assert bpy.ops.roads.analyze(max_order=3) == {'FINISHED'}
    grid.road_analysis.active_index = 0
    before = mesh_state(grid), snapshot()
    calls = cancel_at_first_progress(monkeypatch, analysis_ops.AnalysisJob)
    assert bpy.ops.roads.analyze(max_order=8, full=True) == {'CANCELLED'}
    assert len(calls) == 1
    kind, message = reports()[-1]
    assert kind == 'WARNING' and "cancelled" in message and "nothing changed" in message
    assert (mesh_state(grid), snapshot()) == before
    assert not analysis_ops.running


# --- Find Similar ---------------------------------------------------------------------------

def test_find_similar_selects_every_square(grid, reports, op_results):
    squares = grid_squares(grid)
    seed = sorted(next(iter(squares)))
    select_only(grid, seed)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.roads.find_similar() == {'FINISHED'}
    assert grid.mode == 'EDIT'
    bpy.ops.object.mode_set(mode='OBJECT')
    kind, message = reports()[-1]
    assert kind == 'INFO' and message.startswith("16 occurrences of the selected pattern (4 vertices, 4 edges)")
    assert "4 non-overlapping" in message
    vertices, edges = selection(grid)
    assert vertices == set(grid_cells(grid))  # every grid vertex, not the spurs
    assert edges == induced_edges(grid, vertices)
    slots = pattern_display.read_slots(grid)
    seed_edges = induced_edges(grid, set(seed))
    assert set(np.flatnonzero(slots == SEED_SLOT).tolist()) == seed_edges
    square_edges = induced_edges(grid, set(grid_cells(grid)))
    assert set(np.flatnonzero(slots == MATCH_SLOT).tolist()) == square_edges - seed_edges
    assert np.count_nonzero(slots) == len(square_edges)  # the spurs stay uncoloured
    assert op_results == [{'FINISHED'}]


def test_find_similar_in_object_mode_with_a_spur(grid, reports):
    """A seed with a dead end, within a tight tolerance of the seed only: only the places where the
    spur exists too (one)."""
    cells = grid_cells(grid)
    by_cell = {ij: v for v, ij in cells.items()}
    spur = [v for v in range(len(grid.data.vertices)) if v not in cells]
    positions = mesh_build.positions_xy(grid.data)
    east_spur = max(spur, key=lambda v: positions[v, 0])
    seed = [by_cell[(SIZE - 1, 2)], by_cell[(SIZE - 1, 1)], east_spur]
    select_only(grid, seed)
    assert bpy.ops.roads.find_similar(tolerance=0.05, scale='RIGID', include_analysis_group=False) == {'FINISHED'}
    kind, message = reports()[-1]
    assert message.startswith("1 occurrence of the selected pattern (3 vertices, 2 edges)")
    assert selection(grid)[0] == set(seed)


def _not_adjacent(obj):
    cells = {ij: v for v, ij in grid_cells(obj).items()}
    return [cells[(0, 0)], cells[(1, 1)]]


def _two_apart(obj):
    cells = {ij: v for v, ij in grid_cells(obj).items()}
    return [cells[(0, 0)], cells[(1, 0)], cells[(3, 3)], cells[(4, 3)]]


@pytest.mark.parametrize("seed, expected", [
    (lambda obj: [], "Select the vertices of a piece"),
    (lambda obj: [0], "Only one vertex is selected"),
    (_not_adjacent, "No street joins the 2 selected vertices"),
    (_two_apart, "are not connected by streets"),
])
def test_find_similar_bad_seed(grid, op_results, seed, expected):
    select_only(grid, seed(grid))
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.object.mode_set(mode='OBJECT')
    before = mesh_state(grid), snapshot()
    bpy.ops.object.mode_set(mode='EDIT')
    with pytest.raises(RuntimeError, match=expected):
        bpy.ops.roads.find_similar()
    bpy.ops.object.mode_set(mode='OBJECT')
    assert op_results == [{'CANCELLED'}]
    assert (mesh_state(grid), snapshot()) == before


def test_find_similar_not_a_road_graph(ggg, op_results):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    before = snapshot()
    with pytest.raises(RuntimeError, match="not a road graph"):
        bpy.ops.roads.find_similar()
    bpy.ops.object.mode_set(mode='OBJECT')
    assert op_results == [{'CANCELLED'}]
    assert snapshot() == before
    bpy.context.view_layer.objects.active = None
    with pytest.raises(RuntimeError, match="Select a road graph"):
        bpy.ops.roads.find_similar()


def test_find_similar_native_bug_guard(ggg):
    """ggg.find_similar answers a seed of two vertices with no street between them with an
    unclear message ('induced_pattern: vertex -1 ...'); the add-on checks seeds itself, so
    its message stays clear while the library does so."""
    positions = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 100.0]])
    graph = ggg.Graph.from_arrays(positions, np.array([[0, 1], [1, 2]]))
    assert seed_problem(graph.edges, [0, 2]).startswith("No street joins")
    with pytest.raises(ggg.UsageError):
        ggg.find_similar(graph, [0, 2])


# --- the stored result --------------------------------------------------------------------

def test_results_persist_through_save_and_reload(grid, tmp_path):
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    name = grid.name
    state = mesh_state(grid)
    items = [(i.rank, i.order, i.edge_count, i.frequency, i.non_overlapping_count, i.gain, i.color_slot)
             for i in grid.road_analysis.isogroups]
    parameters = grid.road_analysis.parameters
    path = tmp_path / "analysed.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert name not in bpy.data.objects
    bpy.ops.wm.open_mainfile(filepath=str(path))
    obj = bpy.data.objects[name]
    assert mesh_state(obj) == state
    assert [(i.rank, i.order, i.edge_count, i.frequency, i.non_overlapping_count, i.gain, i.color_slot)
            for i in obj.road_analysis.isogroups] == items
    assert obj.road_analysis.parameters == parameters
    # Choosing an isogroup still works on the reloaded file.
    index = square_group(obj)
    obj.road_analysis.active_index = index
    assert selection(obj)[0] == set(grid_cells(obj))


def test_changed_graph_is_not_shown(grid, op_results):
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    mesh = grid.data
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bm.verts.ensure_lookup_table()
    bm.verts.remove(bm.verts[len(bm.verts) - 1])
    bm.to_mesh(mesh)
    bm.free()
    before = mesh_state(grid)
    grid.road_analysis.active_index = 0  # ignored: the ids no longer fit the mesh
    assert mesh_state(grid)[:2] == before[:2]
    with pytest.raises(RuntimeError, match="changed since it was analysed"):
        bpy.ops.roads.select_isogroup(index=0)
    with pytest.raises(RuntimeError, match="changed since it was analysed"):
        bpy.ops.roads.show_patterns()
    assert op_results[-2:] == [{'CANCELLED'}, {'CANCELLED'}]


def test_clear_patterns(grid):
    assert bpy.ops.roads.analyze(max_order=3) == {'FINISHED'}
    assert bpy.ops.roads.clear_patterns() == {'FINISHED'}
    assert pattern_display.ATTRIBUTE not in grid.data.attributes
    assert pattern_display.patterns_object(grid) is None and "grid Patterns" not in bpy.data.objects
    assert "grid Patterns" not in bpy.data.meshes
    assert grid.road_analysis.has_result()
    assert bpy.ops.roads.clear_patterns(forget=True) == {'FINISHED'}
    assert not grid.road_analysis.has_result() and len(grid.road_analysis.isogroups) == 0
    assert analysis.OCCURRENCES not in grid.road_analysis


def test_display_ribbons(grid):
    """The patterns object draws one ribbon per coloured edge, with its colour's material,
    along the edge, above the road surfaces, wherever the graph object is moved."""
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    grid.location = (1000.0, 500.0, 0.0)
    index = square_group(grid)
    grid.road_analysis.active_index = index
    slots = pattern_display.read_slots(grid)
    child = pattern_display.patterns_object(grid)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ribbons = []
    for instance in depsgraph.object_instances:
        if instance.is_instance and instance.parent is not None and instance.parent.original == child:
            materials = [s.material.name for s in instance.object.material_slots if s.material is not None]
            heights = tuple(sorted({round(v.co.z, 4) for v in instance.object.data.vertices}))
            ribbons.append((materials, tuple(instance.matrix_world.translation), heights))
    slot = grid.road_analysis.isogroups[index].color_slot
    assert slot > 0 and len(ribbons) == np.count_nonzero(slots) == 2 * SIZE * (SIZE - 1)
    assert {tuple(m) for m, _, _ in ribbons} == {(pattern_display.material(slot).name,)}
    # Above the surfaces (their top is < 0.25 m), a little higher per colour.
    assert {h for _, _, h in ribbons} == {(round(0.4 + pattern_display.SLOT_STEP_M * slot, 4),)}
    edges = mesh_build.edge_vertices(grid.data)[slots > 0]
    positions = mesh_build.positions_xy(grid.data)
    midpoints = sorted(map(tuple, np.round((positions[edges[:, 0]] + positions[edges[:, 1]]) / 2 + (1000, 500), 1)))
    assert sorted(tuple(np.round(t[:2], 1)) for _, t, _ in ribbons) == midpoints
    color = pattern_display.material(slot).diffuse_color
    assert tuple(color)[:3] == pytest.approx(slot_color_linear(slot))


def _ribbon_midpoints(obj):
    child = pattern_display.patterns_object(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    return sorted(tuple(np.round(np.array(instance.matrix_world.translation)[:2], 1))
                  for instance in depsgraph.object_instances
                  if instance.is_instance and instance.parent is not None and instance.parent.original == child)


def test_display_follows_the_road_surface(grid):
    """Colours follow the roads' polylines (the curved footway: 3 ribbons for its one
    edge) while the surface fits the graph, and the straight edges once it does not."""
    mesh = grid.data
    edges = mesh_build.edge_vertices(mesh)
    positions = mesh_build.positions_xy(mesh)
    surface = roads.surface_object(grid)
    owner = mesh_build.read_attribute(surface.data, SURFACE_EDGE, np.int64)
    curved = int(np.argmax(np.bincount(owner)))
    assert np.bincount(owner)[curved] == 3
    straight = next(i for i in range(len(edges)) if i != curved)
    slots = np.zeros(len(edges), dtype=np.int32)
    slots[[curved, straight]] = (1, 2)
    pattern_display.write(grid, slots, None, analysis.MeshTopology(grid))
    surface_points = mesh_build.positions_xy(surface.data)
    segments = mesh_build.edge_vertices(surface.data)[np.isin(owner, [curved, straight])]
    expected = sorted(tuple(np.round((surface_points[a] + surface_points[b]) / 2, 1)) for a, b in segments)
    assert len(expected) == 4 and _ribbon_midpoints(grid) == expected
    # An edit moves the footway's end: the surface no longer fits; straight edges.
    end = edges[curved][np.argmin(positions[edges[curved], 0])]
    mesh.vertices[end].co.x -= 10.0
    pattern_display.write(grid, slots, None, analysis.MeshTopology(grid))
    positions = mesh_build.positions_xy(mesh)
    expected = sorted(tuple(np.round((positions[a] + positions[b]) / 2, 1)) for a, b in edges[[curved, straight]])
    assert _ribbon_midpoints(grid) == expected
    # Back on the surface; then a topology edit (the east spur removed, edges renumbered)
    # without writing the colours again: the polylines no longer fit, the straight edges
    # (which keep their colour attribute) are drawn.
    mesh.vertices[end].co.x += 10.0
    pattern_display.write(grid, slots, None, analysis.MeshTopology(grid))
    assert len(_ribbon_midpoints(grid)) == 4
    east = int(np.argmax(positions[:, 0]))
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bm.verts.ensure_lookup_table()
    bm.verts.remove(bm.verts[east])
    bm.to_mesh(mesh)
    bm.free()
    mesh.update()
    edges, positions = mesh_build.edge_vertices(mesh), mesh_build.positions_xy(mesh)
    coloured = edges[pattern_display.read_slots(grid) > 0]
    assert len(coloured) == 2
    assert _ribbon_midpoints(grid) == sorted(tuple(np.round((positions[a] + positions[b]) / 2, 1))
                                             for a, b in coloured)


# --- the panel -------------------------------------------------------------------------------

def test_panels_draw(grid):
    assert "Analyze grid" in draw_panel(patterns_ui.VIEW3D_PT_roads_patterns)
    assert "Not analysed yet" in draw_panel(patterns_ui.VIEW3D_PT_roads_isogroups)
    assert bpy.ops.roads.analyze(max_order=4) == {'FINISHED'}
    grid.road_analysis.active_index = square_group(grid)
    text = draw_panel(patterns_ui.VIEW3D_PT_roads_isogroups)
    assert "{} isogroups, ".format(grid.road_analysis.listed) in text and "max\norder 4" in text
    assert "4 vertices, 4 edges" in text and "16 occurrences" in text and "4 non-overlapping" in text
    labels = []
    item = grid.road_analysis.isogroups[square_group(grid)]
    ui_list = SimpleNamespace(layout_type='DEFAULT')
    patterns_ui.ROADS_UL_isogroups.draw_item(ui_list, bpy.context, PanelLayout(labels), None, item, 0, None, "")
    assert labels == ["4", "16", "4", "{:.0f}".format(item.gain)]


# --- undo and the modal run, in a Blender with a window -------------------------------------

def _session(ggg, tmp_path, mode, *extra_flags):
    return run_analysis_session(ggg, tmp_path, write_grid(tmp_path / "grid.osm"), mode, *extra_flags)


def test_undo_of_analyze_and_find_similar(ggg, tmp_path):
    result = _session(ggg, tmp_path, "undo")
    before, analysed = result["before"], result["analysed"]
    assert result["analyze"] == ['RUNNING_MODAL'] and result["finished"]
    assert analysed["isogroups"] > 0 and analysed["coloured"] > 0 and "Road Patterns" in analysed["modifiers"]
    assert before["isogroups"] == 0 and before["coloured"] == 0
    assert result["undone"] == before
    assert result["redone"] == analysed
    # Find Similar in Edit Mode: undo brings back the selection of the seed only.
    assert result["find_similar"] == ['FINISHED']
    assert result["found"]["selected"] == SIZE * SIZE
    assert result["found_undone"] == result["seeded"]
    assert result["seeded"]["selected"] == 4


def test_modal_analyze_cancelled_with_escape(ggg, tmp_path):
    result = _session(ggg, tmp_path, "escape", "--enable-event-simulate")
    assert result["analyze"] == ['RUNNING_MODAL']
    assert result["was_running"] and result["progress_calls"] >= 1
    assert not result["still_running"]
    assert result["after"] == result["before"]
