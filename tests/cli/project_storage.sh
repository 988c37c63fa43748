#!/usr/bin/env bash
# CLI checks for how a project stores its character and binding: `cagewrap new --embed
# --cache-binding`, `cagewrap project P` (shows it; --embed, --unembed, --cache-binding,
# --no-cache-binding, --character for a moved file), and `cagewrap pose` using the cache: an
# embedded project poses with the character file gone, the cached binding is used (no bind) and
# gives the same skin as a fresh bind, a cache made stale by editing the project is named and not
# used. $1 = cagewrap binary. Uses assets/demo_character.glb and assets/demo_cage.obj.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tests/cli/harness.bash"
need_demo_assets

mkdir -p "$T/a" "$T/b"
cp "$DEMO" "$T/a/hero.glb"
P="$T/a/hero.cagewrap"

run new --character "$T/a/hero.glb" --cage "$CAGE" --embed --cache-binding --out "$P"
check "new --embed --cache-binding exits 0" test "$rc" -eq 0
check "it says it embedded" has "$T/out" "^embedded   the character ($(stat -c %s "$DEMO") bytes)"
check "it says it cached" hasf "$T/out" "cached     the binding in $P.cwb"
check "the cache file is beside the project" test -s "$P.cwb"
check "version 3 (embedded)" grep -q '"version": 3,' "$P"
check "the project records the cache" grep -q '"binding_cache": {"file": "hero.cagewrap.cwb"' "$P"

run project "$P"
check "project shows the storage" test "$rc" -eq 0
check "embedded, with its size" has "$T/out" "^character  embedded ($(stat -c %s "$DEMO") bytes"
check "cache up to date" hasf "$T/out" "binding    cached in $P.cwb (up to date)"

# the project alone: the character file gone, posing uses the embedded character and the cache
rm "$T/a/hero.glb"
run pose --project "$P" --clip walk --time 0.25 --out "$T/cached.bin"
check "pose of an embedded project with its character gone" test "$rc" -eq 0
check "pose uses the cached binding" hasf "$T/err" "using the cached binding $P.cwb (no bind)"
# the same pose from a fresh bind: caching off in a copy, no cache next to it
cp "$P" "$T/b/fresh.cagewrap"
run project "$T/b/fresh.cagewrap" --no-cache-binding
check "--no-cache-binding exits 0" test "$rc" -eq 0
check "no binding_cache record" lacks "$T/b/fresh.cagewrap" '"binding_cache"'
run pose --project "$T/b/fresh.cagewrap" --clip walk --time 0.25 --out "$T/fresh.bin"
check "fresh pose exits 0" test "$rc" -eq 0
check "fresh pose binds" lacks "$T/err" "cached binding"
check "cached and fresh poses are the same bytes" cmp "$T/cached.bin" "$T/fresh.bin"

# a stale cache: the parameters edited in the file
sed 's/"epsilon": 0.1,/"epsilon": 0.2,/' "$P" > "$T/a/stale.cagewrap"
cp "$P.cwb" "$T/a/stale.cagewrap.cwb"
sed -i 's/"file": "hero.cagewrap.cwb"/"file": "stale.cagewrap.cwb"/' "$T/a/stale.cagewrap"
run pose --project "$T/a/stale.cagewrap" --out "$T/stale.bin"
check "a stale cache still poses" test "$rc" -eq 0
check "it says why the cache is not used" hasf "$T/err" "binding cache not used: $T/a/stale.cagewrap.cwb is out of date: the binding parameters changed since it was written; binding again"
run project "$T/a/stale.cagewrap"
check "project names the stale cache" hasf "$T/out" "cache not usable: $T/a/stale.cagewrap.cwb is out of date"
run project "$T/a/stale.cagewrap" --cache-binding
check "--cache-binding refreshes it" test "$rc" -eq 0
run project "$T/a/stale.cagewrap"
check "fresh again" hasf "$T/out" "(up to date)"

# taking the character out again, and a moved character located from the command line
run project "$P" --unembed "$T/a/taken.glb" --out "$T/a/plain.cagewrap"
check "--unembed exits 0" test "$rc" -eq 0
check "the same bytes as the original" cmp "$DEMO" "$T/a/taken.glb"
check "version 2 again" grep -q '"version": 2,' "$T/a/plain.cagewrap"
check "names the file" grep -q '"path": "taken.glb"' "$T/a/plain.cagewrap"
run project "$P" --unembed "$T/a/taken.glb" --out "$T/a/again.cagewrap"
check "same bytes already there: fine" test "$rc" -eq 0
echo "other" > "$T/a/other.glb"
run project "$P" --unembed "$T/a/other.glb" --out "$T/a/x.cagewrap"
check "another file is not replaced" test "$rc" -ne 0
check "it says so" hasf "$T/err" "$T/a/other.glb: already exists"
mkdir -p "$T/a/moved"
mv "$T/a/taken.glb" "$T/a/moved/taken.glb"
run project "$T/a/plain.cagewrap"
check "a moved character fails" test "$rc" -ne 0
check "naming the file" hasf "$T/err" "character file $T/a/taken.glb not found"
check "with the way forward" hasf "$T/err" "hint: give the character's new place with --character FILE"
run project "$T/a/plain.cagewrap" --character "$T/a/moved/taken.glb"
check "--character locates it" test "$rc" -eq 0
check "and the project remembers it" grep -q '"path": "moved/taken.glb"' "$T/a/plain.cagewrap"
run project "$T/a/plain.cagewrap" --embed --unembed "$T/x.glb"
check "--embed and --unembed together are refused" test "$rc" -ne 0

finish
