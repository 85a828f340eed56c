#!/usr/bin/env python3
"""Seed corpora for the libFuzzer harnesses (native/fuzz/, run by scripts/fuzz.sh).

Writes OUT/<harness>/ for osm, geojson, geojson_region, grammar, ggraph and derive from the
sources below, and random bytes for grow:
  - the OpenStreetMap extracts in SHARED (../shared/osm): small slices of the XML ones (a few
    consecutive highway ways with their nodes, a few kB each) in every format the OSM
    harness reads, plus the smallest whole PBFs; nothing from SHARED is kept anywhere else;
  - samples/: the generated sample town (sliced the same way) and the grammars;
  - the (fuzz-built) CLI: the slices exported to GeoJSON and .ggraph, grammars learned from
    them, a derived grammar as .ggraph.
Seeds above --max-bytes are dropped (libFuzzer's -max_len would truncate them).
"""
import argparse
import bz2
import gzip
import io
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

# First byte of an osm seed: the format (native/fuzz/fuzz_osm.cpp), plus option bits * 5.
FORMATS = {"xml": 0, "pbf": 1, "opl": 2, "gz": 3, "bz2": 4}
KEPT_TAGS = {"highway", "name", "oneway", "lanes", "width", "junction", "bridge", "layer", "noexit"}


def read_osm_xml(path):
    data = open(path, "rb").read()
    if path.endswith(".gz"):
        data = gzip.decompress(data)
    elif path.endswith(".bz2"):
        data = bz2.decompress(data)
    nodes, ways = {}, []
    for _, el in ET.iterparse(io.BytesIO(data)):
        if el.tag == "node":
            nodes[el.get("id")] = (el.get("lat"), el.get("lon"),
                                   [(t.get("k"), t.get("v")) for t in el.findall("tag")])
            el.clear()
        elif el.tag == "way":
            tags = [(t.get("k"), t.get("v")) for t in el.findall("tag")]
            if any(k == "highway" for k, _ in tags):
                ways.append((el.get("id"), [n.get("ref") for n in el.findall("nd")], tags))
            el.clear()
    return nodes, ways


def xml_escape(s):
    return (s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;"))


def write_slice(nodes, ways):
    """OSM XML of the given ways and the nodes they reference that the extract holds."""
    refs = []
    seen = set()
    for _, nds, _ in ways:
        for r in nds:
            if r in nodes and r not in seen:
                seen.add(r)
                refs.append(r)
    out = ['<?xml version="1.0" encoding="UTF-8"?>', '<osm version="0.6" generator="ggg fuzz seeds">']
    for r in sorted(refs, key=int):
        lat, lon, tags = nodes[r]
        if tags:
            out.append(f'  <node id="{r}" version="1" lat="{lat}" lon="{lon}">')
            out += [f'    <tag k="{xml_escape(k)}" v="{xml_escape(v)}"/>' for k, v in tags[:3]]
            out.append("  </node>")
        else:
            out.append(f'  <node id="{r}" version="1" lat="{lat}" lon="{lon}"/>')
    for wid, nds, tags in ways:
        out.append(f'  <way id="{wid}" version="1">')
        out += [f'    <nd ref="{r}"/>' for r in nds]
        out += [f'    <tag k="{xml_escape(k)}" v="{xml_escape(v)}"/>' for k, v in tags if k in KEPT_TAGS]
        out.append("  </way>")
    out.append("</osm>\n")
    return "\n".join(out).encode()


def slices(path, count, target_bytes):
    nodes, ways = read_osm_xml(path)
    if not ways:
        return []
    result = []
    for i in range(count):
        start = (i * len(ways)) // count
        chosen = []
        for w in ways[start:]:
            chosen.append(w)
            if len(write_slice(nodes, chosen)) > target_bytes:
                if len(chosen) > 1:
                    chosen.pop()
                break
        result.append(write_slice(nodes, chosen))
    return result


class Seeds:
    def __init__(self, out, max_bytes):
        self.out, self.max_bytes, self.count = out, max_bytes, {}

    def add(self, harness, name, data):
        if len(data) > self.max_bytes.get(harness, 1 << 16):
            return
        d = os.path.join(self.out, harness)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, name), "wb") as f:
            f.write(data)
        self.count[harness] = self.count.get(harness, 0) + 1


