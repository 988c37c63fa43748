#!/usr/bin/env bash
# CLI end to end: bind, then deform with and without the saved binding, for every variant, to .obj and
# .bin, on a tiny hand-written scene whose answer is known (a translated cage translates the skin);
# then the real bench triplet (bind, deform, bench --json) when the shared assets are present.
# Usage: bind_deform.sh <cagewrap binary> [shared assets dir]
set -u

source "$(dirname "$0")/harness.bash"

# same_after_shift_bin SKIN.obj OUT.bin DX DY DZ: the raw float32 x 3 file, in vertex order
same_after_shift_bin() {
  local n
  n=$(grep -c '^v ' "$1")
  [ "$(wc -c <"$2")" -eq $((12 * n)) ] || { echo "  $2 has $(wc -c <"$2") bytes, want $((12 * n))"; return 1; }
  od -An -v -t f4 -w12 "$2" | awk '{ print "v", $1, $2, $3 }' >"$T/bin_as.obj"
  grep '^f ' "$1" >>"$T/bin_as.obj"
  same_after_shift "$1" "$T/bin_as.obj" "$3" "$4" "$5"
}

# ---------------------------------------------------------------------------------------- fixtures
# skin: an octahedron of radius 0.5 with one vertex off-centre; cage: the cube [-1,1]^3 as 6 quads
write_skin_fixture
write_cube_fixture "$T/cage.obj"
awk '$1 == "v" { printf "v %s %s %s\n", $2 + 1, $3 + 2, $4 + 3; next } { print }' "$T/cage.obj" >"$T/cage_posed.obj"
NPTS=7

# ---------------------------------------------------------------------------------------- bind
for variant in basic clamped extended; do
  run bind --mesh "$T/skin.obj" --cage "$T/cage.obj" --variant "$variant" --out "$T/$variant.cwb"
  check "bind $variant exits 0" [ "$rc" -eq 0 ]
  check "bind $variant: summary counts the points" has "$T/out" "^points *$NPTS\$"
  check "bind $variant: summary counts 12 elements" has "$T/out" "^elements *12 "
  check "bind $variant: summary names the variant" has "$T/out" "^variant *$variant "
  check "bind $variant: summary has set sizes" has "$T/out" "^set size *mean [0-9.]* *max [0-9]"
  check "bind $variant: no affected elements" has "$T/out" "^affected elements 0\$"
  check "bind $variant: no affected points" has "$T/out" "^affected points *0\$"
  check "bind $variant: cage quality line" has "$T/out" "^cage quality *[0-9.]*%"
  check "bind $variant: names the file written" has "$T/out" "^wrote *$T/$variant.cwb\$"
  check "bind $variant: nothing on stderr" [ ! -s "$T/err" ]
  check "bind $variant: .cwb starts with the magic" [ "$(head -c 8 "$T/$variant.cwb" 2>/dev/null)" = "CWBIND01" ]
  check "bind $variant: no temporary file left" [ ! -e "$T/$variant.cwb.tmp" ]
done

# ---------------------------------------------------------------------------------------- deform
for variant in basic clamped extended; do
  for ext in obj bin; do
    # bind on the fly
    out="$T/fly_$variant.$ext"
    run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/cage_posed.obj" --variant "$variant" --out "$out"
    check "deform $variant -> .$ext exits 0" [ "$rc" -eq 0 ]
    check "deform $variant -> .$ext reports the variant and file" has "$T/out" "deformed $NPTS points with $variant, wrote $out"
    if [ "$ext" = obj ]; then
      check "deform $variant -> .obj moves every vertex by (1,2,3)" same_after_shift "$T/skin.obj" "$out" 1 2 3
    else
      check "deform $variant -> .bin moves every vertex by (1,2,3)" same_after_shift_bin "$T/skin.obj" "$out" 1 2 3
    fi
    # with the saved binding
    out2="$T/saved_$variant.$ext"
    run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/cage_posed.obj" --binding "$T/$variant.cwb" \
      --variant "$variant" --out "$out2"
    check "deform --binding $variant -> .$ext exits 0" [ "$rc" -eq 0 ]
    check "deform --binding $variant -> .$ext reports the variant" has "$T/out" "with $variant,"
    if [ "$ext" = obj ]; then
      check "deform --binding $variant -> .obj moves every vertex by (1,2,3)" same_after_shift "$T/skin.obj" "$out2" 1 2 3
    else
      check "deform --binding $variant -> .bin moves every vertex by (1,2,3)" same_after_shift_bin "$T/skin.obj" "$out2" 1 2 3
    fi
    check "deform $variant -> .$ext: saved binding gives the same bytes as binding on the fly" cmp -s "$out" "$out2"
  done
  # the rest cage leaves the skin where it is
  run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/cage.obj" --binding "$T/$variant.cwb" --out "$T/rest.obj"
  check "deform $variant with the rest cage exits 0" [ "$rc" -eq 0 ]
  check "deform $variant with the rest cage keeps the skin" same_after_shift "$T/skin.obj" "$T/rest.obj" 0 0 0
