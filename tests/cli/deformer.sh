#!/usr/bin/env bash
# CLI checks for the deformer stack (issue 21, docs/deformer-stack.md): `cagewrap deformer add` puts
# a second cage over the demo's head (a head-region mask from the skin weights), `list` shows it,
# `pose` carries the stack (a copy of the project's own cage changes nothing in order, and a sum
# doubles the motion: the pose differs), `set --mute` takes it out again (the pose is the plain one,
# bit for bit), `remove` and the errors (an unknown layer, an unknown joint, deformer 0, a cage file
# that is not there) name what is wrong and write nothing. $1 = cagewrap binary.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tests/cli/harness.bash"
need_demo_assets

P="$T/hero.cagewrap"
run new --character "$DEMO" --cage "$CAGE" --out "$P"
check "new exits 0" test "$rc" -eq 0
run pose --project "$P" --clip walk --time 0.4 --out "$T/plain.bin"
check "pose of the plain project" test "$rc" -eq 0

run deformer add --project "$P" --cage "$CAGE" --name face --mask-joints head
check "deformer add exits 0" test "$rc" -eq 0
check "it lists the layer with its mask" has "$T/out" "^  1  face .*mask joints head ("
check "version 4 with a deformers field" grep -q '"version": 4,' "$P"
run deformer list --project "$P"
check "list exits 0" test "$rc" -eq 0
check "list: the project's cage first" has "$T/out" "^  0  (project cage)"
check "list: the stack's mode" has "$T/out" "^stack      in_order (2 deformers)"

# in order, a copy of the project's own cage changes nothing
run pose --project "$P" --clip walk --time 0.4 --out "$T/in_order.bin"
check "pose with the layer" test "$rc" -eq 0
check "in order: a copy of the own cage changes nothing" cmp_close "$T/plain.bin" "$T/in_order.bin" 1e-5
run deformer set --project "$P" --stack sum
check "set --stack sum" test "$rc" -eq 0
run pose --project "$P" --clip walk --time 0.4 --out "$T/sum.bin"
check "sum: the head moves twice as far" bash -c "! cmp -s '$T/plain.bin' '$T/sum.bin'"
run deformer set --project "$P" --name face --mute
check "set --mute" test "$rc" -eq 0
check "it says muted" has "$T/out" "^  1  face .*, muted$"
run pose --project "$P" --clip walk --time 0.4 --out "$T/muted.bin"
check "muted: the plain pose, bit for bit" cmp -s "$T/plain.bin" "$T/muted.bin"
check "pose says what is muted" hasf "$T/err" "deformer 1 'face' is muted: it is left out"
# solo: only that deformer moves the skin; the project's own cage muted leaves the layer alone
run deformer set --project "$P" --name face --unmute --hide
check "unmute and hide" has "$T/out" "^  1  face .*, hidden$"
run deformer set --project "$P" --solo 0
check "solo 0" has "$T/out" "^  0  (project cage) .*, soloed$"
check "the layer is left out" has "$T/out" "^  1  face .*left out (deformer 0 is soloed)"
run pose --project "$P" --clip walk --time 0.4 --out "$T/solo.bin"
check "solo 0: the plain pose, bit for bit" cmp -s "$T/plain.bin" "$T/solo.bin"
check "pose says what is soloed" hasf "$T/err" "deformer 0 'cage' is soloed"
run deformer set --project "$P" --solo 5
check "a solo out of range fails" test "$rc" -ne 0
check "naming the range" hasf "$T/err" "--solo '5': the deformers are 0 to 1"
run deformer set --project "$P" --name face --no-mask
run deformer set --project "$P" --solo none --index 0 --mute
check "mute the project's cage" has "$T/out" "^  0  (project cage) .*, muted$"
run pose --project "$P" --clip walk --time 0.4 --out "$T/base_muted.bin"
check "in a sum, the unmasked copy alone moves the skin: the plain pose" cmp_close "$T/plain.bin" "$T/base_muted.bin" 1e-5
run deformer set --project "$P" --index 0 --unmute
run deformer set --project "$P" --name face --mute --mask-joints head
check "the project's cage back, the layer muted" has "$T/out" "^  1  face .*, muted, hidden$"
run deformer set --project "$P" --index 0 --rename x
check "deformer 0 cannot be renamed" test "$rc" -ne 0

