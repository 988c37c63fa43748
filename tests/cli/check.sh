#!/usr/bin/env bash
# CLI checks for `cagewrap check`: the rig against the character's own skinning at every clip's
# frames. A table (and --json) with the worst vertex, RMS and largest edge stretch and where each is;
# exit 0 within the thresholds, 2 over them, 1 on an error; a deliberately bad cage fails and the
# failure names the clip, vertex and joint; a centimetre-scale character is reported in scene units.
# Usage: check.sh <cagewrap binary> [shared assets dir]. Uses assets/demo_character.glb and demo_cage.obj.
set -u

source "$(dirname "$0")/harness.bash"
need_demo_assets

P="$T/hero.cagewrap"
run new --character "$DEMO" --cage "$CAGE" --out "$P"
check "new exits 0" [ "$rc" -eq 0 ]

# ------------------------------------------------------------------------------ the table
run check --project "$P" --fps 5 --max-worst 0.5 --max-rms 0.5 --max-stretch 1000
check "within loose thresholds: exit 0" [ "$rc" -eq 0 ]
check "a row for the rest pose" has "$T/out" "^rest  *1 "
check "a row per clip" has "$T/out" "^walk  *[0-9][0-9]* "
check "the arm_raise row" has "$T/out" "^arm_raise  *[0-9][0-9]* "
check "the overall row" has "$T/out" "^all  *[0-9][0-9]* "
check "the diagonal in metres" has "$T/out" "diagonal [0-9.]* m$"
check "passed" has "$T/out" "^passed$"
run check --project "$P" --fps 5 --max-worst 0.5 --max-rms 0.5 --max-stretch 1000 --json
check "--json exits 0" [ "$rc" -eq 0 ]
check "--json parses" python3 -c "import json,sys; j=json.load(open('$T/out')); assert j['passed'] and j['units']=='m' and len(j['clips'])==3, j"
check "every clip sampled at least at its fractions" python3 -c "
import json; j=json.load(open('$T/out'))
assert all(c['frames'] >= 5 for c in j['clips'][1:]), [c['frames'] for c in j['clips']]"

# ------------------------------------------------------------------------------ over the thresholds
run check --project "$P" --fps 2 --max-worst 0.0001
check "over a threshold: exit 2" [ "$rc" -eq 2 ]
check "it says what failed, where" has "$T/out" "^FAILED: worst vertex .* (clip '.*' at .* s, vertex [0-9]*, joint '.*')$"

# a cage shifted 30 cm sideways: its vertices take the weights of the wrong limbs
awk '/^v /{printf "v %.6f %s %s\n", $2 + 0.3, $3, $4; next} {print}' "$CAGE" >"$T/shifted.obj"
run check --character "$DEMO" --cage "$T/shifted.obj" --clip walk --fps 5
check "a bad cage fails" [ "$rc" -eq 2 ]
check "and names a joint" has "$T/out" "^FAILED: .*joint '"

# ------------------------------------------------------------------------------ the default rig of a character
run check --character "$DEMO" --clip walk --fps 5 --max-stretch 1000
check "the automatic cage's rig is checked" has "$T/out" "^rig: [0-9]* skin points, cage quality"
check "with the cage report" has "$T/out" "^quality  *[0-9.]*% of skin points"

# ------------------------------------------------------------------------------ centimetres
if "$BIN" make-demo --help 2>/dev/null | grep -q -- "--units"; then
  run make-demo --units cm --cell-size 0.03 --out "$T/cm.glb"
  check "a centimetre demo is made" [ "$rc" -eq 0 ]
  run check --character "$T/cm.glb" --clip walk --fps 5 --max-stretch 1000
  check "its diagonal is in scene units, not metres" has "$T/out" "diagonal [0-9.]* scene units$"
  check "no length is printed in metres" lacks "$T/out" " m (vertex"
fi

# ------------------------------------------------------------------------------ errors
run check
check "neither --project nor --character: exit 1" [ "$rc" -eq 1 ]
check "it says so" has "$T/err" "give either --project or --character"
run check --project "$P" --clip nosuch
check "an unknown clip: exit 1" [ "$rc" -eq 1 ]
check "names the clip" has "$T/err" "no clip named or numbered 'nosuch'"
run check --project "$T/missing.cagewrap"
check "a missing project: exit 1" [ "$rc" -eq 1 ]
check "names the file" has "$T/err" "missing.cagewrap"
run check --project "$P" --cage "$CAGE"
check "--cage with --project is refused" [ "$rc" -eq 1 ]
finish
