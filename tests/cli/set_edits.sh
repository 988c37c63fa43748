#!/usr/bin/env bash
# CLI set edits: `cagewrap bind --edits FILE` applies a saved set edits file (docs/edits-format.md):
# per-point rules and rules by point and face lists. On the octahedron in the cube: point 0 sits near
# the +x face; made to follow only the -x face, it stays put when only the +x face moves. A reset rule
# gives the unedited binding back byte for byte; bad files fail naming the file and the JSON path.
# Usage: set_edits.sh <cagewrap binary> [shared assets dir (unused)]
set -u

source "$(dirname "$0")/harness.bash"

write_skin_fixture
write_cube_fixture "$T/cage.obj"
# only the +x face moves: vertices with x = 1 shift by 1 along x
awk '$1 == "v" && $2 == 1 { printf "v 2 %s %s\n", $3, $4; next } { print }' "$T/cage.obj" >"$T/posed.obj"
# x of vertex N (1-based) of an OBJ
vx() { awk -v n="$2" '$1 == "v" { k++; if (k == n) { print $2; exit } }' "$1"; }
near() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 1e-5) }'; }
far() { ! near "$1" "$2"; }

# face 5 (0-based) is "f 4 1 5 8": the x = -1 face, elements 10 and 11
cat >"$T/only.json" <<'EOF2'
{"format": "cagewrap-set-edits", "version": 1,
 "rules": [{"mode": "only", "points": [0], "faces": [5]}]}
EOF2
cat >"$T/per_point.json" <<'EOF2'
{"format": "cagewrap-set-edits", "version": 1, "points": 7, "elements": 12,
 "edits": [{"point": 0, "include": [10, 11], "only": true}]}
EOF2
cat >"$T/reset.json" <<'EOF2'
{"format": "cagewrap-set-edits", "version": 1,
 "edits": [{"point": 0, "exclude": [2, 3]}],
 "rules": [{"mode": "reset", "points": [0]}]}
EOF2

run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --variant basic --out "$T/plain.cwb"
check "plain bind exits 0" [ "$rc" -eq 0 ]
check "plain bind: no set edits line" lacks "$T/out" "^set edits"
for f in only per_point; do
  run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --variant basic --edits "$T/$f.json" --out "$T/$f.cwb"
  check "bind --edits $f exits 0" [ "$rc" -eq 0 ]
  check "bind --edits $f: summary counts the edited points" has "$T/out" "^set edits *1 points ($T/$f.json)\$"
  check "bind --edits $f: nothing on stderr" [ ! -s "$T/err" ]
  run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/posed.obj" --binding "$T/$f.cwb" --out "$T/$f.obj"
  check "deform with the $f binding exits 0" [ "$rc" -eq 0 ]
  check "$f: point 0 follows only the -x face, which did not move" near "$(vx "$T/$f.obj" 1)" 0.5
done
cmp -s "$T/only.cwb" "$T/per_point.cwb"
check "a rule and the per-point edit it stands for give the same binding" [ $? -eq 0 ]
run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/posed.obj" --binding "$T/plain.cwb" --out "$T/plain.obj"
check "without edits point 0 follows the +x face" far "$(vx "$T/plain.obj" 1)" 0.5
run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --variant basic --edits "$T/reset.json" --out "$T/reset.cwb"
check "bind with a reset rule exits 0" [ "$rc" -eq 0 ]
check "bind with a reset rule: no edit left" has "$T/out" "^set edits *0 points"
cmp -s "$T/plain.cwb" "$T/reset.cwb"
check "a reset rule gives the unedited binding byte for byte" [ $? -eq 0 ]

# ---------------------------------------------------------------------------------------- errors
# fails DESCRIPTION EDITS_TEXT TEXT...: bind with that edits file exits non-zero, names the file and
# every TEXT on stderr, and writes no binding
fails() {
  local what=$1 text=$2
  shift 2
  printf '%s\n' "$text" >"$T/bad.json"
  rm -f "$T/out.cwb"
  run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --edits "$T/bad.json" --out "$T/out.cwb"
  check "$what: exits non-zero" [ "$rc" -ne 0 ]
  check "$what: says error on stderr" has "$T/err" "^error: "
  check "$what: names the file" hasf "$T/err" "$T/bad.json"
  for t in "$@"; do check "$what: stderr names '$t'" hasf "$T/err" "$t"; done
  check "$what: writes no binding" [ ! -e "$T/out.cwb" ]
}
head='{"format": "cagewrap-set-edits", "version": 1, '
fails "not JSON" '{"format": ' "not a JSON file" "line 2, column 1"
fails "another format" '{"format": "cagewrap-project", "version": 1}' "not a set edits file"
fails "newer version" '{"format": "cagewrap-set-edits", "version": 9, "edits": []}' "version 9"
fails "element out of range" "$head"'"edits": [{"point": 1, "exclude": [3, 12]}]}' "edits[0].exclude[1] is element 12, but the cage has 12 elements"
fails "point out of range" "$head"'"edits": [{"point": 7}]}' "edits[0].point is skin point 7, but the skin has 7 points"
fails "face out of range" "$head"'"rules": [{"mode": "remove", "points": [1], "faces": [6]}]}' "rules[0].faces[0] is face 6, but the cage has 6 faces"
fails "unknown mode" "$head"'"rules": [{"mode": "erase", "points": [1], "faces": [1]}]}' 'rules[0].mode is "erase"'
fails "another skin" "$head"'"points": 99, "edits": []}' "made for a skin of 99 points"
rm -f "$T/out.cwb"
run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --edits "$T/missing.json" --out "$T/out.cwb"
check "missing edits file: exits non-zero" [ "$rc" -ne 0 ]
check "missing edits file: named" hasf "$T/err" "$T/missing.json"

finish
