#!/usr/bin/env bash
# CLI checks for `cagewrap export`: each glb mode writes a .glb that passes the Khronos glTF
# validator (when node is installed) and reports its error; --format obj writes one OBJ per frame
# (beside F.obj or into a folder), --format json the rig description; a terminal sees the progress;
# bad arguments are refused with a sentence, before any work.
# Usage: export.sh <cagewrap binary> [shared assets dir]. Uses assets/demo_character.glb and demo_cage.obj.
set -u

source "$(dirname "$0")/harness.bash"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
need_demo_assets

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

run export --project "$P" --format glb --mode baked-skin --clips walk --fps 4 --keypose-steps 0 --out "$T/explicit.glb"
check "--format glb is the default made explicit" [ "$rc" -eq 0 ]
check "it wrote the file" [ -s "$T/explicit.glb" ]
check "no keypose line without keypose poses" lacks "$T/out" "keypose"

run export --project "$P" --format obj --clips walk --fps 4 --out "$T/hero.obj"
check "export obj exits 0" [ "$rc" -eq 0 ]
check "obj: one file per frame, named by clip and frame" [ -s "$T/hero_walk_0000.obj" ]
check "obj: up to the last frame" [ -s "$T/hero_walk_0004.obj" ]
check "obj: no more than the frames" [ ! -e "$T/hero_walk_0005.obj" ]
check "obj: it says what it wrote" has "$T/out" "^exported skin as OBJ of .*: 5 frames, wrote 5 OBJ files .*hero_walk_0000.obj .. hero_walk_0004.obj"
check "obj: the skin's vertices" [ "$(grep -c '^v ' "$T/hero_walk_0002.obj")" -eq 34800 ]
run export --project "$P" --format obj --mode cage --clips arm_raise --fps 2 --out "$T/cage_frames"
check "export obj of the cage into a folder exits 0" [ "$rc" -eq 0 ]
check "obj cage: 5 frames in the folder" [ "$(ls "$T/cage_frames" | wc -l)" -eq 5 ]
check "obj cage: the cage's polygons" [ "$(grep -c '^f ' "$T/cage_frames/arm_raise_0004.obj")" -eq "$(grep -c '^f ' "$CAGE")" ]

run export --project "$P" --format json --out "$T/rig.json"
check "export json exits 0" [ "$rc" -eq 0 ]
check "json: it says what it wrote" has "$T/out" "^exported rig as JSON of .*: [0-9]* cage vertices, [0-9]* faces, 0 keypose set(s)"
check "json: the format is named" has "$T/rig.json" '"format": "cagewrap-rig"'
check "json: nodes by name" has "$T/rig.json" '"nodes": \["'
run export --project "$P" --format json --mode cage --out "$T/rig.json"
check "json refuses a mode" [ "$rc" -ne 0 ]
check "it says why" has "$T/err" "has no meaning for --format json"

# the progress line, on a terminal (script gives the command one)
if command -v script > /dev/null; then
  script -qec "'$BIN' export --project '$P' --mode baked-skin --clips walk --fps 4 --out '$T/tty.glb'" /dev/null > "$T/tty.txt" 2>&1
  check "a terminal sees the stages" has "$T/tty.txt" "export: posing *5/5"
  check "and the fit" has "$T/tty.txt" "export: fitting"
  check "up to 100%" has "$T/tty.txt" "100%"
fi
check "without a terminal, no progress line" lacks "$T/err" "export: "

run export --project "$P" --format fbx --out "$T/x.fbx"
check "an unknown format is refused" [ "$rc" -ne 0 ]
check "it names the formats" has "$T/err" "should be glb, obj or json"
run export --project "$P" --out "$T/x.glb"
check "glb without a mode is refused" [ "$rc" -ne 0 ]
check "it asks for one" has "$T/err" "needs --mode"
run export --project "$P" --mode cage --out "$T/nowhere/x.glb"
check "a missing folder is refused" [ "$rc" -ne 0 ]
check "it names the folder" hasf "$T/err" "$T/nowhere/x.glb: the folder $T/nowhere does not exist"
cp "$DEMO" "$T/own.glb"
run new --character "$T/own.glb" --cage "$CAGE" --out "$T/own.cagewrap"
run export --project "$T/own.cagewrap" --mode cage --out "$T/own.glb"
check "the project's own character is not an output" [ "$rc" -ne 0 ]
check "it says so" hasf "$T/err" "$T/own.glb: is the document's own character file; export elsewhere"
check "and the character is untouched" cmp -s "$DEMO" "$T/own.glb"