def osmium_convert(src, dst, fmt):
    subprocess.run(["osmium", "cat", "--no-progress", "-O", src, "-o", dst, "-f", fmt], check=True,
                   stdout=subprocess.DEVNULL)
    return open(dst, "rb").read()


def run_cli(cli, *args):
    r = subprocess.run([cli, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return r.returncode == 0


HAND_GEOJSON = [
    {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"highway": "residential", "name": "A", "oneway": "yes", "lanes": 2},
         "geometry": {"type": "LineString", "coordinates": [[8.95, 46.0], [8.951, 46.0], [8.951, 46.001]]}},
        {"type": "Feature", "properties": {"highway": "primary"},
         "geometry": {"type": "MultiLineString", "coordinates": [[[8.951, 46.0], [8.952, 46.0]],
                                                                  [[8.95, 46.0], [8.95, 46.001], [8.951, 46.001]]]}}]},
    {"type": "Feature", "properties": None,
     "geometry": {"type": "LineString", "coordinates": [[0, 0], [0.001, 0], [0.001, 0.001], [0, 0]]}},
    {"type": "FeatureCollection", "ggg": {"origin_latlon": [46.0, 8.95]}, "features": [
        {"type": "Feature", "properties": {"highway": "service", "width": 3.5},
         "geometry": {"type": "LineString", "coordinates": [[8.95, 46.0, 120.0], [8.9501, 46.0001, 121.0]]}}]},
]

