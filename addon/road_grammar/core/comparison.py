"""How alike two road graphs are, as ggg.compare says it (``ggg compare``, docs/cli.md): the
rows of the Compare panel and the one-line report, from the dict ggg.compare returns.

The dict has ``distances`` (each 0 for the same distribution, at most 1) and a summary of
each network under ``a`` and ``b``. DISTANCES and MEASURES give the order in which they are
shown, a label and what each means to a planner (the words of docs/cli.md's table); the
numbers always come from the dict. A member the tables do not know yet is shown after the
others under its own name, so nothing the library reports is left out."""

import json
import math

# (key in "distances", label, short words of the report line or None, meaning).
DISTANCES = (
    ("degree", "Degree", "degree",
     "do streets meet in crossings, T-junctions or dead ends in the same proportions"),
    ("edge_length", "Edge length", "edge length",
     "are the stretches between junctions as long: the grain of the network"),
    ("orientation", "Orientation", "orientation",
     "is it as much of a grid, or as organic"),
    ("block_area", "Block area", "block area",
     "are the blocks as large: what can be built on them"),
    ("mean", "Mean", None,
     'one number for "how alike"'),
    ("junction_angle", "Junction angles", None,
     "do streets meet at the same angles"),
)

# The distances whose mean is "mean" (docs/cli.md: "the mean of the four above").
MEAN_OF = ("degree", "edge_length", "orientation", "block_area")

# (key in "a" and "b", label, kind of number, short words of the report line or None,
# meaning). Kinds: "share" (a fraction shown as a percentage), "ratio", "number", "metres",
# "area" (m²), "count".
MEASURES = (
    ("dead_end_share", "Dead ends", "share", "dead ends",
     "cul-de-sacs, or streets left unfinished"),
    ("degree2_share", "Degree-2 vertices", "share", "degree 2",
     "where a street bends or changes class, not a junction; many of them in grown streets are fragments"),
    ("star_share", "Star junctions (5+)", "share", "star junctions",
     "rare in real cities (squares, roundabouts drawn as one point); hard to drive through"),
    ("crossing_share", "Crossings (4 streets)", "share", "crossings",
     "how much of a grid the streets form: most junctions of a grid are crossings, a network grown street by street into T-junctions has few"),
    ("right_angle_share", "Right angles (90\u00b0 \u00b1 15\u00b0)", "share", "right angles",
     "how regular the crossings are"),
    ("through_share", "Through streets", "share", "through streets",
     "streets that run on through junctions, rather than ending at each one"),
    ("circuity", "Circuity", "ratio", "circuity",
     "how far one drives compared with the crow's flight: about 1.2 in the cities of ../shared/osm, more for "
     "winding or broken networks"),
    ("orientation_order", "Orientation order", "number", None,
     "Boeing's orientation order, 1 for a perfect grid, 0 for bearings spread evenly"),
    ("orientation_entropy", "Orientation entropy", "number", None,
     "entropy of the orientation histogram, in nats: log 4 = 1.386 for a perfect grid, at most log 36 = 3.584"),
    ("median_edge_length_m", "Median edge length", "metres", None,
     "median edge length, metres"),
    ("median_block_area_m2", "Median block area", "area", None,
     "number of blocks and their median area, m\u00b2"),
    ("vertices", "Vertices", "count", None,
     "size of the network"),
    ("edges", "Edges", "count", None,
     "size of the network"),
    ("blocks", "Blocks", "count", None,
     "number of blocks and their median area, m\u00b2"),
    ("junctions", "Junctions (3+ streets)", "count", None,
     "vertices where three streets or more meet"),
    ("mean_degree", "Mean degree", "number", None,
     "mean vertex degree"),
)

DISTANCE_KEYS = tuple(row[0] for row in DISTANCES)
MEASURE_KEYS = tuple(row[0] for row in MEASURES)

_DISTANCE = {key: (label, short, meaning) for key, label, short, meaning in DISTANCES}
_MEASURE = {key: (label, kind, short, meaning) for key, label, kind, short, meaning in MEASURES}

