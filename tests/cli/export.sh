#!/usr/bin/env bash
# CLI checks for `cagewrap export`: each mode writes a .glb that passes the Khronos glTF validator
# (when node is installed) and reports its error; bad arguments are refused with a sentence.
# Usage: export.sh <cagewrap binary> [shared assets dir]. Uses assets/demo_character.glb and demo_cage.obj.
set -u

source "$(dirname "$0")/harness.bash"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DEMO="$ROOT/assets/demo_character.glb"
CAGE="$ROOT/assets/demo_cage.obj"
[ -f "$DEMO" ] && [ -f "$CAGE" ] || { echo "skipped: $DEMO or $CAGE not found"; exit 77; }

P="$T/hero.cagewrap"
run new --character "$DEMO" --cage "$CAGE" --out "$P"
check "new exits 0" [ "$rc" -eq 0 ]

for mode in cage baked-animation baked-skin; do
  run export --project "$P" --mode "$mode" --clips walk --fps 4 --out "$T/$mode.glb"
  check "export $mode exits 0" [ "$rc" -eq 0 ]
  check "export $mode says what it wrote" has "$T/out" "^exported $mode of .*hero.cagewrap: 5 frames"
  check "export $mode reports its error" has "$T/out" "error at frames: *mean"
  if command -v node > /dev/null; then
    node "$ROOT/tests/gltf_validate/validate.js" "$T/$mode.glb" > "$T/val.txt" 2>&1
    check "export $mode passes the glTF validator" has "$T/val.txt" "$mode.glb: 0 errors"
  fi
done
check "baked-skin reports the skeleton-only error" has "$T/out" "skeleton only"

run export --project "$P" --mode baked --out "$T/x.glb"
check "an unknown mode is refused" [ "$rc" -ne 0 ]
check "it names the modes" has "$T/err" "should be baked-animation, baked-skin or cage"
run export --project "$P" --mode cage --clips run --out "$T/x.glb"
check "an unknown clip is refused" [ "$rc" -ne 0 ]
check "it names the clips there are" has "$T/err" "no clip named or numbered 'run' (it has 2: walk, arm_raise)"
run export --project "$P" --mode cage --out "$T/x.obj"
check "a non-.glb output is refused" [ "$rc" -ne 0 ]

finish
