#!/usr/bin/env bash
# `cagewrap bench --gpu` headless (no DISPLAY: EGL), on the mannequin bench triplet: every variant
# gets GPU figures, and the GPU result is the CPU's within 1e-5 of the diagonal. Skips (77) when
# the shared assets are absent or no OpenGL 4.3 context can be had (the message says which).
# Usage: bench_gpu.sh <cagewrap binary> [shared assets dir]
set -u

source "$(dirname "$0")/harness.bash"

A="$ASSETS/bench/mannequiny"
[ -n "$ASSETS" ] && [ -d "$A" ] || { echo "skipped: shared assets not found"; exit 77; }
mesh=$(ls "$A"/mesh_*.obj | head -1)

run_headless() { env -u DISPLAY -u WAYLAND_DISPLAY "$BIN" "$@" >"$T/out" 2>"$T/err"; rc=$?; last="$*"; }

run_headless bench --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --variant all --gpu --json
if [ "$rc" -ne 0 ] && grep -qE "no headless OpenGL|no EGL|no compute shaders|without OpenGL" "$T/err"; then
  echo "skipped: $(cat "$T/err")"
  exit 77
fi
check "bench --gpu --json exits 0 with no display" [ "$rc" -eq 0 ]
cp "$T/out" "$T/bench.json"
check "bench --gpu: every variant has GPU figures, and GPU agrees with CPU" python3 -c '
import json, math, sys
j = json.load(open(sys.argv[1]))
assert j["gpu_device"], j
assert [v["variant"] for v in j["variants"]] == ["basic", "clamped", "extended"]
for v in j["variants"]:
    g = v["gpu"]
    for k in ("wall_deform_median_ms", "wall_normals_median_ms", "cpu_normals_median_ms", "gpu_bytes", "upload_bytes_per_change"):
        assert math.isfinite(g[k]) and g[k] > 0, (v["variant"], k, g)
    for k in ("deform_median_ms", "normals_median_ms", "cpu_maps_median_ms"):
        assert math.isfinite(g[k]) and g[k] >= 0, (v["variant"], k, g)
    assert g["total_min_ms"] <= g["total_median_ms"] + 1e-9, g
    assert 0 <= g["max_distance_to_cpu"] <= 1e-5, (v["variant"], g["max_distance_to_cpu"])
    assert 0 <= g["max_normal_angle_to_cpu_degrees"] < 0.1, (v["variant"], g["max_normal_angle_to_cpu_degrees"])
' "$T/bench.json"

run_headless bench --mesh "$mesh" --cage "$A/cage.obj" --posed-cage "$A/cage_posed.obj" --gpu
check "bench --gpu table exits 0" [ "$rc" -eq 0 ]
check "bench --gpu table names the device" has "$T/out" "^GPU path: "
check "bench --gpu table has the GPU columns" has "$T/out" "wall def"

finish
