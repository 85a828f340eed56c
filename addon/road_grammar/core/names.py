"""Names the add-on gives to Blender data: the custom properties that mark road graph
objects, their children and the texts it makes, the attributes of the graph mesh, and the
object name made from a file name."""

import os

# Custom properties of a road graph object (GRAPH_KEY, CLASSES_KEY: {class name: code}) and of
# its surface child (SURFACE_KEY).
GRAPH_KEY = "road_graph"
SURFACE_KEY = "road_surface"
CLASSES_KEY = "highway_classes"

# Point attributes of nonterminals: the symbol (0 = terminal street vertex, k = rule k) and
# the similarity frame x -> [[a, -b], [b, a]] x + t of the vertex (paper 3.2), whose origin t
# is the vertex itself, in object-local metres.
SYMBOL = "symbol"
FRAME_A = "frame_a"
FRAME_B = "frame_b"
# Where rules place nonterminals with different frames at one place (the corner two
# Sierpinski triangles share), the vertex carries each further rewrite in a slot k = 2, 3, ...
# of its own: the point attributes symbol_k, frame_a_k, frame_b_k (symbol_k = 0: slot empty).
MORE_REWRITE_PREFIXES = (SYMBOL + "_", FRAME_A + "_", FRAME_B + "_")


def more_rewrite_names(slot):
    """(symbol, frame_a, frame_b) attribute names of slot ``slot`` (2, 3, ...)."""
    return tuple("{}{}".format(prefix, slot) for prefix in MORE_REWRITE_PREFIXES)


def is_more_rewrite_name(name):
    """Whether ``name`` is an attribute of a slot of further rewrites."""
    return any(name.startswith(prefix) and name[len(prefix):].isdigit() for prefix in MORE_REWRITE_PREFIXES)
# Surface segment attribute: the graph edge the segment belongs to.
SURFACE_EDGE = "graph_edge"
# Edge attribute (text) of the graph mesh: the road's name, when some road has one.
NAME = "name"

# Children that draw for a road graph: its pattern colours, its learned grammar's levels.
PATTERNS_KEY = "road_patterns"
RULES_KEY = "road_rules"

# The city of a road graph: on its collection, the name of the road graph; on each of its
# objects, which part it is (ground, roads, blocks, yards, buildings, sun, view).
CITY_KEY = "road_city"
CITY_PART_KEY = "road_city_part"

# Custom property of a grammar Text: the file it was loaded from.
SOURCE_KEY = "road_grammar_source"
# Custom property of a Text made by Learn: the name of the road graph it was learned from.
LEARNED_FROM_KEY = "road_grammar_learned_from"
# Which grammar a nonterminal placed by Place Rule comes from: the point attribute
# RULE_GRAMMAR of the graph mesh is k > 0 for the grammar Text named
# object[RULE_GRAMMARS_KEY][k - 1], 0 for a vertex without a note (a street vertex, or a
# nonterminal of an axiom, a derivation or an imported file: the grammar of its object).
RULE_GRAMMAR = "rule_grammar"
RULE_GRAMMARS_KEY = "rule_grammars"

_SOURCE_SUFFIXES = (".osm.pbf", ".osm.bz2", ".osm.gz", ".osm", ".pbf", ".bz2", ".gz",
                    ".geojson", ".json", ".ggraph")


def basename(path):
    """The file name of ``path``; a Blender-relative path's "//" prefix is skipped."""
    return os.path.basename(path[2:] if path[:2] == "//" else path)


def object_name(path):
    """'paris_marais' for '/data/paris_marais.osm.pbf'."""
    name = basename(path)
    lower = name.lower()
    for suffix in _SOURCE_SUFFIXES:
        if lower.endswith(suffix) and len(name) > len(suffix):
            return name[: -len(suffix)]
    return name
