#!/usr/bin/env bash
# The README's demo command: installs dependencies, builds, runs the demo. Pictures go to out/ (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
out="${1:-out}"
build/samples/unison_demo "$out"
echo "Open $out/*.svg in a browser to see the pictures."
