#!/usr/bin/env bash
# Cross-build determinism check: builds the simulation libraries and `unison_golden` with gcc -O0, gcc -O2,
# gcc -O3, clang -O2 and gcc for aarch64 (run under qemu-aarch64), runs the golden scenes in each, prints a matrix
# builds x scenes of chain hashes (the XXH3 of every tick's state hash) and exits 1 if any build differs from the
# first, 2 if a build or run fails.
#
# Usage: scripts/determinism.sh [--quick] [--reference DIR]
#   --quick           only gcc -O2, clang -O2 and aarch64 (the three code generators; about half the time)
#   --reference DIR   the first row is DIR/replay/unison_golden of an already built tree (e.g. build/ after
#                     scripts/build.sh: gcc, Release -O2, the shipped build), which replaces the gcc -O2 build.
#                     CI runs --quick --reference build: clang -O2 and aarch64 against the tested build.
# Build folders: build-det-NAME/ (kept, so a second run only rebuilds what changed). Uses -j2.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

quick=0
reference=""
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1; shift ;;
    --reference) reference=${2:?usage: scripts/determinism.sh [--quick] [--reference DIR]}; shift 2 ;;
    *) echo "usage: scripts/determinism.sh [--quick] [--reference DIR]" >&2; exit 2 ;;
  esac
done
if [ -n "$reference" ] && [ ! -x "$reference/replay/unison_golden" ]; then
  echo "error: $reference/replay/unison_golden is not built (scripts/build.sh builds it)" >&2
  exit 2
fi

# Cross compiler and emulator (Debian: g++-aarch64-linux-gnu, qemu-user); clang for the clang build.
scripts/setup.sh --determinism

# Header-only dependencies for the cross build: only these folders, never all of /usr/include (its x86-64 C
# library headers must not shadow the aarch64 ones).
headers="$root/build-det-headers"
mkdir -p "$headers"
ln -sfn /usr/include/eigen3 "$headers/eigen3"
ln -sfn /usr/include/nlohmann "$headers/nlohmann"
ln -sfn /usr/include/xxhash.h "$headers/xxhash.h"

# name | C++ compiler | optimisation | extra cmake arguments | runner
builds=(
  "gcc-O0|g++|-O0||"
  "gcc-O2|g++|-O2||"
  "gcc-O3|g++|-O3||"
  "clang-O2|clang++|-O2||"
  "aarch64-gcc-O2|aarch64-linux-gnu-g++|-O2|-DCMAKE_SYSTEM_NAME=Linux -DCMAKE_SYSTEM_PROCESSOR=aarch64 -DUNISON_HEADER_DIR=$headers|qemu-aarch64 -L /usr/aarch64-linux-gnu"
)
if [ "$quick" = 1 ]; then
  builds=("${builds[1]}" "${builds[3]}" "${builds[4]}")
fi
if [ -n "$reference" ]; then
  # The reference tree is the first row; its own build is not repeated.
  rest=()
  for spec in "${builds[@]}"; do [[ "$spec" == gcc-O2\|* ]] || rest+=("$spec"); done
  builds=("reference|||||$reference" "${rest[@]}")
fi

names=()
declare -A result
scenes=()
for spec in "${builds[@]}"; do
  IFS='|' read -r name cxx opt extra runner tree <<<"$spec"
  if [ -n "${tree:-}" ]; then
    golden="$tree/replay/unison_golden"
    echo "== $name: running the golden scenes of $golden" >&2
  else
    dir="$root/build-det-$name"
    log="$dir/determinism.log"
    golden="$dir/replay/unison_golden"
    mkdir -p "$dir"
    echo "== $name: building" >&2
    # A custom build type, so the optimisation level is exactly $opt (Release pins -O2 in CMakeLists.txt).
    cc=${cxx/clang++/clang}
    cc=${cc/g++/gcc}
    # shellcheck disable=SC2086
    if ! cmake -S "$root" -B "$dir" -DCMAKE_BUILD_TYPE=Det -DCMAKE_CXX_FLAGS_DET="$opt" -DCMAKE_CXX_COMPILER="$cxx" \
          -DCMAKE_C_COMPILER="$cc" \
          -DUNISON_MINIMAL=ON $extra >"$log" 2>&1 ||
       ! cmake --build "$dir" -j2 --target unison_golden >>"$log" 2>&1; then
      echo "error: build $name failed; see $log" >&2
      exit 2
    fi
    echo "== $name: running the golden scenes" >&2
  fi
  # shellcheck disable=SC2086
  if ! out=$($runner "$golden"); then
    echo "error: $name: unison_golden failed" >&2
    exit 2
  fi
  names+=("$name")
  while read -r scene steps final chain; do
    result["$name/$scene"]="$chain"
    result["$name/$scene/final"]="$final"
    [ "$name" = "${names[0]}" ] && scenes+=("$scene")
  done <<<"$out"
done

# The matrix: one row per build, one column per scene, each cell the chain hash of that run.
printf '%-16s' "build"
for s in "${scenes[@]}"; do printf ' %-18s' "$s"; done
printf '\n'
status=0
for n in "${names[@]}"; do
  printf '%-16s' "$n"
  for s in "${scenes[@]}"; do
    cell="${result[$n/$s]:-missing}"
    mark=" "
    if [ "$cell" != "${result[${names[0]}/$s]}" ]; then
      mark="!"
      status=1
    fi
    printf ' %-17s%s' "$cell" "$mark"
  done
  printf '\n'
done
printf '%-16s' "final hash"
for s in "${scenes[@]}"; do printf ' %-18s' "${result[${names[0]}/$s/final]}"; done
printf '\n'
if [ "$status" = 0 ]; then
  echo "determinism: all ${#names[@]} builds agree on all ${#scenes[@]} scenes"
else
  echo "determinism: MISMATCH (cells marked !)" >&2
fi
exit $status
