#!/usr/bin/env bash
# Times `ggg learn` in both modes on real extracts and prints the rows of the learning table
# in docs/benchmarks.md (the paper's Table 2 analogue). Needs ../shared/osm beside the project
# and a build (bash scripts/build.sh). Usage: bash scripts/bench_learning.sh [extra ggg learn flags]
set -euo pipefail
cd "$(dirname "$0")/.."
OSM=../shared/osm
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "| extract | mode | vertices | edges | passes | levels | rules | instances | axiom vertices | learn s | total s | original kB | grammar kB | grammar / graph (JSON, CBOR) | edges equal | max / mean error (m) | peak MB |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---:|"
for file in paris_marais.osm.pbf barcelona_eixample.osm columbus_oh.osm.pbf porto_metro.osm.pbf; do
  for mode in "" "--lossless"; do
    /usr/bin/time -f "%e %M" -o "$OUT/time" build/bin/ggg learn "$OSM/$file" --highways all $mode "$@" \
      -o "$OUT/grammar.json" > "$OUT/stats.json" 2>/dev/null
    /usr/bin/python3 - "$file" "$OUT/stats.json" "$OUT/time" <<'PY'
import json, sys
name, stats, timing = sys.argv[1], json.load(open(sys.argv[2])), open(sys.argv[3]).read().split()
s, rt = stats["seconds"], stats["roundtrip"]
b = stats["bytes"]
print("| {} | {} | {:,} | {:,} | {} | {} | {} | {:,} | {:,} | {:.1f} | {:.1f} | {:,} | {:,} | {:.2f}, {:.2f} | {} | {:.3g} / {:.3g} | {} |".format(
    name.split(".")[0], stats["mode"], stats["input"]["vertices"], stats["input"]["edges"], len(stats["per_level"]),
    stats["levels"], stats["rules"], stats["instances"], stats["axiom"]["vertices"], s["analysis"] + s["encoding"],
    s["total"], round(b["original"] / 1000), round(b["encoded"] / 1000), b["encoded"] / b["original"], b["encoded_cbor"] / b["original_cbor"],
    "yes" if rt["edges_equal"] else "no", rt["max_displacement_m"], rt["mean_displacement_m"], int(timing[1]) // 1024))
PY
  done
done
