"""Values that mean nothing (NaN, which Blender's float properties let through, and a region
without area) are refused by the operators as by the CLI and the Python module: an error
report naming the option, CANCELLED, and the scene unchanged."""

import math

import bpy
import numpy as np
import pytest

from conftest import record_executes, snapshot
from road_grammar.operators import analysis as analysis_ops
from road_grammar.operators import learning as learning_ops
from road_grammar.operators import region as region_ops


@pytest.fixture
def op_results(monkeypatch):
    return record_executes(monkeypatch, analysis_ops.ROADS_OT_analyze, learning_ops.ROADS_OT_learn,
                           region_ops.ROADS_OT_grow_region)


def _state(obj):
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    return snapshot(), len(mesh.vertices), len(mesh.edges), co.tobytes()


@pytest.mark.parametrize("option", ["min_aspect", "min_irregularity", "cut", "tolerance"])
def test_analyze_refuses_nan(grid, op_results, option):
    before = _state(grid)
    with pytest.raises(RuntimeError, match=option):
        bpy.ops.roads.analyze(max_order=3, **{option: math.nan})
    assert op_results == [{'CANCELLED'}]
    assert _state(grid) == before


@pytest.mark.parametrize("option", ["min_aspect", "min_irregularity", "cut"])
def test_learn_refuses_nan(town, op_results, option):
    before = _state(town)
    with pytest.raises(RuntimeError, match=option):
        bpy.ops.roads.learn(**{option: math.nan})
    assert op_results == [{'CANCELLED'}]
    assert _state(town) == before


def test_grow_refuses_a_region_without_area(town, op_results):
    assert bpy.ops.roads.learn() == {'FINISHED'}
    mesh = bpy.data.meshes.new("Line")
    # Three corners on a line, joined as a closed loop: a region with no area.
    corners = [(700.0, -600.0, 0.0), (1100.0, 0.0, 0.0), (1500.0, 600.0, 0.0)]
    mesh.from_pydata(corners, [(0, 1), (1, 2), (2, 0)], [])
    line = bpy.data.objects.new("Line", mesh)
    bpy.context.scene.collection.objects.link(line)
    bpy.context.view_layer.objects.active = town
    before = _state(town)
    with pytest.raises(RuntimeError, match="no area"):
        bpy.ops.roads.grow_region(region=line.name, seed=1)
    assert op_results[-1] == {'CANCELLED'}
    assert _state(town) == before
