#!/usr/bin/env bash
# What a glTF runtime shows is what cagewrap showed (issue 22): each exported skin mode of the demo (baked-skin
# with compressed correctives, the default 16 targets; baked-skin with one target per frame; baked-animation;
# the cage skinned) is loaded by three.js (tests/gltf_validate/three_pose.mjs: GLTFLoader, AnimationMixer,
# Mesh.getVertexPosition; the npm package pinned in package.json) and its positions at frames and between
# frames are compared with `cagewrap pose` (the skin, or --cage-out for the cage): within the error the export
# reports (plus 1e-6 m for float rounding) and never beyond 1% of the diagonal. The skinned node, its name and
# the joint order survive the trip, and every file passes the Khronos validator. Exit 77 (skipped) when node
# or three is unavailable. $1 = cagewrap binary.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tests/cli/harness.bash"
need_demo_assets
command -v node > /dev/null || { echo "skipped: node is not installed"; exit 77; }
[ -d "$ROOT/tests/gltf_validate/node_modules/three" ] || { echo "skipped: three is not installed (scripts/setup.sh)"; exit 77; }
THREE="$ROOT/tests/gltf_validate/three_pose.mjs"

P="$T/demo.cagewrap"
run new --character "$DEMO" --cage "$CAGE" --out "$P"
check "new exits 0" test "$rc" -eq 0

# the largest distance between two float32 .bin files, in metres
largest() {
  python3 - "$1" "$2" <<'PY'
import struct, sys
a = open(sys.argv[1], 'rb').read(); b = open(sys.argv[2], 'rb').read()
if len(a) != len(b):
    print('sizes differ: %d and %d bytes' % (len(a), len(b))); sys.exit(1)
fa = struct.unpack('%df' % (len(a) // 4), a); fb = struct.unpack('%df' % (len(b) // 4), b)
print('%.9g' % max(sum((fa[i + k] - fb[i + k]) ** 2 for k in range(3)) ** 0.5 for i in range(0, len(fa), 3)))
PY
}
# the "max" of an export report line whose label matches $2 (in metres), from the export's stdout $1
reported() { grep -m1 -- "$2" "$1" | sed -E 's/.* max ([0-9.e+-]+) m.*/\1/'; }
# within A B LIMIT: A <= LIMIT
within() { python3 -c "import sys; sys.exit(0 if float('$1') <= float('$2') else 1)"; }

DIAG=$(python3 - "$DEMO" <<'PY'
import json, struct, sys
data = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', data[12:16])[0]
doc = json.loads(data[20:20 + n])
acc = doc['accessors'][doc['meshes'][0]['primitives'][0]['attributes']['POSITION']]
print(sum((acc['max'][k] - acc['min'][k]) ** 2 for k in range(3)) ** 0.5)
PY
)
ONE_PERCENT=$(python3 -c "print(0.01 * $DIAG)")
node "$THREE" "$DEMO" walk 0 "$T/source.bin" > "$T/source.json"
SOURCE_BONES=$(python3 -c "import json; print(json.load(open('$T/source.json'))['bones'])")

# walk at 10 fps: frame times 0, 0.1, ...; 0.4 is a frame, 0.45 and 0.05 are between frames
for variant in "skin:baked-skin:" "skin4:baked-skin:--max-targets 4" "skin_frames:baked-skin:--max-targets 0" "opt:baked-skin:--optimize" \
               "anim:baked-animation:" "cage:cage:" "q:baked-skin:--quantize" "qopt:baked-skin:--quantize --optimize" \
               "qanim:baked-animation:--quantize" "qcage:cage:--quantize"; do
  IFS=: read -r name mode extra <<< "$variant"
  run export --project "$P" --format glb --mode "$mode" $extra --clips walk --fps 10 --keypose-steps 0 --out "$T/$name.glb"
  check "$name: export exits 0" test "$rc" -eq 0
  cp "$T/out" "$T/$name.report"
  node "$ROOT/tests/gltf_validate/validate.js" "$T/$name.glb" > "$T/$name.valid" 2>&1
  check "$name: the validator finds no errors" has "$T/$name.valid" ": 0 errors"
  if [ "$mode" = cage ]; then
    at=$(reported "$T/$name.report" "cage error at frames"); between="$at"
  else
    at=$(reported "$T/$name.report" "^  error at frames:"); between=$(reported "$T/$name.report" "^  error between frames:")
  fi
  check "$name: the export reports its errors" test -n "$at" -a -n "$between"
  for t in 0 0.4 0.05 0.45; do
    case "$t" in 0 | 0.4) bound="$at" ;; *) bound="$between" ;; esac
    if [ "$mode" = cage ]; then
      run pose --project "$P" --clip walk --time "$t" --out "$T/skin_$t.bin" --cage-out "$T/rig_$t.bin"
    else
      run pose --project "$P" --clip walk --time "$t" --out "$T/rig_$t.bin"
    fi
    node "$THREE" "$T/$name.glb" walk "$t" "$T/three_$t.bin" > "$T/three.json" 2> "$T/three.err"
    check "$name at $t s: three.js loads and plays it" test $? -eq 0
    gap=$(largest "$T/three_$t.bin" "$T/rig_$t.bin")
    echo "$name at $t s: three.js vs cagewrap pose: largest $gap m (the export reports max $bound m)"
    check "$name at $t s: within the reported error" within "$gap" "$(python3 -c "print($bound + 1e-6)")"
    check "$name at $t s: within 1% of the diagonal" within "$gap" "$ONE_PERCENT"
  done
  cp "$T/three.json" "$T/$name.three.json"
  # the skinned node, its name and the joint order
  if [ "$mode" != baked-animation ]; then
    check "$name: one skinned mesh" has "$T/three.json" '"skinned":1'
    check "$name: the skinned node is named" has "$T/three.json" "\"node\":\"$([ "$mode" = cage ] && echo cage || echo skin)\""
    bones=$(python3 -c "import json; print(json.load(open('$T/three.json'))['bones'])")
    check "$name: the joints in the source's order" test "$bones" = "$SOURCE_BONES"
  fi
