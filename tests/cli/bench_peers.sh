#!/usr/bin/env bash
# bench/peers/run.sh (make bench-peers) without Blender: it says it skips; with a stand-in Blender
# that deforms with cagewrap itself (so the peer's twist fidelity must equal cagewrap's: ratio 1.00),
# the whole pipeline runs on the bench triplets at their own size and prints the table. Also the
# bench options it relies on: --export-skin, --score-deformed and their errors.
source "$(dirname "$0")/harness.bash"
[ -n "$ASSETS" ] && [ -d "$ASSETS/bench" ] || { echo "shared assets not found: skipping"; exit 77; }
command -v python3 >/dev/null || { echo "python3 not found: skipping"; exit 77; }
here=$(cd "$(dirname "$0")/../.." && pwd)
B=$ASSETS/bench/mannequiny

# no Blender: a clear skip, exit 0
BLENDER=$T/no-such-blender bash "$here/bench/peers/run.sh" "$BIN" "$ASSETS" >"$T/out" 2>"$T/err"
rc=$?
last="(bench/peers/run.sh without blender)"
check "run.sh exits 0 without blender" test "$rc" -eq 0
check "run.sh says it skipped and how to install" hasf "$T/out" "skipped: blender is not installed (apt install blender)"

# a stand-in Blender: fixed figures, and the skin deformed by cagewrap itself
cat >"$T/blender" <<FAKE
#!/usr/bin/env bash
[ "\$1" = --version ] && { echo "Stand-in Blender"; exit 0; }
while [ \$# -gt 0 ] && [ "\$1" != -- ]; do shift; done
shift
while [ \$# -gt 0 ]; do
  case \$1 in
    --skin) skin=\$2 ;; --cage) cage=\$2 ;; --posed-cage) posed=\$2 ;; --deformed) out=\$2 ;; --json) json=\$2 ;;
  esac
  shift 2
done
"$BIN" deform --mesh "\$skin" --cage "\$cage" --posed-cage "\$posed" --out "\$out" >/dev/null || exit 1
points=\$(grep -c '^v ' "\$skin")
echo "{\"tool\": \"stand-in\", \"points\": \$points, \"bind_s\": 4.5, \"deform_median_ms\": 30, \"peak_rss_mb\": 900}" >"\$json"
FAKE
chmod +x "$T/blender"
BLENDER=$T/blender PEERS_SUBDIVIDE="mannequiny=0 armadillo=0" bash "$here/bench/peers/run.sh" "$BIN" "$ASSETS" >"$T/out" 2>"$T/err"
rc=$?
last="(bench/peers/run.sh with a stand-in blender)"
check "run.sh runs both tools on both triplets" test "$rc" -eq 0
check "a table per triplet" test "$(grep -c '^| bind s ' "$T/out")" -eq 2
check "mannequiny at its own size" hasf "$T/out" "mannequiny: 7136 skin points"
check "the stand-in's figures are in the table" has "$T/out" "^| peak memory MB *| *[0-9]* | *900 |"
check "the same deformer scores the same twist fidelity (ratio 1.00)" test "$(grep -c '^| twist rms .*| *1.00 |$' "$T/out")" -eq 2
check "each table says cagewrap's kernel table and its share of the bandwidth probe" \
  test "$(grep -c "^cagewrap's kernel: \(compact\|float\) table [0-9.]* B/vertex .* GB/s = [0-9]*% of the bandwidth probe's triad" "$T/out")" -eq 2

# the kernel's table and the bandwidth probe (issue 24)
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --subdivide 3 --variant all --changes 20
check "bench prints the bandwidth probe of the same run" has "$T/out" "^bandwidth probe (same run, [0-9]* threads, 3 x [0-9]* MB, best of [0-9]* runs before and after): triad [0-9.]* GB/s, read [0-9.]* GB/s"
check "bench reads the compact table at 114k points (basic, extended)" \
  test "$(grep -c '^\(basic\|extended\) .* [0-9.]*c ' "$T/out")" -eq 2
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --subdivide 1 --table float --json
check "bench --table float reads the binding's float table" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
v = j["variants"][0]
assert v["table"] == "float", v["table"]
assert abs(v["table_bytes_per_vertex"] - v["binding_bytes_per_vertex"]) < 8, v
assert j["bandwidth_probe"]["triad_gbps"] > 0 and 0 < v["probe_ratio"], j
' "$T/out"
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --table half
check "bench --table half is refused" test "$rc" -ne 0

# the bench options behind it
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --subdivide 1 \
  --export-skin "$T/skin.obj" --json
check "bench --export-skin succeeds" test "$rc" -eq 0
check "the exported skin is the subdivided one the bench timed" \
  test "$(grep -c '^v ' "$T/skin.obj")" -eq "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["points"])' "$T/out")"
run deform --mesh "$T/skin.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --out "$T/deformed.bin"
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --subdivide 1 \
  --twist "$B/inputs.json" --score-deformed "$T/deformed.bin"
check "bench --score-deformed scores a deformed skin" has "$T/out" "twist rms [0-9.e+-]* max"
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" \
  --twist "$B/inputs.json" --score-deformed "$T/deformed.bin"
check "a deformed skin of another size is refused" test "$rc" -ne 0
check "the error names the file and both sizes" has "$T/err" "deformed.bin holds [0-9]* points but the skin .* has 7136"
run bench --mesh "$B/mesh_7136.obj" --cage "$B/cage.obj" --posed-cage "$B/cage_posed.obj" --score-deformed "$T/deformed.bin"
check "--score-deformed without --twist is refused" test "$rc" -ne 0
check "the error says what is missing" hasf "$T/err" "needs --twist"

# the table refuses figures of different skins
echo '{"points": 5, "elements": 2, "peak_rss_mb": 1, "variants": [{"variant": "extended", "bind_s": 1, "deform_median_ms": 1, "twist": {"rms": 1, "max": 1}}]}' >"$T/cw.json"
echo '{"points": 6, "bind_s": 1, "deform_median_ms": 1, "peak_rss_mb": 1}' >"$T/sd.json"
echo '{"points": 6, "twist": {"rms": 1, "max": 1}}' >"$T/score.json"
python3 "$here/bench/peers/table.py" x "$T/cw.json" "$T/sd.json" "$T/score.json" >"$T/out" 2>"$T/err"
rc=$?
last="(table.py on figures of different skins)"
check "table.py refuses different skins" test "$rc" -ne 0
check "and says which file" hasf "$T/err" "sd.json has 6 points but"
finish
