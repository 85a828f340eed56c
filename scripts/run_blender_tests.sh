#!/usr/bin/env bash
# Runs the add-on's tests inside headless Blender (pytest inside `blender -b`).
#   scripts/run_blender_tests.sh [--zip dist/road_grammar.zip] [pytest args...]
# The native module is taken from $GGG_MODULE_DIR (default: build/python), or from the
# zip when --zip is given. Exits non-zero on any failure, including "no tests collected".
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
blender="${BLENDER:-blender}"
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "error: Blender not found (install it with scripts/setup.sh, or set BLENDER=/path/to/blender)" >&2
  exit 1
fi
export GGG_MODULE_DIR="${GGG_MODULE_DIR:-$repo/build/python}"
status=0
"$blender" -b --factory-startup --python-exit-code 1 --python blender_tests/run.py -- "$@" || status=$?
if [ "$status" -ne 0 ]; then
  echo "Blender tests failed (exit $status)" >&2
fi
exit "$status"