done
# reordered for the GPU: fewer cache misses, and three.js read the source order back
check "--optimize reports the cache" has "$T/opt.report" "GPU order: vertex cache misses per triangle"
fewer_misses() {
  python3 - "$1" <<'PY'
import re, sys
m = re.search(r'per triangle ([0-9.]+) before, ([0-9.]+) after', open(sys.argv[1]).read())
print(m.group(0) if m else 'no cache figures')
sys.exit(0 if m and float(m.group(2)) < float(m.group(1)) else 1)
PY
}
check "--optimize lowers the vertex cache misses" fewer_misses "$T/opt.report"
check "three.js saw the reordered mesh" grep -q '"reordered":true' "$T/opt.three.json"
# compressed: at most 16 targets against one per frame, and a smaller file
check "baked-skin: 16 targets by default" has "$T/skin.report" "11 frames, 1[0-6] morph targets"
check "baked-skin --max-targets 0: one per frame" has "$T/skin_frames.report" "11 frames, 11 morph targets"
# pose-driven correctives: the arm raise held out of the fit, then played by three.js twice, with the clip's
# keyed weights and with weights it computes from the bones' angles by the formula in the mesh's extras
for variant in "pd:" "pdq:--quantize"; do
  IFS=: read -r name extra <<< "$variant"
  run export --project "$P" --format glb --mode baked-skin --correctives pose-driven --hold-out arm_raise $extra \
    --clips walk,arm_raise --fps 10 --keypose-steps 0 --out "$T/$name.glb"
  check "$name: export exits 0" test "$rc" -eq 0
  cp "$T/out" "$T/$name.report"
  check "$name: the report names the drivers" has "$T/$name.report" "pose-driven targets (of [0-9]* components), weighted by [0-9]* joint-angle ramps"
  check "$name: the held-out clip is named so" has "$T/$name.report" "arm_raise' (21 frames, held out of the fit) at frames"
  node "$ROOT/tests/gltf_validate/validate.js" "$T/$name.glb" > "$T/$name.valid" 2>&1
  check "$name: the validator finds no errors" has "$T/$name.valid" ": 0 errors"
  held=$(reported "$T/$name.report" "arm_raise' (21 frames, held out of the fit) at frames")
  alone=$(reported "$T/$name.report" "arm_raise' at frames, skeleton alone")
  # the arm raise lies outside everything the walk shows (the skeleton alone misses it by 3.4% of the diagonal
  # there): what is asked of the correctives is not to make it worse
  check "$name: the held-out clip is no worse with the correctives than with the skeleton alone" \
    within "$held" "$(python3 -c "print(${alone:-0} * 1.01 + 1e-5)")"
  for t in 0.5 1 1.5; do
    run pose --project "$P" --clip arm_raise --time "$t" --out "$T/rig_$t.bin"
    node "$THREE" "$T/$name.glb" arm_raise "$t" "$T/keyed_$t.bin" > /dev/null 2>&1
    node "$THREE" "$T/$name.glb" arm_raise "$t" "$T/driven_$t.bin" drivers > "$T/driven.json" 2> "$T/driven.err"
    check "$name at $t s: three.js computes the weights from the drivers" grep -q '"driven":[1-9]' "$T/driven.json"
    gap=$(largest "$T/driven_$t.bin" "$T/rig_$t.bin")
    same=$(largest "$T/driven_$t.bin" "$T/keyed_$t.bin")
    echo "$name at $t s (held out): three.js driven by the joint angles vs cagewrap pose: largest $gap m (reported $held m); vs the keyed weights $same m"
    check "$name at $t s: driven weights are the keyed ones" within "$same" 1e-5
    check "$name at $t s: within the held-out clip's reported error" within "$gap" "$(python3 -c "print($held + 1e-5)")"
  done
