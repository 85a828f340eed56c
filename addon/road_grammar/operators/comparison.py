"""Compare: how alike the active road graph is to another, as ``ggg compare`` and
ggg.compare say it (docs/cli.md).

roads.compare_graphs reads both graphs as the grammar operators do (graph_edit.MeshGraph:
the mesh and the polylines of its surface, each in its own object's frame), calls
ggg.compare, keeps the result on the active object (``object.road_compare``, shown by the
Compare panel) and reports it in one line (core.comparison.summary). It changes no graph;
an error leaves everything as it was."""

from bpy.props import StringProperty
from bpy.types import Operator

from ..core import native
from ..core.comparison import stored_text, summary
from ..core.topology import topology_checksum
from ..data import graph_edit, roads


class ROADS_OT_compare_graphs(Operator):
    """Compare the active road graph with the other selected one: the distances of ggg compare (degree, edge length, orientation, block area, junction angles) and the structure of each (dead ends, right angles, circuity, ...)"""

    bl_idname = "roads.compare_graphs"
    bl_label = "Compare"
    bl_options = {'REGISTER'}

    other: StringProperty(
        name="Other Graph",
        description="Name of the road graph to compare the active one with (empty: the other selected road graph)",
        options={'SKIP_SAVE'},
    )

    def _graphs(self, context):
        """(active graph, other graph) or None after an ERROR report."""
        active, others = roads.selected_graphs(context, self.other)
        if active is None:
            self.report({'ERROR'}, "Compare needs two road graphs: select the other one, then the one to compare "
                        "(active)")
            return None
        if self.other and not others:
            self.report({'ERROR'}, "'{}' is not another road graph to compare {} with".format(self.other, active.name))
            return None
        if len(others) != 1:
            if not others:
                self.report({'ERROR'}, "Compare needs two road graphs: only {} is selected (select the other one "
                            "too)".format(active.name))
            else:
                self.report({'ERROR'}, "Compare takes two road graphs, {} are selected ({}): select one besides "
                            "the active {}".format(len(others) + 1, ", ".join(sorted(o.name for o in others)),
                                                   active.name))
            return None
        return active, others[0]

    def execute(self, context):
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        graphs = self._graphs(context)
        if graphs is None:
            return {'CANCELLED'}
        active, other = graphs
        # As the user sees them: in Edit Mode, the edited mesh (Edit Mode is left for the reading).
        with graph_edit.object_mode(context, active):
            columns = [graph_edit.MeshGraph(obj) for obj in (active, other)]
        for obj, read in zip((active, other), columns):
            if len(read.edges) == 0:
                self.report({'ERROR'}, "Cannot compare {} with {}: {} has no streets".format(
                    active.name, other.name, obj.name))
                return {'CANCELLED'}
        try:
            result = ggg.compare(*(read.graph(ggg) for read in columns))
        except ggg.Error as ex:
            self.report({'ERROR'}, "Cannot compare {} with {}: {}".format(active.name, other.name, ex))
            return {'CANCELLED'}

        kept = active.road_compare
        kept.result = stored_text(result)
        kept.other = other.name
        kept.topology = topology_checksum(len(columns[0].positions), columns[0].edges)
        self.report({'INFO'}, summary(active.name, other.name, result))
        return {'FINISHED'}


classes = (ROADS_OT_compare_graphs,)