run export --project "$P" --mode baked --out "$T/x.glb"
check "an unknown mode is refused" [ "$rc" -ne 0 ]
check "it names the modes" has "$T/err" "should be baked-animation, baked-skin or cage"
run export --project "$P" --mode cage --clips run --out "$T/x.glb"
check "an unknown clip is refused" [ "$rc" -ne 0 ]
check "it names the clips there are" has "$T/err" "no clip named or numbered 'run' (it has 2: walk, arm_raise)"
run export --project "$P" --mode cage --out "$T/x.obj"
check "a non-.glb output is refused" [ "$rc" -ne 0 ]
check "it says what glb writes" has "$T/err" "a glb export is written to a .glb file"
# the corrective targets' options (issue 22)
run export --project "$P" --mode baked-skin --max-targets -3 --out "$T/x.glb"
check "a negative --max-targets is refused" hasf "$T/err" "--max-targets must be a whole number from 0 (one per frame) to 4096"
run export --project "$P" --mode baked-skin --max-targets 0 --max-error 0.001 --out "$T/x.glb"
check "--max-error with one target per frame is refused" hasf "$T/err" "--max-error picks among compressed targets"
run export --project "$P" --mode cage --max-targets 4 --out "$T/x.glb"
check "--max-targets with the cage is refused" hasf "$T/err" "--max-targets and --max-error are for --format glb with a skin mode"
run export --project "$P" --mode baked-skin --max-error nan --out "$T/x.glb"
check "a --max-error that is not a length is refused" [ "$rc" -ne 0 ]
check "no file is left by the refusals" test ! -e "$T/x.glb"
run export --project "$P" --mode baked-skin --max-influences 6 --out "$T/x.glb"
check "--max-influences 6 is refused" hasf "$T/err" "--max-influences must be 4 or 8"
run export --project "$P" --mode baked-animation --max-influences 8 --out "$T/x.glb"
check "--max-influences without baked-skin is refused" hasf "$T/err" "--max-influences is for --format glb --mode baked-skin"
run export --project "$P" --mode cage --correctives pose-driven --out "$T/x.glb"
check "pose-driven correctives without baked-skin are refused" hasf "$T/err" "--correctives pose-driven is for --format glb --mode baked-skin"
run export --project "$P" --mode baked-skin --correctives sideways --out "$T/x.glb"
check "an unknown --correctives is refused" hasf "$T/err" "--correctives 'sideways' should be baked or pose-driven"
run export --project "$P" --mode baked-skin --hold-out walk --out "$T/x.glb"
check "--hold-out without pose-driven is refused" hasf "$T/err" "--hold-out is for --correctives pose-driven"
run export --project "$P" --mode baked-skin --correctives pose-driven --hold-out jog --out "$T/x.glb"
check "--hold-out of no clip is refused by name" hasf "$T/err" "--hold-out 'jog': its character"
run export --project "$P" --mode baked-skin --correctives pose-driven --hold-out walk --clips walk --fps 4 --out "$T/x.glb"
check "holding out the only clip is refused" hasf "$T/err" "holding out 'walk', the only exported clip, leaves nothing to fit"
run export --project "$P" --mode baked-skin --correctives pose-driven --hold-out arm_raise --clips walk --fps 4 --out "$T/x.glb"
check "holding out a clip that is not exported is refused" hasf "$T/err" "the held-out clip 'arm_raise' is not one of the exported clips"
check "no file is left by those refusals" test ! -e "$T/x.glb"
run export --project "$P" --mode baked-skin --max-influences 8 --clips walk --fps 4 --out "$T/eight.glb"
check "--max-influences 8 exports" test "$rc" -eq 0
check "it reports the joints a vertex" has "$T/out" "skin: up to [5-8] joints a vertex (asked 8)"
if command -v node > /dev/null && [ -d "$ROOT/tests/gltf_validate/node_modules/gltf-validator" ]; then
  node "$ROOT/tests/gltf_validate/validate.js" "$T/eight.glb" > "$T/eight.valid" 2>&1
  check "the 8-joint file passes the validator" has "$T/eight.valid" ": 0 errors"
fi

finish
