#!/usr/bin/env bash
# CLI checks for `cagewrap patch` (parametric drivers, docs/parametric-drivers.md): a hand-written
# 4 x 4 driver moved rigidly moves the skin rigidly; the rest driver leaves it in place; fitting a
# driver to cage quads; the generated demo and the density bench; bad files and options refused
# naming the file and control point.
# Usage: patch.sh <cagewrap binary> [shared assets dir]
set -u

source "$(dirname "$0")/harness.bash"

# driver FILE DX DY DZ [ROW1]: a 4 x 4 B-spline grid on the plane y = 0 over x, z in [-1.5, 1.5],
# shifted by (DX, DY, DZ); ROW1 replaces the second row's points when given
driver() {
  local rows=() r c x z
  for r in 0 1 2 3; do
    local row=()
    for c in 0 1 2 3; do
      x=$(awk -v c="$c" -v d="$2" 'BEGIN { print c - 1.5 + d }')
      z=$(awk -v r="$r" -v d="$4" 'BEGIN { print r - 1.5 + d }')
      row+=("[$x, $3, $z]")
    done
    local joined
    joined=$(IFS=,; echo "${row[*]}")
    rows+=("[$joined]")
  done
  [ -n "${5:-}" ] && rows[1]=$5
  local all
  all=$(IFS=,; echo "${rows[*]}")
  printf '{"format": "cagewrap-patch", "version": 1, "grids": [{"basis": "bspline", "rows": 4, "cols": 4, "points": [%s]}]}\n' "$all" >"$1"
}

write_skin_fixture
driver "$T/rest.cwpatch" 0 0 0
driver "$T/moved.cwpatch" 0.25 -1 0.5

run patch deform --mesh "$T/skin.obj" --patch "$T/rest.cwpatch" --posed-patch "$T/rest.cwpatch" --out "$T/same.obj"
check "deform by the rest driver exits 0" test "$rc" -eq 0
check "the rest driver leaves the skin in place" same_after_shift "$T/skin.obj" "$T/same.obj" 0 0 0
check "the report names samples and density (one span: 3 x 3 samples)" has "$T/out" "to 9 samples (density 2"
run patch deform --mesh "$T/skin.obj" --patch "$T/rest.cwpatch" --posed-patch "$T/moved.cwpatch" --density 3 --out "$T/moved.obj"
check "deform by a translated driver exits 0" test "$rc" -eq 0
check "a translated driver translates the skin" same_after_shift "$T/skin.obj" "$T/moved.obj" 0.25 -1 0.5
check "density 3 gives 4 x 4 samples" has "$T/out" "to 16 samples (density 3"

# the same driver through glTF extras (written by `patch fit`, below) and a driver fitted to cage quads
cat >"$T/cage.obj" <<'EOF2'
v -1.5 0 -1.5
v -0.5 0 -1.5
v 0.5 0 -1.5
v 1.5 0 -1.5
v -1.5 0 -0.5
v -0.5 0 -0.5
v 0.5 0 -0.5
v 1.5 0 -0.5
v -1.5 0 0.5
v -0.5 0 0.5
v 0.5 0 0.5
v 1.5 0 0.5
v -1.5 0 1.5
v -0.5 0 1.5
v 0.5 0 1.5
v 1.5 0 1.5
v 0 3 0
f 1 5 6 2
f 2 6 7 3
f 3 7 8 4
f 5 9 10 6
f 6 10 11 7
f 7 11 12 8
f 9 13 14 10
f 10 14 15 11
f 11 15 16 12
f 1 2 17
EOF2
run patch fit --cage "$T/cage.obj" --faces 0,1,2,3,4,5,6,7,8 --out "$T/fit.glb"
check "fit to 3 x 3 quads exits 0" test "$rc" -eq 0
check "fit reports a 4 x 4 grid" has "$T/out" "a 4 x 4 control-point"
run patch deform --mesh "$T/skin.obj" --patch "$T/fit.glb" --posed-patch "$T/fit.glb" --out "$T/fit_same.bin"
check "a fitted driver read from .glb extras binds and leaves the skin in place" test "$rc" -eq 0
check "the .bin output has 7 points" test "$(wc -c <"$T/fit_same.bin")" -eq 84
run patch fit --cage "$T/cage.obj" --faces 0,1,9 --out "$T/bad.cwpatch"
check "fit refuses a triangle" test "$rc" -ne 0
check "the refusal names the cage file and face 9" has "$T/err" "cage.obj: .*cage face 9 has 3 corners"
check "no file is written" test ! -e "$T/bad.cwpatch"
run patch fit --cage "$T/cage.obj" --faces 0,x --out "$T/bad.cwpatch"
check "fit refuses a bad face list" has "$T/err" '"x" is not a whole number'

# bad drivers and options
driver "$T/nan.cwpatch" 0 0 0 '[[0, 0, 0], [1, 0, 0], [2, null, 0], [3, 0, 0]]'
run patch deform --mesh "$T/skin.obj" --patch "$T/rest.cwpatch" --posed-patch "$T/nan.cwpatch" --out "$T/x.obj"
check "a non-finite control point fails" test "$rc" -ne 0
check "the error names the file and control point" has "$T/err" "nan.cwpatch: .*row 1 column 2"
driver "$T/short.cwpatch" 0 0 0 '[[0, 0, 0], [1, 0, 0], [2, 0, 0]]'
run patch deform --mesh "$T/skin.obj" --patch "$T/short.cwpatch" --posed-patch "$T/rest.cwpatch" --out "$T/x.obj"
check "a short row fails naming file and row" has "$T/err" "short.cwpatch: grid 0 row 1 .*3 control points but"
run patch deform --mesh "$T/skin.obj" --patch "$T/rest.cwpatch" --posed-patch "$T/rest.cwpatch" --density 0 --out "$T/x.obj"
check "density 0 fails" test "$rc" -ne 0
check "density 0 is named" has "$T/err" "density must be between 1 and 1024"
check "nothing is written on errors" test ! -e "$T/x.obj"

# the generated case and the density bench
run patch demo --out-dir "$T/demo" --resolution 2
check "patch demo exits 0" test "$rc" -eq 0
check "patch demo writes four files" test -s "$T/demo/mesh.obj" -a -s "$T/demo/driver.cwpatch" -a -s "$T/demo/driver_posed.cwpatch" -a -s "$T/demo/inputs.json"
run patch bench --mesh "$T/demo/mesh.obj" --patch "$T/demo/driver.cwpatch" --twist "$T/demo/inputs.json" --densities 1,4 --reference 8 --json
check "patch bench exits 0" test "$rc" -eq 0
if command -v python3 >/dev/null; then
  check "two rows with timings and fidelity; density 4 is nearer the reference than density 1" python3 - "$T/out" <<'EOF2'
import json, sys
j = json.load(open(sys.argv[1]))
rows = j["rows"]
assert [r["density"] for r in rows] == [1, 4], rows
assert rows[0]["samples"] == 10 * 4 and rows[1]["samples"] == 37 * 13, rows
for r in rows:
    assert r["bind_s"] > 0 and r["deform_median_ms"] > 0 and r["twist"]["rms"] > 0, r
assert rows[1]["reference"]["rms"] < rows[0]["reference"]["rms"], rows
assert rows[1]["twist"]["rms"] < 0.05, rows
EOF2
fi
finish
