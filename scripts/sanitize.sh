#!/usr/bin/env bash
# The sanitizer tree (docs/input-policy.md "CI": CI builds its fuzz targets through scripts/fuzz.sh; the whole suite
# here runs before a release): one clang Debug tree, build-asan/, with AddressSanitizer and
# UndefinedBehaviorSanitizer (-O1, every report fatal), warnings as errors in the project's own code, and the
# fuzz targets' coverage instrumentation (so scripts/fuzz.sh reuses the same tree). Then:
#   default          build, then run every doctest suite and the CLI under ASan+UBSan (ctest); with -O2 -g it took
#                    17 min to build and 11-13 min to test on 2 cores (the tests run 15-20x slower than in Release)
#   --build-only     only build
#   --build-fuzz     only build the fuzz targets and the libraries they link (about 5.5 min; scripts/fuzz.sh)
# ThreadSanitizer has its own script and tree: scripts/tsan.sh (build-tsan/).
# Uses -j2. Exit status: that of the build or of the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --sanitize

common=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DUNISON_BUILD_TESTS=ON
        -DUNISON_BUILD_SAMPLES=ON -DUNISON_BUILD_BENCH=OFF -DUNISON_BUILD_SHARED=OFF -DUNISON_WERROR=ON)
flags="-fsanitize=address,undefined -fsanitize=fuzzer-no-link -fno-sanitize-recover=all -fno-omit-frame-pointer"

cmake -S . -B build-asan "${common[@]}" -DUNISON_BUILD_FUZZ=ON \
  -DCMAKE_CXX_FLAGS="-O1 -DEIGEN_NO_DEBUG $flags" -DCMAKE_C_FLAGS="-O1 $flags" \
  -DCMAKE_CXX_FLAGS_DEBUG=-gline-tables-only -DCMAKE_C_FLAGS_DEBUG=-gline-tables-only \
  >/dev/null
if [ "${1:-}" = "--build-fuzz" ]; then
  cmake --build build-asan -j2 --target fuzz_targets  # every target of fuzz/CMakeLists.txt
  exit 0
fi
cmake --build build-asan -j2
[ "${1:-}" = "--build-only" ] && exit 0
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# The largest Box2D-manifold LCPs take minutes under the sanitizers; the suite skips them there (its smaller
# members run the same code).
export UNISON_SANITIZER_QUICK=1
ctest --test-dir build-asan --output-on-failure -j 2
