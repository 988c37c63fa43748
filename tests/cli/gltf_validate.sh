#!/usr/bin/env bash
# The generated demo character (fresh from make-demo, and the committed assets/ copy) passes the
# Khronos glTF validator with no errors. Exit 77 (skipped) only when node is unavailable.
# $1 = cagewrap binary.
set -uo pipefail
BIN="$1"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
command -v node > /dev/null || { echo "node is not installed; skipped"; exit 77; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$BIN" make-demo --out "$TMP/demo.glb" > /dev/null || { echo "FAIL: make-demo"; exit 1; }
node "$ROOT/tests/gltf_validate/validate.js" "$TMP/demo.glb" "$ROOT/assets/demo_character.glb"
rc=$?
(( rc == 2 )) && echo "FAIL: gltf-validator is missing: run scripts/setup.sh"
exit $rc
