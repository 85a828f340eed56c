"""numpy arrays -> Blender meshes, in bulk (foreach_set), never per vertex in Python."""

import bpy
import numpy as np

# numpy dtype and foreach_set key of each attribute type the add-on writes.
_ATTRIBUTE_KINDS = {
    'FLOAT': (np.float32, "value"),
    'INT': (np.int32, "value"),
    'BOOLEAN': (np.bool_, "value"),
}
# Text attributes (edge names): Blender has no bulk access to them, so only the non-empty
# values are set one by one.
STRING = 'STRING'


def _xyz(points_xy):
    """(N, 2) metres -> flat (3N,) float32 with z = 0."""
    points_xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    xyz = np.zeros((len(points_xy), 3), dtype=np.float32)
    xyz[:, :2] = points_xy
    return xyz.ravel()


def new_edge_mesh(name, points_xy, edges, edge_attributes=None, point_attributes=None):
    """A mesh of loose edges: vertices at ``points_xy`` (z = 0), ``edges`` (M, 2) vertex
    indices, ``edge_attributes`` {name: (type, values)} on the EDGE domain and
    ``point_attributes`` on the POINT domain."""
    mesh = bpy.data.meshes.new(name)
    try:
        fill_edge_mesh(mesh, points_xy, edges, edge_attributes, point_attributes)
    except Exception:
        bpy.data.meshes.remove(mesh)
        raise
    return mesh


def fill_edge_mesh(mesh, points_xy, edges, edge_attributes=None, point_attributes=None):
    """Replace the geometry and attributes of ``mesh`` (the datablock stays the same)."""
    edges = np.asarray(edges, dtype=np.int32).reshape(-1, 2)
    points = _xyz(points_xy)
    mesh.clear_geometry()
    mesh.vertices.add(len(points) // 3)
    mesh.vertices.foreach_set("co", points)
    mesh.edges.add(len(edges))
    mesh.edges.foreach_set("vertices", edges.ravel())
    for attribute_name, (kind, values) in (edge_attributes or {}).items():
        set_attribute(mesh, attribute_name, kind, 'EDGE', values)
    for attribute_name, (kind, values) in (point_attributes or {}).items():
        set_attribute(mesh, attribute_name, kind, 'POINT', values)
    mesh.update()
    return mesh


def positions_xy(mesh):
    """(N, 2) float64 x, y of the mesh's vertices (object-local)."""
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)[:, :2].astype(np.float64)


def edge_vertices(mesh):
    """(M, 2) int64 vertex indices of the mesh's edges."""
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int32)
    mesh.edges.foreach_get("vertices", edges)
    return edges.reshape(-1, 2).astype(np.int64)


def user_attributes(mesh, domain):
    """{name: (type, values)} of the generic FLOAT, INT and BOOLEAN attributes on ``domain``
    (not Blender's internal ones, whose names start with a dot)."""
    found = {}
    for attribute in mesh.attributes:
        if attribute.domain != domain or attribute.data_type not in _ATTRIBUTE_KINDS:
            continue
        if attribute.name.startswith(".") or getattr(attribute, "is_internal", False):
            continue
        if attribute.name in ("position",):
            continue
        found[attribute.name] = (attribute.data_type,
                                 read_attribute(mesh, attribute.name, _ATTRIBUTE_KINDS[attribute.data_type][0]))
    return found


def set_attribute(mesh, name, kind, domain, values):
    """Create (or replace) a generic attribute and fill it from ``values`` (a sequence of
    str for a STRING attribute)."""
    existing = mesh.attributes.get(name)
    if existing is not None:
        mesh.attributes.remove(existing)
    attribute = mesh.attributes.new(name, kind, domain)
    if kind != STRING:
        values = np.ascontiguousarray(values, dtype=_ATTRIBUTE_KINDS[kind][0]).ravel()
    if len(values) != len(attribute.data):
        raise ValueError(
            "attribute {!r}: {} values for {} {} elements".format(name, len(values), len(attribute.data), domain)
        )
    if kind == STRING:
        data = attribute.data
        for index, value in enumerate(values):
            if value:
                data[index].value = value
    else:
        attribute.data.foreach_set(_ATTRIBUTE_KINDS[kind][1], values)
    return attribute


def read_attribute(mesh, name, dtype=np.float64):
    """The values of a FLOAT or INT attribute as a numpy array."""
    attribute = mesh.attributes[name]
    values = np.empty(len(attribute.data), dtype=dtype)
    attribute.data.foreach_get("value", values)
    return values


