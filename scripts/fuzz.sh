#!/usr/bin/env bash
# Runs the fuzz targets of fuzz/ one after the other, each for a fixed time (or a fixed number of executions), in the
# sanitizer tree build-asan/ (its fuzz targets built here through scripts/sanitize.sh --build-fuzz if needed).
#
# Usage: scripts/fuzz.sh [--seconds S | --runs N] [TARGET...]
#   --seconds S   run each target S seconds (default 25; .ci/run uses 10)
#   --runs N      run each target for N executions instead (docs/input-policy.md lists the long runs)
#   TARGET        a target of fuzz/CMakeLists.txt without its fuzz_ prefix, e.g. scene2d or lcp (default: all of
#                 them, as listed in build-asan/fuzz/targets.txt)
# The seeds in fuzz/corpus/TARGET are copied to build-asan/fuzz-corpus/TARGET, where new inputs accumulate between
# runs (the repository's corpus stays small). A finding (crash, sanitizer report, leak, timeout, out-of-memory) is
# saved in build-asan/fuzz-findings/TARGET/ and makes the script exit 1 after all targets ran.
# Prints one line per target: executions, executions per second, coverage edges, corpus size.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

limit=(-max_total_time=25)
if [ "${1:-}" = "--seconds" ]; then limit=(-max_total_time="$2"); shift 2; fi
if [ "${1:-}" = "--runs" ]; then limit=(-runs="$2"); shift 2; fi
targets=("$@")

# Up to date after scripts/sanitize.sh (nothing to do); the build's output goes to a log unless it fails.
mkdir -p build-asan
scripts/sanitize.sh --build-fuzz >build-asan/fuzz-build.log 2>&1 || { cat build-asan/fuzz-build.log; exit 2; }
[ ${#targets[@]} -eq 0 ] && mapfile -t targets < build-asan/fuzz/targets.txt
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

status=0
for t in "${targets[@]}"; do
  corpus="$root/build-asan/fuzz-corpus/$t" findings="$root/build-asan/fuzz-findings/$t" log="$root/build-asan/fuzz-$t.log"
  mkdir -p "$corpus" "$findings"
  cp -n "$root/fuzz/corpus/$t/"* "$corpus/" 2>/dev/null || true
  # -timeout: one input may take at most 10 s; -rss_limit_mb: the whole process at most 2 GB; -max_len: 16 KiB inputs.
  if build-asan/fuzz/fuzz_"$t" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
       -artifact_prefix="$findings/" "$corpus" >"$log" 2>&1; then
    result=ok
  else
    result="FINDING (see $log and $findings/)"
    status=1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  files=$(find "$corpus" -type f | wc -l)
  printf 'fuzz %-10s executions %10s  per second %6s  coverage %6s  corpus %5s  %s\n' "$t" "$runs" "$rate" "$cov" "$files" "$result"
done
exit $status
