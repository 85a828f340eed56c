"""Stitch Cities (paper Fig. 18): two road graphs side by side, each with its own grammar,
joined by growing the gap between them with the rules of both.

roads.stitch_cities joins the other selected road graph into the active one (its vertices
brought into the active object's frame, every edge attribute kept), grows the region with
the active city's grammar (seed), then again with the other city's (seed + 1) from the
streets that reach the region, the first city's new ones among them, so that growth from
both sides meets, continues the main roads of both cities through the grown streets
(ggg.continue_hierarchy), writes the result into the active object (graph_edit.Replacement, as
Grow into Region does) and removes the other graph object with its surface and displays.
Everything is computed before the first change: an error leaves the scene as it was.
"""

import numpy as np
from bpy.props import StringProperty
from bpy.types import Operator

from ..core import native
from ..core.columns import appended, induced_subgraph, joined
from ..core.growth import ThrottledProgress, placed_rules, placements_that_fit
from ..core.names import RULE_GRAMMAR, RULE_GRAMMARS_KEY
from ..core.text import plural, rejections, tries
from ..data import graph_edit, roads, texts
from ..properties import grammar
from .common import class_widths
from .region import GrowSettings, region_object, region_polygon


class ROADS_OT_stitch_cities(GrowSettings, Operator):
    """Stitch two road graphs (the active one and one other selected): join the other into the active one and grow the region between them with the grammar of each"""

    bl_idname = "roads.stitch_cities"
    bl_label = "Stitch Cities"
    bl_options = {'REGISTER', 'UNDO'}

    other: StringProperty(
        name="Other City",
        description="Name of the road graph joined into the active one (empty: the other selected road graph)",
        options={'SKIP_SAVE'},
    )
    region: StringProperty(
        name="Region",
        description="Name of the curve or mesh object to fill (empty: the Region of the Grammar panel, else the "
        "selected curve or mesh that is not a road graph)",
        options={'SKIP_SAVE'},
    )
    share: grammar.share_property()
    seed: grammar.seed_property()
    max_placements: grammar.max_placements_property()
    max_vertices: grammar.region_max_vertices_property()
    patience: grammar.patience_property()
    use_placed_rules: grammar.use_placed_property()

    _FROM_SETTINGS = {"share": "stitch_share", "seed": "region_seed", "max_placements": "region_max_placements",
                      "max_vertices": "region_max_vertices", "patience": "region_patience",
                      "use_placed_rules": "region_use_placed"}

    _OBJECTS = ("other", "region")

    # --- what to stitch ------------------------------------------------------------------

    def _cities(self, context):
        """(active graph, other graph) or None after an ERROR report."""
        active, others = roads.selected_graphs(context, self.other)
        if active is None:
            self.report({'ERROR'}, "Stitch Cities needs two road graphs: select the other one, then the one to keep "
                        "(active)")
            return None
        if self.other and not others:
            self.report({'ERROR'}, "'{}' is not another road graph to stitch to {}".format(self.other, active.name))
            return None
        if len(others) != 1:
            if not others:
                self.report({'ERROR'}, "Stitch Cities needs two road graphs: only {} is selected (select the other "
                            "city too)".format(active.name))
            else:
                self.report({'ERROR'}, "Stitch Cities joins two road graphs, {} are selected ({}): select one "
                            "besides the active {}".format(len(others) + 1, ", ".join(sorted(o.name for o in others)),
                                                           active.name))
            return None
        other = others[0]
        if context.view_layer.objects.get(other.name) != other:
            self.report({'ERROR'}, "The road graph {} is not in the view layer".format(other.name))
            return None
        return active, other

    def _grammars(self, context, active, other):
        """((Text, Grammar) of the active city, (Text, Grammar) of the other or None), or
        None after an ERROR report; a warning when the other city has none."""
        text_a = texts.city_grammar_text(context, active, True)
        if text_a is None:
            self.report({'ERROR'}, "No grammar for {}: learn it (Roads sidebar > Learn) or load one into the scene"
                        .format(active.name))
            return None
        text_b = texts.city_grammar_text(context, other, False)
        try:
            first = texts.of_text(text_a)
            second = texts.of_text(text_b) if text_b is not None else None
        except (texts.GrammarUnavailable, native.NativeModuleError) as ex:
            self.report({'ERROR'}, str(ex))
            return None
        return first, second

    def _placements(self, old, notes, text_name, parsed):
        """(vertex ids of the joined graph, placements) of the nonterminals that come from
        the grammar ``text_name`` and have a rule in it (with Use Placed Rules)."""
        if not self.use_placed_rules or parsed is None:
            return [], []
        return placed_rules(old, parsed, [note == text_name for note in notes])

    # --- running -------------------------------------------------------------------------

    def execute(self, context):
        ggg = native.load_or_report(self)
        if ggg is None:
            return {'CANCELLED'}
        cities = self._cities(context)
        if cities is None:
            return {'CANCELLED'}
        active, other = cities
        grammars = self._grammars(context, active, other)
        if grammars is None:
            return {'CANCELLED'}
        (text_a, parsed_a), second = grammars
        text_b, parsed_b = second if second is not None else (None, None)
        region_obj = region_object(self, context, (active, other))
        read = region_polygon(self, context, region_obj, active, "Cannot stitch into")
        if read is None:
            return {'CANCELLED'}
        polygon, loops = read
        # The redo panel stitches the same objects.
        self.region, self.other = region_obj.name, other.name
        name_a, name_b = active.name, other.name

        with graph_edit.object_mode(context, active):
            outcome = self._stitch(context, ggg, active, other, region_obj, polygon, text_a, parsed_a, text_b,
                                   parsed_b)
        if outcome is None:
            return {'CANCELLED'}
        reports, left = outcome

        if second is None:
            self.report({'WARNING'}, "{} has no grammar (learn it first): the gap grew with {}'s rules only".format(
                name_b, name_a))
        if loops > 1:
            self.report({'WARNING'}, "{} has {} outlines: grew into the largest".format(region_obj.name, loops))
        if left:
            self.report({'WARNING'}, "{} did not fit into {} and {} left as {}".format(
                plural(left, "placed rule"), region_obj.name, "is" if left == 1 else "are",
                "it was" if left == 1 else "they were"))
        budget = any(report["stopped_by_budget"] for report in reports["passes"])
        self.report({'WARNING'} if budget else {'INFO'}, self._summary(name_a, name_b, region_obj, reports))
        return {'FINISHED'}

    def _stitch(self, context, ggg, active, other, region_obj, polygon, text_a, parsed_a, text_b, parsed_b):
        """Compute, then write; (counts, placed rules left) or None after a report."""
        old_a, old_b = graph_edit.MeshGraph(active), graph_edit.MeshGraph(other)
        n_a, n_b = len(old_a.positions), len(old_b.positions)
        matrix = np.array(active.matrix_world.inverted() @ other.matrix_world, dtype=np.float64)
        # Which grammar each nonterminal comes from: Place Rule's note, else its city's.
        notes = graph_edit.noted_grammars(active, old_a, text_a.name) + \
            graph_edit.noted_grammars(other, old_b, text_b.name if text_b is not None else "")
        old = joined(ggg, old_a, old_b, matrix)
        names = sorted({note for note, symbol in zip(notes, old.symbols.tolist()) if note and symbol > 0})
        if names or RULE_GRAMMAR in old.point_attributes:
            # The notes, renumbered for the joined graph's list of grammar names.
            old.point_attributes[RULE_GRAMMAR] = ('INT', np.array(
                [names.index(note) + 1 if note and symbol > 0 else 0
                 for note, symbol in zip(notes, old.symbols.tolist())], dtype=np.int64))

        label = "Stitching {} and {}".format(active.name, other.name)
        with roads.Progress(context, read_share=0.9, label=label) as progress:
            passes = [(text_a, parsed_a, self.seed, parsed_b is not None and self.share < 1.0)]
            if parsed_b is not None:
                passes.append((text_b, parsed_b, self.seed + 1, False))
            used, reports, first_placed, traced = [], [], None, None
            left = 0
            try:
                graph = old.graph(ggg)
                streets = old.symbols == 0
                base, base_ids, base_edge_ids = induced_subgraph(ggg, graph, streets)
                grown = base
                # The rules placed by hand go first, each with its own grammar: the other
                # city's before anything grows (patience 0: only them), the active city's
                # at the start of its growth.
                placed = {}
                for text, parsed in ((text_b, parsed_b), (text_a, parsed_a)):
                    if parsed is None or text.name in placed:
                        continue
                    candidates, placements = self._placements(old, notes, text.name, parsed)
                    fits = placements_that_fit(ggg, grown, parsed, polygon, placements)
                    used.extend(vertex for vertex, fit in zip(candidates, fits) if fit)
                    placed[text.name] = [p for p, fit in zip(placements, fits) if fit]
                    left += len(placements) - len(placed[text.name])
                    if text is not text_a and placed[text.name]:
                        grown, first_placed = ggg.grow_region(
                            grown, parsed, polygon, seed=self.seed + 1, max_placements=len(placed[text.name]),
                            max_vertices=self.max_vertices, patience=0, placements=placed[text.name],
                            continue_hierarchy=False, trace_streets=False)
                        placed[text.name] = []
                # The streets of both cities that reach the gap are traced on into it first,
                # after the junctions around it (patience 0: no rule yet); the grammars' rules
                # then fill what is left.
                grown, traced = ggg.grow_region(
                    grown, parsed_a, polygon, seed=self.seed, patience=0, max_vertices=self.max_vertices,
                    continue_hierarchy=False, progress=ThrottledProgress(progress))
                for text, parsed, seed, shared in passes:
                    fitting = placed.pop(text.name, [])

                    def grow(max_placements):
                        return ggg.grow_region(
                            grown, parsed, polygon, seed=seed, max_placements=max_placements,
                            max_vertices=self.max_vertices, patience=self.patience, placements=fitting,
                            continue_hierarchy=False, trace_streets=False, progress=ThrottledProgress(progress))

                    result = grow(self.max_placements)
                    if shared:
                        # The active city's share of what it would place alone; the other's
                        # grammar grows the rest of the region.
                        alone = result[1]["placements"]
                        limit = max(len(fitting), int(round(self.share * alone)))
                        if limit == 0:  # (share 0: the other city's grammar grows it all)
                            result = (grown, {key: (False if isinstance(value, bool) else 0)
                                              for key, value in result[1].items()})
                        elif limit < alone:
                            result = grow(limit)
                        if limit < alone:
                            result[1]["stopped_by_budget"] = False  # (the share, not a budget)
                            result[1]["share_of"] = alone
                    grown, report = result
                    reports.append(report)
                # The main roads are continued once, over the streets of both growths: across
                # the seam, those of one city meet those of the other only through both.
                grown, hierarchy = ggg.continue_hierarchy(grown, base.edge_count, region=polygon)
            except ggg.Error as ex:
                hint = " (or turn off Use Placed Rules)" if isinstance(ex, ggg.UsageError) and self.use_placed_rules \
                    else ""
                self.report({'ERROR'}, "Cannot stitch {} and {} into {}: {}{}".format(
                    active.name, other.name, region_obj.name, ex, hint))
                return None
            if first_placed is not None:
                # (The other city's placed rules count as its rules.)
                reports[-1]["placements"] += first_placed["placements"]
                for key in ("added_vertices", "added_edges"):
                    reports[-1][key] += first_placed[key]
            # (The main roads' connectors add streets and intersections after the growths.)
            added = grown.vertex_count - base.vertex_count
            if added == 0:
                self.report({'WARNING'}, "Nothing grew in {} between {} and {}: no rule fits there ({}: {}). The "
                            "scene is unchanged.".format(region_obj.name, active.name, other.name,
                                                         tries(reports[0]["attempts"]), rejections(reports[0])))
                return None
            progress.step(0.0, "updating the mesh")
            keep = np.ones(len(old.positions), dtype=bool)
            keep[np.asarray(used, dtype=np.int64)] = False
            try:
                result, source = appended(ggg, graph, keep, grown, base_ids, len(base_edge_ids))
            except ggg.Error as ex:
                self.report({'ERROR'}, "Cannot stitch {} and {}: {}".format(active.name, other.name, ex))
                return None
            replacement = graph_edit.Replacement(active, old, result, {"source_vertex": source},
                                                 class_widths(context, ggg, result))
            # The new streets that end on a vertex of either city.
            edges = np.asarray(result.edges, dtype=np.int64).reshape(-1, 2)
            new_edges = grown.edge_count - base.edge_count
            ends = source[edges[len(edges) - new_edges:]]
            from_a = int(np.count_nonzero(((ends >= 0) & (ends < n_a)).any(axis=1)))
            from_b = int(np.count_nonzero(((ends >= n_a) & (ends < n_a + n_b)).any(axis=1)))

            replacement.apply(context)
            if names:
                active[RULE_GRAMMARS_KEY] = names
            elif RULE_GRAMMARS_KEY in active:
                del active[RULE_GRAMMARS_KEY]
            roads.remove_graph_object(other)
            active.select_set(True)
            context.view_layer.objects.active = active
            progress.step(1.0, "done")
        counts = {"passes": reports, "traced": traced, "added_vertices": added, "added_edges": new_edges, "from_a": from_a,
                  "from_b": from_b, "placed": len(used), "hierarchy": hierarchy}
        return counts, left

    def _summary(self, name_a, name_b, region_obj, counts):
        passes = counts["passes"]
        rules_b = passes[1]["placements"] if len(passes) > 1 else 0
        parts = ["Stitched {} and {} in {}: {} of {}, {} of {}, {}, {} new streets, {} from {}'s streets, {} from "
                 "{}'s".format(name_a, name_b, region_obj.name, plural(passes[0]["placements"], "rule"), name_a,
                               plural(rules_b, "rule"), name_b, plural(counts["added_vertices"], "vertex"),
                               "{:,}".format(counts["added_edges"]), counts["from_a"], name_a, counts["from_b"],
                               name_b)]
        traced = counts["traced"]
        if traced and traced["traced_streets"]:
            parts.append("{} traced on into it from {} of both".format(
                plural(traced["traced_streets"], "street"), plural(traced["traced_seeds"], "street")))
        if counts["placed"]:
            parts.append("{} grown".format(plural(counts["placed"], "placed rule")))
        hierarchy = counts["hierarchy"]
        joined = hierarchy["routes"] + hierarchy["connectors"]
        if joined:
            part = "{} continued across the gap ({} raised to their class".format(
                plural(joined, "main road"), plural(hierarchy["raised_streets"] + hierarchy["connector_streets"],
                                                       "street"))
            if hierarchy["intersections"]:
                part += ", {}".format(plural(hierarchy["intersections"], "new intersection"))
            parts.append(part + ")")
        ends = []
        for name, report in zip((name_a, name_b), passes):
            if "share_of" in report:
                ends.append("{}: its share ({:,} of {})".format(name, report["placements"],
                                                                plural(report["share_of"], "rule")))
                continue
            end = "stopped by budget" if report["stopped_by_budget"] else "region full"
            ends.append("{}: {} after {}".format(name, end, tries(report["attempts"])))
        parts.append(", ".join(ends))
        parts.append("seed {}".format(self.seed) + (" and {}".format(self.seed + 1) if len(passes) > 1 else ""))
        return "; ".join(parts)


classes = (ROADS_OT_stitch_cities,)
