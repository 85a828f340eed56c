#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: GoogleTest through ctest, the
# add-on's core with pytest, then pytest inside headless Blender. Tests that need the real
# OSM extracts read ../shared/osm.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_BUILD_DIR:-$root/build}
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh"
if [ ! -d "$root/../shared/osm" ]; then
  echo "note: ../shared/osm is absent: the tests on real OpenStreetMap extracts will be skipped" >&2
fi
(cd "$build" && ctest --output-on-failure --parallel "$(nproc)")
# The add-on's pure-Python core (addon/road_grammar/core), outside Blender.
GGG_MODULE_DIR="$build/python" /usr/bin/python3 -B -m pytest -q -p no:cacheprovider "$root/addon/tests"
bash "$root/scripts/run_blender_tests.sh" --zip "$root/dist/road_grammar.zip"
# The library and its fast tests again under AddressSanitizer and UndefinedBehaviorSanitizer
# (build-sanitize/; docs/reliability.md): any finding fails the run.
bash "$root/scripts/sanitize.sh"
