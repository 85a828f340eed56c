#!/usr/bin/env python3
"""Write a small synthetic OpenStreetMap town ("Borgo Finzio") as OSM XML 0.6.

The town is fictional: every coordinate, name and tag below is generated here, none
comes from OpenStreetMap.  It sits at about lat 46.0, lon 8.95 only so that the
coordinates look plausible; the bounds are a 1.5 km x 1.5 km square around that point.

Layout, in a local metric frame (x east, y north, origin at LAT0/LON0):
  * west:   a regular grid district, 8 x 8 blocks of 100 m x 80 m, residential streets
            (some named, some one-way, some with lanes=* or width=*), one primary avenue
            (a column) and one secondary avenue (a row), two missing street segments,
            driveways, service alleys, footpaths, a parking loop, a park with footways;
  * east:   an irregular old town: a small roundabout at its centre, curved radial
            streets, three wobbly rings of arcs (pedestrian, living_street, residential),
            alleys (living_street / pedestrian / footway / steps) and dead ends, all
            inside an irregular tertiary ring road;
  * around: three roads between the districts; an industrial road with service roads;
            a motorway (two one-way carriageways) with a four-ramp interchange whose
            access road crosses it on a bridge; a curving street with courts south of
            the grid; a small quarter by old kilns; a suburban loop with cul-de-sacs
            north of the old town; a hillside road to a hamlet; tracks; roads that end
            at the edge of the map;
  * other:  buildings, a park, a parking area and a stream (not highways: an importer
            must ignore them), tagged nodes (traffic signals, turning circles, noexit)
            and a fountain that belongs to no way.

Every street meets every other street at a shared node; the only highway crossing
without one is the bridge (bridge=yes, layer=1) over the motorway.  The script checks
this (and the other invariants) before writing.  Standard library only; the output
depends on --seed alone and is byte-identical for the same seed.

usage: python3 samples/make_sample_city.py [-o samples/sample_city.osm] [--seed N]
"""

import argparse
import math
import os
import random
import sys
from xml.sax.saxutils import escape

LAT0 = 46.0
LON0 = 8.95
HALF_EXTENT_M = 750.0          # the bounds: a square of 2 x 750 m around (LAT0, LON0)
EDGE = 745.0                   # roads that leave the map end this far from the centre
EARTH_RADIUS_M = 6371008.8
M_PER_DEG_LAT = EARTH_RADIUS_M * math.pi / 180.0
M_PER_DEG_LON = M_PER_DEG_LAT * math.cos(math.radians(LAT0))
DEFAULT_SEED = 1
GENERATOR = "make_sample_city.py"

# Grid district: columns x = GX0 + i*GDX (i = 0..GN), rows y = GY0 + j*GDY (j = 0..GN).
GX0, GDX = -730.0, 100.0
GY0, GDY = -360.0, 80.0
GN = 8
AVENUE_COL, AVENUE_ROW = 4, 4

# Old town: centre, roundabout radius, mean ring-road radius, mean radii of the arc rings.
OT_CX, OT_CY = 400.0, -40.0
RB_R, RING_R = 18.0, 255.0
ARC_RADII = (65.0, 120.0, 175.0)
# Radials, counter-clockwise from the west one (which continues the grid's avenue).
RADIAL_BASE_DEG = [180.0, 225.0, 268.0, 310.0, 350.0, 395.0, 440.0, 485.0]
RADIAL_SOUTH, RADIAL_EAST, RADIAL_NORTH = 2, 4, 6   # these continue beyond the ring road
CONNECTOR_SECTORS = (7, 0)                         # the grid's other two roads arrive here

# Motorway: straight (y = MW_Y) within MW_STRAIGHT of the interchange at x = MW_X0,
# curving south beyond; carriageways MW_HALF_SEP either side of the centre line.
MW_X0, MW_Y, MW_STRAIGHT, MW_CURVE, MW_HALF_SEP = -330.0, -587.0, 320.0, 7e-5, 10.0
RAMP_DX, RAMP_RISE = 250.0, 35.0
INDUSTRIAL_Y = -480.0
# Suburban estate: a loop road (an ellipse) north of the old town.
EST_X, EST_Y, EST_RX, EST_RY = 420.0, 445.0, 230.0, 95.0

STREET_NAMES = [
    "Via dei Tigli", "Via dei Platani", "Via dei Castagni", "Via degli Ulivi",
    "Via dei Faggi", "Via delle Betulle", "Via degli Aceri", "Via degli Olmi",
    "Via dei Noci", "Via dei Ciliegi", "Via dei Larici", "Via dei Pini",
    "Via dei Salici", "Via delle Querce", "Via dei Frassini", "Via degli Abeti",
    "Via delle Rose", "Via dei Gigli", "Via delle Viole", "Via dei Tulipani",
]
OLD_TOWN_NAMES = [
    "Contrada del Forno", "Contrada dei Mercanti", "Contrada Sant'Anna",
    "Contrada della Torre", "Contrada dei Tessitori", "Via di Mezzo", "Via del Pozzo",
    "Via Città Vecchia", "Via delle Mura", "Via del Duomo",
]
ALLEY_NAMES = [
    "Vicolo del Gatto", "Vicolo Stretto", "Vicolo dei Fabbri", "Vicolo della Luna",
    "Vicolo del Sole", "Passaggio Nascosto", "Vicolo dell'Orto", "Vicolo delle Rondini",
    "Vicolo del Pane", "Vicolo dei Sarti", "Vicolo del Vino", "Vicolo Storto",
]
DEAD_END_NAMES = ["Vicolo Cieco", "Corte dei Miracoli", "Corte del Pozzo", "Corte Nascosta",
                  "Corte dei Tigli", "Corte Rossa"]
ESTATE_NAMES = [
    "Via dei Ginepri", "Via delle Ginestre", "Via dei Gelsomini", "Via delle Camelie",
    "Via delle Azalee", "Via dei Lillà", "Via delle Magnolie", "Via delle Glicini",
    "Via dei Mughetti", "Via delle Ortensie", "Via dei Girasoli",
]


def to_latlon(x, y):
    return LAT0 + y / M_PER_DEG_LAT, LON0 + x / M_PER_DEG_LON


def polar(r, a_deg):
    a = math.radians(a_deg)
    return OT_CX + r * math.cos(a), OT_CY + r * math.sin(a)


def bezier(p0, p1, p2, p3, t):
    u = 1.0 - t
    return (u * u * u * p0[0] + 3 * u * u * t * p1[0] + 3 * u * t * t * p2[0] + t * t * t * p3[0],
            u * u * u * p0[1] + 3 * u * u * t * p1[1] + 3 * u * t * t * p2[1] + t * t * t * p3[1])