done
# a saved binding's variant decides: the output says which one ran
run deform --mesh "$T/skin.obj" --cage "$T/cage.obj" --posed-cage "$T/cage_posed.obj" --binding "$T/clamped.cwb" --out "$T/x.obj"
check "deform --binding clamped.cwb runs the clamped variant" has "$T/out" "with clamped,"

# ---------------------------------------------------------------------------------------- real bench triplet
A="$ASSETS/bench/mannequiny"
if [ -n "$ASSETS" ] && [ -d "$A" ]; then
  mesh=$(ls "$A"/mesh_*.obj | head -1)
  nv=$(grep -c '^v ' "$mesh")
  run bind --mesh "$mesh" --cage "$A/cage.obj" --out "$T/m.cwb"
  check "bench triplet: bind exits 0" [ "$rc" -eq 0 ]
  check "bench triplet: bind counts $nv points" has "$T/out" "^points *$nv\$"
  check "bench triplet: bind writes the binding" [ -s "$T/m.cwb" ]
  run deform --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --binding "$T/m.cwb" --out "$T/m.bin"
  check "bench triplet: deform exits 0" [ "$rc" -eq 0 ]
  check "bench triplet: deform writes $nv x 12 bytes" [ "$(wc -c <"$T/m.bin" 2>/dev/null || echo 0)" -eq $((12 * nv)) ]
  run deform --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage.obj" --binding "$T/m.cwb" --out "$T/m_rest.obj"
  check "bench triplet: the rest cage keeps the skin" same_after_shift "$mesh" "$T/m_rest.obj" 0 0 0

  run bench --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --variant all --twist "$A/inputs.json" --json
  check "bench --json --twist exits 0" [ "$rc" -eq 0 ]
  cp "$T/out" "$T/bench.json"
  check "bench --json: every variant reports timings, memory and twist fidelity" python3 -c '
import json, math, sys
j = json.load(open(sys.argv[1]))
n = int(sys.argv[2])
assert j["points"] == n, ("points", j["points"], n)
assert j["elements"] > 0 and j["peak_rss_mb"] > 0
names = [v["variant"] for v in j["variants"]]
assert names == ["basic", "clamped", "extended"], names
for v in j["variants"]:
    for k in ("bind_s", "deform_median_ms", "deform_min_ms", "binding_bytes_per_vertex", "mean_set_size"):
        assert isinstance(v[k], (int, float)) and math.isfinite(v[k]) and v[k] > 0, (v["variant"], k, v.get(k))
    assert v["deform_min_ms"] <= v["deform_median_ms"], v
    assert 0 <= v["cage_quality"] <= 1, v
    t = v["twist"]
    assert math.isfinite(t["rms"]) and 0 < t["rms"] <= t["max"], (v["variant"], t)
    # a deformer that follows the twisted cage lands within 1% of the diagonal of the analytic twist
    # (measured: about 1e-4); one that ignores the pose is off by tens of percent
    assert t["rms"] < 0.01, (v["variant"], t)
' "$T/bench.json" "$nv"

  run bench --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --variant basic --changes 20 --json
  check "bench --json without --twist exits 0" [ "$rc" -eq 0 ]
  cp "$T/out" "$T/bench2.json"
  check "bench --json without --twist: one variant, no twist entry" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert [v["variant"] for v in j["variants"]] == ["basic"], j["variants"]
assert "twist" not in j["variants"][0], j["variants"][0]
' "$T/bench2.json"

  run bench --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --variant extended --twist "$A/inputs.json"
  check "bench table exits 0" [ "$rc" -eq 0 ]
  check "bench table has a row for extended" has "$T/out" "^extended "
  check "bench table reports peak memory" has "$T/out" "^peak memory [0-9]* MB"
else
  echo "note: no bench triplet under '$ASSETS/bench/mannequiny' (set CAGEWRAP_SHARED_ASSETS); real-data checks skipped"
fi

finish
