#!/usr/bin/env bash
# Sizes of learned grammars against their graphs on every extract of ../shared/osm, default
# options, both modes: the table of docs/learning.md#size. Both are packed the same way
# (docs/grammar-format.md) and measured as JSON text and as CBOR. Needs a build
# (bash scripts/build.sh). Usage: bash scripts/size_table.sh [extra ggg learn flags]
set -euo pipefail
cd "$(dirname "$0")/.."
OSM=../shared/osm
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "| extract | vertices | paper: rules | axiom vertices | JSON | CBOR | mean / max error (m) | lossless: rules | JSON | CBOR |"
echo "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|"
for path in "$OSM"/*.osm*; do
  name=$(basename "$path")
  build/bin/ggg learn "$path" "$@" -o "$OUT/paper.json" > "$OUT/paper.stats" 2>/dev/null
  build/bin/ggg learn "$path" --lossless "$@" -o "$OUT/lossless.json" > "$OUT/lossless.stats" 2>/dev/null
  /usr/bin/python3 - "$name" "$OUT/paper.stats" "$OUT/lossless.stats" <<'PY'
import json, sys
name, paper, lossless = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
def ratios(s):
    b = s["bytes"]
    return b["encoded"] / b["original"], b["encoded_cbor"] / b["original_cbor"]
pj, pc = ratios(paper)
lj, lc = ratios(lossless)
rt = paper["roundtrip"]
print("| {} | {:,} | {} | {:,} | {:.2f} | {:.2f} | {:.2f} / {:.2f} | {} | {:.2f} | {:.2f} |".format(
    name.split(".")[0], paper["input"]["vertices"], paper["rules"], paper["axiom"]["vertices"], pj, pc,
    rt["mean_displacement_m"], rt["max_displacement_m"], lossless["rules"], lj, lc))
PY
done
