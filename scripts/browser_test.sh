#!/usr/bin/env bash
# Browser tests of the replay viewer (`unison view`): makes recordings (the 20-row pyramid awake for 600 ticks, a
# networked match with a desync and the host's report, a replay with a changed input and `unison verify --report`,
# a 3D scene), writes their viewer pages and opens them in Debian's chromium, headless, through puppeteer-core
# (tests/browser/viewer_test.mjs). Prints each page's load time. Needs scripts/setup.sh's packages; builds if needed;
# installs the pinned npm packages with `npm ci` (no browser download: the tests use /usr/bin/chromium).
# Usage: scripts/browser_test.sh [--screenshot FILE.png]   (a picture of the match page, for docs/viewer.png)
set -euo pipefail
cd "$(dirname "$0")/.."
U=build/samples/unison
L=build/samples/lockstep/lockstep
if [ ! -x "$U" ] || [ ! -x "$L" ]; then scripts/build.sh; fi
(cd tests/browser && npm ci --no-audit --no-fund --loglevel=error)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# field KEY: a key of the JSON document on stdin (with --first-line, of its first line only).
field() { node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>{if(process.argv[2])s=s.split("\n")[0];console.log(JSON.parse(s)[process.argv[1]])})' "$@"; }

# 1. The 20-row pyramid (scenes::pyramidScene(20, 0.5, false): scenes/pyramid20.json without sleep), 600 ticks.
node -e 'const fs=require("fs");const s=JSON.parse(fs.readFileSync(process.argv[1]));s.sleep=false;fs.writeFileSync(process.argv[2],JSON.stringify(s))' \
  scenes/pyramid20.json "$work/pyramid20.json"
"$U" record "$work/pyramid20.json" --steps 600 -o "$work/pyramid20.urec" >/dev/null
"$U" view "$work/pyramid20.urec" -o "$work/pyramid20.html" >/dev/null
hash300=$("$U" run "$work/pyramid20.json" --steps 300 --hash-every 300 | field hash --first-line)

# 2. A networked match (host + 3 peers over ENet) where one peer desyncs at tick 97: its recording and report.
status=0
"$L" --peers 3 --ticks 240 --rows 8 --fast --desync-at 97 --record "$work/match.urec" --report "$work/match.json" \
  >/dev/null 2>"$work/match.err" || status=$?
if [ "$status" -ne 1 ]; then cat "$work/match.err"; echo "lockstep: expected a desync (exit 1), got $status" >&2; exit 1; fi
"$U" view "$work/match.urec" -o "$work/match.html" --report "$work/match.json" >/dev/null

# 3. A recording replayed with one input changed: `unison verify --report`, then the page with that report.
cat >"$work/inputs.json" <<'EOF'
{"inputs": [{"tick": 10, "type": "apply_impulse", "body": 3, "impulse": [2, 5]},
            {"tick": 40, "type": "apply_impulse", "body": 12, "impulse": [-3, 4]}]}
EOF
sed 's/\[-3, 4\]/[-3, 4.001]/' "$work/inputs.json" >"$work/changed.json"
"$U" record scenes/mixed_pile.json --inputs "$work/inputs.json" --steps 120 --snapshot-every 1 -o "$work/pile.urec" >/dev/null
status=0
"$U" verify "$work/pile.urec" --inputs "$work/changed.json" --report "$work/pile.json" >/dev/null 2>&1 || status=$?
if [ "$status" -ne 1 ]; then echo "verify: expected a desync (exit 1), got $status" >&2; exit 1; fi
"$U" view "$work/pile.urec" -o "$work/pile.html" --report "$work/pile.json" >/dev/null
pileTick=$(field first_desync_tick <"$work/pile.json")

# 4. A 3D scene (boxes, a sphere, a mesh bunny on a plane).
"$U" record scenes/mixed3d.json --steps 120 -o "$work/mixed3d.urec" >/dev/null
"$U" view "$work/mixed3d.urec" -o "$work/mixed3d.html" >/dev/null

cat >"$work/cases.json" <<EOF
[{"page": "$work/pyramid20.html", "tick": 300, "hash": "$hash300", "other_tick": 20},
 {"page": "$work/match.html", "report_tick": 97, "other_tick": 30, "screenshot": true},
 {"page": "$work/pile.html", "report_tick": $pileTick, "tick": $pileTick, "other_tick": 100},
 {"page": "$work/mixed3d.html", "tick": 60, "other_tick": 5}]
EOF
node tests/browser/viewer_test.mjs "$work/cases.json" "$@"
