#!/usr/bin/env bash
# The benchmarks of record (docs/benchmarks.md). Usage: scripts/bench.sh [cagewrap] [assets dir] [cpu|gpu]
#   cpu (make bench): both bench triplets, every variant, at their own size and subdivided to about
#     1,000,000 skin vertices.
#   gpu (make bench-gpu): the GPU path, `bench --gpu` on both triplets at about 1,000,000 vertices
#     (headless EGL: a GPU server needs no display), the 4,000,000-vertex memory run, and the editor's
#     frame playing a clip with a 1,000,000-vertex demo character (`cagewrap --offscreen`: headless
#     EGL as well; EDITOR_FRAMES sets how many frames, default 240).
set -euo pipefail
bin=${1:-build/cagewrap}
assets=${2:-../shared/assets}
mode=${3:-cpu}
[ -d "$assets/bench" ] || { echo "bench: $assets/bench not found (give the shared assets folder)" >&2; exit 1; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(free -g | awk '/Mem:/ {print $2}') GB"
triplets=("mannequiny mesh_7136.obj 11" "armadillo mesh_10001.obj 9")

if [ "$mode" = cpu ]; then
  for spec in "${triplets[@]}"; do
    set -- $spec
    d=$assets/bench/$1
    for sub in 0 $3; do
      echo
      echo "== $1, --subdivide $sub"
      "$bin" bench --mesh "$d/$2" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --twist "$d/inputs.json" \
        --subdivide "$sub" --variant all
    done
  done
  # the deformer stack (issue 21): the demo's body cage and fine arm cage, each alone and together
  stack_dir=$(mktemp -d)
  bash "$(dirname "$0")/demo_stack.sh" "$bin" "$stack_dir" >/dev/null
  echo
  echo "== deformer stack (scripts/demo_stack.sh)"
  "$bin" bench --project "$stack_dir/stack.cagewrap" --clip walk
  rm -rf "$stack_dir"
  exit 0
fi
[ "$mode" = gpu ] || { echo "bench: mode must be cpu or gpu, not '$mode'" >&2; exit 1; }

for spec in "${triplets[@]}"; do
  set -- $spec
  d=$assets/bench/$1
  echo
  echo "== $1, --subdivide $3, --gpu"
  "$bin" bench --mesh "$d/$2" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --subdivide "$3" --variant all --gpu
done

d=$assets/bench/mannequiny
echo
echo "== memory: mannequiny, --subdivide 23 (about 4,000,000 vertices), CPU path, then with the GPU path too"
"$bin" bench --mesh "$d/mesh_7136.obj" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --subdivide 23 --variant all
"$bin" bench --mesh "$d/mesh_7136.obj" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --subdivide 23 --gpu

# the editor playing the walk with a 1,000,000-vertex skin and the 2,000-face demo cage, offscreen
# (a headless EGL context: no display needed, on a GPU server too), per part (--frame-stats) and
# as the artist sees it (--frame-time), on the GPU path and the CPU path
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
big=$(dirname "$bin")/demo_1m.glb
[ -f "$big" ] || "$bin" make-demo --cell-size 0.0028 --out "$big"
script=$(mktemp)
config=$(mktemp -d)
echo "wait ${EDITOR_FRAMES:-240}" > "$script"
for path in "" --cpu-deform; do
  for stats in --frame-stats --frame-time; do
    echo
    echo "== editor: $big, walk playing, 1280 x 720, offscreen ${path:-(GPU path)} $stats"
    CAGEWRAP_CONFIG_DIR=$config "$bin" "$big" --cage "$here/assets/demo_cage.obj" --offscreen --width 1280 --height 720 --play \
      --script "$script" --frames 1 $stats $path --screenshot "$config/frame.png" | grep -E "^(offscreen|skin deformed|bound|frame stats)"
  done
done
rm -rf "$script" "$config"
