"""Growth figures of docs/benchmarks.md and docs/synthesis.md: time to grow 1,000 rules at
Porto's east edge, and how alike regions grown from Columbus' and the Marais' grammars are to
each city (the four distances of ggg.compare, seeds 1 to 8).

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


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two seeds, no Porto")
    args = parser.parse_args(argv)
    if not OSM.is_dir():
        sys.exit("needs the extracts in {}".format(OSM))
    if not args.quick:
        porto_edge()
    style(range(1, 3) if args.quick else range(1, 9))


if __name__ == "__main__":
    main(sys.argv[1:])
