#!/usr/bin/env bash
# Installs what is missing, builds, and runs the demo on the bundled sample city:
# the OSM file is imported into a headless Blender scene and a picture of it is rendered.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_BUILD_DIR:-$root/build}
out=${1:-$root/out/demo}
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh"
mkdir -p "$out"
"$build/bin/ggg" info "$root/samples/sample_city.osm" --highways all | tee "$out/sample_city_info.json"
"$build/bin/ggg" export "$root/samples/sample_city.osm" --highways all -o "$out/sample_city.geojson"
# Its grammar: learned losslessly, written, and decoded back to the same streets.
"$build/bin/ggg" learn "$root/samples/sample_city.osm" --highways all --lossless -o "$out/sample_city.grammar.json" \
  --stats "$out/sample_city.learn.json" >/dev/null
"$build/bin/ggg" decode "$out/sample_city.grammar.json" -o "$out/sample_city.decoded.geojson" >/dev/null
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/blender_demo.py" -- "$root/samples/sample_city.osm" "$out/sample_city.png" --credit ""
# The 3-D city of the sample town: a still and a three-second fly-through (MP4).
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/render_city.py" -- "$root/samples/sample_city.osm" --out "$out" --credit "" \
  --size 960x540 --samples 16 --flythrough 3 --fly-size 480x270 --fly-samples 2
echo "demo written to $out (sample_city.png, sample_city.geojson, sample_city_info.json, sample_city.grammar.json," \
  "sample_city.learn.json, sample_city.decoded.geojson, city.png, flythrough.mp4)"
