#!/bin/bash
# docs/editor-actions.md is what `cagewrap actions` prints: the editor's action table, which menus,
# shortcuts, panels and --script all run. Regenerate it with: ./build/cagewrap actions > docs/editor-actions.md
set -u
bin=$1
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$bin" actions > "$out" || { echo "cagewrap actions failed"; exit 1; }
grep -q '^| `select` | `all\\|none' "$out" || { echo "the table has no select row:"; head -20 "$out"; exit 1; }
grep -q '^| `screenshot` |' "$out" || { echo "the window's actions are missing (screenshot)"; exit 1; }
if ! diff -u "$here/../../docs/editor-actions.md" "$out"; then
  echo "docs/editor-actions.md is out of date: ./build/cagewrap actions > docs/editor-actions.md"
  exit 1
fi
echo "docs/editor-actions.md matches the action table ($(grep -c '^| `' "$out") actions)"
