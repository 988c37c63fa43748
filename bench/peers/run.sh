#!/usr/bin/env bash
# cagewrap against Blender's Surface Deform modifier on exactly the same meshes (docs/benchmarks.md,
# "Peers"). Usage: bench/peers/run.sh [cagewrap] [assets dir]
#   PEERS_SUBDIVIDE="mannequiny=N armadillo=M"  skin subdivision per triplet (default 11 and 9: about
#                                               1,000,000 vertices each, as `make bench`)
#   PEERS_CHANGES=20                            cage changes timed
#   BLENDER=blender                             the Blender to run
# For each bench triplet: `cagewrap bench --export-skin` times cagewrap and writes the skin it
# deformed; Blender (bench/peers/surface_deform.py) binds Surface Deform to the same skin and cage,
# times the bind and the cage changes and writes its deformed skin, which `cagewrap bench
# --score-deformed` scores with the same twist-fidelity figure; table.py prints both with ratios.
set -euo pipefail
bin=${1:-build/cagewrap}
assets=${2:-../shared/assets}
blender=${BLENDER:-blender}
changes=${PEERS_CHANGES:-20}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "bench-peers skipped: blender is not installed (apt install blender)"
  exit 0
fi
[ -x "$bin" ] || { echo "bench-peers: $bin is not an executable cagewrap (build first)" >&2; exit 1; }
[ -d "$assets/bench" ] || { echo "bench-peers: $assets/bench not found (give the shared assets folder)" >&2; exit 1; }
subdivide_of() {  # triplet name -> subdivision
  local spec
  for spec in ${PEERS_SUBDIVIDE:-mannequiny=11 armadillo=9}; do
    [ "${spec%%=*}" = "$1" ] && { echo "${spec#*=}"; return; }
  done
  echo 0
}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(free -g | awk '/Mem:/ {print $2}') GB"
echo "$("$blender" --version 2>/dev/null | head -1); both use every core"
table_args=()
for spec in "mannequiny mesh_7136.obj" "armadillo mesh_10001.obj"; do
  set -- $spec
  d=$assets/bench/$1
  sub=$(subdivide_of "$1")
  common=(--mesh "$d/$2" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --twist "$d/inputs.json" --subdivide "$sub")
  echo "== $1, --subdivide $sub: cagewrap"
  "$bin" bench "${common[@]}" --changes "$changes" --export-skin "$work/$1_skin.obj" --json > "$work/$1_cagewrap.json"
  echo "== $1, --subdivide $sub: Blender Surface Deform"
  "$blender" -b --factory-startup -noaudio --python-exit-code 1 --python "$here/surface_deform.py" -- \
    --skin "$work/$1_skin.obj" --cage "$d/cage.obj" --posed-cage "$d/cage_posed.obj" --changes "$changes" \
    --deformed "$work/$1_sd.bin" --json "$work/$1_sd.json" > "$work/$1_blender.log" 2>&1 ||
    { cat "$work/$1_blender.log" >&2; echo "bench-peers: Blender failed on $1" >&2; exit 1; }
  "$bin" bench "${common[@]}" --score-deformed "$work/$1_sd.bin" --json > "$work/$1_sd_score.json"
  table_args+=("$1" "$work/$1_cagewrap.json" "$work/$1_sd.json" "$work/$1_sd_score.json")
done
echo
python3 "$here/table.py" "${table_args[@]}"
