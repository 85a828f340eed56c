#!/usr/bin/env bash
# Builds the libFuzzer harnesses (native/fuzz/, clang, ASan + UBSan) in build-fuzz/, makes
# their seed corpora (scripts/fuzz_seeds.py) and runs each harness in turn.
#
#   scripts/fuzz.sh [--runs N] [--seconds S] [--keep-going] [--reseed] [--no-build] [HARNESS...]
#
#   --runs N       stop each harness after N executions (default: no limit)
#   --seconds S    stop each harness after S seconds (default 60 when --runs is not given)
#   --keep-going   fork mode: record crashes, timeouts and out-of-memory and go on
#   --reseed       make the seed corpora again (they are made once, when absent)
#   --no-build     use the harnesses already built
#   HARNESS        osm geojson geojson_region grammar ggraph derive grow (default: all)
#
# Corpora grow in build-fuzz/corpus/<harness>/; crashes, timeouts and out-of-memory inputs are
# written to build-fuzz/findings/<harness>/, the fuzzer's output to build-fuzz/findings/<harness>.log
# and one line per run to build-fuzz/findings/summary.tsv. Limits: 10 s per input, 2 GB.
# Environment: GGG_FUZZ_BUILD_DIR (default build-fuzz), GGG_FUZZ_JOBS (build jobs, default nproc).
# docs/reliability.md explains the harnesses and what was found.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GGG_FUZZ_BUILD_DIR:-$root/build-fuzz}
all=(osm geojson geojson_region grammar ggraph derive grow)
runs=-1
seconds=
keep_going=0
reseed=0
do_build=1
harnesses=()
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --keep-going) keep_going=1; shift ;;
    --reseed) reseed=1; shift ;;
    --no-build) do_build=0; shift ;;
    -h|--help) sed -n '2,/^set -e/{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
[ ${#harnesses[@]} -gt 0 ] || harnesses=("${all[@]}")
for h in "${harnesses[@]}"; do
  [[ " ${all[*]} " == *" $h "* ]] || { echo "fuzz.sh: unknown harness '$h' (${all[*]})" >&2; exit 2; }
done
if [ -z "$seconds" ]; then
  if [ "$runs" -lt 0 ]; then seconds=60; else seconds=0; fi
fi

if [ "$do_build" = 1 ]; then
  bash "$root/scripts/setup.sh"
  if [ ! -f "$build/CMakeCache.txt" ]; then
    generator=()
    command -v ninja >/dev/null && generator=(-G Ninja)
    cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_COMPILER=clang++ -DGGG_FUZZ=ON \
      -DGGG_BUILD_PYTHON=OFF -DGGG_BUILD_TESTS=OFF -DGGG_BUILD_BENCH=OFF
  fi
  cmake --build "$build" --parallel "${GGG_FUZZ_JOBS:-$(nproc)}"
fi

corpus=$build/corpus
if [ "$reseed" = 1 ] || [ ! -d "$corpus" ]; then
  rm -rf "$corpus"
  python3 "$root/scripts/fuzz_seeds.py" --cli "$build/bin/ggg" --out "$corpus"
fi

declare -A max_len=([osm]=131072 [geojson]=65536 [geojson_region]=65536 [grammar]=65536 [ggraph]=65536 [derive]=65536 [grow]=1024)
declare -A dict=([osm]=osm.dict [geojson]=json.dict [geojson_region]=json.dict [grammar]=json.dict [ggraph]=json.dict [derive]=json.dict [grow]=)
findings=$build/findings
mkdir -p "$findings"
# Harnesses write the input to a temporary file for readers that take a path; one that
# crashes leaves it behind, so keep them in the build folder.
export TMPDIR=$build/tmp
mkdir -p "$TMPDIR"
[ -f "$findings/summary.tsv" ] || printf 'date\tharness\texecutions\tseconds\tcov\tft\tcorpus\tfindings\texit\n' > "$findings/summary.tsv"
status=0
for h in "${harnesses[@]}"; do
  mkdir -p "$corpus/$h" "$findings/$h"
  log=$findings/$h.log
  before=$(find "$corpus/$h" -type f | wc -l)
  options=(-rss_limit_mb=2048 -timeout=10 -max_len="${max_len[$h]}" -print_final_stats=1
           -artifact_prefix="$findings/$h/" -runs="$runs")
  [ -n "${dict[$h]}" ] && options+=(-dict="$root/native/fuzz/${dict[$h]}")
  [ "$seconds" -gt 0 ] && options+=(-max_total_time="$seconds")
  [ "$keep_going" = 1 ] && options+=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
  echo "fuzz.sh: $h (log: $log)"
  rm -f "$TMPDIR"/ggg-fuzz-*
  start=$(date +%s)
  rc=0
  (cd "$findings/$h" && "$build/fuzz/fuzz_$h" "${options[@]}" "$corpus/$h") >"$log" 2>&1 || rc=$?
  elapsed=$(( $(date +%s) - start ))
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || true)
  [ -n "$execs" ] || execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#' || true)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+' || true)
  ft=$(grep -oE 'ft: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+' || true)
  files=$(find "$corpus/$h" -type f | wc -l)
  found=$(find "$findings/$h" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' \) | wc -l)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -I)" "$h" "${execs:-?}" "$elapsed" "${cov:-?}" "${ft:-?}" \
    "$files" "$found" "$rc" >> "$findings/summary.tsv"
  echo "fuzz.sh: $h: ${execs:-?} executions in ${elapsed} s, cov ${cov:-?} ft ${ft:-?}, $found finding(s) so far, exit $rc"
  # libFuzzer reads the whole corpus before it tries anything new and looks at the time only
  # after: a run no longer than that has fuzzed nothing.
  if [ -n "$execs" ] && [ "$execs" -le $((before + 1)) ] && [ "$rc" = 0 ]; then
    echo "fuzz.sh: $h: only the $before inputs of its corpus were run (reading them took longer than --seconds): give it more time" >&2
  fi
  [ "$rc" = 0 ] || status=1
done
exit $status
