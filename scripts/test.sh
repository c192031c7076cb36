#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs every test suite through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j 2
