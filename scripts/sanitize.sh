#!/usr/bin/env bash
# Builds the library, the CLI and the unit tests with AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer (cmake -DGGG_SANITIZE=ON, in build-sanitize/) and runs the tests
# labelled `fast` (native/tests/test_labels.cmake) under them; the CLI cases run the
# sanitized `ggg`. Any sanitizer report, from a test or from a `ggg` that a test starts, fails
# the script. Extra arguments go to ctest (e.g. -R Growth, or -L slow for the other tests).
# See docs/reliability.md.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_SANITIZE_BUILD_DIR:-$root/build-sanitize}
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -d "$root/../shared/osm" ]; then
  echo "note: ../shared/osm is absent: the tests on real OpenStreetMap extracts will be skipped" >&2
fi

# -O1: several times faster tests than -O0 for a longer build; -g1: line tables for the stack
# traces at a third less compile time than -g; asserts on (no NDEBUG), and the standard
# library's own checks (bounds of operator[], preconditions) as well.
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="-D_GLIBCXX_ASSERTIONS" \
  -DGGG_SANITIZE=ON -DGGG_BUILD_TESTS=ON -DGGG_BUILD_PYTHON=OFF -DGGG_BUILD_BENCH=OFF \
  -DGGG_STRICT_WARNINGS=OFF >/dev/null
start=$SECONDS
cmake --build "$build" --parallel "$(nproc)" --target ggg ggg_cli ggg_tests
echo "sanitize: build took $((SECONDS - start)) s"

# AddressSanitizer's reports go to files, one per process named after its program, and the
# script fails when there is any: a `ggg` started by a test that expects it to fail (exit
# code 1) would otherwise hide its report. UndefinedBehaviorSanitizer writes to stderr only
# (its log_path has no effect beside AddressSanitizer in GCC 12), so its exit code is
# unusual: a test that runs `ggg` and sees exit code 97 has met undefined behaviour there.
logs=$build/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:exitcode=98:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1:log_path=$logs/asan:log_exe_name=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=97"
labels=(-L fast)
for a in "$@"; do
  case $a in -L|-LE|--label-regex|--label-exclude) labels=() ;; esac
done
start=$SECONDS
status=0
(cd "$build" && ctest "${labels[@]}" --output-on-failure --parallel "$(nproc)" "$@") || status=$?
echo "sanitize: tests took $((SECONDS - start)) s"
reports=("$logs"/*)
if [ -e "${reports[0]}" ]; then
  echo "sanitize: ${#reports[@]} sanitizer report(s):" >&2
  for r in "${reports[@]}"; do
    echo "==== $r" >&2
    cat "$r" >&2
  done
  status=1
fi
if [ "$status" -ne 0 ]; then
  echo "sanitize: FAILED" >&2
else
  echo "sanitize: no findings"
fi
exit "$status"
