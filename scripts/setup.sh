#!/usr/bin/env bash
# Installs every Debian package the project needs (build, tests, Blender, demo).
# Idempotent: packages already present are left as they are.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libosmium2-dev libprotozero-dev libbz2-dev zlib1g-dev libexpat1-dev
  libeigen3-dev libboost-dev libproj-dev proj-data libtbb-dev
  nlohmann-json3-dev libcli11-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  libgtest-dev libgmock-dev libbenchmark-dev
  blender zip xvfb xauth python3-matplotlib time
  # Blender opens OpenGL at run time (libepoxy); headless Eevee renders and the windowed
  # undo test under Xvfb need Mesa's software renderer, which Blender does not depend on.
  libgl1 libegl1 libglx-mesa0 libegl-mesa0 libgl1-mesa-dri
  # The windowed render test presses Esc as a keyboard does (XTest): Blender stops its render
  # job on a real key only.
  libxtst6
  # The 3-D city: Clipper polygon clipping (native), PIL for the docs pictures' palettes.
  libpolyclipping-dev python3-pil
  # The JSON Schemas of docs/schemas, checked against the files ggg writes.
  python3-jsonschema
  # libFuzzer harnesses (cmake -DGGG_FUZZ=ON, scripts/fuzz.sh): clang 14 with its sanitizer
  # runtimes; osmium-tool turns the OSM seed slices into PBF and OPL.
  clang libclang-rt-14-dev osmium-tool
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: missing packages (${missing[*]}); run this script as root" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
