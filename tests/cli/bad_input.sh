#!/usr/bin/env bash
# CLI bad input: every kind of bad file, binding, option and output name must end the command with a
# non-zero exit and one "error: ..." line on stderr naming the file (and the face, vertex or count where
# there is one), without writing the output. A cage with bad elements is not bad input: it binds and
# the summary names the elements it skipped.
# Usage: bad_input.sh <cagewrap binary> [shared assets dir (unused)]
set -u

source "$(dirname "$0")/harness.bash"
no_outputs() {
  local f found=0
  for f in "$T"/out.obj "$T"/out.bin "$T"/out.cwb "$T"/out.txt; do
    [ -e "$f" ] && { echo "$f was written"; found=1; }
  done
  return $found
}

# the "affected elements" line lists exactly elements 12, 13 and 14
lists_only_bad_ids() {
  local ids
  ids=$(grep '^affected elements' "$T/out" | sed 's/^affected elements [0-9]*: //' | grep -o '[0-9][0-9]* (' | tr -d ' (' | tr '\n' ' ')
  [ "$ids" = "12 13 14 " ] || { echo "listed: '$ids'"; return 1; }
}

# fails DESCRIPTION [TEXT...] -- ARGS...: `cagewrap ARGS` exits non-zero, prints "error:" on stderr
# with every TEXT in it (fixed strings), and writes none of $T/out.{obj,bin,cwb,txt}
fails() {
  local what=$1 t
  shift
  local texts=()
  while [ "$1" != "--" ]; do
    texts+=("$1")
    shift
  done
  shift
  rm -f "$T"/out.obj "$T"/out.bin "$T"/out.cwb "$T"/out.txt
  run "$@"
  check "$what: exits non-zero" [ "$rc" -ne 0 ]
  check "$what: says error on stderr" has "$T/err" "error"
  for t in "${texts[@]}"; do check "$what: stderr names '$t'" hasf "$T/err" "$t"; done
  check "$what: writes no output" no_outputs
}

# ---------------------------------------------------------------------------------------- fixtures
write_skin_fixture
head -6 "$T/skin.obj" >"$T/skin6.obj"  # the first six vertices, no faces: another skin
cube_vertices='v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1'
cube_faces='f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8'
printf '%s\n%s\n' "$cube_vertices" "$cube_faces" >"$T/cage.obj"
awk '$1 == "v" { printf "v %s %s %s\n", $2 + 1, $3 + 2, $4 + 3; next } { print }' "$T/cage.obj" >"$T/posed.obj"
# the same 8 vertices with the faces in another order: same counts, other elements
printf '%s\n%s\n' "$cube_vertices" "$(printf '%s\n' "$cube_faces" | tac)" >"$T/cage_reordered.obj"
cat >"$T/tet.obj" <<'EOF'
v -2 -2 -2
v 3 -2 -2
v -2 3 -2
v -2 -2 3
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
EOF
: >"$T/empty.obj"
printf 'hello world\nthis is not a mesh\n\001\002\003\n' >"$T/garbage.ply"
printf 'hello world\nthis is not a mesh\n' >"$T/garbage.obj"
cp "$T/skin.obj" "$T/skin.txt"
# face 1 (0-based) uses vertex index 9 (1-based), i.e. vertex 8 of 0..3
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 9\n' >"$T/oor.obj"
# vertex 2 (0-based) is not a number
printf 'v 0 0 0\nv 1 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 4\n' >"$T/nan.obj"
# a binary PLY cage (the cube) whose vertex 3 is NaN: little-endian float32 0x7fc00000
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n'
  printf 'property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n'
  m='\x00\x00\x80\xbf' p='\x00\x00\x80\x3f' nan='\x00\x00\xc0\x7f'
  printf "$m$m$m" ; printf "$p$m$m"; printf "$p$p$m"; printf "$nan$p$m"
  printf "$m$m$p" ; printf "$p$m$p"; printf "$p$p$p"; printf "$m$p$p"
  for f in '0 3 2 1' '4 5 6 7' '0 1 5 4' '1 2 6 5' '2 3 7 6' '3 0 4 7'; do
    printf '\x04'
    for i in $f; do printf "\\x0$i\\x00\\x00\\x00"; done
  done
} >"$T/posed_nan.ply"

run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --out "$T/cube.cwb"
check "fixture bind exits 0" [ "$rc" -eq 0 ]
check "fixture binding is written" [ -s "$T/cube.cwb" ]
head -c 100 "$T/cube.cwb" >"$T/cut.cwb"
{ printf 'XXBIND01'; tail -c +9 "$T/cube.cwb"; } >"$T/magic.cwb"
: >"$T/empty.cwb"

