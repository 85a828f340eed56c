"""Colours: the road surface's per importance rank, and the colour slots shared by the
pattern colours (isogroups, Find Similar) and the learned rules' display.

A colour slot is an int: 0 = no colour, 1..PALETTE_SIZE = the palette's colours (the
isogroups of the overview, best first; rule k of a grammar has slot (k - 1) mod
PALETTE_SIZE + 1), MATCH_SLOT = an occurrence found by Find Similar, SEED_SLOT = the seed.
"""

# Colours (sRGB) of the isogroups in the overview, best first: saturated and of medium to
# high lightness, so that they stand out on the dark viewport grid, on a dark ground in
# renders and against the grey road surfaces (after Kelly's and Trubetskoy's palettes).
PALETTE = (
    "e6194b",  # red
    "3cb44b",  # green
    "ffe119",  # yellow
    "4f8dff",  # blue
    "f58231",  # orange
    "b05cff",  # violet
    "42d4f4",  # cyan
    "f032e6",  # magenta
    "bfef45",  # lime
    "ff8fb1",  # pink
    "1fc9a4",  # teal
    "c8a2ff",  # lavender
)
PALETTE_SIZE = len(PALETTE)
MATCH_SLOT = PALETTE_SIZE + 1  # occurrences of a Find Similar seed
SEED_SLOT = PALETTE_SIZE + 2   # the seed itself
# Match: sky blue; seed: magenta. Both differ from Edit Mode's orange selection, from each
# other (also for red-green colour blindness) and from the grey roads.
SLOT_COLORS = PALETTE + ("38b6ff", "ff3dcc")
SLOT_NAMES = tuple(str(k) for k in range(1, PALETTE_SIZE + 1)) + ("Match", "Seed")
NO_COLOR = (0.35, 0.35, 0.35)

# The learned rules' display: streets outside every instance, and markers of the rules other
# than the chosen one, are neutral grey.
NEUTRAL_SLOT = 0
DIMMED_SLOT = PALETTE_SIZE + 1

# Surface colour per importance rank 1, 2, ... (linear RGB), after the usual map styles:
# motorway red, trunk orange, primary amber, secondary yellow, minor roads light grey,
# paths tan. The ranks themselves come from the native library (ggg.highway_ranks());
# ranks past the end of this table take its last colour.
RANK_COLORS = (
    (0.80, 0.22, 0.20),  # 1 motorway
    (0.90, 0.40, 0.16),  # 2 trunk, motorway links
    (0.95, 0.60, 0.18),  # 3 primary, trunk links
    (0.95, 0.82, 0.30),  # 4 secondary, primary links
    (0.92, 0.90, 0.62),  # 5 tertiary, secondary links
    (0.80, 0.80, 0.78),  # 6 unclassified, tertiary links
    (0.70, 0.70, 0.70),  # 7 residential, road
    (0.62, 0.66, 0.70),  # 8 living street
    (0.50, 0.50, 0.52),  # 9 service, busway
    (0.55, 0.47, 0.38),  # 10 pedestrian, track
    (0.45, 0.36, 0.30),  # 11 footway, cycleway, path, steps
    (0.40, 0.40, 0.40),  # 12 other
)


def srgb(hex_color):
    """(r, g, b) in [0, 1] of a hex colour 'e6194b'."""
    return tuple(int(hex_color[i:i + 2], 16) / 255.0 for i in (0, 2, 4))


def to_linear(c):
    """An sRGB component in linear light."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def slot_color_srgb(slot):
    """The display (sRGB) colour of a colour slot; grey for 0 (no colour)."""
    if 1 <= slot <= len(SLOT_COLORS):
        return srgb(SLOT_COLORS[slot - 1])
    return NO_COLOR


def slot_color_linear(slot):
    return tuple(to_linear(c) for c in slot_color_srgb(slot))


def rule_slot(index):
    """Colour slot of the rule at ``index`` (from 0) in the grammar's rules."""
    return index % PALETTE_SIZE + 1


def rule_color_srgb(slot):
    """The display colour of a slot of the learned rules' display (neutral and dimmed: grey)."""
    return NO_COLOR if slot in (NEUTRAL_SLOT, DIMMED_SLOT) else slot_color_srgb(slot)


def rank_color(rank):
    return RANK_COLORS[min(max(int(rank), 1), len(RANK_COLORS)) - 1]
