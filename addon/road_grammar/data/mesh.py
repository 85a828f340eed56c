"""numpy arrays <-> Blender meshes, in bulk (foreach_set, foreach_get), never per vertex in
Python. (The polylines of edges, as arrays: core.polylines.)"""

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
