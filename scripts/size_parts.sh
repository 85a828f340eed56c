#!/usr/bin/env bash
# Where the bytes of a learned grammar go, against its graph's positions and edges: the
# `bytes.parts_cbor` of `ggg learn` (docs/learning.md#size), as the table there. Default
# options and import, paper mode (add --lossless for lossless). Needs a build (bash
# scripts/build.sh) and ../shared/osm. Usage: bash scripts/size_parts.sh [extra ggg learn flags]
set -euo pipefail
cd "$(dirname "$0")/.."
OSM=../shared/osm
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "| extract | graph: positions | edges | header | grammar: axiom positions | axiom edges | nonterminals | links | corrections | residuals | rules | header | grammar / graph |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for file in moscow_north.osm.gz oakland_west.osm.bz2 krems_at.osm.gz paris_marais.osm.pbf columbus_oh.osm.pbf porto_metro.osm.pbf; do
  build/bin/ggg learn "$OSM/$file" "$@" -o "$OUT/grammar.json" > "$OUT/stats.json" 2>/dev/null
  /usr/bin/python3 - "$file" "$OUT/stats.json" <<'PY'
import json, sys
name, stats = sys.argv[1], json.load(open(sys.argv[2]))
b = stats["bytes"]
g, e = b["parts_cbor"]["original"], b["parts_cbor"]["encoded"]
cells = [g["positions"], g["edges"], g["header"]] + [e[k] for k in ("axiom_positions", "axiom_edges", "nonterminals", "links",
                                                                   "corrections", "residuals", "rules", "header")]
print("| {} | {} | {:.2f} |".format(name.split(".")[0], " | ".join("{:,}".format(c) for c in cells), b["encoded_cbor"] / b["original_cbor"]))
PY
done
