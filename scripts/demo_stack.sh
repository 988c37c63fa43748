#!/usr/bin/env bash
# The deformer stack's demo (issue 21, docs/deformer-stack.md): the demo character with a
# low-resolution body cage (250 triangles, about what an artist models by hand) and, as layers over
# it, a fine cage (6000 triangles) under a mask of the arms' skin (the shoulders and their children,
# feathered by the skin weights) and a garment-like cage: the torso's skin alone (`cagewrap skin
# --region-joints spine,-neck,-shoulder.L,-shoulder.R`) wrapped in a closed cage (3000 faces asked),
# like a shirt, under the torso's mask. It prints the arms' and the torso's fidelity to the character's
# own skinning with the body cage alone and with the stacks (`cagewrap check --region-joints`).
# Usage: demo_stack.sh CAGEWRAP OUT_DIR [CHARACTER]
# Writes OUT_DIR/body.obj, arms.obj, torso.obj (the torso's skin), garment.obj, body.cagewrap (the body
# cage alone), stack.cagewrap (body + arms), garment.cagewrap (body + arms + garment) and the regions'
# reports: body.json, stack.json (the arms), torso_body.json, torso_garment.json (the torso).
set -euo pipefail
CW=${1:?usage: demo_stack.sh CAGEWRAP OUT_DIR [CHARACTER]}
OUT=${2:?usage: demo_stack.sh CAGEWRAP OUT_DIR [CHARACTER]}
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CHARACTER=${3:-$ROOT/assets/demo_character.glb}
REGION=shoulder.L,shoulder.R
TORSO=spine,-neck,-shoulder.L,-shoulder.R
mkdir -p "$OUT"
"$CW" cage --mesh "$CHARACTER" --faces 250 --out "$OUT/body.obj" >/dev/null
"$CW" cage --mesh "$CHARACTER" --faces 6000 --out "$OUT/arms.obj" >/dev/null
"$CW" skin --character "$CHARACTER" --region-joints "$TORSO" --out "$OUT/torso.obj"
"$CW" cage --mesh "$OUT/torso.obj" --faces 3000 --wrap always --out "$OUT/garment.obj" >/dev/null
"$CW" new --character "$CHARACTER" --cage "$OUT/body.obj" --out "$OUT/body.cagewrap" >/dev/null
cp "$OUT/body.cagewrap" "$OUT/stack.cagewrap"
"$CW" deformer add --project "$OUT/stack.cagewrap" --cage "$OUT/arms.obj" --name arms --mask-joints "$REGION"
"$CW" deformer add --project "$OUT/stack.cagewrap" --cage "$OUT/garment.obj" --name garment --mask-joints "$TORSO" \
  --out "$OUT/garment.cagewrap"
for p in body stack; do
  echo "== $p.cagewrap: the arms' skin"
  "$CW" check --project "$OUT/$p.cagewrap" --region-joints "$REGION" --clip arm_raise --clip walk
  "$CW" check --project "$OUT/$p.cagewrap" --region-joints "$REGION" --clip arm_raise --clip walk --json >"$OUT/$p.json" 2>/dev/null
done
for p in body garment; do
  echo "== $p.cagewrap: the torso's skin"
  "$CW" check --project "$OUT/$p.cagewrap" --region-joints "$TORSO" --clip arm_raise --clip walk
  "$CW" check --project "$OUT/$p.cagewrap" --region-joints "$TORSO" --clip arm_raise --clip walk --json >"$OUT/torso_$p.json" 2>/dev/null
done
