"""Operators of the 3-D city: build the city of a road graph, a camera fly-through along its
roads, and rendering (a still or the fly-through as an MP4); their scene settings are
``scene.road_city`` (properties.city, shown in the sidebar's City panel).

Build City runs as a job (operators.jobs.ModalJobOperator): the graph is read on the main
thread, its ground plan (ggg.city_layout and the building heights, core.city.Plan) is made
in a worker thread, modal from the UI (progress in the status bar, Esc cancels), waited for
from scripts; the meshes are made on the main thread when it has finished, so a cancelled
or failed run leaves the scene as it was. Render City from the UI is Blender's own render job,
watched to its end (operators.jobs.ModalRenderOperator: the frames written in the status bar
and the panel, Esc cancels, the report says what was written); from scripts it renders at
once. The fly-through is quick and runs at once.
"""

import os
from types import SimpleNamespace

import bmesh
import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty
from bpy.types import Operator

from ..core import flythrough, native
from ..core.city import CityError, Plan
from ..core.jobs import StepsJob
from ..core.names import CITY_PART_KEY
from ..core.polylines import complete_polylines
from ..data import graph_edit
from ..data import mesh as mesh_data
from ..display import city
from ..properties.city import (ENGINE_ITEMS, fly_properties, seed_property, sidewalk_property, sun_azimuth_property,
                               sun_elevation_property)
from .jobs import ModalJobOperator, ModalRenderOperator
from .region import changed_since, read_columns

FLY_PART = "flythrough"
FLY_PATH_PART = "flythrough path"
GRAPH_NAME_KEY = "road_graph_name"

# (camera height, look-at height, look ahead, speed of a tour, lens) per height mode.
HEIGHTS = {
    'STREET': (2.0, 1.6, 30.0, 11.0, 24.0),
    'DRONE': (70.0, 0.0, 140.0, 25.0, 30.0),
}


def _report_error(op, message):
    op.report({'ERROR'}, message)
    return {'CANCELLED'}


# Cities being built in the UI: graph object name -> StepsJob (for the panel, and so that
# one city is not built twice at once).
running = {}


def plan_city(job, ggg, columns, settings):
    """The Plan of the city of the GraphColumns ``columns`` (worker thread, no Blender data);
    raises ggg.Error or CityError (ggg.Cancelled once the user cancelled)."""
    job.step(0.0, "reading the graph")
    graph = columns.graph(ggg)
    widths = ggg.road_widths(graph)
    plan = Plan(ggg, graph, widths, settings, progress=job.stage(0.02, 1.0))
    job.step(1.0, "done")
    return plan


class ROADS_OT_build_city(ModalJobOperator, Operator):
    """Build a 3-D city on the active road graph: road surfaces, blocks with kerbs and sidewalks, yards, buildings, ground, sun and sky (replaces this graph's earlier city); Esc cancels"""

    bl_idname = "roads.build_city"
    bl_label = "Build City"
    bl_options = {'REGISTER', 'UNDO'}

    seed: seed_property()
    sidewalk_m: sidewalk_property()
    sun_elevation: sun_elevation_property()
    sun_azimuth: sun_azimuth_property()

    _FROM_SETTINGS = ("seed", "sidewalk_m", "sun_elevation", "sun_azimuth")
    _running = running
    _doing = "Building the city of"
    _noun = "the city"
    _progress_label = "Building city"
    _subject = "Building the city of {}"
    _cannot = "Cannot build the city of {}"
    _result_noun = "the city"
    _changed = "{} changed while its city was planned; build it again"

    @classmethod
    def poll(cls, context):
        obj = city.city_graph(context)
        return obj is None or obj.name not in cls._running

    def _settings(self, context):
        return context.scene.road_city

    def _start(self, context):
        """Read the road graph (main thread) and start planning its city; False after an
        ERROR report."""
        graph_obj = city.city_graph(context)
        if graph_obj is None:
            self.report({'ERROR'}, "No road graph is active: select a road graph (import OpenStreetMap roads first)")
            return False
        ggg = native.load_or_report(self)
        if ggg is None:
            return False
        if graph_obj.name in running:
            self.report({'ERROR'}, "The city of {} is being built already".format(graph_obj.name))
            return False
        columns, self._topology = read_columns(context, graph_obj)
        settings = SimpleNamespace(seed=self.seed, sidewalk_m=self.sidewalk_m)
        self._ggg, self._object_name = ggg, graph_obj.name
        self._job = StepsJob(ggg, lambda job: plan_city(job, ggg, columns, settings), "road_grammar city")
        self._job.start()
        return True

    def _report_error(self, error):
        if isinstance(error, (self._ggg.Error, CityError)):
            self.report({'ERROR'}, "{}: {}".format(self._object_name, error))
        else:
            super()._report_error(error)

    def _gone(self, context):
        if changed_since(bpy.data.objects.get(self._object_name), self._topology):
            return self._changed.format(self._object_name)
        return None

    def _keep(self, context, graph_obj, _topology):
        """Make the city's meshes from the finished plan (main thread) and report."""
        collection = city.build(context, graph_obj, self._job.result, self)
        self.report({'INFO'}, "Built {}: {:,} blocks, {:,} buildings, {:,} road pieces".format(
            collection.name, collection["blocks"], collection["buildings"], collection["road_pieces"]))
        return {'FINISHED'}


