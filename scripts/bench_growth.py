"""Growth figures of docs/benchmarks.md and docs/synthesis.md: time to grow a 1 km² hole cut
out of Porto (all highways) back with default options, time to grow 1,000 rules at Porto's east
edge, time to replace the copies of Porto's most frequent block by a plaza (Fig. 1), and how
alike regions grown from Columbus' and the Marais' grammars are to each city (the four
distances of ggg.compare, seeds 1 to 8).

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench_growth.py [--quick]

Needs ../shared/osm beside the project (OpenStreetMap extracts, (c) OpenStreetMap contributors,
ODbL) and a build (bash scripts/build.sh).
"""
import argparse
import sys
import time
from pathlib import Path

import numpy as np

import ggg

OSM = Path(__file__).resolve().parent.parent.parent / "shared" / "osm"


def porto_edge():
    porto = ggg.read_graph(str(OSM / "porto_metro.osm.pbf"))
    t = time.perf_counter()
    grammar, _ = ggg.learn(porto)
    learned = time.perf_counter() - t
    p = porto.positions
    x1 = p[:, 0].max()
    y = np.median(p[:, 1])
    region = np.array([[x1 - 200, y - 1500], [x1 + 2000, y - 1500], [x1 + 2000, y + 1500], [x1 - 200, y + 1500]])
    t = time.perf_counter()
    grown, report = ggg.grow_region(porto, grammar, region, seed=1, max_placements=1000, patience=1000)
    seconds = time.perf_counter() - t
    print("porto east edge: learn {:.1f} s; grow {:.2f} s: {} rules, {:,} tries, {:,} new vertices, "
          "{} main road routes ({} streets raised), {} connectors, {} intersections".format(
              learned, seconds, report["placements"], report["attempts"], report["added_vertices"],
              report["main_road_routes"], report["raised_streets"], report["main_road_connectors"],
              report["intersections"]))


def porto_hole():
    """A 1 km x 1 km hole at the middle of Porto (all highways), grown back with default options."""
    porto = ggg.read_graph(str(OSM / "porto_metro.osm.pbf"), highways="all")
    p = porto.positions
    centre = np.median(p, axis=0)
    lo, hi = centre - 500.0, centre + 500.0
    in_hole = np.all((p > lo) & (p < hi), axis=1)
    edges = np.asarray(porto.edges)
    keep = ~in_hole[edges[:, 0]] & ~in_hole[edges[:, 1]]
    index = np.cumsum(~in_hole) - 1
    offsets, points = porto.edge_geometry()
    kept = np.flatnonzero(keep)
    lines = [points[offsets[e]:offsets[e + 1]] for e in kept]
    rest = ggg.Graph.from_arrays(p[~in_hole], index[edges[kept]], porto.origin_latlon,
                                 edge_highway=np.asarray(porto.edge_highway)[kept],
                                 edge_geometry=(np.concatenate([[0], np.cumsum([len(x) for x in lines])]).astype(np.int64),
                                                np.concatenate(lines)))
    t = time.perf_counter()
    grammar, _ = ggg.learn(rest)
    learned = time.perf_counter() - t
    region = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    t = time.perf_counter()
    grown, report = ggg.grow_region(rest, grammar, region, seed=1)
    seconds = time.perf_counter() - t
    real = int(np.count_nonzero(in_hole[edges[:, 0]] | in_hole[edges[:, 1]]))
    print("porto 1 km2 hole (all highways, {:,} vertices): learn {:.1f} s; grow {:.2f} s: {:,} streets traced from {:,} "
          "at the border, {} rules, {:,} new streets (the hole had {:,}); {} offset crossings joined, {} streets thinned".format(
              rest.vertex_count, learned, seconds, report["traced_streets"], report["traced_seeds"],
              report["placements"], report["added_edges"], real, report["traced_joined_offsets"], report["thinned_streets"]))


def style(seeds):
    columbus = ggg.read_graph(str(OSM / "columbus_oh.osm.pbf"))
    paris = ggg.read_graph(str(OSM / "paris_marais.osm.pbf"))
    grammars = {"columbus": ggg.learn(columbus)[0], "marais": ggg.learn(paris)[0]}
    region = np.array([[0, 0], [900, 0], [900, 900], [0, 900]], float)
    empty = ggg.Graph.from_arrays(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64))
    for name, grammar in grammars.items():
        for seed in seeds:
            grown, report = ggg.grow_region(empty, grammar, region, seed=seed)
            to_c = ggg.compare(grown, columbus)["distances"]
            to_p = ggg.compare(grown, paris)["distances"]
            print("{} grammar, seed {}: {} rules; against Columbus / the Marais: ".format(name, seed, report["placements"]) +
                  ", ".join("{} {:.3f} / {:.3f}".format(k, to_c[k], to_p[k])
                            for k in ("degree", "edge_length", "orientation", "block_area", "mean")))


def porto_replacement():
    porto = ggg.read_graph(str(OSM / "porto_metro.osm.pbf"), highways="all")
    t = time.perf_counter()
    analysis = ggg.analyze(porto, max_order=8)
    analysed = time.perf_counter() - t
    blocks = [iso for iso in analysis.isogroups if iso.edge_count == iso.order >= 4]
    block = max(blocks, key=lambda iso: len(iso.non_overlapping))
    n = 16
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    plaza = np.c_[np.cos(angles), np.sin(angles)]
    edges = np.array([(i, (i + 1) % n) for i in range(n)])
    t = time.perf_counter()
    _, report = ggg.replace_isogroup(porto, block, plaza, edges)
    replaced = time.perf_counter() - t
    print("porto replacement (all highways, {:,} vertices): analyse {:.1f} s; replace {:.2f} s: {:,} copies of the "
          "{}-vertex block by a {}-vertex plaza, {:,} streets joined, {:,} intersections".format(
              porto.vertex_count, analysed, replaced, report["replaced"], block.order, n, report["joined_streets"],
              report["intersections"]), flush=True)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two seeds, no Porto")
    args = parser.parse_args(argv)
    if not OSM.is_dir():
        sys.exit("needs the extracts in {}".format(OSM))
    if not args.quick:
        porto_hole()
        porto_edge()
        porto_replacement()
    style(range(1, 3) if args.quick else range(1, 9))


if __name__ == "__main__":
    main(sys.argv[1:])
