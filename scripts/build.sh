#!/usr/bin/env bash
# Configures and builds the library, the CLI, the Python module (against /usr/bin/python3,
# the Python Debian's Blender runs), the tests and benchmarks, and packages the add-on.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_BUILD_DIR:-$root/build}
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DPython_EXECUTABLE=/usr/bin/python3 -DGGG_STRICT_WARNINGS=ON
fi
cmake --build "$build" --parallel "$(nproc)"
/usr/bin/python3 "$root/scripts/package_addon.py" --module-dir "$build/python" --out "$root/dist/road_grammar.zip"
