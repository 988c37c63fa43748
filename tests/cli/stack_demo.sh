#!/usr/bin/env bash
# The deformer stack's demo (issue 21, scripts/demo_stack.sh): a fine arm cage over a low-resolution
# body cage brings the arms' skin closer to the character's own skinning than the body cage alone:
# the worst vertex at most 0.6x and the RMS at most 0.5x (measured: 0.298% -> 0.125% of the diagonal,
# RMS 0.060% -> 0.010%), the largest edge stretch no more than 5% higher (1.19 -> 1.21). The garment-like
# cage over the torso (the third deformer) brings the torso's skin closer too: the worst vertex at most 0.9x
# and the RMS at most 0.7x (measured: 0.176% -> 0.152%, RMS 0.030% -> 0.018%), the stretch no more than 5%
# higher (1.15 -> 1.18). $1 = cagewrap.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tests/cli/harness.bash"
need_demo_assets

last="scripts/demo_stack.sh"
bash "$ROOT/scripts/demo_stack.sh" "$BIN" "$T/demo" "$DEMO" >"$T/out" 2>"$T/err"
rc=$?
check "the demo runs" test "$rc" -eq 0
check "it prints the stack" has "$T/out" "^  1  arms .*mask joints shoulder.L,shoulder.R"
check "with the garment third" has "$T/out" "^  2  garment .*mask joints spine,-neck,-shoulder.L,-shoulder.R"
check "and the region's figures" has "$T/out" "^region: the skin of joints shoulder.L,shoulder.R"
figures() {  # figures JSON: worst rms stretch of the whole report
  python3 -c "import json,sys; o=json.load(open(sys.argv[1]))['overall']; print(o['worst']['worst'], o['rms']['rms'], o['stretch']['stretch'])" "$1"
}
read -r bw br bs < <(figures "$T/demo/body.json")
read -r sw sr ss < <(figures "$T/demo/stack.json")
echo "body: worst $bw rms $br stretch $bs; stack: worst $sw rms $sr stretch $ss"
check "the worst vertex is at most 0.6x" python3 -c "import sys; sys.exit(0 if $sw <= 0.6 * $bw else 1)"
check "the RMS is at most 0.5x" python3 -c "import sys; sys.exit(0 if $sr <= 0.5 * $br else 1)"
check "the stretch is no more than 5% higher" python3 -c "import sys; sys.exit(0 if $ss <= 1.05 * $bs else 1)"
read -r tbw tbr tbs < <(figures "$T/demo/torso_body.json")
read -r tgw tgr tgs < <(figures "$T/demo/torso_garment.json")
echo "torso: body: worst $tbw rms $tbr stretch $tbs; with the garment: worst $tgw rms $tgr stretch $tgs"
check "the garment: it is the torso's skin alone" has "$T/out" "^region spine,-neck,-shoulder.L,-shoulder.R: [0-9]* of 69596 triangles"
check "the garment: the torso's worst vertex at most 0.9x" python3 -c "import sys; sys.exit(0 if $tgw <= 0.9 * $tbw else 1)"
check "the garment: the torso's RMS at most 0.7x" python3 -c "import sys; sys.exit(0 if $tgr <= 0.7 * $tbr else 1)"
check "the garment: the torso's stretch no more than 5% higher" python3 -c "import sys; sys.exit(0 if $tgs <= 1.05 * $tbs else 1)"
check "the region is the arms' skin, not all of it" python3 -c "import json,sys; sys.exit(0 if 0 < json.load(open('$T/demo/stack.json'))['vertices'] < 34800 else 1)"
finish
