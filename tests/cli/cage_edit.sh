#!/usr/bin/env bash
# CLI checks for `cagewrap cage-edit`: linear and Loop subdivision, local red-green refinement, flipping,
# welding and merging on hand-written cages with known counts; the result binds a skin; bad input ends
# with a non-zero exit, an "error: ..." line naming the problem, and no output file.
# Usage: cage_edit.sh <cagewrap binary> [shared assets dir (unused)]
set -u

source "$(dirname "$0")/harness.bash"

field_line() { grep -E "^$1 " "$T/out"; }  # the report line starting with a key
obj_faces() { grep -c '^f ' "$1"; }
obj_vertices() { grep -c '^v ' "$1"; }
# every vertex of OBJ within the cube [-L, L]^3
inside_cube() {
  awk -v l="$2" 'function abs(x) { return x < 0 ? -x : x }
    $1 == "v" { if (abs($2) > l || abs($3) > l || abs($4) > l) { bad++; print "  outside: " $0 } }
    END { exit bad > 0 }' "$1"
}

# ---------------------------------------------------------------------------------------- fixtures
write_skin_fixture
write_cube_fixture "$T/cube.obj"
# a triangle cage: the skin's octahedron without its off-centre vertex, scaled to radius 1.5
awk '$1 == "v" && ++v <= 6 { print "v", 3 * $2, 3 * $3, 3 * $4 } $1 == "f" && ++f <= 8' "$T/skin.obj" >"$T/oct.obj"
# the cube with vertex 1 doubled (vertex 9, 1e-4 away) for the faces that do not start with it
sed -e 's/^f 4 1 5 8$/f 4 9 5 8/' -e 's/^f 1 2 6 5$/f 9 2 6 5/' "$T/cube.obj" >"$T/seam.obj"
sed -i '8a v -1.0001 -1 -1' "$T/seam.obj"

# ---------------------------------------------------------------------------------------- subdivision
run cage-edit --in "$T/cube.obj" --out "$T/linear.obj" --subdivide linear
check "linear exits 0" [ "$rc" -eq 0 ]
check "linear: 26 vertices, 24 quads" has "$T/out" '^out  *26 vertices, 24 faces, 48 elements$'
check "linear: the OBJ has 24 faces" [ "$(obj_faces "$T/linear.obj")" -eq 24 ]
check "linear: the shape is kept (every vertex on the cube)" inside_cube "$T/linear.obj" 1
check "linear: the quads stay quads" lacks "$T/linear.obj" '^f [0-9]* [0-9]* [0-9]*$'

run cage-edit --in "$T/cube.obj" --out "$T/linear2.obj" --subdivide linear --levels 2
check "two levels: 96 faces" [ "$(obj_faces "$T/linear2.obj")" -eq 96 ]

run cage-edit --in "$T/cube.obj" --out "$T/loop.obj" --subdivide loop
check "loop exits 0" [ "$rc" -eq 0 ]
check "loop: V + E vertices, 4 F triangles of the triangulated cube" has "$T/out" '^out  *26 vertices, 48 faces, 48 elements$'
check "loop: says the quads were triangulated first" hasf "$T/out" "6 faces that are not triangles"
check "loop: every vertex inside the cube" inside_cube "$T/loop.obj" 1
check "loop: the corners move inside" inside_cube <(head -8 "$T/loop.obj") 0.9

# ---------------------------------------------------------------------------------------- local
run cage-edit --in "$T/oct.obj" --out "$T/refined.obj" --refine-faces 0,2
check "refine exits 0" [ "$rc" -eq 0 ]
check "refine: 2 red faces close to 4 red + 4 green" has "$T/out" '^out  *14 vertices, 24 faces, 24 elements$'
check "refine: the operation is echoed" has "$T/out" '^operation  *refine faces 0 2$'
run bind --mesh "$T/skin.obj" --cage "$T/refined.obj" --out "$T/refined.cwb"
check "the refined cage binds the skin" [ "$rc" -eq 0 ]

# ---------------------------------------------------------------------------------------- flip, weld, merge
run cage-edit --in "$T/cube.obj" --out "$T/flipped.obj" --flip
check "flip exits 0" [ "$rc" -eq 0 ]
check "flip reverses the first face" has "$T/flipped.obj" '^f 1 2 3 4$'
check "flip reverses the last face" has "$T/flipped.obj" '^f 4 8 5 1$'
run cage-edit --in "$T/cube.obj" --out "$T/flip1.obj" --flip-faces 1
check "flip one face: only face 1 changes" [ "$(diff <(grep '^f' "$T/cube.obj") <(grep '^f' "$T/flip1.obj") | grep -c '^>')" -eq 1 ]

run cage-edit --in "$T/seam.obj" --out "$T/welded.obj" --weld-distance 0.001
check "weld exits 0" [ "$rc" -eq 0 ]
check "weld: 9 vertices become 8" has "$T/out" '^out  *8 vertices, 6 faces, 12 elements$'
check "weld: nothing dropped" has "$T/out" '^dropped faces  *0$'

run cage-edit --in "$T/cube.obj" --out "$T/merged.obj" --merge-vertices 0,1
check "merge exits 0" [ "$rc" -eq 0 ]
check "merge: 7 vertices, the two quads on the edge become triangles" has "$T/out" '^out  *7 vertices, 6 faces, 10 elements$'
run cage-edit --in "$T/oct.obj" --out "$T/merged2.obj" --merge-vertices 0,2
check "merge on triangles drops the two collapsed faces" has "$T/out" '^dropped faces  *2: 0 4$'
check "and warns about each" has "$T/out" 'face 4 collapsed'
check "the merged octahedron has 6 faces" [ "$(obj_faces "$T/merged2.obj")" -eq 6 ]

# ---------------------------------------------------------------------------------------- errors
# fails DESCRIPTION TEXT -- ARGS...: non-zero exit, TEXT (fixed) on stderr, no $T/x.obj written
fails() {
  local what=$1 text=$2
  shift 3
  rm -f "$T/x.obj"
  run "$@"
  check "$what: exits non-zero" [ "$rc" -ne 0 ]
  check "$what: stderr names '$text'" hasf "$T/err" "$text"
  check "$what: writes no output" [ ! -e "$T/x.obj" ]
}
fails "a face out of range" "face 9 out of range: the cage has 6 faces" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --refine-faces 0,9
fails "a vertex out of range" "vertex 40 out of range: the cage has 8 vertices" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --merge-vertices 1,40
fails "no operation" "give exactly one operation" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj"
fails "two operations" "2 given" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --flip --subdivide loop
fails "too many levels" "levels must be 1 to 6, not 9" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --subdivide linear --levels 9
fails "levels without subdivide" "--levels goes with --subdivide" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --levels 2 --flip
fails "an unknown scheme" "cubic not in" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --subdivide cubic
fails "a negative weld distance" "weld distance must be positive and finite, not -1" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --weld-distance -1
fails "a weld that collapses everything" "collapses every face" -- cage-edit --in "$T/cube.obj" --out "$T/x.obj" --weld-distance 5
fails "a missing cage" "none.obj: no such file" -- cage-edit --in "$T/none.obj" --out "$T/x.obj" --flip
fails "a non-OBJ output" "x.ply: the cage is written as .obj" -- cage-edit --in "$T/cube.obj" --out "$T/x.ply" --flip

finish
