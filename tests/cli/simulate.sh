#!/usr/bin/env bash
# CLI checks for the cage simulation: `cagewrap demo-sim belly|cape` writes the use cases as projects,
# `cagewrap simulate` runs them (frames, timing, displacement; two runs agree), `pose` at a clip time
# and `export --mode baked-animation` carry the simulation, and bad settings in a project file are
# refused naming the vertex. Usage: simulate.sh <cagewrap binary> [shared assets dir].
set -u

source "$(dirname "$0")/harness.bash"
need_demo_assets

# number_above / number_below FILE REGEX LIMIT: the first number after REGEX in FILE is above / below LIMIT
number_below() { local v; v=$(grep -o -- "$2 [0-9.e+-]*" "$1" | head -1 | awk '{print $NF}'); awk -v v="$v" -v l="$3" 'BEGIN { exit !(v != "" && v + 0 < l) }' || { echo "'$2' is '$v', want < $3"; return 1; }; }
number_above() { local v; v=$(grep -o -- "$2 [0-9.e+-]*" "$1" | head -1 | awk '{print $NF}'); awk -v v="$v" -v l="$3" 'BEGIN { exit !(v + 0 > l) }' || { echo "'$2' is '$v', want > $3"; return 1; }; }

# ------------------------------------------------------------------------------------ belly
B="$T/belly.cagewrap"
run demo-sim belly --out "$B" --character "$DEMO" --cage "$CAGE"
check "demo-sim belly exits 0" [ "$rc" -eq 0 ]
check "demo-sim says how many vertices are simulated" has "$T/out" "^wrote .*belly.cagewrap: belly demo, cage of [0-9]* vertices, [1-9][0-9]* simulated"
check "the project records the simulation" has "$B" '"simulation": {'
# without --character / --cage, from another folder: the bundled demo is found
cd "$T" || exit 1
run demo-sim belly --out "$T/belly2.cagewrap"
cd - >/dev/null || exit 1
check "demo-sim finds the bundled demo from any folder" [ "$rc" -eq 0 ]
check "...and writes the simulation into the project" has "$T/belly2.cagewrap" '"simulation": {'

run simulate --project "$B" --clip walk --every 10
check "simulate exits 0" [ "$rc" -eq 0 ]
check "simulate names the clip and the solver" has "$T/out" "^clip 'walk': [0-9]* frames at 30 fps, 8 substeps"
check "simulate prints the time per frame" has "$T/out" "solve ms/frame: median [0-9.]*, mean"
check "the belly moves" number_above "$T/out" "largest displacement" 0.001
# the frame lines without their solve time (column 3)
frames_of() { grep -E '^ +[0-9]' "$1" | awk '{ $3 = ""; print }'; }
frames_of "$T/out" >"$T/first.txt"
run simulate --project "$B" --clip walk --every 10
frames_of "$T/out" >"$T/second.txt"
check "the frame lines are there" [ "$(wc -l <"$T/first.txt")" -ge 3 ]
check "two runs give the same frames" cmp "$T/first.txt" "$T/second.txt"
run simulate --project "$B" --json --every 0
check "simulate --json covers both clips" has "$T/out" '"clip": "arm_raise"'

# the skin at a clip time: with the simulation it differs from the plain rig
run new --character "$DEMO" --cage "$CAGE" --out "$T/plain.cagewrap"
run pose --project "$T/plain.cagewrap" --clip walk --time 0.4 --out "$T/plain.obj"
check "pose without simulation exits 0" [ "$rc" -eq 0 ]
run pose --project "$B" --clip walk --time 0.4 --out "$T/sim.obj"
check "pose with simulation exits 0" [ "$rc" -eq 0 ]
check "pose says the cage was simulated" has "$T/out" "cage simulated), wrote"
check "the simulated skin differs" above 0.001 "$T/plain.obj" "$T/sim.obj"
run pose --project "$B" --out "$T/rest_sim.obj"
run pose --project "$T/plain.cagewrap" --out "$T/rest_plain.obj"
check "at rest (no clip) nothing is simulated" cmp "$T/rest_sim.obj" "$T/rest_plain.obj"

run export --project "$B" --mode baked-animation --clips walk --fps 10 --out "$T/belly.glb"
check "baked-animation export of a simulated cage exits 0" [ "$rc" -eq 0 ]
check "the export wrote its file" [ -s "$T/belly.glb" ]

# simulation off: simulate refuses unless told
run simulate --project "$T/plain.cagewrap"
check "simulate refuses a project with the simulation off" [ "$rc" -ne 0 ]
check "and says how to turn it on" has "$T/err" "the simulation is off"
run simulate --project "$T/plain.cagewrap" --enable --clip walk --every 0
check "--enable runs it (every vertex pinned: nothing moves)" has "$T/out" "(0 free)"

# bad settings in the file are named
sed 's/"mass": \[1\(\.0\)\{0,1\}, /"mass": [-1, /' "$B" >"$T/bad.cagewrap"
differs() { ! cmp -s "$1" "$2"; }
check "the bad file differs" differs "$B" "$T/bad.cagewrap"
run simulate --project "$T/bad.cagewrap"
check "a negative mass is refused" [ "$rc" -ne 0 ]
check "naming the vertex" has "$T/err" "cage vertex 0 has mass -1"
run simulate --project "$B" --clip nosuch
check "an unknown clip is refused" [ "$rc" -ne 0 ]
check "naming it" has "$T/err" "no clip named or numbered 'nosuch'"

# ------------------------------------------------------------------------------------- cape
C="$T/cape.cagewrap"
run demo-sim cape --out "$C" --character "$DEMO" --cage "$CAGE"
check "demo-sim cape exits 0" [ "$rc" -eq 0 ]
check "the cape character is written beside the project" [ -s "$T/cape.glb" ]
run simulate --project "$C" --clip walk --every 0
check "simulate the cape exits 0" [ "$rc" -eq 0 ]
check "the cape's sheet is free below its top row" has "$T/out" "(70 free)"
check "the cape drapes (moves well off its modelled shape)" number_above "$T/out" "largest displacement" 0.05
check "the cloth keeps its edge lengths within 10%" number_below "$T/out" "largest edge stretch" 10

finish