S=(--mesh "$T/skin.obj")
C=(--cage "$T/cage.obj")
P=(--posed-cage "$T/posed.obj")

# ---------------------------------------------------------------------------------------- bad mesh files
for cmd in bind deform bench; do
  case $cmd in
    bind) rest=("${C[@]}" --out "$T/out.cwb") ;;
    deform) rest=("${C[@]}" "${P[@]}" --out "$T/out.obj") ;;
    bench) rest=("${C[@]}" "${P[@]}") ;;
  esac
  fails "$cmd: missing --mesh file" "$T/missing.obj" "no such file" -- $cmd --mesh "$T/missing.obj" "${rest[@]}"
  fails "$cmd: empty --mesh file" "$T/empty.obj" "empty" -- $cmd --mesh "$T/empty.obj" "${rest[@]}"
  fails "$cmd: garbage .ply" "$T/garbage.ply" "parse" -- $cmd --mesh "$T/garbage.ply" "${rest[@]}"
  fails "$cmd: garbage .obj" "$T/garbage.obj" "no vertices" -- $cmd --mesh "$T/garbage.obj" "${rest[@]}"
  fails "$cmd: unsupported extension" "$T/skin.txt" ".obj" -- $cmd --mesh "$T/skin.txt" "${rest[@]}"
  fails "$cmd: face index out of range" "$T/oor.obj" "face 1" "vertex 8" -- $cmd --mesh "$T/oor.obj" "${rest[@]}"
  fails "$cmd: non-finite vertex" "$T/nan.obj" "vertex 2" "non-finite" -- $cmd --mesh "$T/nan.obj" "${rest[@]}"
done
fails "bind: cage with a face index out of range" "$T/oor.obj" "face 1" "vertex 8" -- \
  bind "${S[@]}" --cage "$T/oor.obj" --out "$T/out.cwb"
fails "bind: missing cage" "$T/nocage.obj" -- bind "${S[@]}" --cage "$T/nocage.obj" --out "$T/out.cwb"
fails "deform: missing posed cage" "$T/noposed.obj" -- deform "${S[@]}" "${C[@]}" --posed-cage "$T/noposed.obj" --out "$T/out.obj"
fails "deform: posed cage with a non-finite vertex" "$T/posed_nan.ply" "vertex 3" "non-finite" -- \
  deform "${S[@]}" "${C[@]}" --posed-cage "$T/posed_nan.ply" --out "$T/out.obj"

# ---------------------------------------------------------------------------------------- mismatched cages and bindings
fails "deform: posed cage with another vertex count" "$T/tet.obj" "has 4 vertices" "has 8" -- \
  deform "${S[@]}" "${C[@]}" --posed-cage "$T/tet.obj" --out "$T/out.obj"
fails "deform --binding: posed cage with another vertex count" "$T/tet.obj" "has 4 vertices" "has 8" -- \
  deform "${S[@]}" "${C[@]}" --posed-cage "$T/tet.obj" --binding "$T/cube.cwb" --out "$T/out.obj"
fails "bench: posed cage with another vertex count" "$T/tet.obj" "has 4 vertices" "has 8" -- \
  bench "${S[@]}" "${C[@]}" --posed-cage "$T/tet.obj"
fails "deform: binding from a cage with other counts" "$T/cube.cwb" "8 vertices" "$T/tet.obj" -- \
  deform "${S[@]}" --cage "$T/tet.obj" --posed-cage "$T/tet.obj" --binding "$T/cube.cwb" --out "$T/out.obj"
fails "deform: binding from a cage with the same counts, other faces" "$T/cube.cwb" "$T/cage_reordered.obj" -- \
  deform "${S[@]}" --cage "$T/cage_reordered.obj" --posed-cage "$T/cage_reordered.obj" --binding "$T/cube.cwb" --out "$T/out.obj"
fails "deform: binding from another skin" "$T/cube.cwb" "7 skin points" "6" -- \
  deform --mesh "$T/skin6.obj" "${C[@]}" "${P[@]}" --binding "$T/cube.cwb" --out "$T/out.obj"
fails "deform: truncated binding" "$T/cut.cwb" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --binding "$T/cut.cwb" --out "$T/out.obj"
fails "deform: binding with a wrong magic" "$T/magic.cwb" "magic" -- \
  deform "${S[@]}" "${C[@]}" "${P[@]}" --binding "$T/magic.cwb" --out "$T/out.obj"
fails "deform: empty binding" "$T/empty.cwb" "empty" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --binding "$T/empty.cwb" --out "$T/out.obj"
fails "deform: missing binding" "$T/none.cwb" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --binding "$T/none.cwb" --out "$T/out.obj"
fails "deform: a mesh given as the binding" "$T/skin.obj" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --binding "$T/skin.obj" --out "$T/out.obj"

