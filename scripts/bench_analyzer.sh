#!/usr/bin/env bash
# Times `ggg analyze` (pruned and --full) on real extracts; the figures in docs/benchmarks.md.
# Needs ../shared/osm beside the project and a build (bash scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
OSM=../shared/osm
OUT=$(mktemp -d)
for spec in "barcelona_eixample.osm drivable" "barcelona_eixample.osm all" "columbus_oh.osm.pbf drivable" "porto_metro.osm.pbf all"; do
  set -- $spec
  for mode in "" "--full"; do
    if [ "$2" = all ] && [ "$1" = porto_metro.osm.pbf ] && [ "$mode" = "--full" ]; then continue; fi
    /usr/bin/time -f "%e %M" -o $OUT/t build/bin/ggg analyze $OSM/$1 --highways $2 --max-order 6 $mode --top 3 > $OUT/o.json 2>/dev/null
    python3 -c "
import json; d=json.load(open('$OUT/o.json')); t=open('$OUT/t').read().split()
print('$1', '$2', '${mode:-pruned}', d['graph']['vertices'], d['graph']['edges'], 'analysis_s=%.2f'%d['seconds'], 'detected', d['detected'], 'wall', t[0], 'MB', int(t[1])//1024, 'top', [(g['order'], g['occurrences']) for g in d['isogroups']])"
  done
done
/usr/bin/time -f "%e %M" -o $OUT/t build/bin/ggg analyze $OSM/porto_metro.osm.pbf --highways all --max-order 8 --top 3 > $OUT/o.json 2>/dev/null
python3 -c "
import json; d=json.load(open('$OUT/o.json')); t=open('$OUT/t').read().split()
print('porto order8', d['graph']['vertices'], d['graph']['edges'], 'analysis_s=%.2f'%d['seconds'], 'detected', d['detected'], 'wall', t[0], 'MB', int(t[1])//1024)"
# Table 1 of the paper: the leading patterns' frequencies, pruned against full, each leading
# pattern recounted until it is the mean of its copies (--recount 8).
for spec in "barcelona_eixample.osm drivable" "columbus_oh.osm.pbf drivable"; do
  set -- $spec
  for mode in "" "--full"; do
    /usr/bin/time -f "%e %M" -o $OUT/t build/bin/ggg analyze $OSM/$1 --highways $2 --max-order 6 $mode --recount 8 --top 5 > $OUT/o.json 2>/dev/null
    python3 -c "
import json; d=json.load(open('$OUT/o.json')); t=open('$OUT/t').read().split()
print('$1', '$2', '${mode:-pruned}', 'recount 8', 'analysis_s=%.2f'%d['seconds'], 'wall', t[0], 'MB', int(t[1])//1024, 'top', [(g['order'], g['edge_count'], g['occurrences']) for g in d['isogroups']])"
  done
done
