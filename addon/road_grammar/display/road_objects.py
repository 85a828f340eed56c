"""Road graph objects with what draws them: ``build`` makes the objects of a ggg.Graph
(data.roads) with the Road Surface modifier on the surface (surface) and, when the graph has
nonterminals, the Rule Frames modifier (frames); ``rewrite`` puts a derived graph into its
object (data.graph_edit.Replacement), with the Rule Frames modifier when the new graph has
nonterminals. Either everything is made or nothing is."""

from ..data import roads
from . import frames, surface


def build(context, graph, classes, widths, name, source, options, with_surface=True, progress=None,
          target=None, with_frames=None, properties=None):
    """Create the road objects for ``graph``; returns (graph object, surface object or None).
    Either everything is created or nothing is.

    ``target`` (a georef.Target) places the object and sets the scene's georeference for
    the first graph; ``with_frames`` adds the nonterminal attributes and the Rule Frames
    modifier (default: when the graph has nonterminals); ``properties`` are more custom
    properties of the graph object; ``progress`` (a data.roads.Progress) is told each step."""
    def step(fraction, message):
        if progress is not None:
            progress.step(fraction, message)

    if with_frames is None:
        with_frames = roads.has_nonterminals(graph)
    location = target.location if target is not None else (0.0, 0.0)
    created = roads.Created()
    try:
        graph_obj, surface_obj = roads.new_objects(
            graph, classes, widths, name, source, options, created, with_surface=with_surface,
            with_frames=with_frames, location=location, properties=properties, step=step)
        if surface_obj is not None:
            step(0.7, "surface modifier")
            surface.add_to(surface_obj, created)
        if with_frames:
            frames.add_to(graph_obj, created)
        step(0.9, "linking")
        roads.link(context, graph_obj, surface_obj, graph, target)
        step(1.0, "done")
    except BaseException:
        created.remove_all()
        raise
    return graph_obj, surface_obj


def rewrite(replacement):
    """Write the data.graph_edit.Replacement ``replacement`` into its road graph object and
    rebuild its surface, adding the Rule Frames modifier when the new graph has
    nonterminals. What is made first (the new surface mesh, the modifier) is removed again
    if making it fails, so that the object is left as it was."""
    created = roads.Created()
    try:
        surface_mesh = replacement.new_surface_mesh(created)
        if replacement.with_frames:
            frames.add_to(replacement.graph_obj, created)
    except BaseException:
        created.remove_all()
        raise
    replacement.apply(surface_mesh)
