#!/usr/bin/env bash
# The benchmark of record (docs/benchmarks.md): both bench triplets, every variant, at their own size
# and subdivided to about 1,000,000 skin vertices. Usage: scripts/bench.sh [cagewrap] [assets dir]
set -euo pipefail
bin=${1:-build/cagewrap}
assets=${2:-../shared/assets}
[ -d "$assets/bench" ] || { echo "bench: $assets/bench not found (give the shared assets folder)" >&2; exit 1; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for spec in "mannequiny mesh_7136.obj 11" "armadillo mesh_10001.obj 9"; do
  set -- $spec
  d=$assets/bench/$1
  for sub in 0 $3; do
    echo
    echo "== $1, --subdivide $sub"
    "$bin" bench --mesh "$d/$2" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --twist "$d/inputs.json" \
      --subdivide "$sub" --variant all
  done
done