def resample(curve, step_m, samples=400):
    """Interior points of the parametric curve (t in [0, 1]) about step_m apart."""
    pts = [curve(i / samples) for i in range(samples + 1)]
    cum = [0.0]
    for a, b in zip(pts, pts[1:]):
        cum.append(cum[-1] + math.dist(a, b))
    total = cum[-1]
    n = max(1, round(total / step_m))
    out, k = [], 0
    for s in range(1, n):
        target = total * s / n
        while cum[k + 1] < target:
            k += 1
        f = (target - cum[k]) / (cum[k + 1] - cum[k])
        out.append((pts[k][0] + f * (pts[k + 1][0] - pts[k][0]),
                    pts[k][1] + f * (pts[k + 1][1] - pts[k][1])))
    return out


class NamePool:
    """Names in a seeded order; numbered ("... II") once the list is used up."""

    def __init__(self, rng, names):
        self._names = rng.sample(names, len(names))
        self._n = 0

    def pop(self):
        name = self._names[self._n % len(self._names)]
        rounds = self._n // len(self._names)
        self._n += 1
        return name if rounds == 0 else f"{name} {'I' * (rounds + 1)}"


class Osm:
    """Nodes and ways in the local frame; ids positive, unique, sparse, in creation order."""

    def __init__(self, seed):
        self._id_rng = random.Random(f"{seed}:ids")
        self.nodes = {}            # id -> [x, y, tags]
        self.ways = {}             # id -> (refs, tags)
        self._next_node = 1000
        self._next_way = 50000

    def _bump(self, n):
        # Real extracts have gaps in their ids; so does this one.
        return n + 1 + (self._id_rng.randint(1, 9) if self._id_rng.random() < 0.1 else 0)

    def node(self, x, y, **tags):
        if not (-HALF_EXTENT_M < x < HALF_EXTENT_M and -HALF_EXTENT_M < y < HALF_EXTENT_M):
            raise ValueError(f"node ({x:.1f}, {y:.1f}) outside the bounds")
        nid = self._next_node
        self._next_node = self._bump(nid)
        self.nodes[nid] = [x, y, dict(tags)]
        return nid

    def nodes_along(self, points):
        return [self.node(x, y) for x, y in points]

    def way(self, refs, **tags):
        refs = list(refs)
        if len(refs) < 2 or any(a == b for a, b in zip(refs, refs[1:])):
            raise ValueError(f"bad node list for way {tags}: {refs}")
        wid = self._next_way
        self._next_way = self._bump(wid)
        self.ways[wid] = (refs, {k: str(v) for k, v in tags.items()})
        return wid

    def xy(self, nid):
        return self.nodes[nid][0], self.nodes[nid][1]


# --------------------------------------------------------------------------- grid district

