#!/usr/bin/env bash
# CLI robustness (docs/robustness.md): bad characters and projects end the command with a non-zero
# exit and an "error:" line naming the file, never a crash (exit >= 128) or a hang (ctest's timeout):
# an empty and a truncated GLB, a GLB with a wrong magic, a cage with no faces, a project file cut
# short, a project of a newer version, a project whose JSON is broken.
# Usage: robustness.sh <cagewrap binary> [shared assets dir (unused)]
set -u

source "$(dirname "$0")/harness.bash"

# fails DESCRIPTION FILE -- ARGS...: `cagewrap ARGS` exits 1..127 with "error" and FILE on stderr
fails() {
  local what=$1 file=$2
  shift 3
  run "$@"
  check "$what: exits non-zero" [ "$rc" -ne 0 ]
  check "$what: does not crash" [ "$rc" -lt 128 ]
  check "$what: says error" has "$T/err" "error"
  check "$what: names $file" hasf "$T/err" "$file"
}

run make-demo --out "$T/demo.glb" --cell-size 0.05
check "make-demo exits 0" [ "$rc" -eq 0 ]
# a cell size outside the range is refused by name, before any work, and writes nothing
fails "make-demo: cell size too small" "--cell-size 0.001" -- make-demo --out "$T/tiny.glb" --cell-size 0.001
check "make-demo: the range is given" hasf "$T/err" "0.00125..0.1"
check "make-demo: nothing written" [ ! -e "$T/tiny.glb" ]
write_skin_fixture
printf 'v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n' >"$T/nofaces.obj"
cp "$T/nofaces.obj" "$T/cage.obj"
printf 'f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n' >>"$T/cage.obj"

# ------------------------------------------------------------------ characters
: >"$T/empty.glb"
fails "info: empty GLB" "$T/empty.glb" -- info "$T/empty.glb"
size=$(stat -c %s "$T/demo.glb")
for cut in 3 12 20 100 $((size / 2)) $((size - 1)); do
  head -c "$cut" "$T/demo.glb" >"$T/cut$cut.glb"
  fails "info: GLB cut at byte $cut of $size" "$T/cut$cut.glb" -- info "$T/cut$cut.glb"
  fails "new: GLB cut at byte $cut of $size" "$T/cut$cut.glb" -- new --character "$T/cut$cut.glb" --out "$T/p.cagewrap"
done
{ printf 'GLTF'; tail -c +5 "$T/demo.glb"; } >"$T/magic.glb"
fails "info: GLB with a wrong magic" "$T/magic.glb" -- info "$T/magic.glb"

# ------------------------------------------------------------------ cages
fails "bind: cage with no faces" "$T/nofaces.obj" -- bind --mesh "$T/skin.obj" --cage "$T/nofaces.obj" --out "$T/o.cwb"
fails "new: cage with no faces" "$T/nofaces.obj" -- new --character "$T/demo.glb" --cage "$T/nofaces.obj" --out "$T/p.cagewrap"

# ------------------------------------------------------------------ projects
run new --character "$T/demo.glb" --cage "$T/cage.obj" --out "$T/good.cagewrap"
check "new exits 0" [ "$rc" -eq 0 ]
run pose --project "$T/good.cagewrap" --out "$T/o.obj"
check "pose of the good project exits 0" [ "$rc" -eq 0 ]
size=$(stat -c %s "$T/good.cagewrap")
for cut in 0 1 $((size / 3)) $((size / 2)) $((size - 3)); do
  head -c "$cut" "$T/good.cagewrap" >"$T/cut.cagewrap"
  fails "pose: project cut at byte $cut of $size" "$T/cut.cagewrap" -- pose --project "$T/cut.cagewrap" --out "$T/o.obj"
done
sed 's/"version": 2/"version": 99/' "$T/good.cagewrap" >"$T/newer.cagewrap"
fails "pose: project of a newer version" "$T/newer.cagewrap" -- pose --project "$T/newer.cagewrap" --out "$T/o.obj"
check "pose: newer version says so" hasf "$T/err" "newer"
sed '0,/"cage"/s/"cage"/"cage" oops/' "$T/good.cagewrap" >"$T/syntax.cagewrap"
fails "pose: project with a JSON syntax error" "$T/syntax.cagewrap" -- pose --project "$T/syntax.cagewrap" --out "$T/o.obj"
check "pose: syntax error names the line" hasf "$T/err" "line"

finish
