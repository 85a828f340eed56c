"""Helpers for the add-on's Geometry Nodes groups: sockets of the group interface (Blender
3.x and 4.x), the group every modifier of the add-on starts from, and nodes."""

import bpy


def new_socket(tree, in_out, socket_type, name):
    """A group input/output socket, on Blender 3.x (tree.inputs) and 4.x (tree.interface)."""
    if hasattr(tree, "interface"):
        return tree.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    sockets = tree.inputs if in_out == 'INPUT' else tree.outputs
    return sockets.new(socket_type, name)


def new_geometry_group(name, markers, float_inputs, io_x):
    """A new Geometry Nodes group with the custom properties ``markers`` and the interface
    of the add-on's modifiers: a Geometry input, the float inputs ``float_inputs`` ((name,
    default, min, max), ...), a Material input and a Geometry output. Returns (tree, Group
    Input node at x = -io_x, Group Output node at x = io_x)."""
    tree = bpy.data.node_groups.new(name, 'GeometryNodeTree')
    for key, value in markers.items():
        tree[key] = value
    new_socket(tree, 'INPUT', 'NodeSocketGeometry', "Geometry")
    for socket_name, default, low, high in float_inputs:
        socket = new_socket(tree, 'INPUT', 'NodeSocketFloat', socket_name)
        socket.default_value, socket.min_value, socket.max_value = default, low, high
    new_socket(tree, 'INPUT', 'NodeSocketMaterial', "Material")
    new_socket(tree, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
    group_in = tree.nodes.new('NodeGroupInput')
    group_in.location = (-io_x, 0)
    group_out = tree.nodes.new('NodeGroupOutput')
    group_out.location = (io_x, 0)
    return tree, group_in, group_out


def input_sockets(tree):
    if hasattr(tree, "interface"):
        return [item for item in tree.interface.items_tree
                if item.item_type == 'SOCKET' and item.in_out == 'INPUT']
    return list(tree.inputs)


def enabled_output(node):
    """The first visible output (Named Attribute has one per data type on Blender 3.x)."""
    return next(socket for socket in node.outputs if socket.enabled)


def named_float(nodes, name, location):
    node = nodes.new('GeometryNodeInputNamedAttribute')
    node.data_type = 'FLOAT'
    node.inputs["Name"].default_value = name
    node.location = location
    return node


def math_node(nodes, operation, location, value=None):
    node = nodes.new('ShaderNodeMath')
    node.operation = operation
    node.location = location
    if value is not None:
        node.inputs[1].default_value = value
    return node


def new_node(nodes, kind, location, **settings):
    """A new node of ``kind`` at ``location``, with the attributes ``settings``."""
    node = nodes.new(kind)
    node.location = location
    for key, value in settings.items():
        setattr(node, key, value)
    return node


def find_socket(sockets, name, kind=None):
    """The enabled socket ``name`` (of type ``kind``, e.g. 'INT') among ``sockets``: nodes
    such as Compare have one socket per data type under the same name."""
    return next(s for s in sockets if s.name == name and s.enabled and (kind is None or s.type == kind))