def build_grid(osm, rng):
    gx = lambda i: GX0 + i * GDX
    gy = lambda j: GY0 + j * GDY
    g = {(i, j): osm.node(gx(i), gy(j)) for j in range(GN + 1) for i in range(GN + 1)}
    osm.nodes[g[AVENUE_COL, AVENUE_ROW]][2]["highway"] = "traffic_signals"
    osm.nodes[g[AVENUE_COL, 2]][2]["highway"] = "traffic_signals"

    # Segments: ("v", i, j) on column i from row j to j+1; ("h", i, j) on row j from column i to i+1.
    def block_sides(bi, bj):
        return {"S": ("h", bi, bj), "N": ("h", bi, bj + 1), "W": ("v", bi, bj), "E": ("v", bi + 1, bj)}

    # Two interior segments (not on an avenue, sharing no node) are missing: T-junctions.
    removed = []
    candidates = ([("v", i, j) for i in range(1, GN) if i != AVENUE_COL for j in range(1, GN - 1)] +
                  [("h", i, j) for j in range(1, GN) if j != AVENUE_ROW for i in range(1, GN - 1)])
    while len(removed) < 2:
        s = rng.choice(candidates)
        ends = lambda seg: ({(seg[1], seg[2]), (seg[1], seg[2] + 1)} if seg[0] == "v"
                            else {(seg[1], seg[2]), (seg[1] + 1, seg[2])})
        if all(not (ends(s) & ends(r)) for r in removed):
            removed.append(s)

    blocks = [(bi, bj) for bj in range(GN) for bi in range(GN)]
    used_blocks, used_segs = set(), set(removed)
    quiet = [b for b in blocks if b[0] not in (AVENUE_COL - 1, AVENUE_COL)
             and b[1] not in (AVENUE_ROW - 1, AVENUE_ROW)
             and not (set(block_sides(*b).values()) & used_segs)]

    def take(pool):
        b = rng.choice([b for b in pool if b not in used_blocks])
        used_blocks.add(b)
        return b

    extra = {}  # ("v", i) / ("h", j) -> [(param, node id)]: junction nodes between grid nodes

    def side_node(seg, frac):
        kind, i, j = seg
        if kind == "v":
            nid = osm.node(gx(i), gy(j) + frac * GDY)
            extra.setdefault(("v", i), []).append((j + frac, nid))
        else:
            nid = osm.node(gx(i) + frac * GDX, gy(j))
            extra.setdefault(("h", j), []).append((i + frac, nid))
        used_segs.add(seg)
        return nid

    # A park crossed by two diagonal footways meeting at its centre.
    pb = take(quiet)
    centre = osm.node(gx(pb[0]) + GDX / 2, gy(pb[1]) + GDY / 2)
    osm.way([g[pb], centre, g[pb[0] + 1, pb[1] + 1]], highway="footway")
    osm.way([g[pb[0] + 1, pb[1]], centre, g[pb[0], pb[1] + 1]], highway="footway", surface="gravel")
    inset = [(gx(pb[0]) + 6, gy(pb[1]) + 6), (gx(pb[0] + 1) - 6, gy(pb[1]) + 6),
             (gx(pb[0] + 1) - 6, gy(pb[1] + 1) - 6), (gx(pb[0]) + 6, gy(pb[1] + 1) - 6)]
    ring = osm.nodes_along(inset)
    osm.way(ring + ring[:1], leisure="park", name="Parco dei Giochi")

    # A parking lot: a one-way loop of parking aisles reached by a driveway from the south.
    kb = take([b for b in quiet if b != pb])
    x0, y0 = gx(kb[0]), gy(kb[1])
    entry = side_node(block_sides(*kb)["S"], 0.5)
    loop = osm.nodes_along([(x0 + 50, y0 + 15), (x0 + 80, y0 + 15), (x0 + 80, y0 + 55),
                            (x0 + 20, y0 + 55), (x0 + 20, y0 + 15)])
    osm.way([entry, loop[0]], highway="service", service="driveway")
    osm.way(loop + loop[:1], highway="service", service="parking_aisle", oneway="yes")
    lot = osm.nodes_along([(x0 + 10, y0 + 8), (x0 + 90, y0 + 8), (x0 + 90, y0 + 68), (x0 + 10, y0 + 68)])
    osm.way(lot + lot[:1], amenity="parking", parking="surface")

    # A town hall: a building in a block no street ends in.
    hb = take(blocks)
    x0, y0 = gx(hb[0]), gy(hb[1])
    hall = osm.nodes_along([(x0 + 15, y0 + 15), (x0 + 85, y0 + 15), (x0 + 85, y0 + 65), (x0 + 15, y0 + 65)])
    osm.way(hall + hall[:1], building="civic", name="Municipio")

    # Service alleys through four blocks, from the middle of the south side to the north side.
    for _ in range(4):
        pool = [b for b in blocks if not ({block_sides(*b)["S"], block_sides(*b)["N"]} & used_segs)]
        b = take(pool)
        osm.way([side_node(block_sides(*b)["S"], 0.5), side_node(block_sides(*b)["N"], 0.5)],
                highway="service", service="alley")

    # Footpaths through three blocks, from the middle of the west side to the east side.
    for _ in range(3):
        pool = [b for b in blocks if not ({block_sides(*b)["W"], block_sides(*b)["E"]} & used_segs)]
        b = take(pool)
        osm.way([side_node(block_sides(*b)["W"], 0.5), side_node(block_sides(*b)["E"], 0.5)],
                highway="footway")

    # Driveways: dead ends 30-35 m into a block from a street.
    for _ in range(24):
        b = rng.choice([b for b in blocks if b not in used_blocks])
        side = rng.choice("SNWE")
        seg = block_sides(*b)[side]
        if seg in used_segs:
            continue
        frac = rng.choice([0.3, 0.35, 0.4, 0.6, 0.65, 0.7])
        start = side_node(seg, frac)
        sx, sy = osm.xy(start)
        dx, dy = {"S": (0, 30), "N": (0, -30), "W": (35, 0), "E": (-35, 0)}[side]
        osm.way([start, osm.node(sx + dx, sy + dy)], highway="service", service="driveway")
        used_blocks.add(b)  # one driveway per block: two could cross

    # Streets: every column and row, cut where a segment is missing, split into ways of
    # 1-3 blocks (so most intersections fall in the middle of a way).  Nodes only at
    # intersections and where a driveway, alley or footpath joins: the streets are straight.
    names = rng.sample(STREET_NAMES, 2 * (GN + 1))
    plain = [("v", i) for i in range(1, GN) if i != AVENUE_COL] + \
            [("h", j) for j in range(1, GN) if j != AVENUE_ROW]
    oneways = rng.sample(plain, 4)
    for line in [("v", i) for i in range(GN + 1)] + [("h", j) for j in range(GN + 1)]:
        kind, k = line
        pts = [(float(m), g[(k, m) if kind == "v" else (m, k)]) for m in range(GN + 1)]
        pts = sorted(pts + extra.get(line, []))
        runs, cur = [], [pts[0]]
        for a, b in zip(pts, pts[1:]):
            seg = (kind, k, math.floor(a[0])) if kind == "v" else (kind, math.floor(a[0]), k)
            if seg in removed:
                runs.append(cur)
                cur = []
            cur.append(b)
        runs.append(cur)

        if line == ("v", AVENUE_COL):
            base = dict(highway="primary", name="Viale della Stazione", lanes="4", maxspeed="50")
        elif line == ("h", AVENUE_ROW):
            base = dict(highway="secondary", name="Corso Centrale", lanes="2", maxspeed="50")
        else:
            base = dict(highway="residential")
            if rng.random() < 0.85:
                base["name"] = names[k if kind == "v" else GN + 1 + k]
        direction = 1
        if line in oneways:
            style = oneways.index(line)
            if style == 0:
                base["oneway"] = "-1"          # tagged against the node order
            else:
                base["oneway"] = "yes"
                direction = 1 if style % 2 else -1
        for run in runs:
            if len(run) < 2:
                continue
            grid_idx = [n for n, (p, _) in enumerate(run) if p == int(p)]
            cuts, pos = [0], 0
            while pos < len(grid_idx) - 1:
                pos = min(pos + rng.randint(1, 3), len(grid_idx) - 1)
                cuts.append(grid_idx[pos])
            cuts[-1] = len(run) - 1
            for a, b in zip(cuts, cuts[1:]):
                refs = [nid for _, nid in run[a:b + 1]][::direction]
                tags = dict(base)
                if tags["highway"] == "residential" and rng.random() < 0.3:
                    tags["lanes"] = "1" if "oneway" in tags else "2"
                if rng.random() < 0.3:
                    tags["width"] = (rng.choice(["12", "13.5", "14"]) if tags["highway"] == "primary"
                                     else rng.choice(["5", "5.5", "6", "6.5", "7", "7.5", "8"]))
                osm.way(refs, **tags)
    return g


# --------------------------------------------------------------------------- old town