# errors name what is wrong and write nothing
cp "$P" "$T/before.cagewrap"
run deformer set --project "$P" --name nose --unmute
check "an unknown layer fails" test "$rc" -ne 0
check "naming it" hasf "$T/err" "has no deformer named 'nose'"
run deformer set --project "$P" --name face --mask-joints hed
check "an unknown joint fails" test "$rc" -ne 0
check "naming it" hasf "$T/err" "has no node 'hed'"
run deformer remove --project "$P" --index 0
check "deformer 0 cannot be removed" test "$rc" -ne 0
check "saying why" hasf "$T/err" "deformer 0 is the project's own cage"
run deformer add --project "$P" --cage "$T/missing.obj"
check "a missing cage fails" test "$rc" -ne 0
check "naming the file" hasf "$T/err" "missing.obj"
run deformer add --project "$P" --cage "$CAGE" --name face
check "a second 'face' fails" test "$rc" -ne 0
check "the project is unchanged" cmp -s "$P" "$T/before.cagewrap"

run deformer remove --project "$P" --name face
check "remove exits 0" test "$rc" -eq 0
check "no layers left" has "$T/out" "^stack      sum (1 deformer)"

# the rig JSON describes one cage: a stack is refused, naming it
run deformer add --project "$P" --cage "$CAGE" --name coat
run export --project "$P" --format json --out "$T/rig.json"
check "the rig JSON refuses a stack" test "$rc" -ne 0
check "saying how many" hasf "$T/err" "this project has 1 more deformer(s)"

# `new` with two cages: the second is a layer over the first, combined as --stack says
run new --character "$DEMO" --cage "$CAGE" --cage "$CAGE" --stack blend --out "$T/two.cagewrap"
check "new with two cages exits 0" test "$rc" -eq 0
check "it names the layer" has "$T/out" "^deformer   demo_cage: 1002 vertices, 2000 faces (a layer, blend)"
run deformer list --project "$T/two.cagewrap"
check "two deformers, blended" has "$T/out" "^stack      blend m=2"
run pose --project "$T/two.cagewrap" --clip walk --time 0.4 --out "$T/two.bin"
check "blend of two copies: the plain pose" cmp_close "$T/plain.bin" "$T/two.bin" 1e-5
# each deformer's binding cached beside the project (P.cwb, P.1.cwb), and used by pose
run project "$T/two.cagewrap" --cache-binding
check "project --cache-binding exits 0" test "$rc" -eq 0
check "the layer's cache is listed" has "$T/out" "^deformer 1 'demo_cage': cached in .*two.cagewrap.1.cwb (up to date)"
check "both files are there" test -f "$T/two.cagewrap.cwb" -a -f "$T/two.cagewrap.1.cwb"
run pose --project "$T/two.cagewrap" --clip walk --time 0.4 --out "$T/two_cached.bin"
check "pose uses both caches" hasf "$T/err" "using the cached bindings of 2 of 2 deformers (no bind)"
check "the same pose, bit for bit" cmp -s "$T/two.bin" "$T/two_cached.bin"
# a layer's own binding parameters changed (deformer set --epsilon; 0.2 binds the demo as 0.1 does): saved, its stale record is dropped; the
# project's cage keeps its cache
run deformer set --project "$T/two.cagewrap" --name demo_cage --epsilon 0.3
check "set --epsilon on a layer" test "$rc" -eq 0
run project "$T/two.cagewrap"
check "the layer's record is dropped" has "$T/out" "^deformer 1 'demo_cage': cached on save; nothing cached yet"
check "deformer 0's is kept" has "$T/out" "^binding    cached in .*two.cagewrap.cwb (up to date)"
run pose --project "$T/two.cagewrap" --clip walk --time 0.4 --out "$T/two_eps.bin"
check "pose binds the layer alone" hasf "$T/err" "using the cached bindings of 1 of 2 deformers (the others bound)"
check "its new parameters change the pose" bash -c "! cmp -s '$T/two.bin' '$T/two_eps.bin'"
# a muted deformer is neither bound nor cached, and the listing says so
run deformer set --project "$T/two.cagewrap" --name demo_cage --mute
run project "$T/two.cagewrap"
check "a muted layer: not cached" has "$T/out" "^deformer 1 'demo_cage': muted: not bound, not cached"
run deformer set --project "$T/two.cagewrap" --index 0 --epsilon 2
check "a bad parameter fails" test "$rc" -ne 0
run new --character "$DEMO" --cage "$CAGE" --cage "$CAGE" --stack sideways --out "$T/bad.cagewrap"
check "an unknown stack mode fails" test "$rc" -ne 0
check "naming it" hasf "$T/err" "--stack 'sideways'"

