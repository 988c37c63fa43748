#!/usr/bin/env bash
# CLI checks for the parametric driver in the rig (issue 21, core/rig/driver_layer.h): a driver fitted
# to a sheet in front of the demo's chest (`patch fit`), one control point pushed out (the sculpt),
# `new --patch --posed-patch` makes the project; `pose` carries the sculpt (the walk at 0.4 s differs
# from the plain project's by 1 to 6 cm, only above the legs), a driver without a sculpt changes
# nothing, the rig JSON refuses a sculpted driver, bad files are named. $1 = cagewrap binary.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tests/cli/harness.bash"
need_demo_assets

# the chest sheet of tests/patch_fixtures.h: 5 x 4 quads at z = 0.1
python3 - "$T/sheet.obj" <<'PY'
import sys
nx, ny = 5, 4
with open(sys.argv[1], 'w') as f:
    for j in range(ny + 1):
        for i in range(nx + 1):
            f.write('v %f %f 0.1\n' % (-0.25 + 0.5 * i / nx, 0.95 + 0.5 * j / ny))
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i + 1
            f.write('f %d %d %d %d\n' % (a, a + 1, a + nx + 2, a + nx + 1))
PY
run patch fit --cage "$T/sheet.obj" --faces 0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19 --out "$T/rest.cwpatch"
check "patch fit exits 0" test "$rc" -eq 0
python3 - "$T/rest.cwpatch" "$T/posed.cwpatch" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
g = d['grids'][0]
r, c = divmod(14, g['cols'])
g['points'][r][c][2] += 0.06  # control point 14 pushed out of the chest
json.dump(d, open(sys.argv[2], 'w'))
PY
check "a sculpted copy" test -s "$T/posed.cwpatch"