def build_old_town(osm, rng, grid):
    nrad = len(RADIAL_BASE_DEG)
    base = [RADIAL_BASE_DEG[0]] + [a + rng.uniform(-5, 5) for a in RADIAL_BASE_DEG[1:]]
    bend = [0.0] + [rng.uniform(-9, 9) for _ in RADIAL_BASE_DEG[1:]]

    # Closed curves around the centre, r = rho(m, angle): three rings of arcs and the ring road.
    nring = len(ARC_RADII) + 1
    ROAD = nring - 1
    wobble = []
    for m in range(nring):
        amp = 1.0 if m < ROAD else 3.5
        wobble.append([(n, amp * rng.uniform(1.5, 3.0) * (4 - n), rng.uniform(0, 2 * math.pi))
                       for n in (2, 3)])
    means = list(ARC_RADII) + [RING_R]

    def rho(m, a_deg):
        a = math.radians(a_deg)
        return means[m] + sum(amp * math.sin(n * a + ph) for n, amp, ph in wobble[m])

    def rad_angle(k, r):  # radial k is the curve r -> polar(r, rad_angle(k, r)); k may be nrad
        return (base[k % nrad] + bend[k % nrad] * ((r - RB_R) / (RING_R - RB_R)) ** 2
                + (360.0 if k >= nrad else 0.0))

    hit = [[0.0] * nring for _ in range(nrad + 1)]   # radius where radial k crosses curve m
    for k in range(nrad + 1):
        for m in range(nring):
            r = means[m]
            for _ in range(60):
                r = rho(m, rad_angle(k, r))
            hit[k][m] = r

    def sector_angle(m, k, f):  # angle at fraction f of sector k (radial k to k+1) on curve m
        lo, hi = rad_angle(k, hit[k][m]), rad_angle(k + 1, hit[k + 1][m])
        return lo + f * (hi - lo)

    def norm(a):
        return (a - 180.0) % 360.0 + 180.0

    cross = {}                                # (radial, curve) -> node id
    req = {m: {} for m in range(nring)}       # curve -> sector -> {angle: node id}

    def curve_node(m, k, a):  # the node of curve m at angle a in sector k, shared if it exists
        nodes = req[m].setdefault(k, {})
        if a not in nodes:
            nodes[a] = osm.node(*polar(rho(m, a), a))
        return nodes[a]

    # Which sectors each ring of arcs covers (never all of them: no arc ring is closed).
    present = [set(rng.sample(range(nrad), n)) for n in (5, 6, 7)]

    # Radials: from the roundabout to the ring road, crossing the arc rings; shape nodes
    # every ~25 m where they bend, none on the straight one.
    rb_start = {k: osm.node(*polar(RB_R, base[k])) for k in range(nrad)}
    radial_refs = []
    for k in range(nrad):
        stops = [hit[k][m] for m in range(ROAD)]
        shape = [] if bend[k] == 0 else [float(r) for r in range(40, int(hit[k][ROAD]) - 10, 25)
                                          if all(abs(r - s) > 8 for s in stops)]
        refs = [rb_start[k]]
        for r in sorted(shape + stops):
            nid = osm.node(*polar(r, rad_angle(k, r)))
            if r in stops:
                cross[k, stops.index(r)] = nid
            refs.append(nid)
        end = osm.node(*polar(hit[k][ROAD], rad_angle(k, hit[k][ROAD])))
        cross[k, ROAD] = end
        refs.append(end)
        radial_refs.append(refs)
    for m in range(nring):
        cross[nrad, m] = cross[0, m]

    names = NamePool(rng, OLD_TOWN_NAMES)
    alley_names = NamePool(rng, ALLEY_NAMES)
    dead_names = NamePool(rng, DEAD_END_NAMES)
    for k, refs in enumerate(radial_refs):
        split = refs.index(cross[k, 1])
        if k == 0:
            inner = outer = dict(highway="secondary", name="Corso Centrale", lanes="2")
        else:
            tags = dict(highway="tertiary" if k in (RADIAL_SOUTH, RADIAL_EAST) else "residential",
                        name=names.pop())
            inner, outer = dict(tags), dict(tags)
            if k == 1:
                inner["highway"] = "living_street"
            elif k == 3:
                inner["highway"] = "pedestrian"
            elif k == 5:
                inner["oneway"] = "yes"
            if rng.random() < 0.4:
                outer["width"] = rng.choice(["5", "6", "6.5"])
        osm.way(refs[:split + 1], **inner)
        osm.way(refs[split:], **outer)

    # Roundabout: closed, counter-clockwise (right-hand traffic), a fountain in the middle.
    rb = [(norm(base[k]), rb_start[k]) for k in range(nrad)]
    for a in range(180, 540, 30):
        if all(abs(a - b) > 10 for b, _ in rb):
            rb.append((float(a), osm.node(*polar(RB_R, a))))
    rb_refs = [nid for _, nid in sorted(rb)]
    osm.way(rb_refs + rb_refs[:1], highway="tertiary", junction="roundabout")
    osm.node(OT_CX, OT_CY, amenity="fountain", name="Fontana Vecchia")  # in no way

    # Between consecutive arc rings: alleys (some with a dog-leg) where both rings pass,
    # a dead end where only the inner one does.
    for m in range(ROAD - 1):
        for k in range(nrad):
            if k in present[m] and k in present[m + 1]:
                for f in rng.choice([[0.5], [0.5], [0.35, 0.65]]):
                    n1 = curve_node(m, k, sector_angle(m, k, f))
                    n2 = curve_node(m + 1, k, sector_angle(m + 1, k, f))
                    mid = []
                    if rng.random() < 0.5:
                        rm = (hit[k][m] + hit[k][m + 1]) / 2
                        am = (sector_angle(m, k, f) + sector_angle(m + 1, k, f)) / 2 + rng.choice([-2.5, 2.5])
                        mid = [osm.node(*polar(rm, am))]
                    hw = rng.choice(["living_street", "pedestrian", "footway", "footway", "steps"])
                    tags = dict(highway=hw)
                    if hw in ("living_street", "pedestrian"):
                        tags["name"] = alley_names.pop()
                    osm.way([n1] + mid + [n2], **tags)
            elif k in present[m]:
                a = sector_angle(m, k, 0.5)
                r_end = rho(m, a) + 0.6 * (rho(m + 1, a) - rho(m, a))
                end = osm.node(*polar(r_end, a), noexit="yes")
                osm.way([curve_node(m, k, a), end], highway="residential", name=dead_names.pop())

    # Between the outer arc ring and the ring road (not in the sectors the connectors from
    # the grid use): footpaths, and dead ends off the ring road.
    last = ROAD - 1
    for k in range(nrad):
        if k in CONNECTOR_SECTORS:
            continue
        if k in present[last] and rng.random() < 0.6:
            n1 = curve_node(last, k, sector_angle(last, k, 0.5))
            n2 = curve_node(ROAD, k, sector_angle(ROAD, k, 0.5))
            hw = rng.choice(["footway", "steps", "pedestrian"])
            tags = dict(highway=hw)
            if hw == "pedestrian":
                tags["name"] = alley_names.pop()
            osm.way([n1, n2], **tags)
        if rng.random() < 0.5:
            a = sector_angle(ROAD, k, 0.22)
            end = osm.node(*polar(rho(last, a) + 20, a), noexit="yes")
            osm.way([curve_node(ROAD, k, a), end], highway="residential", name=dead_names.pop())

    # Connections to the grid.  The avenue: straight from the grid's east edge to the
    # west radial, no shape nodes; two more roads curve into the ring road.
    osm.way([grid[GN, AVENUE_ROW], cross[0, ROAD]], highway="secondary",
            name="Corso Centrale", lanes="2", maxspeed="50")
    for (row, tags), k in zip(((6, dict(highway="tertiary", name="Via Nuova")),
                               (2, dict(highway="unclassified", name="Via Vecchia"))),
                              CONNECTOR_SECTORS):
        a = sector_angle(ROAD, k, 0.5)
        q = curve_node(ROAD, k, a)
        p0, p3 = osm.xy(grid[GN, row]), osm.xy(q)
        out = (math.cos(math.radians(a)), math.sin(math.radians(a)))
        p1 = (p0[0] + 50, p0[1])
        p2 = (p3[0] + 50 * out[0], p3[1] + 50 * out[1])
        mid = osm.nodes_along(resample(lambda t: bezier(p0, p1, p2, p3, t), 12.0))
        osm.way([grid[GN, row]] + mid + [q], **tags)

    # The curves themselves: nodes at the crossings, the junctions and every few degrees.
    # Arc rings: runs of consecutive sectors are single ways through the radials.
    def curve_refs(m, ks, step):
        refs = [cross[ks[0], m]]
        for k in ks:
            lo, hi = rad_angle(k, hit[k][m]), rad_angle(k + 1, hit[k + 1][m])
            fixed = sorted(req[m].get(k, {}).items())
            n = math.ceil((hi - lo) / step)
            shape = [lo + s * (hi - lo) / n for s in range(1, n)]
            pts = fixed + [(a, None) for a in shape if all(abs(a - b) > step / 3 for b, _ in fixed)]
            for a, nid in sorted(pts, key=lambda t: t[0]):
                refs.append(nid if nid is not None else osm.node(*polar(rho(m, a), a)))
            refs.append(cross[k + 1, m])
        return refs

    for m in range(ROAD):
        start = next(k for k in range(nrad) if k in present[m] and (k - 1) % nrad not in present[m])
        chains, cur = [], []
        for step in range(nrad):
            k = (start + step) % nrad
            if k in present[m]:
                cur.append(k)
            elif cur:
                chains.append(cur)
                cur = []
        if cur:
            chains.append(cur)
        for c, chain in enumerate(chains):
            tags = dict(name=names.pop())
            if m == 0:
                tags["highway"] = "pedestrian" if c == 0 else "living_street"
            elif m == 1:
                tags["highway"] = "residential" if c == 0 else "living_street"
            else:
                tags["highway"] = "residential"
                if c == 0 and len(chain) >= 2:
                    tags["oneway"] = "yes"
            osm.way(curve_refs(m, chain, 6.0 if m == 0 else 4.0), **tags)

    # The ring road: closed, split into four ways at every other radial.
    refs = curve_refs(ROAD, list(range(nrad)), 3.0)
    cuts = [refs.index(cross[k, ROAD]) for k in range(0, nrad, 2)] + [len(refs) - 1]
    for n, (a, b) in enumerate(zip(cuts, cuts[1:])):
        tags = dict(highway="tertiary", name="Circonvallazione", maxspeed="30")
        if n == 1:
            tags["lanes"] = "2"
            tags["width"] = "7"
        osm.way(refs[a:b + 1], **tags)

    angle = lambda k: rad_angle(k, hit[k][ROAD])
    return {"south": cross[RADIAL_SOUTH, ROAD], "east": cross[RADIAL_EAST, ROAD],
            "north": cross[RADIAL_NORTH, ROAD], "south_angle": angle(RADIAL_SOUTH),
            "east_angle": angle(RADIAL_EAST), "north_angle": angle(RADIAL_NORTH)}


