#!/usr/bin/env bash
# CLI checks for `cagewrap cage`: the demo character's cage, a round trip through `bind`, the real
# mannequin when present, and errors.
# $1 = cagewrap binary, $2 = shared assets folder (may be absent).
set -uo pipefail
BIN="$1"
ASSETS="${2:-}"
DEMO="$(cd "$(dirname "$0")/../.." && pwd)/assets/demo_character.glb"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0
check() {  # check "what" command...
  local what="$1"
  shift
  if "$@"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: $what"
  fi
}
field() { awk -v k="$1" '$1 == k {print $2}' "$2"; }  # first value after a one-word key
between() { [[ "$1" =~ ^[0-9.]+$ ]] && awk -v x="$1" -v lo="$2" -v hi="$3" 'BEGIN {exit !(x >= lo && x <= hi)}'; }

# The demo character: a closed, clean cage of 2,000 triangles paired into 1,000-3,000 faces (quads
# and triangles) that wraps every skin vertex.
"$BIN" cage --mesh "$DEMO" --faces 2000 --failures "$TMP/failures.txt" --out "$TMP/cage.obj" > "$TMP/report.txt" 2> "$TMP/err.txt"
check "cage on the demo exits 0 ($(cat "$TMP/err.txt"))" test $? -eq 0
cat "$TMP/report.txt"
faces=$(field faces "$TMP/report.txt")
check "faces '$faces' in 1000..3000" between "$faces" 1000 3000
elements=$(field elements "$TMP/report.txt")
check "elements '$elements' in 1900..2000 (--faces is the decimation's triangle target)" between "$elements" 1900 2000
quads=$(awk '$1 == "faces" {print $3}' "$TMP/report.txt" | tr -d '(')
check "quads '$quads' reported and present" between "$quads" 1 "$faces"
check "the OBJ has $quads quads" test "$(awk '/^f / && NF == 5' "$TMP/cage.obj" | wc -l)" -eq "$quads"
check "the OBJ has only quads and triangles" test "$(awk '/^f / && NF != 4 && NF != 5' "$TMP/cage.obj" | wc -l)" -eq 0
check "the cage is closed" grep -Eq '^closed +yes \(0 boundary edges, 1 components\)' "$TMP/report.txt"
check "no non-manifold edges" grep -Eq '^non-manifold +0 edges' "$TMP/report.txt"
check "consistently oriented" grep -Eq '^misoriented +0 edges' "$TMP/report.txt"
check "no self-crossings" grep -Eq '^self-crossings +0 ' "$TMP/report.txt"
check "no crossings between pieces" grep -Eq '^piece crossings +0 ' "$TMP/report.txt"
check "no degenerate triangles" grep -Eq '^degenerate +0 triangles' "$TMP/report.txt"
check "no needles" grep -Eq '^needles +0 triangles' "$TMP/report.txt"
check "no skin vertex outside" grep -Eq '^outside points +0$' "$TMP/report.txt"
check "one closed piece is not wrapped" grep -Eq '^wrapped +no$' "$TMP/report.txt"
quality=$(field quality "$TMP/report.txt" | tr -d '%')
check "quality '$quality' reported and at least 95%" between "$quality" 95 100
failing=$(awk '$1 == "failing" && $2 == "points" {print $3}' "$TMP/report.txt")
check "failing points '$failing' reported" between "$failing" 1 100000
check "--failures lists $failing points" test "$(grep -vc '^#' "$TMP/failures.txt")" -eq "$failing"
check "the failing points are skin vertex indices" test "$(grep -v '^#' "$TMP/failures.txt" | grep -vc '^[0-9][0-9]*$')" -eq 0
seconds=$(field seconds "$TMP/report.txt")
check "seconds '$seconds' reported" between "$seconds" 0 100000  # timing belongs to benchmarks
check "the OBJ has $faces faces" test "$(grep -c '^f ' "$TMP/cage.obj")" -eq "$faces"
verts=$(field vertices "$TMP/report.txt")
check "the OBJ has $verts vertices" test "$(grep -c '^v ' "$TMP/cage.obj")" -eq "$verts"

# Round trip: the written cage, bound as a project's rig (the character's separation labels and
# attachment), gives the same quality figure as the cage report: one figure everywhere.
"$BIN" new --character "$DEMO" --cage "$TMP/cage.obj" --out "$TMP/p.cagewrap" > /dev/null
"$BIN" check --project "$TMP/p.cagewrap" --clip walk --fps 1 --max-worst 1 --max-rms 1 --max-stretch 1000 > "$TMP/check.txt"
check "the rig of the written cage is checked (exit 0)" test $? -eq 0
bq=$(sed -n 's/^rig: .* cage quality \([0-9.]*\)%.*/\1/p' "$TMP/check.txt")
check "the rig reports the same quality ($bq vs $quality)" awk -v a="$bq" -v b="$quality" 'BEGIN {d = a - b; exit !(a != "" && d < 0.05 && d > -0.05)}'
# a plain mesh (no skeleton, so no separation) binds with its own figure, also printed
"$BIN" skin --character "$DEMO" --out "$TMP/skin.obj" > /dev/null
"$BIN" bind --mesh "$TMP/skin.obj" --cage "$TMP/cage.obj" --out "$TMP/b.cwb" > "$TMP/bind.txt"
check "bind with the written cage exits 0" test $? -eq 0
check "bind prints a quality figure" grep -q '^cage  *quality  *[0-9.]*%' "$TMP/bind.txt"

