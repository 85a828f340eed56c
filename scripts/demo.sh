#!/usr/bin/env bash
# Installs what is missing, builds, and runs the demo on the bundled sample city: the OSM
# file is imported into a headless Blender scene and a picture of it is rendered; its grammar
# is learned, decoded back and used to grow a new district; the grown town is built as a 3-D
# city and rendered as a still and a fly-through.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_BUILD_DIR:-$root/build}
out=${1:-$root/out/demo}
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh"
mkdir -p "$out"
"$build/bin/ggg" info "$root/samples/sample_city.osm" --highways all | tee "$out/sample_city_info.json"
"$build/bin/ggg" export "$root/samples/sample_city.osm" --highways all -o "$out/sample_city.geojson"
# Its grammar: learned losslessly from the drivable streets, written, decoded back to the same
# streets, and used to grow a new district west of the grid (a 750 m x 780 m region).
"$build/bin/ggg" learn "$root/samples/sample_city.osm" --lossless -o "$out/sample_city.grammar.json" \
  --stats "$out/sample_city.learn.json" >/dev/null
"$build/bin/ggg" decode "$out/sample_city.grammar.json" -o "$out/sample_city.decoded.geojson" >/dev/null
cat > "$out/new_district.geojson" <<'GEOJSON'
{"type": "Feature", "properties": {"name": "new district"}, "geometry": {"type": "Polygon", "coordinates":
 [[[8.9306, 45.9956], [8.9403, 45.9956], [8.9403, 46.0026], [8.9306, 46.0026], [8.9306, 45.9956]]]}}
GEOJSON
"$build/bin/ggg" grow "$out/sample_city.grammar.json" --base "$root/samples/sample_city.osm" --highways all \
  --region "$out/new_district.geojson" --seed 1 -o "$out/grown_town.ggraph" | tee "$out/grow.json"
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/blender_demo.py" -- "$root/samples/sample_city.osm" "$out/sample_city.png" --credit ""
# The 3-D city of the grown town: a still and a three-second fly-through (MP4).
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/render_city.py" -- "$out/grown_town.ggraph" --out "$out" --credit "" \
  --size 960x540 --samples 16 --flythrough 3 --fly-size 480x270 --fly-samples 2
echo "demo written to $out (sample_city.png, sample_city.geojson, sample_city_info.json, sample_city.grammar.json," \
  "sample_city.learn.json, sample_city.decoded.geojson, new_district.geojson, grown_town.ggraph, grow.json," \
  "city.png of the grown town, flythrough.mp4)"
