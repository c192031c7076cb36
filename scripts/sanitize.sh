#!/usr/bin/env bash
# The sanitizer jobs of CI (docs/input-policy.md "CI"): one clang Debug tree, build-asan/, with AddressSanitizer and
# UndefinedBehaviorSanitizer (-O1, every report fatal), warnings as errors in the project's own code, and the
# fuzz targets' coverage instrumentation (so scripts/fuzz.sh reuses the same tree). Then:
#   default          build, then run every doctest suite and the CLI under ASan+UBSan (ctest)
#   --build-only     only build
#   --tsan PATTERN   build build-tsan/ with ThreadSanitizer and run the doctest cases whose names match PATTERN
#                    (doctest's --test-case filter, e.g. '*thread*'); a pattern that matches no case is reported and
#                    passes, so the job can sit in CI before the threaded code lands.
# Uses -j2. Exit status: that of the build or of the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --sanitize

common=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DUNISON_BUILD_BENCH=OFF
        -DUNISON_WERROR=ON)
if [ "${1:-}" = "--tsan" ]; then
  pattern="${2:?usage: scripts/sanitize.sh --tsan PATTERN}"
  # No test case name matches (doctest wildcards, case-insensitive): say so without building a tree for nothing.
  regex=$(printf '%s' "$pattern" | sed 's/[.[\^$]/\\&/g; s/\*/.*/g; s/?/./g')
  matches=$(grep -hoE 'TEST_CASE\("[^"]*"' tests/*.cpp | sed 's/^TEST_CASE("//; s/"$//' | grep -ciE "^${regex}$" || true)
  if [ "$matches" = 0 ]; then
    echo "sanitize --tsan: no test case matches '$pattern' yet; nothing to run"
    exit 0
  fi
  cmake -S . -B build-tsan "${common[@]}" -DCMAKE_CXX_FLAGS="-O1 -g -fsanitize=thread -fno-omit-frame-pointer" >/dev/null
  cmake --build build-tsan -j2 --target unison_tests
  TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" build-tsan/tests/unison_tests --test-case="$pattern" --no-intro
  exit $?
fi

cmake -S . -B build-asan "${common[@]}" -DUNISON_BUILD_FUZZ=ON \
  -DCMAKE_CXX_FLAGS="-O2 -g -DEIGEN_NO_DEBUG -fsanitize=address,undefined -fsanitize=fuzzer-no-link -fno-sanitize-recover=all -fno-omit-frame-pointer" \
  >/dev/null
cmake --build build-asan -j2
[ "${1:-}" = "--build-only" ] && exit 0
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-asan --output-on-failure -j 2