# --------------------------------------------------------------------------- the rest

def mw_centre(x):
    d = abs(x - MW_X0) - MW_STRAIGHT
    return MW_Y - (MW_CURVE * d * d if d > 0 else 0.0)


def build_south(osm, rng, grid, old_town):
    # Industrial road along y = INDUSTRIAL_Y, from the primary avenue to the east edge.
    ind = {}   # x -> node id
    ind_x = [MW_X0, -130.0, GX0 + GN * GDX, 560.0, 700.0, EDGE]
    for x in ind_x:
        ind[x] = osm.node(x, INDUSTRIAL_Y)
    sx, sy = osm.xy(old_town["south"])
    ind[round(sx, 1)] = osm.node(round(sx, 1), INDUSTRIAL_Y)
    xs = sorted(ind)
    split = xs.index(GX0 + GN * GDX)
    osm.way([ind[x] for x in xs[:split + 1]], highway="unclassified", name="Via Industriale", width="7")
    osm.way([ind[x] for x in xs[split:]], highway="unclassified", name="Via Industriale")

    # The old town's south radial down to it.
    a = old_town["south_angle"]
    out = (math.cos(math.radians(a)), math.sin(math.radians(a)))
    p0, p3 = (sx, sy), osm.xy(ind[round(sx, 1)])
    p1, p2 = (sx + 50 * out[0], sy + 50 * out[1]), (p3[0], p3[1] + 60)
    mid = osm.nodes_along(resample(lambda t: bezier(p0, p1, p2, p3, t), 15.0))
    osm.way([old_town["south"]] + mid + [ind[round(sx, 1)]], highway="tertiary", name="Via della Fornace")

    # Grid column GN continues south to it.
    osm.way([grid[GN, 0], ind[GX0 + GN * GDX]], highway="residential", name="Via del Porto")

    # Industrial estate: a service road with two dead-end branches, two warehouses.
    j = osm.node(-130.0, -410.0)
    osm.way([ind[-130.0], j], highway="service")
    osm.way([osm.node(-250.0, -410.0), j, osm.node(-10.0, -410.0)], highway="service")
    for x0, x1 in ((-290.0, -160.0), (-100.0, 30.0)):
        b = osm.nodes_along([(x0, -465.0), (x1, -465.0), (x1, -425.0), (x0, -425.0)])
        osm.way(b + b[:1], building="warehouse")

    # West of the avenue: a curving street from the grid's south-west corner to the
    # avenue, two grid columns continuing down to it, two courts and a school path.
    campi_y = lambda x: (INDUSTRIAL_Y + 10 - 10 * (x - GX0) / (MW_X0 - GX0)
                         + 8 * math.sin(2 * math.pi * (x - GX0) / (MW_X0 - GX0)))
    fixed = [GX0, GX0 + 2 * GDX, -650.0, -600.0, -430.0]
    xs = sorted(fixed + [x for x in range(int(GX0) + 20, int(MW_X0), 20)
                         if all(abs(x - f) > 8 for f in fixed)])
    campi = {x: osm.node(x, campi_y(x)) for x in xs}
    refs = [campi[x] for x in xs] + [ind[MW_X0]]
    k = xs.index(GX0 + 2 * GDX)
    osm.way(refs[:k + 1], highway="residential", name="Via dei Campi")
    osm.way(refs[k:], highway="residential", name="Via dei Campi", lanes="2")
    osm.way([grid[0, 0], campi[GX0]], highway="residential", name="Via del Mulino")
    osm.way([grid[2, 0], campi[GX0 + 2 * GDX]], highway="residential", name="Via della Scuola",
            oneway="yes")
    for x, name in ((-650.0, "Corte dei Campi"), (-430.0, "Corte del Gelso")):
        y = campi_y(x)
        osm.way([campi[x], osm.node(x + 4, y - 18), osm.node(x, y - 35, highway="turning_circle")],
                highway="residential", name=name)
    osm.way([campi[-600.0], osm.node(-600.0, -430.0)], highway="footway")
    b = osm.nodes_along([(-700.0, -428.0), (-640.0, -428.0), (-640.0, -395.0), (-700.0, -395.0)])
    osm.way(b + b[:1], building="school", name="Scuola Elementare")

    # A small quarter by the old kilns, south-east of the old town: a lane leaving the
    # map, two dead-end branches, a footpath back to the industrial road, a building.
    lane_pts = [(560.0, -440.0), (560.0, -410.0)]
    lane = [ind[560.0]] + osm.nodes_along(lane_pts)
    bend_pts = resample(lambda t: bezier((560.0, -410.0), (562.0, -350.0), (640.0, -345.0),
                                         (EDGE, -362.0), t), 15.0)
    lane += osm.nodes_along(bend_pts) + [osm.node(EDGE, -362.0)]
    osm.way(lane[:3], highway="residential", name="Via delle Fornaci", width="5")
    osm.way(lane[2:], highway="residential", name="Via delle Fornaci", width="5", maxspeed="30")
    kiln_end = osm.node(700.0, -440.0, highway="turning_circle")
    osm.way([lane[1], osm.node(630.0, -442.0), kiln_end], highway="residential", name="Vicolo del Forno")
    osm.way([lane[2], osm.node(505.0, -405.0, noexit="yes")], highway="service")
    osm.way([kiln_end, osm.node(702.0, -462.0), ind[700.0]], highway="footway")
    b = osm.nodes_along([(600.0, -428.0), (680.0, -428.0), (680.0, -392.0), (600.0, -392.0)])
    osm.way(b + b[:1], building="industrial", name="Fornace Vecchia")

    # Motorway: two one-way carriageways, straight at the interchange, curving beyond.
    ramp_w, ramp_e = MW_X0 - RAMP_DX, MW_X0 + RAMP_DX
    xs = sorted({-EDGE, EDGE, ramp_w, ramp_e, MW_X0 - MW_STRAIGHT, MW_X0 + MW_STRAIGHT} |
                {float(x) for x in range(-725, 745, 25) if abs(x - MW_X0) > MW_STRAIGHT + 10})
    mw_tags = dict(highway="motorway", oneway="yes", lanes="2", ref="A 0", maxspeed="120")
    for side, order, (first_jn, second_jn) in ((+1, -1, (ramp_e, ramp_w)), (-1, +1, (ramp_w, ramp_e))):
        nodes = {x: osm.node(x, mw_centre(x) + side * MW_HALF_SEP) for x in xs}
        seq = sorted(xs, reverse=(order < 0))
        i1, i2 = seq.index(first_jn), seq.index(second_jn)
        refs = [nodes[x] for x in seq]
        osm.way(refs[:i1 + 1], **mw_tags)
        osm.way(refs[i1:i2 + 1], **mw_tags)
        osm.way(refs[i2:], **mw_tags)
        # Access node beside the carriageway, ramps from and to it.
        ay = MW_Y + side * (MW_HALF_SEP + RAMP_RISE)
        access = osm.node(MW_X0, ay)

        def ramp(xj, to_access):
            cy = MW_Y + side * MW_HALF_SEP
            n = 14
            pts = []
            for s in range(1, n):
                t = s / n
                x = xj + (MW_X0 - xj) * t
                pts.append((x, cy + side * RAMP_RISE * (1.0 - (1.0 - t) ** 2)))  # leaves at ~16 deg
            inner = osm.nodes_along(pts)
            refs = [nodes[xj]] + inner + [access]
            return refs if to_access else refs[::-1]

        osm.way(ramp(first_jn, True), highway="motorway_link", oneway="yes", lanes="1")
        osm.way(ramp(second_jn, False), highway="motorway_link", oneway="yes", lanes="1")
        if side > 0:
            north_access = access
        else:
            south_access = access

    # The primary avenue runs south through the industrial road and over the motorway.
    osm.way([grid[AVENUE_COL, 0], ind[MW_X0], north_access], highway="primary",
            name="Viale della Stazione", lanes="2", maxspeed="50")
    osm.way([north_access, south_access], highway="primary", name="Ponte dell'Autostrada",
            bridge="yes", layer="1", lanes="2")
    fork = osm.node(MW_X0, -690.0)
    osm.way([south_access, fork, osm.node(MW_X0, -EDGE)], highway="primary", name="Strada Cantonale",
            lanes="2")
    # A track along the fields south of the motorway.
    pts = resample(lambda t: (MW_X0 + (-EDGE - MW_X0) * t,
                              -690.0 - 25 * t + 12 * math.sin(3 * math.pi * t)), 20.0)
    osm.way([fork] + osm.nodes_along(pts) + [osm.node(-EDGE, -715.0)], highway="track",
            tracktype="grade3")


