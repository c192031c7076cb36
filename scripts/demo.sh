#!/usr/bin/env bash
# The README's demo command: installs dependencies, builds, runs the demo. Pictures go to out/ (or $1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
out="${1:-out}"
build/samples/unison_demo "$out"
build/samples/bunnies --quiet --out "$out/bunnies"   # the paper's figs. 4-5: SVG frames every 30 steps
echo "Open $out/*.svg and $out/bunnies/*.svg in a browser to see the pictures."