run new --character "$DEMO" --cage "$CAGE" --out "$T/plain.cagewrap"
run pose --project "$T/plain.cagewrap" --clip walk --time 0.4 --out "$T/plain.bin"
check "pose of the plain project" test "$rc" -eq 0
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --posed-patch "$T/posed.cwpatch" --out "$T/driven.cagewrap"
check "new --patch exits 0" test "$rc" -eq 0
check "it names the driver" has "$T/out" "^driver     .*rest.cwpatch: .* control points, density 2 (drives the skin)"
run pose --project "$T/driven.cagewrap" --clip walk --time 0.4 --out "$T/driven.bin"
check "pose with the driver" test "$rc" -eq 0
compare() {  # compare A B: the largest distance between the poses, and the largest below y = 0.6 (the legs)
  python3 - "$1" "$2" "$3" <<'PY'
import struct, sys
a = open(sys.argv[1], 'rb').read(); b = open(sys.argv[2], 'rb').read()
assert len(a) == len(b), (len(a), len(b))
fa = struct.unpack('%df' % (len(a) // 4), a); fb = struct.unpack('%df' % (len(b) // 4), b)
worst = legs = 0.0
for i in range(0, len(fa), 3):
    d = sum((fa[i + k] - fb[i + k]) ** 2 for k in range(3)) ** 0.5
    worst = max(worst, d)
    if fa[i + 1] < 0.6: legs = max(legs, d)
lo, hi, legs_max = map(float, sys.argv[3].split(','))
print('largest %.5f, legs %.6f' % (worst, legs))
sys.exit(0 if lo <= worst <= hi and legs <= legs_max else 1)
PY
}
check "the sculpt moves the chest 1 to 6 cm and not the legs" compare "$T/plain.bin" "$T/driven.bin" 0.01,0.06,0.0001
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --out "$T/idle.cagewrap"
run pose --project "$T/idle.cagewrap" --clip walk --time 0.4 --out "$T/idle.bin"
check "a driver without a sculpt changes nothing" cmp -s "$T/plain.bin" "$T/idle.bin"
run export --project "$T/driven.cagewrap" --format json --out "$T/rig.json"
check "the rig JSON refuses a sculpted driver" test "$rc" -ne 0
check "saying why" hasf "$T/err" "parametric driver moves the skin"
# the driver as a deformer of the stack (deformer set --driver): listed at its place, masked, muted, placed
run deformer list --project "$T/driven.cagewrap"
check "deformer list shows the driver" has "$T/out" "^  D  (driver) *parametric driver, .* control points, density 2, the cage's binding local 4 epsilon 0.1 K 8, 0 keypose sets, no mask, after every layer$"
# its own binding parameters: listed, and the pose changes with them (a wider reach of the samples)
run deformer set --project "$T/driven.cagewrap" --driver --local 8 --out "$T/own.cagewrap"
check "set --driver --local" has "$T/out" "^  D  (driver) .*, own binding local 8 epsilon 0.1 K 8,"
run pose --project "$T/own.cagewrap" --clip walk --time 0.4 --out "$T/own.bin"
check "its own parameters change the pose" bash -c "! cmp -s '$T/driven.bin' '$T/own.bin'"
run deformer set --project "$T/driven.cagewrap" --driver --epsilon 2
check "a bad driver parameter fails" test "$rc" -ne 0
run deformer set --project "$T/driven.cagewrap" --driver --mask-joints foot.L --out "$T/legmask.cagewrap"
check "set --driver --mask-joints exits 0" test "$rc" -eq 0
check "it lists the mask" has "$T/out" "^  D  (driver) .*mask joints foot.L ("
run pose --project "$T/legmask.cagewrap" --clip walk --time 0.4 --out "$T/legmask.bin"
check "masked to a foot: the chest sculpt is gone" cmp -s "$T/plain.bin" "$T/legmask.bin"
run deformer set --project "$T/driven.cagewrap" --driver --mute --out "$T/drmuted.cagewrap"
check "set --driver --mute says so" has "$T/out" "^  D  (driver) .*, muted$"
run pose --project "$T/drmuted.cagewrap" --clip walk --time 0.4 --out "$T/drmuted.bin"
check "muted: the plain pose" cmp -s "$T/plain.bin" "$T/drmuted.bin"
# a copy of the project's cage as a layer: before it (--after 0) the driver is taken over, after it (last) not
run deformer add --project "$T/driven.cagewrap" --cage "$CAGE" --name over --out "$T/layered.cagewrap"
run deformer set --project "$T/layered.cagewrap" --driver --after 0 --out "$T/under.cagewrap"
check "set --driver --after 0" has "$T/out" "^  D  (driver) .*, after layer 0$"
run pose --project "$T/under.cagewrap" --clip walk --time 0.4 --out "$T/under.bin"
check "under the layer: the sculpt is gone" cmp_close "$T/plain.bin" "$T/under.bin" 1e-5
run pose --project "$T/layered.cagewrap" --clip walk --time 0.4 --out "$T/layered.bin"
check "over the layer: the sculpt" compare "$T/plain.bin" "$T/layered.bin" 0.01,0.06,0.0001
run deformer set --project "$T/layered.cagewrap" --driver --after 2
check "--after past the layers fails" test "$rc" -ne 0
check "naming the range" hasf "$T/err" "--after '2': give 0 to 1 layers, or last"
run deformer set --project "$T/plain.cagewrap" --driver --mute
check "--driver without a driver fails" hasf "$T/err" "has no parametric driver"
run new --character "$DEMO" --cage "$CAGE" --patch "$T/missing.cwpatch" --out "$T/bad.cagewrap"
check "a missing driver file fails" test "$rc" -ne 0
check "naming it" hasf "$T/err" "missing.cwpatch"
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --patch-density 0 --out "$T/bad.cagewrap"
check "density 0 fails" test "$rc" -ne 0
check "naming the range" hasf "$T/err" "--patch-density 0: use 1..1024"
# several drivers (issue 21: any number): a second one on the same sheet, another control point pushed; the
# pose of both is the plain pose plus each one's sculpt; each is listed, named, muted and removed by name
python3 - "$T/rest.cwpatch" "$T/posed2.cwpatch" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
g = d['grids'][0]
r, c = divmod(20, g['cols'])
g['points'][r][c][1] -= 0.04
g['points'][r][c][2] += 0.03
json.dump(d, open(sys.argv[2], 'w'))
PY
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --posed-patch "$T/posed2.cwpatch" --out "$T/second.cagewrap"
run pose --project "$T/second.cagewrap" --clip walk --time 0.4 --out "$T/second.bin"
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --posed-patch "$T/posed.cwpatch" \
  --patch "$T/rest.cwpatch" --posed-patch "$T/posed2.cwpatch" --out "$T/two.cagewrap"
check "new with two --patch exits 0" test "$rc" -eq 0
run deformer list --project "$T/two.cagewrap"
check "the stack counts the drivers" has "$T/out" "^stack      in_order (1 deformer, 2 parametric drivers)$"
check "the second driver is listed, named after its file" has "$T/out" "^  D2 rest  *parametric driver, 30 control points,"
run pose --project "$T/two.cagewrap" --clip walk --time 0.4 --out "$T/two.bin"
sum_of() {  # sum_of PLAIN A B BOTH: BOTH = A + B - PLAIN within 1e-5 m, and A, B each move the skin
  python3 - "$@" <<'PY'
import struct, sys
f = [open(n, 'rb').read() for n in sys.argv[1:5]]
p, a, b, ab = [struct.unpack('%df' % (len(x) // 4), x) for x in f]
worst = max(abs(ab[i] - (a[i] + b[i] - p[i])) for i in range(len(p)))
ma = max(abs(a[i] - p[i]) for i in range(len(p))); mb = max(abs(b[i] - p[i]) for i in range(len(p)))
print('two drivers vs the sum of each: %.3g m; each moves %.3g, %.3g' % (worst, ma, mb))
sys.exit(0 if worst < 1e-5 and ma > 0.01 and mb > 0.01 else 1)
PY
}
check "the two drivers' sculpts add" sum_of "$T/plain.bin" "$T/driven.bin" "$T/second.bin" "$T/two.bin"
run deformer set --project "$T/two.cagewrap" --driver --name rest --rename chest2 --mute --out "$T/two_muted.cagewrap"
check "set --driver --name --rename --mute" has "$T/out" "^  D2 chest2 .*, muted$"
check "the first stays on" has "$T/out" "^  D  (driver) .*, after every layer$"
run deformer set --project "$T/two_muted.cagewrap" --driver --name chest2 --hide
check "set --driver --hide" has "$T/out" "^  D2 chest2 .*, muted, hidden$"
run pose --project "$T/two_muted.cagewrap" --clip walk --time 0.4 --out "$T/two_muted.bin"
check "the second muted: the first's pose" cmp_close "$T/driven.bin" "$T/two_muted.bin" 1e-5
run deformer set --project "$T/two.cagewrap" --solo D2 --out "$T/two_solo.cagewrap"
check "--solo D2 solos the second driver" has "$T/out" "^  D2 rest .*, soloed$"
check "the cage is left out" has "$T/out" "^  0  (project cage) .*, left out (driver 'rest' is soloed)"
check "and the first driver" has "$T/out" "^  D  (driver) .*, left out (driver 'rest' is soloed)"
run deformer set --project "$T/two_solo.cagewrap" --solo none
check "--solo none" has "$T/out" "^  D2 rest .*, after every layer$"
run deformer set --project "$T/two.cagewrap" --solo D3
check "a driver that is not there" hasf "$T/err" "--solo 'D3': the project's drivers are D to D2"
run deformer remove --project "$T/two.cagewrap" --driver --out "$T/two_removed.cagewrap"
check "remove --driver removes the first" has "$T/out" "^removed    driver$"
check "the other becomes the first" has "$T/out" "^  D  rest  *parametric driver"
run pose --project "$T/two_removed.cagewrap" --clip walk --time 0.4 --out "$T/two_removed.bin"
check "what is left is the second's pose" cmp_close "$T/second.bin" "$T/two_removed.bin" 1e-5
run deformer add --project "$T/driven.cagewrap" --patch "$T/rest.cwpatch" --posed-patch "$T/posed2.cwpatch" --name arm \
  --after last --mask-joints spine --out "$T/added.cagewrap"
check "deformer add --patch adds a driver" has "$T/out" "^  D2 arm  *parametric driver, .*mask joints spine ("
run deformer add --project "$T/added.cagewrap" --patch "$T/rest.cwpatch" --name arm
check "a name taken fails" hasf "$T/err" "already has a deformer named 'arm'"
run deformer set --project "$T/two.cagewrap" --driver --name nobody --mute
check "an unknown driver fails" test "$rc" -ne 0
check "naming the drivers there are" hasf "$T/err" "has no parametric driver named 'nobody' (its drivers: driver, rest)"
# the driver's attachment: its control points follow the joints named, like a cage's vertices
run deformer set --project "$T/driven.cagewrap" --driver --attach skin_weights --attach-point 14:hips --out "$T/attached.cagewrap"
check "--attach --attach-point" has "$T/out" "^  D  (driver) .*, attached skin_weights (1 assigned)$"
run pose --project "$T/attached.cagewrap" --clip walk --time 0.4 --out "$T/attached.bin"
check "the attachment changes the pose" bash -c "! cmp -s '$T/driven.bin' '$T/attached.bin'"
run deformer set --project "$T/attached.cagewrap" --driver --attach closest --out "$T/closest.cagewrap"
run pose --project "$T/closest.cagewrap" --clip walk --time 0.4 --out "$T/closest.bin"
check "--attach closest: as before" cmp_close "$T/driven.bin" "$T/closest.bin" 1e-6
run deformer set --project "$T/driven.cagewrap" --driver --attach fitted
check "fitted is refused" hasf "$T/err" "--attach 'fitted': give rigid, smooth, skin_weights or closest"
run deformer set --project "$T/driven.cagewrap" --driver --attach-point 30:hips
check "a control point past the driver's is refused" hasf "$T/err" "--attach-point '30:hips': the driver has control points 0 to 29"
run deformer set --project "$T/driven.cagewrap" --driver --attach-point 3:nowhere
check "an unknown joint is refused" hasf "$T/err" "the skeleton has no node 'nowhere'"
run deformer set --project "$T/driven.cagewrap" --attach rigid
check "--attach without --driver is refused" hasf "$T/err" "are the parametric driver's: give --driver too"
# the driver's contributing-set edits (element ids are its samples: 35 at density 2): a chest vertex follows
# the sheet's first sample alone
cat > "$T/edits.json" <<'JSON'
{"format": "cagewrap-set-edits", "version": 1, "elements": 35,
 "edits": [{"point": 32831, "include": [0], "only": true}]}
JSON
run deformer set --project "$T/driven.cagewrap" --driver --set-edits "$T/edits.json" --out "$T/edited.cagewrap"
check "--set-edits" has "$T/out" "^  D  (driver) .*, 1 set edit$"
run pose --project "$T/edited.cagewrap" --clip walk --time 0.4 --out "$T/edited.bin"
check "the set edit changes the pose" bash -c "! cmp -s '$T/driven.bin' '$T/edited.bin'"
run deformer set --project "$T/edited.cagewrap" --driver --set-edits none --out "$T/unedited.cagewrap"
run pose --project "$T/unedited.cagewrap" --clip walk --time 0.4 --out "$T/unedited.bin"
check "--set-edits none: as before" cmp_close "$T/driven.bin" "$T/unedited.bin" 1e-6
sed 's/"include": \[0\]/"include": [35]/; s/"elements": 35, //' "$T/edits.json" > "$T/edits_bad.json"
run deformer set --project "$T/driven.cagewrap" --driver --set-edits "$T/edits_bad.json"
check "a sample past the driver's is refused" hasf "$T/err" "the edit of skin point 32831 names sample 35 (the skin has 34800 points, the driver 35 samples)"
cat > "$T/edits_rules.json" <<'JSON'
{"format": "cagewrap-set-edits", "version": 1, "rules": [{"mode": "remove", "points": [1], "faces": [0]}]}
JSON
run deformer set --project "$T/driven.cagewrap" --driver --set-edits "$T/edits_rules.json"
check "rules by faces are refused" hasf "$T/err" "rules by cage faces do not apply to a parametric driver"
run new --character "$DEMO" --cage "$CAGE" --patch "$T/rest.cwpatch" --patch "$T/rest.cwpatch" --posed-patch "$T/posed.cwpatch" \
  --out "$T/bad.cagewrap"
check "one --posed-patch for two --patch fails" hasf "$T/err" "1 --posed-patch for 2 --patch"

# the drivers' bindings in the binding cache (P.cagewrap.D1.cwb, .D2.cwb): used by pose (no bind, the same
# skin), dropped with a message naming the file and what changed
cp "$T/two.cagewrap" "$T/cached.cagewrap"
run project "$T/cached.cagewrap" --cache-binding
check "project --cache-binding exits 0" test "$rc" -eq 0
check "it caches the first driver" test -s "$T/cached.cagewrap.D1.cwb"
check "it caches the second driver" test -s "$T/cached.cagewrap.D2.cwb"
check "it reports the drivers' caches" has "$T/out" "^driver D2 'rest': cached in .*cached.cagewrap.D2.cwb (up to date)"
run pose --project "$T/cached.cagewrap" --clip walk --time 0.4 --out "$T/cached.bin"
check "pose uses the drivers' caches" hasf "$T/err" "using the cached bindings of 1 of 1 deformers and 2 of 2 parametric drivers (no bind)"
check "the cached rig poses as the bound one" cmp_close "$T/two.bin" "$T/cached.bin" 1e-7
cp "$T/cached.cagewrap" "$T/cached.keep"
run deformer set --project "$T/cached.cagewrap" --driver --name rest --set-edits "$T/edits.json"
run pose --project "$T/cached.cagewrap" --clip walk --time 0.4 --out "$T/cached_edited.bin"
check "a driver's new set edits: its cache is dropped, the other's used" \
  hasf "$T/err" "using the cached bindings of 1 of 1 deformers and 1 of 2 parametric drivers (the others bound)"
check "... and the set edit changes the pose" bash -c "! cmp -s '$T/two.bin' '$T/cached_edited.bin'"
cp "$T/cached.keep" "$T/cached.cagewrap"
python3 - "$T/cached.cagewrap" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
p['more_drivers'][0]['binding_cache']['inputs']['set_edits'] = 'fnv1a64:0000000000000000'
json.dump(p, open(sys.argv[1], 'w'))
PY
run pose --project "$T/cached.cagewrap" --clip walk --time 0.4 --out "$T/cached1.bin"
check "an out-of-date driver cache is named" hasf "$T/err" "cached.cagewrap.D2.cwb is out of date: the set edits changed since it was written"
cp "$T/cached.keep" "$T/cached.cagewrap"
cp "$T/cached.cagewrap.D2.cwb" "$T/keep.cwb"
printf 'x' >> "$T/cached.cagewrap.D2.cwb"
run pose --project "$T/cached.cagewrap" --clip walk --time 0.4 --out "$T/cached2.bin"
check "a replaced driver cache is named and not used" hasf "$T/err" "cached.cagewrap.D2.cwb was changed or replaced since the project was saved"
check "binding again gives the same skin" cmp_close "$T/two.bin" "$T/cached2.bin" 1e-7
cp "$T/keep.cwb" "$T/cached.cagewrap.D2.cwb"
run project "$T/cached.cagewrap" --no-cache-binding
check "--no-cache-binding removes the drivers' caches" bash -c "test ! -e '$T/cached.cagewrap.D1.cwb' && test ! -e '$T/cached.cagewrap.D2.cwb'"
finish