HAND_REGIONS = [
    {"type": "Polygon", "coordinates": [[[8.94, 45.99], [8.96, 45.99], [8.96, 46.01], [8.94, 46.01], [8.94, 45.99]]]},
    {"type": "MultiPolygon", "coordinates": [[[[0, 0], [0.01, 0], [0.005, 0.01], [0, 0]]],
                                             [[[1, 1], [1.01, 1], [1, 1.01], [1, 1]]]]},
    {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [8.95, 46.0]}},
        {"type": "Feature", "properties": {"name": "district"}, "geometry": {
            "type": "Polygon", "coordinates": [[[8.95, 46.0], [8.952, 46.0], [8.952, 46.002], [8.95, 46.0]],
                                               [[8.9505, 46.0005], [8.951, 46.0005], [8.951, 46.001], [8.9505, 46.0005]]]}}]},
    {"type": "Feature", "geometry": {"type": "GeometryCollection", "geometries": [
        {"type": "LineString", "coordinates": [[0, 0], [1, 1]]},
        {"type": "Polygon", "coordinates": [[[-179.9, -80], [179.9, -80], [0, 80], [-179.9, -80]]]}]}},
]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shared", default=None, help="folder of OSM extracts (default: ../shared/osm beside the repository)")
    ap.add_argument("--cli", required=True, help="the ggg CLI used to export and learn")
    ap.add_argument("--out", required=True, help="corpus folder (one subfolder per harness)")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    shared = args.shared or os.path.join(os.path.dirname(root), "shared", "osm")
    samples = os.path.join(root, "samples")
    max_bytes = {"osm": 1 << 17}
    seeds = Seeds(args.out, max_bytes)
    tmp = tempfile.mkdtemp(prefix="ggg-fuzz-seeds-")
    try:
        # --- OSM slices, from the sample town and every XML extract (plain or compressed)
        sources = [os.path.join(samples, "sample_city.osm")]
        if os.path.isdir(shared):
            sources += [os.path.join(shared, f) for f in sorted(os.listdir(shared))
                        if f.endswith((".osm", ".osm.gz", ".osm.bz2"))]
        else:
            print(f"fuzz_seeds: {shared} is absent: OSM seeds from samples/ only", file=sys.stderr)
        xml_slices = []
        for src in sources:
            base = os.path.basename(src).split(".")[0]
            for i, data in enumerate(slices(src, 6, 4000)):
                xml_slices.append((f"{base}_{i}", data))
        for n, (name, data) in enumerate(xml_slices):
            opts = (n % 8) * 5
            path = os.path.join(tmp, name + ".osm")
            open(path, "wb").write(data)
            seeds.add("osm", name + ".osm", bytes([FORMATS["xml"] + opts]) + data)
            seeds.add("osm", name + ".osm.gz", bytes([FORMATS["gz"] + opts]) + gzip.compress(data, mtime=0))
            seeds.add("osm", name + ".osm.bz2", bytes([FORMATS["bz2"] + opts]) + bz2.compress(data))
            seeds.add("osm", name + ".opl", bytes([FORMATS["opl"] + opts]) + osmium_convert(path, path + ".opl", "opl"))
            # Uncompressed PBF blobs let the fuzzer reach the protobuf decoding directly.
            seeds.add("osm", name + ".raw.osm.pbf",
                      bytes([FORMATS["pbf"] + opts]) + osmium_convert(path, path + ".raw.pbf", "pbf,pbf_compression=none"))
            if n % 3 == 0:
                seeds.add("osm", name + ".osm.pbf", bytes([FORMATS["pbf"] + opts]) + osmium_convert(path, path + ".pbf", "pbf"))
        # A truncated file and a whole small town, as they are.
        town = open(os.path.join(samples, "sample_city.osm"), "rb").read()
        seeds.add("osm", "sample_city_head.osm", bytes([FORMATS["xml"]]) + town[:3000])
        seeds.add("osm", "sample_city.osm.gz", bytes([FORMATS["gz"] + 5]) + gzip.compress(town, mtime=0))
        if os.path.isdir(shared):
            for f in ("aguascalientes_mx.osm.pbf", "paris_marais.osm.pbf"):
                if os.path.exists(os.path.join(shared, f)):
                    seeds.add("osm", f, bytes([FORMATS["pbf"] + 5]) + open(os.path.join(shared, f), "rb").read())

        # --- GeoJSON and .ggraph exported by the CLI, grammars learned from the slices
        grammars = [open(os.path.join(samples, "sierpinski.grammar.json"), "rb").read()]
        for n, (name, data) in enumerate(xml_slices):
            path = os.path.join(tmp, name + ".osm")
            highways = "all" if n % 2 else "drivable"
            if run_cli(args.cli, "export", path, "-o", path + ".geojson", "--highways", highways):
                seeds.add("geojson", name + ".geojson", open(path + ".geojson", "rb").read())
                if n % 4 == 0:
                    seeds.add("geojson_region", name + ".geojson", open(path + ".geojson", "rb").read())
            if run_cli(args.cli, "export", path, "-o", path + ".ggraph", "--highways", highways):
                seeds.add("ggraph", name + ".ggraph", open(path + ".ggraph", "rb").read())
            if n % 2 == 0:
                mode = ["--lossless"] if n % 4 == 0 else []
                if run_cli(args.cli, "learn", path, "-o", path + ".grammar.json", *mode):
                    grammars.append(open(path + ".grammar.json", "rb").read())
                # The same grammar packed in CBOR (the reader tells it by its first byte).
                if n % 8 == 0 and run_cli(args.cli, "learn", path, "-o", path + ".grammar.cbor", *mode):
                    grammars.append(open(path + ".grammar.cbor", "rb").read())
        sierpinski = os.path.join(samples, "sierpinski.grammar.json")
        for steps in (0, 2):
            out = os.path.join(tmp, f"sierpinski{steps}.ggraph")
            if run_cli(args.cli, "derive", sierpinski, "--steps", str(steps), "-o", out):
                seeds.add("ggraph", f"sierpinski{steps}.ggraph", open(out, "rb").read())
        for i, g in enumerate(HAND_GEOJSON):
            seeds.add("geojson", f"hand{i}.geojson", json.dumps(g).encode())
        for i, g in enumerate(HAND_REGIONS):
            seeds.add("geojson_region", f"hand{i}.geojson", json.dumps(g).encode())
        for i, g in enumerate(grammars):
            seeds.add("grammar", f"grammar{i}.json", g)
            seeds.add("derive", f"grammar{i}.json", g)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    # grow reads its base, region and options as numbers (FuzzedDataProvider): bytes will do.
    rng = random.Random(7)
    for i in range(16):
        seeds.add("grow", f"random{i}.bin", bytes(rng.randrange(256) for _ in range(rng.randrange(64, 1024))))
    for h in sorted(seeds.count):
        print(f"fuzz_seeds: {h}: {seeds.count[h]} seeds")


if __name__ == "__main__":
    main()
