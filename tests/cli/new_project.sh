#!/usr/bin/env bash
# CLI checks for `cagewrap new`: it writes a project that names the character relative to itself,
# holds the cage and the binding parameters; bad inputs fail with a message naming the file.
# $1 = cagewrap binary, $2 = shared assets folder (unused here). Uses assets/demo_character.glb.
set -uo pipefail
BIN="$1"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DEMO="$ROOT/assets/demo_character.glb"
[[ -x "$BIN" ]] || { echo "skipped: $BIN is not an executable"; exit 77; }
[[ -f "$DEMO" ]] || { echo "skipped: $DEMO not found"; exit 77; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0
check() {  # check "description" command...
  local what="$1"
  shift
  if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $what"; fi
}
runs() { "$BIN" "$@" > "$TMP/out.txt" 2>&1 || { cat "$TMP/out.txt"; return 1; }; }
fails_naming() {  # fails_naming TEXT args...: exits non-zero and says TEXT on stderr
  local text="$1"
  shift
  if "$BIN" "$@" > /dev/null 2> "$TMP/err.txt"; then echo "  exited 0: $*"; return 1; fi
  grep -qF -- "$text" "$TMP/err.txt" || { echo "  stderr: $(cat "$TMP/err.txt")"; return 1; }
}

mkdir -p "$TMP/work/chars"
cp "$DEMO" "$TMP/work/chars/hero.glb"
# an 8-vertex box cage around the demo character
cat > "$TMP/work/cage.obj" <<'OBJ'
v -1 -0.2 -1
v 1 -0.2 -1
v 1 2.2 -1
v -1 2.2 -1
v -1 -0.2 1
v 1 -0.2 1
v 1 2.2 1
v -1 2.2 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
OBJ
P="$TMP/work/hero.cagewrap"
check "new exits 0" runs new --character "$TMP/work/chars/hero.glb" --cage "$TMP/work/cage.obj" --epsilon 0.25 \
  --variant clamped --out "$P"
check "it says what it wrote" grep -q "^wrote .*hero.cagewrap$" "$TMP/out.txt"
check "it names the cage" grep -Eq "^cage .*cage.obj: 8 vertices, 6 faces$" "$TMP/out.txt"
check "the project exists" test -s "$P"
check "no temporary file is left" test ! -e "$P.tmp"
check "format" grep -q '"format": "cagewrap-project"' "$P"
check "version" grep -q '"version": 2,' "$P"
check "character path is relative to the project" grep -q '"path": "chars/hero.glb"' "$P"
check "character hash" grep -Eq '"hash": "fnv1a64:[0-9a-f]{16}"' "$P"
check "8 cage positions" test "$(grep -cE '^      \[-?[0-9.]+, -?[0-9.]+, -?[0-9.]+\],?$' "$P")" -eq 8
check "binding options reach the project" grep -q '"variant": "clamped"' "$P"
check "epsilon" grep -q '"epsilon": 0.25' "$P"
check "the character is untouched" cmp -s "$DEMO" "$TMP/work/chars/hero.glb"

# without a cage: a project with an empty cage
check "new without a cage" runs new --character "$TMP/work/chars/hero.glb" --out "$TMP/work/bare.cagewrap"
check "empty cage" grep -q '"positions": \[\],' "$TMP/work/bare.cagewrap"

# an automatic cage: the project holds it, and the report names its quality
check "new --auto-cage" runs new --character "$TMP/work/chars/hero.glb" --auto-cage 600 --out "$TMP/work/auto.cagewrap"
check "automatic cage in the project" test "$(grep -cE '^      \[-?[0-9.e-]+, -?[0-9.e-]+, -?[0-9.e-]+\],?$' "$TMP/work/auto.cagewrap")" -gt 100
check "both cage options refused" fails_naming "either --cage or --auto-cage" new --character "$DEMO" --cage "$TMP/work/cage.obj" \
  --auto-cage 600 --out "$TMP/x.cagewrap"
check "bad auto-cage parameter named" fails_naming "joint detail" new --character "$DEMO" --auto-cage 600 --joint-detail -1 --out "$TMP/x.cagewrap"

# errors: non-zero exit and a message naming the file
check "missing character" fails_naming "ghost.glb" new --character "$TMP/ghost.glb" --cage "$TMP/work/cage.obj" --out "$TMP/x.cagewrap"
check "missing cage" fails_naming "ghost.obj" new --character "$DEMO" --cage "$TMP/ghost.obj" --out "$TMP/x.cagewrap"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' > "$TMP/bad.obj"
check "bad cage" fails_naming "bad.obj" new --character "$DEMO" --cage "$TMP/bad.obj" --out "$TMP/x.cagewrap"
check "no project after failures" test ! -e "$TMP/x.cagewrap"
check "missing output folder" fails_naming "$TMP/no/dir/x.cagewrap: could not save" new --character "$DEMO" \
  --cage "$TMP/work/cage.obj" --out "$TMP/no/dir/x.cagewrap"
check "refuses the character as output" fails_naming "that is the character file" new \
  --character "$TMP/work/chars/hero.glb" --cage "$TMP/work/cage.obj" --out "$TMP/work/chars/hero.glb"
check "the character survived" cmp -s "$DEMO" "$TMP/work/chars/hero.glb"
check "bad variant" fails_naming "unknown variant 'fancy'" new --character "$DEMO" --variant fancy --out "$TMP/x.cagewrap"
check "--out is required" fails_naming "--out" new --character "$DEMO"

echo "$passed passed, $failed failed"
(( failed == 0 ))