def read_strings(mesh, name, domain):
    """The values of the STRING attribute ``name`` on ``domain`` as a list of str, or None
    when the mesh has no such attribute."""
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != domain or attribute.data_type != STRING:
        return None
    return [item.value for item in attribute.data]


def read_flags(elements):
    """{"select": bool array, "hide": bool array} of mesh.vertices or mesh.edges."""
    flags = {}
    for name in ("select", "hide"):
        values = np.zeros(len(elements), dtype=bool)
        elements.foreach_get(name, values)
        flags[name] = values
    return flags


def write_flags(elements, flags):
    """Set the flags of read_flags on mesh.vertices or mesh.edges."""
    for name, values in flags.items():
        values = np.ascontiguousarray(values, dtype=bool)
        if len(values) != len(elements):
            raise ValueError("{}: {} values for {} elements".format(name, len(values), len(elements)))
        elements.foreach_set(name, values)


def complete_polylines(offsets, points, positions, edges):
    """(offsets, points) of ``Graph.edge_geometry()`` form where every edge has a polyline
    of two points or more: one with fewer points becomes the straight segment between the
    edge's vertices (``positions``, ``edges``)."""
    offsets = np.asarray(offsets, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    counts = np.diff(offsets)
    short = np.flatnonzero(counts < 2)
    if len(short) == 0:
        return offsets, points
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    new_counts = counts.copy()
    new_counts[short] = 2
    new_offsets = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(new_counts, out=new_offsets[1:])
    new_points = np.empty((new_offsets[-1], 2), dtype=np.float64)
    keep = counts >= 2
    src = np.repeat(offsets[:-1][keep], counts[keep]) + _ramp(counts[keep])
    dst = np.repeat(new_offsets[:-1][keep], counts[keep]) + _ramp(counts[keep])
    new_points[dst] = points[src]
    new_points[new_offsets[short]] = positions[edges[short, 0]]
    new_points[new_offsets[short] + 1] = positions[edges[short, 1]]
    return new_offsets, new_points


def polyline_segments(offsets, points, positions, edges):
    """Segments of the edge polylines.

    ``offsets`` (M+1,) and ``points`` (P, 2) are ``Graph.edge_geometry()``. A polyline with
    fewer than two points stands for the straight segment between the edge's vertices
    (``positions``, ``edges``); those end points are appended to the point array.
    Returns (points (P', 2), segments (S, 2) int32, owner (S,) int64: the edge of each segment).
    """
    offsets, points = complete_polylines(offsets, points, positions, edges)
    segment_counts = np.diff(offsets) - 1
    owner = np.repeat(np.arange(len(segment_counts), dtype=np.int64), segment_counts)
    start = np.repeat(offsets[:-1], segment_counts) + _ramp(segment_counts)
    segments = np.stack((start, start + 1), axis=1).astype(np.int32)
    return points, segments, owner


def _ramp(counts):
    """0..c-1 for each count c, concatenated (np.concatenate([np.arange(c) for c in counts]))."""
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    starts = np.cumsum(counts) - counts
    return np.arange(total, dtype=np.int64) - np.repeat(starts, counts)


def segment_polylines(points, segments, owner, edge_count):
    """The inverse of polyline_segments: (offsets (edge_count+1,) int64, points (P, 2)), the
    polyline of each edge from its segments (a chain, in order, as polyline_segments makes
    them). An edge without segments gets no points (it stands for the straight segment)."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    segments = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
    owner = np.asarray(owner, dtype=np.int64)
    valid = (owner >= 0) & (owner < edge_count)
    order = np.argsort(owner[valid], kind="stable")
    segments = segments[valid][order]
    owner = owner[valid][order]
    counts = np.bincount(owner, minlength=edge_count).astype(np.int64)
    point_counts = np.where(counts > 0, counts + 1, 0)
    offsets = np.zeros(edge_count + 1, dtype=np.int64)
    np.cumsum(point_counts, out=offsets[1:])
    out = np.empty((offsets[-1], 2), dtype=np.float64)
    first_segment = np.cumsum(counts) - counts
    has = counts > 0
    out[offsets[:-1][has]] = points[segments[first_segment[has], 0]]
    out[np.repeat(offsets[:-1], counts) + 1 + _ramp(counts)] = points[segments[:, 1]]
    return offsets, out
