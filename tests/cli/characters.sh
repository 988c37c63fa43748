#!/usr/bin/env bash
# CLI checks for the character commands: make-demo, info, skin, and their errors.
# $1 = cagewrap binary, $2 = shared assets folder (may be absent).
set -uo pipefail
BIN="$1"
ASSETS="${2:-}"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# make-demo writes a glb that info reads back: 20k-50k vertices, 21 joints, walk and arm_raise.
"$BIN" make-demo --out "$TMP/demo.glb" > "$TMP/make.txt" || fail "make-demo exited non-zero"
"$BIN" info "$TMP/demo.glb" > "$TMP/info.txt" || fail "info on the demo exited non-zero"
verts=$(awk '$1 == "vertices" {print $2}' "$TMP/info.txt")
[[ "$verts" =~ ^[0-9]+$ ]] && (( verts >= 20000 && verts <= 50000 )) || fail "demo vertices '$verts' not in 20k..50k"
grep -Eq '^joints +21:' "$TMP/info.txt" || fail "demo should have 21 joints"
grep -Eq '^ +0 walk +1\.000 s' "$TMP/info.txt" || fail "demo clip 0 should be a 1 s walk"
grep -Eq '^ +1 arm_raise +2\.000 s' "$TMP/info.txt" || fail "demo clip 1 should be a 2 s arm_raise"
grep -Eq '^warnings +0$' "$TMP/info.txt" || fail "the demo should load without warnings"

# A second run writes the same bytes.
"$BIN" make-demo --out "$TMP/demo2.glb" > /dev/null || fail "second make-demo failed"
cmp -s "$TMP/demo.glb" "$TMP/demo2.glb" || fail "make-demo is not deterministic"

# skin: .bin holds #V x 3 float32; .obj holds #V vertex lines; clip by name and by index agree.
"$BIN" skin --character "$TMP/demo.glb" --clip walk --time 0.25 --out "$TMP/walk.bin" > /dev/null || fail "skin .bin"
size=$(stat -c %s "$TMP/walk.bin")
(( size == verts * 12 )) || fail "walk.bin is $size bytes, expected $((verts * 12))"
"$BIN" skin --character "$TMP/demo.glb" --clip 0 --time 0.25 --out "$TMP/walk0.bin" > /dev/null || fail "skin by index"
cmp -s "$TMP/walk.bin" "$TMP/walk0.bin" || fail "clip 'walk' and clip 0 differ"
"$BIN" skin --character "$TMP/demo.glb" --clip walk --time 1.25 --loop --out "$TMP/walk_loop.bin" > /dev/null || fail "skin --loop"
cmp -s "$TMP/walk.bin" "$TMP/walk_loop.bin" || fail "--loop should wrap 1.25 s to 0.25 s of the 1 s walk"
"$BIN" skin --character "$TMP/demo.glb" --clip arm_raise --time 1 --out "$TMP/raise.obj" > /dev/null || fail "skin .obj"
(( $(grep -c '^v ' "$TMP/raise.obj") == verts )) || fail "raise.obj vertex count"
grep -q '^f ' "$TMP/raise.obj" || fail "raise.obj has no faces"

# Errors: non-zero exit and a message naming the problem.
"$BIN" skin --character "$TMP/demo.glb" --clip jump --out "$TMP/x.bin" 2> "$TMP/err.txt" && fail "unknown clip should fail"
grep -q "no clip named or numbered 'jump' (it has 2: walk, arm_raise)" "$TMP/err.txt" || fail "unknown clip message: $(cat "$TMP/err.txt")"
"$BIN" skin --character "$TMP/demo.glb" --out "$TMP/x.ply" 2> "$TMP/err.txt" && fail "bad output extension should fail"
"$BIN" info "$TMP/none.glb" 2> "$TMP/err.txt" && fail "missing file should fail"
grep -q "none.glb: no such file" "$TMP/err.txt" || fail "missing file message"
printf '{"asset":{"version":"2.0"},"buffers":[{"uri":"gone.bin","byteLength":12}]}' > "$TMP/gone.gltf"
"$BIN" info "$TMP/gone.gltf" 2> "$TMP/err.txt" && fail "missing buffer should fail"
grep -q "buffer 0 refers to 'gone.bin', which does not exist" "$TMP/err.txt" || fail "missing buffer message: $(cat "$TMP/err.txt")"

# The real mannequin, when the shared assets are here.
if [[ -n "$ASSETS" && -f "$ASSETS/mannequiny.glb" ]]; then
  "$BIN" info "$ASSETS/mannequiny.glb" > "$TMP/m.txt" || fail "info mannequiny"
  grep -Eq '^joints +45:' "$TMP/m.txt" || fail "mannequiny should have 45 joints"
  grep -Eq '^clips +10$' "$TMP/m.txt" || fail "mannequiny should have 10 clips"
  grep -Eq '^meshes +1 \(3 primitives\)$' "$TMP/m.txt" || fail "mannequiny should have 3 primitives"
  mv=$(awk '$1 == "vertices" {print $2}' "$TMP/m.txt")
  "$BIN" skin --character "$ASSETS/mannequiny.glb" --clip run --time 0.3 --out "$TMP/run.bin" > /dev/null || fail "skin run"
  (( $(stat -c %s "$TMP/run.bin") == mv * 12 )) || fail "run.bin size"
else
  echo "shared assets not found; skipped the mannequin checks"
fi
echo "characters CLI: all checks passed"
