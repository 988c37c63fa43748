#!/usr/bin/env bash
# CLI checks for `cagewrap pose`: a saved project's skin deformed through its cage at a clip time and
# per-joint rotations. At rest it matches the character's rest skin; other poses differ; keyposes and
# the attachment mode saved in the project act on the output; errors name the project and the clip.
# Usage: pose.sh <cagewrap binary> [shared assets dir]. Uses assets/demo_character.glb and demo_cage.obj.
set -u

source "$(dirname "$0")/harness.bash"
need_demo_assets


P="$T/hero.cagewrap"
run new --character "$DEMO" --cage "$CAGE" --out "$P"
check "new exits 0" [ "$rc" -eq 0 ]
NV=$(grep -c '^v ' <("$BIN" skin --character "$DEMO" --out "$T/lbs_rest.obj" >/dev/null && cat "$T/lbs_rest.obj"))

# ---------------------------------------------------------------------------------------- rest
run pose --project "$P" --out "$T/rest.obj"
check "pose at rest exits 0" [ "$rc" -eq 0 ]
check "pose says what it did" has "$T/out" "^posed $NV skin vertices of .*hero.cagewrap at the rest pose (fitted attachment, 0 of 0 keypose sets active), wrote $T/rest.obj\$"
check "at rest the skin is the character's rest skin" below 2e-5 "$T/rest.obj" "$T/lbs_rest.obj"
check "the output has the character's triangles" [ "$(grep -c '^f ' "$T/rest.obj")" -eq "$(grep -c '^f ' "$T/lbs_rest.obj")" ]
run pose --project "$P" --clip rest --out "$T/rest2.obj"
check "--clip rest is the rest pose" cmp -s "$T/rest.obj" "$T/rest2.obj"
run pose --project "$P" --out "$T/rest.bin"
check ".bin output: float32 x 3 per vertex" [ "$(wc -c <"$T/rest.bin")" -eq $((12 * NV)) ]

# ---------------------------------------------------------------------------------------- poses
run pose --project "$P" --clip arm_raise --time 1 --out "$T/raise.obj" --cage-out "$T/raise_cage.obj"
check "pose arm_raise exits 0" [ "$rc" -eq 0 ]
check "it names the clip and time" has "$T/out" "at clip 'arm_raise' t=1 s"
check "arm_raise at 1 s differs from rest" above 0.1 "$T/raise.obj" "$T/rest.obj"
check "the posed cage is written" [ "$(grep -c '^v ' "$T/raise_cage.obj")" -eq "$(grep -c '^v ' "$CAGE")" ]
run pose --project "$P" --clip 1 --time 1 --out "$T/raise_by_index.obj"
check "a clip by index" cmp -s "$T/raise.obj" "$T/raise_by_index.obj"
run pose --project "$P" --pose forearm.L=90,0,0 --out "$T/bent.obj"
check "--pose exits 0" [ "$rc" -eq 0 ]
check "--pose is reported" has "$T/out" "with --pose overrides"
check "bending the left elbow moves the left arm" above 0.05 "$T/bent.obj" "$T/rest.obj" left
check "and leaves the right side alone" below 1e-6 "$T/bent.obj" "$T/rest.obj" right
run pose --project "$P" --clip rest --pose forearm.L=45,0,0 --pose forearm.L=45,0,0 --out "$T/bent2.obj"
check "repeated --pose for one joint compose" below 1e-4 "$T/bent2.obj" "$T/bent.obj"

# ---------------------------------------------------------------------------------------- keyposes
# a bulge keyed at 90 degrees of left elbow flexion on the cage vertices around the left upper arm
python3 - "$P" "$T/keyed.cagewrap" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
verts = [i for i, (x, y, z) in enumerate(p["cage"]["positions"]) if x > 0.22 and 1.15 < y < 1.35 and z > 0]
assert len(verts) >= 3, verts
p["keyposes"] = [{"name": "biceps.L", "drivers": [{"node": "forearm.L", "kind": "rotation", "axis": [1, 0, 0]}],
                  "keys": [{"values": [90], "vertices": verts, "offsets": [[0, 0, 0.03]] * len(verts)}]}]
