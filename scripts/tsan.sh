#!/usr/bin/env bash
# ThreadSanitizer run of the threaded tests: builds the simulation libraries and the "threads" suite
# (tests/test_threads.cpp: the built-in pool, an embedding job system's callbacks, and worlds stepped on 2 and 4
# threads with and without a budget) with -fsanitize=thread in build-tsan/, and runs it. Exits non-zero on any
# data race ThreadSanitizer reports (halt_on_error) or any failed check.
#
# Usage: scripts/tsan.sh            (build folder build-tsan/ is kept, so a second run only rebuilds what changed)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --tsan
# clang: GCC builds one function of the solver in two versions picked by an ifunc resolver at load time
# (core/lcp_workspace.h), and an instrumented resolver runs before the ThreadSanitizer runtime is up (a crash at
# start-up); clang builds only the one version.
cxx=${CXX:-clang++}
mkdir -p build-tsan
log=build-tsan/tsan-build.log
# A cache made with another compiler would be wiped by CMake together with the sanitizer flags: start over then.
if [ -f build-tsan/CMakeCache.txt ] && ! grep -q "CMAKE_CXX_COMPILER:[A-Z]*=.*$(basename "$cxx")\$" build-tsan/CMakeCache.txt; then
  rm -rf build-tsan/CMakeCache.txt build-tsan/CMakeFiles
fi
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Tsan -DCMAKE_CXX_COMPILER="$cxx" \
      -DCMAKE_CXX_FLAGS_TSAN="-O1 -gline-tables-only -fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" \
      -DUNISON_BUILD_TESTS=ON -DUNISON_BUILD_BENCH=OFF -DUNISON_BUILD_SHARED=OFF >"$log" 2>&1 || { cat "$log"; exit 2; }
cmake --build build-tsan -j2 --target unison_threads_tests >>"$log" 2>&1 || { tail -50 "$log"; exit 2; }
# The build must really be instrumented: an uninstrumented binary would pass without checking anything.
nm build-tsan/tests/unison_threads_tests >build-tsan/symbols.txt
grep -q " T __tsan_init$" build-tsan/symbols.txt || { echo "error: not built with ThreadSanitizer" >&2; exit 2; }
# The golden-scene case steps every golden scene 6 times; under TSan (5-15x slower) UNISON_THREADS_QUICK makes it
# step each scene 30 ticks instead of up to 120 (read by the test).
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" UNISON_THREADS_QUICK=1 \
  build-tsan/tests/unison_threads_tests --test-suite=threads