done
# quantized: the extension required, integer positions and targets, and files smaller than the float ones
quantized() {
  python3 - "$1" <<'PY'
import json, struct, sys
data = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', data[12:16])[0]
doc = json.loads(data[20:20 + n])
prim = doc['meshes'][0]['primitives'][0]
types = [doc['accessors'][prim['attributes']['POSITION']]['componentType']]
types += [doc['accessors'][t['POSITION']]['componentType'] for t in prim.get('targets', [])]
print('required', doc.get('extensionsRequired'), 'component types', sorted(set(types)))
sys.exit(0 if doc.get('extensionsRequired') == ['KHR_mesh_quantization'] and set(types) == {5122} else 1)
PY
}
smaller() { test "$(stat -c %s "$1")" -lt "$(python3 -c "print(int(0.8 * $(stat -c %s "$2")))")"; }
for pair in q:skin qanim:anim qcage:cage; do
  IFS=: read -r q f <<< "$pair"
  check "$q: KHR_mesh_quantization, SHORT positions and targets" quantized "$T/$q.glb"
  check "$q: the report says it is quantized" has "$T/$q.report" "quantized (KHR_mesh_quantization)"
  echo "$q: $(stat -c %s "$T/$q.glb") bytes, $f: $(stat -c %s "$T/$f.glb") bytes"
done
check "q: at least a fifth smaller than the float baked-skin" smaller "$T/q.glb" "$T/skin.glb"
check "qanim: at least a fifth smaller than the float baked-animation" smaller "$T/qanim.glb" "$T/anim.glb"
# cagewrap reads its own quantized export back: its skinning (morphs at the clip's weights, then the folded
# inverse bind matrices) matches three.js's reading of the same file
run skin --character "$T/q.glb" --clip walk --time 0.4 --out "$T/q_own.bin"
check "cagewrap reads the quantized export" test "$rc" -eq 0
node "$THREE" "$T/q.glb" walk 0.4 "$T/q_three.bin" > /dev/null 2>&1
gap=$(largest "$T/q_own.bin" "$T/q_three.bin")
echo "q at 0.4 s: cagewrap skin vs three.js on the quantized file: largest $gap m"
check "cagewrap and three.js read the quantized file alike" within "$gap" 1e-5
finish