def build_north(osm, rng, grid, old_town):
    # The road east out of the map from the old town's east radial.
    ex, ey = osm.xy(old_town["east"])
    a = old_town["east_angle"]
    out = (math.cos(math.radians(a)), math.sin(math.radians(a)))
    p0, p3 = (ex, ey), (EDGE, ey - 30)
    p1, p2 = (ex + 30 * out[0], ey + 30 * out[1]), (EDGE - 30, ey - 30)
    mid = osm.nodes_along(resample(lambda t: bezier(p0, p1, p2, p3, t), 15.0))
    osm.way([old_town["east"]] + mid + [osm.node(*p3)], highway="tertiary", name="Via per Levante",
            lanes="2", width="6.5")

    # A suburban estate north of the old town: a loop road around a curved spine, with
    # cul-de-sacs (turning circles) inside and outside the loop.
    names = NamePool(rng, ESTATE_NAMES)
    wob, ph = rng.uniform(0.03, 0.06), rng.uniform(0, 2 * math.pi)

    def loop_pt(psi):
        p = math.radians(psi)
        f = 1.0 + wob * math.sin(3 * p + ph)
        return EST_X + EST_RX * math.cos(p) * f, EST_Y + EST_RY * math.sin(p) * f

    def loop_normal(psi):
        p = math.radians(psi)
        nx_, ny_ = math.cos(p) / EST_RX, math.sin(p) / EST_RY
        n = math.hypot(nx_, ny_)
        return nx_ / n, ny_ / n

    fixed = {0.0: None, 180.0: None, 260.0: None, 62.0: None, 95.0: None, 128.0: None,
             215.0: None, 325.0: None}
    psis = sorted(set(fixed) | {float(p) for p in range(0, 360, 5) if all(abs(p - q) > 2 for q in fixed)})
    loop = {p: osm.node(*loop_pt(p)) for p in psis}
    ring = [loop[p] for p in psis] + [loop[0.0]]
    i180, i260 = psis.index(180.0), psis.index(260.0)
    osm.way(ring[:i180 + 1], highway="residential", name=names.pop())
    loop_name = names.pop()
    osm.way(ring[i180:i260 + 1], highway="residential", name=loop_name, oneway="yes")
    osm.way(ring[i260:], highway="residential", name=loop_name)
    cul_ends = {}
    for psi in (62.0, 95.0, 128.0, 215.0, 325.0):
        (x, y), (nx_, ny_) = loop_pt(psi), loop_normal(psi)
        length = rng.uniform(40, 50)
        mid = osm.node(x + nx_ * length / 2 - ny_ * 4, y + ny_ * length / 2 + nx_ * 4)
        end = osm.node(x + nx_ * length, y + ny_ * length, highway="turning_circle")
        cul_ends[psi] = end
        osm.way([loop[psi], mid, end], highway="residential", name=names.pop())

    west, east = loop_pt(180.0), loop_pt(0.0)
    spine = lambda t: (west[0] + (east[0] - west[0]) * t,
                       west[1] + (east[1] - west[1]) * t + 12 * math.sin(2 * math.pi * t))
    branches = {0.22: 1, 0.4: -1, 0.6: 1, 0.78: -1}
    ts = sorted(set(branches) | {s / 30 for s in range(1, 30) if all(abs(s / 30 - b) > 0.015 for b in branches)})
    spine_nodes = {t: osm.node(*spine(t)) for t in ts}
    osm.way([loop[180.0]] + [spine_nodes[t] for t in ts] + [loop[0.0]], highway="residential",
            name="Viale dei Mirti", width="7")
    for t, up in sorted(branches.items()):
        x, y = spine(t)
        length = rng.uniform(42, 50)
        osm.way([spine_nodes[t], osm.node(x + 3, y + up * length / 2),
                 osm.node(x, y + up * length, highway="turning_circle")], highway="residential",
                name=names.pop())

    # A few houses between the spine and the loop.
    for t in (0.31, 0.5, 0.69):
        for up in (1, -1):
            x, y = spine(t)
            y += up * 22
            b = osm.nodes_along([(x - 7, y - 5), (x + 7, y - 5), (x + 7, y + 5), (x - 7, y + 5)])
            osm.way(b + b[:1], building="house")

    # The north radial continues as "Via al Bosco" into the estate; another road links it
    # with the grid's north-east corner.
    nx, ny = osm.xy(old_town["north"])
    a = old_town["north_angle"]
    out = (math.cos(math.radians(a)), math.sin(math.radians(a)))
    p0, p3 = (nx, ny), loop_pt(260.0)
    p1, p2 = (nx + 40 * out[0], ny + 40 * out[1]), (p3[0], p3[1] - 40)
    mid = osm.nodes_along(resample(lambda t: bezier(p0, p1, p2, p3, t), 15.0))
    osm.way([old_town["north"]] + mid + [loop[260.0]], highway="residential", name="Via al Bosco")
    p0, p3 = osm.xy(grid[GN, GN]), west
    p1, p2 = (p0[0] + 60, p0[1] + 10), (p3[0] - 50, p3[1])
    mid = osm.nodes_along(resample(lambda t: bezier(p0, p1, p2, p3, t), 12.0))
    osm.way([grid[GN, GN]] + mid + [loop[180.0]], highway="tertiary", name="Via della Collina")

    # A hillside road with bends from the grid's north edge up to a hamlet.
    top = grid[2, GN]
    tx, ty = osm.xy(top)
    amp = rng.uniform(80, 100)
    bend = osm.node(tx, ty + 40)
    pts = resample(lambda t: (tx + amp * math.sin(4 * math.pi * t), ty + 40 + 220 * t), 10.0)
    hamlet0 = osm.node(tx, ty + 260)
    refs = [top, bend] + osm.nodes_along(pts) + [hamlet0]
    half = len(refs) // 2
    osm.way(refs[:half + 1], highway="unclassified", name="Strada di Monte", width="4.5")
    osm.way(refs[half:], highway="unclassified", name="Strada di Monte", width="4", surface="asphalt")

    # The hamlet: one closed lane (a way whose first and last node are the same) around
    # a few houses.
    hx, hy = tx, ty + 260
    corners = [(hx + 70, hy + 8), (hx + 100, hy + 40), (hx + 65, hy + 82), (hx - 10, hy + 88),
               (hx - 55, hy + 60), (hx - 45, hy + 20)]
    hamlet = [hamlet0]
    prev = (hx, hy)
    for c in corners + [(hx, hy)]:
        mx, my = (prev[0] + c[0]) / 2, (prev[1] + c[1]) / 2
        hamlet.append(osm.node(mx + rng.uniform(-3, 3), my + rng.uniform(-3, 3)))
        if c != (hx, hy):
            hamlet.append(osm.node(*c))
        prev = c
    hamlet.append(hamlet0)
    osm.way(hamlet, highway="residential", name="Nucleo di Monte")
    hamlet_east = hamlet[4]  # the corner (hx + 100, hy + 40)
    for bx, by in ((hx + 10, hy + 30), (hx + 45, hy + 45), (hx + 5, hy + 60)):
        b = osm.nodes_along([(bx - 8, by - 6), (bx + 8, by - 6), (bx + 8, by + 6), (bx - 8, by + 6)])
        osm.way(b + b[:1], building="house")

    # A track over the fields from the hamlet to the estate's westernmost cul-de-sac.
    a0, b0 = osm.xy(hamlet_east), osm.xy(cul_ends[128.0])
    dx, dy = b0[0] - a0[0], b0[1] - a0[1]
    length = math.hypot(dx, dy)
    nxv, nyv = -dy / length, dx / length
    wig = rng.uniform(12, 20)
    w = lambda t: wig * math.sin(3 * math.pi * t) * math.sin(math.pi * t)
    pts = resample(lambda t: (a0[0] + dx * t + nxv * w(t), a0[1] + dy * t + nyv * w(t)), 20.0)
    track = [hamlet_east] + osm.nodes_along(pts) + [cul_ends[128.0]]
    k = len(track) // 2
    osm.way(track[:k + 1], highway="track", tracktype="grade2")
    osm.way(track[k:], highway="track", tracktype="grade4", access="agricultural")

    # A stream across the north of the map, crossing nothing.
    p, q = rng.uniform(0, 2 * math.pi), rng.uniform(0, 2 * math.pi)
    pts = [(float(x), 690 + 20 * math.sin(x / 140 + p) + 8 * math.sin(x / 53 + q))
           for x in range(int(EDGE), -int(EDGE) - 1, -30)]
    osm.way(osm.nodes_along(pts), waterway="stream", name="Riale Finzio")


