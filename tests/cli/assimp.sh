#!/usr/bin/env bash
# CLI checks for characters read through assimp (issue 23): FBX, Collada and DirectX characters from
# assimp-testmodels go through info (units and up axis), check (the default rig against the file's own
# skinning), new / project (with --keep-units and --embed) and export --mode baked-skin, whose .glb passes the
# Khronos validator; a broken FBX is refused naming the file. Skips (77) without assimp-testmodels.
# Usage: assimp.sh <cagewrap binary> [shared assets dir]
set -u

source "$(dirname "$0")/harness.bash"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
M=${CAGEWRAP_ASSIMP_MODELS:-/usr/share/assimp/models}
[ -f "$M/X/Testwuson.X" ] || { echo "skipped: $M has no X/Testwuson.X: install assimp-testmodels (scripts/setup.sh)"; exit 77; }
FBX="$M/FBX/huesitos.fbx"
DAE="$M/Collada/box_nested_animation.dae"
X="$M/X/Testwuson.X"
MULTI="$M/X/BCN_Epileptic.X"

run info "$FBX"
check "info reads an FBX" [ "$rc" -eq 0 ]
check "it lists the joints" has "$T/out" "^joints *9: Bone"
check "and the clip" has "$T/out" "Armature|Action"
check "and the file's units, brought to metres" has "$T/out" "^units *the file: 0.01 m a unit, +Y up; brought to metres, Y up"
run info "$FBX" --keep-units
check "--keep-units keeps them" has "$T/out" "^units .*kept (--keep-units)"
run info "$M/Collada/kwxport_test_vcolors.dae"
check "a Collada file's <unit> and <up_axis> are read" has "$T/out" "^units *the file: 0.0254 m a unit, +Z up; brought to metres, Y up"
run info "$M/FBX/animation_with_skeleton.fbx"
check "weights that do not sum to one are renormalised with a counted warning" hasf "$T/out" "mesh 0 ('Cube.001'): 2458 vertices have weights that do not sum to one (e.g. vertex 0 sums to 1.20"
run info "$X"
check "info reads a DirectX character" has "$T/out" "^joints *37:"
check "with its three clips" has "$T/out" "Wuson_Walk"

# the default rig of each, judged against the file's own skinning at every clip's frames
for f in "$X" "$MULTI" "$DAE" "$FBX"; do
  run check --character "$f"
  check "check passes on $(basename "$f")" [ "$rc" -eq 0 ]
  check "and says so" has "$T/out" "^passed"
done

# a project from an FBX in its own units, saved with the choice; export through the validator
run new --character "$FBX" --auto-cage 600 --keep-units --out "$T/bones.cagewrap"
check "new from an FBX exits 0" [ "$rc" -eq 0 ]
check "the project keeps the units choice" hasf "$T/bones.cagewrap" '"keep_units": true'
run project "$T/bones.cagewrap"
check "project opens it" [ "$rc" -eq 0 ]
run export --project "$T/bones.cagewrap" --mode baked-skin --fps 10 --out "$T/bones.glb"
check "export baked-skin of the FBX project exits 0" [ "$rc" -eq 0 ]
if command -v node > /dev/null && [ -d "$ROOT/tests/gltf_validate/node_modules/gltf-validator" ]; then
  for f in "$X" "$DAE"; do
    name=$(basename "$f")
    run new --character "$f" --auto-cage 600 --out "$T/$name.cagewrap"
    check "new from $name exits 0" [ "$rc" -eq 0 ]
    run export --project "$T/$name.cagewrap" --mode baked-skin --fps 10 --out "$T/$name.glb"
    check "export baked-skin of $name exits 0" [ "$rc" -eq 0 ]
    node "$ROOT/tests/gltf_validate/validate.js" "$T/$name.glb" > "$T/$name.valid" 2>&1
    check "the export of $name passes the glTF validator" has "$T/$name.valid" "$name.glb: 0 errors"
  done
  node "$ROOT/tests/gltf_validate/validate.js" "$T/bones.glb" > "$T/bones.valid" 2>&1
  check "the FBX project's export passes the glTF validator" has "$T/bones.valid" "bones.glb: 0 errors"
fi

# the project kept the file's centimetres, yet its glTF is in metres: its skin at rest spans what the file's own
# skinning, brought to metres, spans (a root node scales and turns the scene)
run skin --character "$T/bones.glb" --clip 0 --time 0 --out "$T/exported.obj"
check "the keep-units export reads back" [ "$rc" -eq 0 ]
run skin --character "$FBX" --clip 0 --time 0 --out "$T/file.obj"
check "the FBX's own skinning in metres" [ "$rc" -eq 0 ]
extent() { awk '$1 == "v" { for (i = 2; i <= 4; ++i) { if (!(i in lo) || $i < lo[i]) lo[i] = $i; if (!(i in hi) || $i > hi[i]) hi[i] = $i } }
  END { print hi[2] - lo[2], hi[3] - lo[3], hi[4] - lo[4] }' "$1"; }
read -r ex ey ez < <(extent "$T/exported.obj")
read -r fx fy fz < <(extent "$T/file.obj")
check "the keep-units export is in metres, Y up (extent $ex $ey $ez against the file's $fx $fy $fz)" \
  awk -v a="$ex $ey $ez" -v b="$fx $fy $fz" 'BEGIN { split(a, p); split(b, q); for (i = 1; i <= 3; ++i) { d = p[i] - q[i]; if (d < 0) d = -d; if (d > 0.05 * (q[i] + 0.01)) exit 1 } }'

# an embedded FBX opens with the file gone
cp "$FBX" "$T/moved.fbx"
run new --character "$T/moved.fbx" --auto-cage 600 --embed --out "$T/embedded.cagewrap"
check "new --embed of an FBX exits 0" [ "$rc" -eq 0 ]
rm "$T/moved.fbx"
run project "$T/embedded.cagewrap"
check "the embedded FBX opens with its file gone" [ "$rc" -eq 0 ]

# broken files are named
printf 'Kaydara FBX Binary  \0\x1a\0garbage' > "$T/broken.fbx"
run info "$T/broken.fbx"
check "a broken FBX exits non-zero" [ "$rc" -ne 0 ]
check "naming the file" hasf "$T/err" "$T/broken.fbx: "
run new --character "$T/broken.fbx" --auto-cage 600 --out "$T/broken.cagewrap"
check "new refuses it" [ "$rc" -ne 0 ]
check "naming the file" hasf "$T/err" "$T/broken.fbx: "
check "and writes no project" [ ! -e "$T/broken.cagewrap" ]

finish
