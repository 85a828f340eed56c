"""The Blender data of the add-on: road graph objects and their meshes (roads, mesh,
graph_edit), grammar texts (texts), region and piece objects (region, replacement), and the
results kept on objects (analysis, learning). Modules here read and write ``bpy.data``;
what they compute without it is in ``core``."""