# painted masks from a file (--mask-weights: a JSON array or numbers, one per skin vertex) and glTF meshes
# (--mask-meshes): a sum with a copy of the project's cage doubles the motion where the weight is 1 and
# leaves the plain pose where it is 0
run new --character "$DEMO" --cage "$CAGE" --cage "$CAGE" --stack sum --out "$T/sum.cagewrap"
python3 -c "print(' '.join(['0'] * 34800))" > "$T/zeros.txt"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-weights "$T/zeros.txt" --out "$T/zeros.cagewrap"
check "--mask-weights exits 0" test "$rc" -eq 0
check "it lists a painted mask" has "$T/out" "^  1  demo_cage .*mask painted (0 of 34800 skin vertices)"
run pose --project "$T/zeros.cagewrap" --clip walk --time 0.4 --out "$T/zeros.bin"
check "weights 0: the plain pose" cmp_close "$T/plain.bin" "$T/zeros.bin" 1e-5
python3 -c "import json; print(json.dumps([1.0] * 34800))" > "$T/ones.json"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-weights "$T/ones.json" --out "$T/ones.cagewrap"
check "a JSON array" has "$T/out" "mask painted (34800 of 34800 skin vertices)"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-meshes body --out "$T/meshes.cagewrap"
check "--mask-meshes by name" has "$T/out" "mask meshes body (34800 of 34800 skin vertices)"
run pose --project "$T/ones.cagewrap" --clip walk --time 0.4 --out "$T/ones.bin"
run pose --project "$T/meshes.cagewrap" --clip walk --time 0.4 --out "$T/meshes.bin"
check "weights 1 and the whole mesh: the same pose" cmp_close "$T/ones.bin" "$T/meshes.bin" 1e-6
check "and not the plain one (the sum doubles the motion)" bash -c "! cmp -s '$T/plain.bin' '$T/ones.bin'"
python3 -c "print(' '.join(['0.5'] * 34799))" > "$T/short.txt"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-weights "$T/short.txt"
check "too few weights fail" hasf "$T/err" "short.txt: 34799 weights, but the skin has 34800 vertices"
python3 -c "print(' '.join(['0.5'] * 100 + ['1.5'] + ['0.5'] * 34699))" > "$T/big.txt"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-weights "$T/big.txt"
check "a weight out of range fails, naming the vertex" hasf "$T/err" "big.txt: weight 100 (skin vertex 100) is 1.500000; weights are 0 to 1"
run deformer set --project "$T/sum.cagewrap" --index 1 --mask-meshes hat
check "an unknown mesh fails, naming the meshes" hasf "$T/err" "has no mesh named or numbered 'hat' (its meshes: 0 'body')"
finish