# ---------------------------------------------------------------------------------------- options
fails "bind: unknown variant" "wobbly" -- bind "${S[@]}" "${C[@]}" --variant wobbly --out "$T/out.cwb"
fails "deform: unknown variant" "wobbly" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --variant wobbly --out "$T/out.obj"
fails "bench: unknown variant" "wobbly" -- bench "${S[@]}" "${C[@]}" "${P[@]}" --variant wobbly
for bad in "--epsilon 0:epsilon" "--epsilon 1.5:epsilon" "--epsilon -0.1:epsilon" "--local -1:local" "--local nan:local" \
  "-K 0:K" "-K 65:K" "--scale -1:scale" "--max-distance -1:max distance"; do
  opt=${bad%%:*}
  word=${bad#*:}
  # shellcheck disable=SC2086  # $opt is an option and its value
  fails "bind $opt" "$word" -- bind "${S[@]}" "${C[@]}" $opt --out "$T/out.cwb"
  # shellcheck disable=SC2086
  fails "deform $opt" "$word" -- deform "${S[@]}" "${C[@]}" "${P[@]}" $opt --out "$T/out.obj"
done
fails "bench --changes 5" "--changes" "20" -- bench "${S[@]}" "${C[@]}" "${P[@]}" --changes 5
fails "deform: output with a .txt extension" "$T/out.txt" ".obj" ".bin" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --out "$T/out.txt"
fails "deform: output in a missing folder" "$T/no/such/out.obj" -- deform "${S[@]}" "${C[@]}" "${P[@]}" --out "$T/no/such/out.obj"
fails "bind: output in a missing folder" "$T/no/such/out.cwb" -- bind "${S[@]}" "${C[@]}" --out "$T/no/such/out.cwb"

# CLI11 rejects a missing required option and a non-number before any work
run bind "${S[@]}" --out "$T/out.cwb"
check "bind without --cage exits non-zero" [ "$rc" -ne 0 ]
check "bind without --cage names --cage" has "$T/err" "--cage"
run bind "${S[@]}" "${C[@]}" --epsilon abc --out "$T/out.cwb"
check "bind --epsilon abc exits non-zero" [ "$rc" -ne 0 ]
check "bind --epsilon abc names the option" has "$T/err" "epsilon"
check "bind --epsilon abc writes nothing" no_outputs

# ---------------------------------------------------------------------------------------- bad elements still bind
# The cube (6 quads = elements 0-11), then face 6: a zero-area triangle on a new vertex at the middle of
# the edge 1-2 (element 12), then face 7: a second copy of face 0 (elements 13 and 14).
printf '%s\nv 0 -1 -1\n%s\nf 1 9 2\nf 1 4 3 2\n' "$cube_vertices" "$cube_faces" >"$T/cage_bad.obj"
run bind "${S[@]}" --cage "$T/cage_bad.obj" --out "$T/bad.cwb"
check "cage with a zero-area and a duplicate face binds" [ "$rc" -eq 0 ]
check "binding written for the cage with bad faces" [ -s "$T/bad.cwb" ]
check "summary counts 15 elements" has "$T/out" "^elements *15 "
check "summary counts 3 affected elements" has "$T/out" "^affected elements 3: "
check "summary names element 12 as zero area" hasf "$T/out" "12 (zero area)"
check "summary names element 13 as a duplicate" hasf "$T/out" "13 (duplicate)"
check "summary names element 14 as a duplicate" hasf "$T/out" "14 (duplicate)"
check "summary lists only those elements" lists_only_bad_ids
check "stderr warns about the cage file" hasf "$T/err" "$T/cage_bad.obj"
awk '$1 == "v" { printf "v %s %s %s\n", $2 + 1, $3 + 2, $4 + 3; next } { print }' "$T/cage_bad.obj" >"$T/posed_bad.obj"
run deform "${S[@]}" --cage "$T/cage_bad.obj" --posed-cage "$T/posed_bad.obj" --binding "$T/bad.cwb" --out "$T/moved.obj"
check "the cage with bad faces deforms" [ "$rc" -eq 0 ]
check "the cage with bad faces still translates the skin" awk '
  function abs(x) { return x < 0 ? -x : x }
  FNR == NR { if ($1 == "v") { n++; x[n] = $2; y[n] = $3; z[n] = $4 } next }
  $1 == "v" { m++; if (abs($2 - x[m] - 1) > 1e-5 || abs($3 - y[m] - 2) > 1e-5 || abs($4 - z[m] - 3) > 1e-5) bad++ }
  END { exit !(bad == 0 && m == n && n > 0) }' "$T/skin.obj" "$T/moved.obj"

finish