json.dump(p, open(sys.argv[2], "w"), indent=1)
PY
run pose --project "$T/keyed.cagewrap" --pose forearm.L=90,0,0 --out "$T/keyed_bent.obj"
check "pose with keyposes exits 0" [ "$rc" -eq 0 ]
check "it counts the active keypose sets" has "$T/out" "1 of 1 keypose sets active"
check "the keyed bulge shows at 90 degrees" above 0.005 "$T/keyed_bent.obj" "$T/bent.obj"
check "only on the left" below 1e-6 "$T/keyed_bent.obj" "$T/bent.obj" right
run pose --project "$T/keyed.cagewrap" --out "$T/keyed_rest.obj"
check "and not at rest" cmp -s "$T/keyed_rest.obj" "$T/rest.obj"
python3 -c 'import json,sys; p=json.load(open(sys.argv[1])); p["keyposes"][0]["mute"]=True; json.dump(p,open(sys.argv[2],"w"))' \
  "$T/keyed.cagewrap" "$T/muted.cagewrap"
run pose --project "$T/muted.cagewrap" --pose forearm.L=90,0,0 --out "$T/muted_bent.obj"
check "a muted set does nothing" cmp -s "$T/muted_bent.obj" "$T/bent.obj"

# ---------------------------------------------------------------------------------------- smooth attachment
python3 -c 'import json,sys; p=json.load(open(sys.argv[1])); p["attachment"]["mode"]="smooth"; json.dump(p,open(sys.argv[2],"w"))' \
  "$P" "$T/smooth.cagewrap"
run pose --project "$T/smooth.cagewrap" --pose forearm.L=90,0,0 --out "$T/smooth_bent.obj"
check "smooth attachment exits 0 and says so" has "$T/out" "(smooth attachment,"
check "smooth attachment bends differently" above 1e-3 "$T/smooth_bent.obj" "$T/bent.obj"
run pose --project "$T/smooth.cagewrap" --out "$T/smooth_rest.obj"
check "smooth attachment at rest is the rest skin" below 2e-5 "$T/smooth_rest.obj" "$T/lbs_rest.obj"

# ---------------------------------------------------------------------------------------- errors
run pose --project "$P" --clip dance --out "$T/x.obj"
check "unknown clip fails" [ "$rc" -ne 0 ]
check "unknown clip: names the project, the clip and the clips there are" has "$T/err" "error: $P: its character .* has no clip named or numbered 'dance' (it has 2: walk, arm_raise; or 'rest')"
run pose --project "$P" --pose elbow=1,2,3 --out "$T/x.obj"
check "unknown joint fails naming it" has "$T/err" "error: $P: --pose 'elbow=1,2,3': the character has no node named 'elbow'"
run pose --project "$P" --pose forearm.L=1,two,3 --out "$T/x.obj"
check "a bad angle fails naming it" has "$T/err" "'two' is not a finite number of degrees"
run pose --project "$P" --pose forearm.L=1,2 --out "$T/x.obj"
check "two angles fail" has "$T/err" "should give three angles rx,ry,rz in degrees"
run pose --project "$T/missing.cagewrap" --out "$T/x.obj"
check "a missing project fails naming it" has "$T/err" "$T/missing.cagewrap: no such file"
run new --character "$DEMO" --out "$T/bare.cagewrap"
run pose --project "$T/bare.cagewrap" --out "$T/x.obj"
check "a project without a cage fails saying so" has "$T/err" "$T/bare.cagewrap: the project has no cage yet"
run pose --project "$P" --out "$T/x.ply"
check "a bad output extension fails" has "$T/err" "output must end in .obj or .bin"
python3 -c 'import json,sys; p=json.load(open(sys.argv[1])); p["keyposes"][0]["drivers"][0]["node"]="elbow.L"; json.dump(p,open(sys.argv[2],"w"))' \
  "$T/keyed.cagewrap" "$T/badnode.cagewrap"
run pose --project "$T/badnode.cagewrap" --out "$T/x.obj"
check "a keypose naming no node fails with the JSON path" has "$T/err" "badnode.cagewrap: keyposes\[0\].drivers\[0\].node is node 'elbow.L'"
check "nothing written on failure" [ ! -e "$T/x.obj" ]

finish