def _network(graph_obj):
    mesh = graph_obj.data
    positions = mesh_data.positions_xy(mesh)
    edges = mesh_data.edge_vertices(mesh)
    offsets, points = graph_edit.surface_polylines(graph_obj, positions, edges) or \
        complete_polylines(np.zeros(len(edges) + 1, dtype=np.int64), np.zeros((0, 2)), positions, edges)
    rank = mesh.attributes.get("rank")
    ranks = mesh_data.read_attribute(mesh, "rank", np.int64) if rank is not None and rank.domain == 'EDGE' \
        else np.ones(len(edges), dtype=np.int64)
    return flythrough.Network(positions, edges, offsets, points, ranks)


def _selected_vertices(graph_obj):
    """The selected vertices, in the order they were picked in Edit Mode when Blender knows
    it (else by index)."""
    order = []
    if graph_obj.mode == 'EDIT':
        history = bmesh.from_edit_mesh(graph_obj.data).select_history
        order = [element.index for element in history if isinstance(element, bmesh.types.BMVert)]
        graph_obj.update_from_editmode()
    flags = mesh_data.read_flags(graph_obj.data.vertices)
    selected = np.flatnonzero(flags["select"] & ~flags["hide"]).tolist()
    if sorted(order) == selected:
        return order
    return selected


def _remove_parts(graph_name, parts):
    for obj in [o for o in bpy.data.objects if o.get(GRAPH_NAME_KEY) == graph_name and o.get(CITY_PART_KEY) in parts]:
        data = obj.data
        bpy.data.objects.remove(obj)
        if data is not None and data.users == 0:
            (bpy.data.cameras if isinstance(data, bpy.types.Camera) else bpy.data.curves).remove(data)