# --------------------------------------------------------------------------- checks

def check(osm):
    """Raise ValueError unless the invariants the sample promises hold."""
    for wid, (refs, tags) in osm.ways.items():
        for r in refs:
            if r not in osm.nodes:
                raise ValueError(f"way {wid} references missing node {r}")
        inner = refs[:-1] if refs[0] == refs[-1] else refs
        if len(set(inner)) != len(inner):
            raise ValueError(f"way {wid} visits a node twice")
    # Distinct nodes never share a position.
    seen = {}
    for nid, (x, y, _) in osm.nodes.items():
        key = (round(x), round(y))
        for ddx in (-1, 0, 1):
            for ddy in (-1, 0, 1):
                for other in seen.get((key[0] + ddx, key[1] + ddy), []):
                    if math.dist((x, y), osm.xy(other)) < 1.0:
                        raise ValueError(f"nodes {nid} and {other} less than 1 m apart")
        seen.setdefault(key, []).append(nid)
    # Highway segments only touch at shared nodes (except across layers: the bridge).
    segs = []
    for wid, (refs, tags) in osm.ways.items():
        if "highway" in tags:
            layer = int(tags.get("layer", "0"))
            segs += [(wid, a, b, layer) for a, b in zip(refs, refs[1:])]
    cell = 40.0
    buckets = {}
    for n, (_, a, b, _) in enumerate(segs):
        (x1, y1), (x2, y2) = osm.xy(a), osm.xy(b)
        for cx in range(math.floor(min(x1, x2) / cell), math.floor(max(x1, x2) / cell) + 1):
            for cy in range(math.floor(min(y1, y2) / cell), math.floor(max(y1, y2) / cell) + 1):
                buckets.setdefault((cx, cy), []).append(n)
    done = set()
    for members in buckets.values():
        for i in range(len(members)):
            for j in range(i + 1, len(members)):
                s, t = segs[members[i]], segs[members[j]]
                if (members[i], members[j]) in done:
                    continue
                done.add((members[i], members[j]))
                if {s[1], s[2]} & {t[1], t[2]} or s[3] != t[3]:
                    continue
                d = _seg_dist(osm.xy(s[1]), osm.xy(s[2]), osm.xy(t[1]), osm.xy(t[2]))
                if d < 2.0:
                    raise ValueError(f"ways {s[0]} and {t[0]} meet without a shared node "
                                     f"(segments {s[1]}-{s[2]} and {t[1]}-{t[2]}, {d:.2f} m)")