# Parameters: more joint detail and a uniform clearance still give clean cages; no fit is allowed.
"$BIN" cage --mesh "$DEMO" --faces 1500 --joint-detail 2 --concave-share 1 --inflate 0.005 --no-quads --out "$TMP/c2.obj" > "$TMP/r2.txt"
check "cage with options exits 0" test $? -eq 0
check "1500 faces asked, at most 1500 built" between "$(field faces "$TMP/r2.txt")" 1400 1500
check "--no-quads: triangles only" grep -Eq '^faces +[0-9]+ \(0 quads' "$TMP/r2.txt"
check "--no-quads: one element per face" test "$(field faces "$TMP/r2.txt")" -eq "$(field elements "$TMP/r2.txt")"
check "clean with options" grep -Eq '^needles +0 triangles' "$TMP/r2.txt"
"$BIN" cage --mesh "$TMP/skin.obj" --faces 800 --inflate 0.02 --inflate-absolute --out "$TMP/c3.obj" > "$TMP/r3.txt"
check "cage from an OBJ mesh (no skeleton) exits 0" test $? -eq 0
check "no joints from an OBJ" grep -Eq '^joints +0$' "$TMP/r3.txt"
check "absolute inflate is printed as given" grep -Eq '^inflate +0\.02$' "$TMP/r3.txt"

# Errors: non-zero exit and a message naming the problem.
"$BIN" cage --mesh "$DEMO" --faces 2 --out "$TMP/x.obj" 2> "$TMP/err.txt"
check "too few faces fails" test $? -ne 0
check "too few faces is named" grep -q "target faces must be at least 4" "$TMP/err.txt"
"$BIN" cage --mesh "$TMP/none.glb" --out "$TMP/x.obj" 2> "$TMP/err.txt"
check "a missing file fails" test $? -ne 0
check "a missing file is named" grep -q "none.glb: no such file" "$TMP/err.txt"
"$BIN" cage --mesh "$DEMO" --out "$TMP/x.ply" 2> "$TMP/err.txt"
check "a non-OBJ output fails" test $? -ne 0
check "a non-OBJ output is named" grep -q "x.ply: the cage is written as .obj" "$TMP/err.txt"
"$BIN" cage --mesh "$DEMO" --concave-share 3 --out "$TMP/x.obj" 2> "$TMP/err.txt"
check "a bad concave share fails and is named" grep -q "concave share must be in" "$TMP/err.txt"
"$BIN" cage --mesh "$DEMO" --wrap sometimes --out "$TMP/x.obj" 2> "$TMP/err.txt"
check "a bad wrap mode fails" test $? -ne 0

# The real mannequin (59 separate, overlapping segments), when the shared assets are here: one
# closed shell per segment (small neighbours grouped), at least 95% on the quality figure.
if [[ -n "$ASSETS" && -f "$ASSETS/mannequiny.glb" ]]; then
  "$BIN" cage --mesh "$ASSETS/mannequiny.glb" --out "$TMP/m.obj" > "$TMP/m.txt"
  check "cage on mannequiny exits 0" test $? -eq 0
  cat "$TMP/m.txt"
  check "mannequiny faces in 1000..3000" between "$(field faces "$TMP/m.txt")" 1000 3000
  check "mannequiny elements in 1800..2000" between "$(field elements "$TMP/m.txt")" 1800 2000
  check "mannequiny: 45 joints" grep -Eq '^joints +45$' "$TMP/m.txt"
  check "mannequiny: its 59 pieces are reported" grep -q "the welded skin is 59 pieces" "$TMP/m.txt"
  shells=$(awk '$1 == "wrapped" {print $3}' "$TMP/m.txt" | tr -d '(')
  check "mannequiny: wrapped in '$shells' closed surfaces" between "$shells" 2 58
  check "mannequiny: every shell closed" grep -Eq "^closed +yes \(0 boundary edges, $shells components\)" "$TMP/m.txt"
  check "mannequiny: no shell folds over itself" grep -Eq '^self-crossings +0 ' "$TMP/m.txt"
  check "mannequiny: no needles" grep -Eq '^needles +0 triangles' "$TMP/m.txt"
  check "mannequiny: no degenerate triangles" grep -Eq '^degenerate +0 triangles' "$TMP/m.txt"
  check "mannequiny: no skin vertex outside" grep -Eq '^outside points +0$' "$TMP/m.txt"
  mq=$(field quality "$TMP/m.txt" | tr -d '%')
  check "mannequiny: quality '$mq' at least 95%" between "$mq" 95 100
  "$BIN" cage --mesh "$ASSETS/mannequiny.glb" --one-surface --out "$TMP/m1.obj" > "$TMP/m1.txt"
  check "mannequiny --one-surface: one closed cage" grep -Eq '^closed +yes \(0 boundary edges, 1 components\)' "$TMP/m1.txt"
  "$BIN" cage --mesh "$ASSETS/mannequiny.glb" --wrap never --out "$TMP/m2.obj" > "$TMP/m2.txt"
  check "mannequiny --wrap never keeps the pieces" grep -Eq '^closed +no' "$TMP/m2.txt"
else
  echo "shared assets not found; skipped the mannequin checks"
fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