class ROADS_OT_flythrough(Operator):
    """Animate a camera along the roads of the active road graph: the shortest path between the two selected vertices, or a seeded tour of the major roads"""

    bl_idname = "roads.flythrough"
    bl_label = "Fly-Through"
    bl_options = {'REGISTER', 'UNDO'}

    mode: fly_properties()["mode"]
    height: fly_properties()["height"]
    duration_s: fly_properties()["duration_s"]
    seed: fly_properties()["seed"]
    smoothing_m: fly_properties()["smoothing_m"]
    start: IntProperty(name="Start Vertex", description="First vertex of the shortest path (-1: the selection)",
                       default=-1, min=-1)
    end: IntProperty(name="End Vertex", description="Last vertex of the shortest path (-1: the selection)",
                     default=-1, min=-1)

    _FROM_SETTINGS = {"mode": "fly_mode", "height": "fly_height", "duration_s": "fly_duration_s",
                      "seed": "fly_seed", "smoothing_m": "fly_smoothing_m"}

    def execute(self, context):
        graph_obj = city.city_graph(context)
        if graph_obj is None:
            return _report_error(self, "No road graph is active: select a road graph (import OpenStreetMap roads "
                                 "first)")
        if graph_obj.mode == 'EDIT' and (self.mode != 'PATH' or self.start >= 0 or self.end >= 0):
            graph_obj.update_from_editmode()  # (_selected_vertices does it after reading the pick order)
        if len(graph_obj.data.edges) == 0:
            return _report_error(self, "{} has no roads to fly along".format(graph_obj.name))
        scene = context.scene
        fps = scene.render.fps / scene.render.fps_base
        frames = max(2, int(round(self.duration_s * fps)))
        height, look_height, look_ahead, speed, lens = HEIGHTS[self.height]
        ends = None
        if self.mode == 'PATH':
            # The pick order first: leaving Edit Mode's data for the mesh forgets it.
            ends = [self.start, self.end] if self.start >= 0 or self.end >= 0 else _selected_vertices(graph_obj)
            if len(ends) != 2:
                return _report_error(self, "Select exactly two vertices of {} in Edit Mode for a shortest "
                                     "path ({} selected), or use a Tour".format(graph_obj.name, len(ends)))
        network = _network(graph_obj)
        try:
            if self.mode == 'PATH':
                steps = network.shortest_path(int(ends[0]), int(ends[1]))
            else:
                steps = network.tour(speed * self.duration_s, self.seed)
            line = network.path_points(steps)
            locations, targets, length = flythrough.camera_track(line, frames, height, look_ahead, look_height,
                                                                 self.smoothing_m)
        except flythrough.PathError as ex:
            return _report_error(self, "{}: {}".format(graph_obj.name, ex))

        matrix = graph_obj.matrix_world
        _remove_parts(graph_obj.name, (FLY_PART, FLY_PATH_PART))
        collection = city.find_collection(graph_obj) or context.collection or scene.collection
        camera_data = bpy.data.cameras.new(graph_obj.name + " Flythrough")
        camera_data.lens = lens
        camera_data.clip_start = 0.3 if self.height == 'STREET' else 2.0
        camera_data.clip_end = 6000.0
        camera = bpy.data.objects.new(graph_obj.name + " Flythrough", camera_data)
        camera[CITY_PART_KEY] = FLY_PART
        camera[GRAPH_NAME_KEY] = graph_obj.name
        camera["path_length_m"] = float(length)
        collection.objects.link(camera)
        _keyframe(camera, matrix, locations, targets, scene.frame_start)

        curve = bpy.data.curves.new(graph_obj.name + " Flythrough Path", 'CURVE')
        curve.dimensions = '3D'
        spline = curve.splines.new('POLY')
        spline.points.add(len(locations) - 1)
        co = np.column_stack((locations, np.ones(len(locations))))
        spline.points.foreach_set("co", co.astype(np.float32).ravel())
        path_obj = bpy.data.objects.new(graph_obj.name + " Flythrough Path", curve)
        path_obj.matrix_world = matrix
        path_obj.hide_render = True
        path_obj[CITY_PART_KEY] = FLY_PATH_PART
        path_obj[GRAPH_NAME_KEY] = graph_obj.name
        collection.objects.link(path_obj)

        scene.camera = camera
        scene.frame_end = scene.frame_start + frames - 1
        self.report({'INFO'}, "Fly-through of {}: {:.0f} m in {} frames ({:.1f} s at {:g} fps), {} road{}".format(
            graph_obj.name, length, frames, frames / fps, fps, len(steps), "" if len(steps) == 1 else "s"))
        return {'FINISHED'}


def _keyframe(camera, matrix, locations, targets, first_frame):
    """A key on every frame: location and rotation (looking at the target), linear."""
    from mathutils import Vector
    world_locations = [matrix @ Vector(p) for p in locations]
    world_targets = [matrix @ Vector(p) for p in targets]
    previous = None
    keys = np.empty((len(locations), 6))
    for i, (p, t) in enumerate(zip(world_locations, world_targets)):
        euler = (t - p).to_track_quat('-Z', 'Y').to_euler('XYZ', previous) if previous is not None \
            else (t - p).to_track_quat('-Z', 'Y').to_euler('XYZ')
        previous = euler
        keys[i, :3] = p
        keys[i, 3:] = euler
    action = bpy.data.actions.new(camera.name + " Action")
    camera.animation_data_create().action = action
    frames = first_frame + np.arange(len(locations), dtype=np.float64)
    for path, base in (("location", 0), ("rotation_euler", 3)):
        for index in range(3):
            curve = action.fcurves.new(path, index=index)
            curve.keyframe_points.add(len(frames))
            co = np.column_stack((frames, keys[:, base + index])).astype(np.float32).ravel()
            curve.keyframe_points.foreach_set("co", co)
            curve.keyframe_points.foreach_set("interpolation", np.full(len(frames), 1, dtype=np.int32))  # LINEAR
            curve.update()
    camera.location = keys[0, :3]
    camera.rotation_euler = keys[0, 3:]