def _seg_dist(p1, p2, q1, q2):
    def orient(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    def pt_seg(p, a, b):
        vx, vy = b[0] - a[0], b[1] - a[1]
        t = max(0.0, min(1.0, ((p[0] - a[0]) * vx + (p[1] - a[1]) * vy) / (vx * vx + vy * vy)))
        return math.dist(p, (a[0] + t * vx, a[1] + t * vy))

    if (orient(p1, p2, q1) * orient(p1, p2, q2) < 0) and (orient(q1, q2, p1) * orient(q1, q2, p2) < 0):
        return 0.0
    return min(pt_seg(p1, q1, q2), pt_seg(p2, q1, q2), pt_seg(q1, p1, p2), pt_seg(q2, p1, p2))


# --------------------------------------------------------------------------- output

def write_xml(osm, path, seed):
    def attr(v):
        return escape(v, {'"': "&quot;"})

    def tag_lines(tags, indent):
        return [f'{indent}<tag k="{attr(k)}" v="{attr(v)}"/>' for k, v in sorted(tags.items())]

    minlat, minlon = to_latlon(-HALF_EXTENT_M, -HALF_EXTENT_M)
    maxlat, maxlon = to_latlon(HALF_EXTENT_M, HALF_EXTENT_M)
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f"<!-- Synthetic, fictional town generated by {GENERATOR} (seed {seed}); not OpenStreetMap data. -->",
             f'<osm version="0.6" generator="{GENERATOR}">',
             f'  <bounds minlat="{minlat:.7f}" minlon="{minlon:.7f}" maxlat="{maxlat:.7f}" maxlon="{maxlon:.7f}"/>']
    for nid in sorted(osm.nodes):
        x, y, tags = osm.nodes[nid]
        lat, lon = to_latlon(x, y)
        head = f'  <node id="{nid}" version="1" lat="{lat:.7f}" lon="{lon:.7f}"'
        if tags:
            lines += [head + ">"] + tag_lines(tags, "    ") + ["  </node>"]
        else:
            lines.append(head + "/>")
    for wid in sorted(osm.ways):
        refs, tags = osm.ways[wid]
        lines.append(f'  <way id="{wid}" version="1">')
        lines += [f'    <nd ref="{r}"/>' for r in refs]
        lines += tag_lines(tags, "    ")
        lines.append("  </way>")
    lines.append("</osm>")
    data = ("\n".join(lines) + "\n").encode("utf-8")
    with open(path, "wb") as f:
        f.write(data)


def build(seed):
    osm = Osm(seed)
    grid = build_grid(osm, random.Random(f"{seed}:grid"))
    old_town = build_old_town(osm, random.Random(f"{seed}:old_town"), grid)
    build_south(osm, random.Random(f"{seed}:south"), grid, old_town)
    build_north(osm, random.Random(f"{seed}:north"), grid, old_town)
    check(osm)
    return osm


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description="Write a synthetic OSM XML town (fictional, generated).")
    ap.add_argument("-o", "--output", default=os.path.join(here, "sample_city.osm"),
                    help="output .osm path (default: sample_city.osm beside this script)")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED, help=f"random seed (default {DEFAULT_SEED})")
    args = ap.parse_args(argv)
    osm = build(args.seed)
    write_xml(osm, args.output, args.seed)
    hw = [w for w in osm.ways.values() if "highway" in w[1]]
    hw_nodes = {r for refs, _ in hw for r in refs}
    print(f"{args.output}: {len(osm.nodes)} nodes, {len(osm.ways)} ways "
          f"({len(hw)} highway ways over {len(hw_nodes)} nodes), seed {args.seed}")


if __name__ == "__main__":
    sys.exit(main())
