#!/usr/bin/env bash
# Configures and builds Unison in build/ (Release, deterministic flags). Usage: scripts/build.sh [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DUNISON_BUILD_TESTS=ON -DUNISON_BUILD_BENCH=ON -DUNISON_BUILD_SAMPLES=ON "$@" >/dev/null
cmake --build build -j "$(nproc)"