class ROADS_OT_render_city(ModalRenderOperator, Operator):
    """Render the scene's camera: a still (city.png) or the animation as an MP4 (flythrough.mp4); Esc cancels"""

    bl_idname = "roads.render_city"
    bl_label = "Render City"
    bl_options = {'REGISTER'}

    animation: BoolProperty(name="Animation", description="Render the frame range as an MP4 instead of a still",
                            default=False)
    engine: EnumProperty(name="Engine", items=ENGINE_ITEMS, default='BLENDER_EEVEE')
    resolution_x: IntProperty(name="Width", default=1280, min=16, max=16384, subtype='PIXEL')
    resolution_y: IntProperty(name="Height", default=720, min=16, max=16384, subtype='PIXEL')
    samples: IntProperty(name="Samples", default=16, min=1, max=4096)
    directory: StringProperty(name="Output", default="//render/", subtype='DIR_PATH')

    _FROM_SETTINGS = ("engine", "resolution_x", "resolution_y", "samples", "directory")

    def _prepare(self, context):
        scene = context.scene
        if scene.camera is None:
            self.report({'ERROR'}, "The scene has no camera: build a city (it adds a view) or make a fly-through")
            return None
        directory = bpy.path.abspath(self.directory or "//")
        if not directory or (directory.startswith("//") and not bpy.data.filepath):
            directory = os.path.join(os.getcwd(), "render")
        try:
            os.makedirs(directory, exist_ok=True)
        except OSError as ex:
            self.report({'ERROR'}, "Cannot write to {}: {}".format(directory, ex))
            return None
        configure_render(scene, self.engine, self.resolution_x, self.resolution_y, self.samples)
        if self.animation:
            path = os.path.join(directory, "flythrough.mp4")
            configure_movie(scene)
        else:
            path = os.path.join(directory, "city.png")
            scene.render.image_settings.file_format = 'PNG'
        scene.render.filepath = path
        return path

    def execute(self, context):
        path = self._prepare(context)
        if path is None:
            return {'CANCELLED'}
        if self.animation:
            bpy.ops.render.render(animation=True)
        else:
            bpy.ops.render.render(write_still=True)
        if not os.path.isfile(path):
            return _report_error(self, "Rendering wrote no file {}".format(path))
        self.report({'INFO'}, "Rendered {}".format(path))
        return {'FINISHED'}


def configure_render(scene, engine, width, height, samples):
    render = scene.render
    render.engine = engine
    render.resolution_x, render.resolution_y = int(width), int(height)
    render.resolution_percentage = 100
    if engine == 'CYCLES':
        scene.cycles.device = 'CPU'
        scene.cycles.samples = int(samples)
        scene.cycles.use_denoising = False
    else:
        scene.eevee.taa_render_samples = int(samples)
        # Soft shadows and ambient occlusion need several samples to converge; Mesa's software
        # OpenGL renders a 1024 shadow cascade in a fraction of the time of a 2048 one.
        scene.eevee.use_gtao = samples >= 8
        scene.eevee.use_soft_shadows = samples >= 8
        scene.eevee.shadow_cascade_size = '1024'


def configure_movie(scene):
    """H.264 in an MP4 container (Blender 3.4's FFmpeg output)."""
    settings = scene.render.image_settings
    settings.file_format = 'FFMPEG'
    ffmpeg = scene.render.ffmpeg
    ffmpeg.format = 'MPEG4'
    ffmpeg.codec = 'H264'
    ffmpeg.constant_rate_factor = 'MEDIUM'
    ffmpeg.ffmpeg_preset = 'GOOD'
    ffmpeg.audio_codec = 'NONE'


classes = (ROADS_OT_build_city, ROADS_OT_flythrough, ROADS_OT_render_city)
