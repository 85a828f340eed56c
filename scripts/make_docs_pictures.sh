#!/usr/bin/env bash
# Makes every picture in docs/ and the README (after scripts/build.sh).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_BUILD_DIR:-$root/build}
out="$root/docs/figures"
mkdir -p "$out"
render() { # INPUT OUTPUT [demo options]
  GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
    --python "$root/scripts/blender_demo.py" -- "$@" >/dev/null
}
render "$root/samples/sample_city.osm" "$out/sample_city.png" --credit ""
if [ -d "$root/../shared/osm" ]; then
  render "$root/../shared/osm/paris_marais.osm.pbf" "$out/paris_marais.png"
else
  echo "note: ../shared/osm is absent: docs/figures/paris_marais.png is not remade" >&2
fi
if [ -f "$root/scripts/make_figures.py" ]; then
  GGG_MODULE_DIR="$build/python" /usr/bin/python3 "$root/scripts/make_figures.py" --out-dir "$out"
fi
# Grammar learning (docs/learning.md): the levels of an encoding and paper against lossless mode.
learn_osm=()
[ -f "$root/../shared/osm/paris_marais.osm.pbf" ] && learn_osm=(--osm "$root/../shared/osm/paris_marais.osm.pbf")
GGG_MODULE_DIR="$build/python" /usr/bin/python3 "$root/scripts/make_learning_figures.py" --out-dir "$out" "${learn_osm[@]}"
# Synthesis (docs/synthesis.md): terminal replacement and two cities stitched by growth.
if [ -d "$root/../shared/osm" ]; then
  GGG_MODULE_DIR="$build/python" /usr/bin/python3 "$root/scripts/make_synthesis_figures.py" --out-dir "$out"
else
  echo "note: ../shared/osm is absent: the synthesis pictures are not remade" >&2
fi
if [ -f "$root/scripts/render_grammar_demo.py" ]; then
  GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
    --python "$root/scripts/render_grammar_demo.py" -- "$out/sierpinski_blender.png" >/dev/null
fi
# The 3-D city (docs/user-guide.md): Build City, Fly-Through and Render City on the sample
# town, and a city on a real extract when ../shared/osm is there.
city_osm=()
[ -f "$root/../shared/osm/paris_marais.osm.pbf" ] && city_osm=(--osm "$root/../shared/osm/paris_marais.osm.pbf")
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/make_city_pictures.py" -- --out-dir "$out" "${city_osm[@]}" >/dev/null
if [ -f "$root/scripts/render_patterns_demo.py" ]; then
  GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
    --python "$root/scripts/render_patterns_demo.py" -- "$out/patterns_overview.png" "$out/patterns_similar.png" \
    >/dev/null
fi
GGG_MODULE_DIR="$build/python" blender -b --factory-startup --python-exit-code 1 \
  --python "$root/scripts/render_synthesis_demo.py" -- "$out/learn_blender.png" "$out/grow_blender.png" \
  --replaced "$out/replace_blender.png" --stitched "$out/stitch_blender.png" --size 1200 >/dev/null
echo "pictures written to $out"