NOTHING = "\u2013"  # a value the library has not (circuity without a pair of vertices)


def _label_of(key):
    """'new_measure' -> 'New measure' (a member the tables do not know)."""
    return key.replace("_", " ").capitalize()


def _ordered(keys, known):
    """``keys`` in the order of ``known``, then those ``known`` lacks, sorted."""
    keys = list(keys)
    return [key for key in known if key in keys] + sorted(key for key in keys if key not in known)


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def value_text(value, kind="number"):
    """A value of a network's summary as the panel shows it: a share as a percentage
    ('15.8%'), metres ('80.7 m'), an area ('8,020 m²'), a count ('1,248'), other numbers
    with two decimals ('1.31'); NOTHING for a missing value (None)."""
    if not _is_number(value):
        return NOTHING
    if kind == "share":
        return "{:.1f}%".format(100.0 * value)
    if kind == "metres":
        return "{:,.1f} m".format(value)
    if kind == "area":
        return "{:,.0f} m\u00b2".format(value)
    if kind == "count":
        return "{:,}".format(int(value)) if float(value).is_integer() else "{:,.2f}".format(value)
    return "{:.2f}".format(value)


def distance_text(value, digits=3):
    """A distance ('0.212'); NOTHING for a missing one."""
    return "{:.{}f}".format(value, digits) if _is_number(value) else NOTHING


def measure_rows(result):
    """(key, label, text of A, text of B, meaning) of each member of the networks'
    summaries in ``result`` (a ggg.compare dict)."""
    a, b = result.get("a", {}), result.get("b", {})
    rows = []
    for key in _ordered(set(a) | set(b), MEASURE_KEYS):
        label, kind, _short, meaning = _MEASURE.get(key, (_label_of(key), "number", None, ""))
        rows.append((key, label, value_text(a.get(key), kind), value_text(b.get(key), kind), meaning))
    return rows


def distance_rows(result):
    """(key, label, text, meaning) of each distance in ``result`` (a ggg.compare dict)."""
    distances = result.get("distances", {})
    rows = []
    for key in _ordered(distances, DISTANCE_KEYS):
        label, _short, meaning = _DISTANCE.get(key, (_label_of(key), None, ""))
        rows.append((key, label, distance_text(distances[key]), meaning))
    return rows


def summary(name_a, name_b, result):
    """The report line of a comparison, e.g. 'Compared A with B: mean distance 0.21 (degree
    0.05, edge length 0.10, orientation 0.08, block area 0.30); junction angles 0.07; dead
    ends 15.8% / 10.0%, ...; circuity 1.31 / 1.37' (A's value, then B's)."""
    distances = result.get("distances", {})
    parts = ["{} {}".format(_DISTANCE[key][1], distance_text(distances.get(key), 2))
             for key in MEAN_OF if key in distances]
    line = "Compared {} with {}: mean distance {}".format(name_a, name_b, distance_text(distances.get("mean"), 2))
    if parts:
        line += " ({})".format(", ".join(parts))
    if "junction_angle" in distances:
        line += "; junction angles {}".format(distance_text(distances["junction_angle"], 2))
    a, b = result.get("a", {}), result.get("b", {})
    shares = []
    others = []
    for key, _label, kind, short, _meaning in MEASURES:
        if short is None or (key not in a and key not in b):
            continue
        text = "{} {} / {}".format(short, value_text(a.get(key), kind), value_text(b.get(key), kind))
        (shares if kind == "share" else others).append(text)
    for group in (shares, others):
        if group:
            line += "; " + ", ".join(group)
    return line


def stored_text(result):
    """``result`` (a ggg.compare dict) as the JSON kept in the .blend."""
    return json.dumps(result, sort_keys=True)


def read_stored(text):
    """The ggg.compare dict kept as ``text`` (stored_text), or None when there is none or it
    is not one."""
    if not text:
        return None
    try:
        result = json.loads(text)
    except ValueError:
        return None
    if not isinstance(result, dict) or not all(isinstance(result.get(key), dict) for key in ("a", "b", "distances")):
        return None
    return result
