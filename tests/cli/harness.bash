# Shared by the tests/cli/*.sh scripts (sourced, not run): the binary and assets from the arguments,
# a temporary folder $T, and run/check helpers that count passes and failures.
BIN=${1:?usage: $(basename "$0") <cagewrap binary> [shared assets dir]}
ASSETS=${CAGEWRAP_SHARED_ASSETS:-${2:-}}  # the environment overrides the configured folder
[ -x "$BIN" ] || { echo "not an executable: $BIN"; exit 1; }

T=$(mktemp -d "${TMPDIR:-/tmp}/cagewrap-cli-$(basename "$0" .sh).XXXXXX")
trap '[ -n "${KEEP_T:-}" ] || rm -rf "$T"' EXIT
passed=0
failed=0

# run ARGS...: runs the binary, stdout in $T/out, stderr in $T/err, exit status in $rc
run() {
  "$BIN" "$@" >"$T/out" 2>"$T/err"
  rc=$?
  last="$*"
}
# check DESCRIPTION COMMAND...: counts a pass when COMMAND succeeds, else prints what failed
check() {
  local what=$1 said
  shift
  if said=$("$@" 2>&1); then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: $what"
    [ -n "$said" ] && printf '%s\n' "$said" | sed 's/^/  check: /'
    echo "  command: cagewrap $last (exit $rc)"
    sed 's/^/  stdout: /' "$T/out" | head -20
    sed 's/^/  stderr: /' "$T/err" | head -20
  fi
}
has() { grep -q -- "$2" "$1"; }  # has FILE REGEX
lacks() { ! grep -q -- "$2" "$1"; }
hasf() { grep -qF -- "$2" "$1"; }  # hasf FILE TEXT
# finish: the closing line ctest and CI read, and the exit status
finish() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}


# write_skin_fixture: $T/skin.obj, an octahedron of radius 0.5 with one vertex off-centre (7 vertices, 9 faces)
write_skin_fixture() {
cat >"$T/skin.obj" <<'EOF'
v 0.5 0 0
v -0.5 0 0
v 0 0.5 0
v 0 -0.5 0
v 0 0 0.5
v 0 0 -0.5
v 0.1 0.2 -0.3
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
f 1 7 3
EOF
}

# write_cube_fixture FILE: the cube [-1,1]^3 as 6 outward quads (8 vertices)
write_cube_fixture() {
cat >"$1" <<'EOF2'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
EOF2
}

# maxdiff A.obj B.obj [x-filter]: the largest coordinate difference between their vertices (same count
# required); with "left" or "right" only vertices of A with x > 0.1 or x < -0.1 count
maxdiff() {
  awk -v side="${3:-all}" '
    function abs(x) { return x < 0 ? -x : x }
    FNR == NR { if ($1 == "v") { n++; x[n] = $2; y[n] = $3; z[n] = $4 } next }
    $1 == "v" { m++
      if (side == "left" && x[m] <= 0.1) next
      if (side == "right" && x[m] >= -0.1) next
      d = abs($2 - x[m]); if (abs($3 - y[m]) > d) d = abs($3 - y[m]); if (abs($4 - z[m]) > d) d = abs($4 - z[m])
      if (d > worst) worst = d }
    END { if (m != n) { print "count " m " != " n; exit 1 } printf "%.9g\n", worst }' "$1" "$2"
}
# below LIMIT A B [side] / above LIMIT A B [side]
below() { local d; d=$(maxdiff "$2" "$3" "${4:-all}") || { echo "$d"; return 1; }; awk -v d="$d" -v l="$1" 'BEGIN { exit !(d < l) }' || { echo "max difference $d, want < $1"; return 1; }; }
above() { local d; d=$(maxdiff "$2" "$3" "${4:-all}") || { echo "$d"; return 1; }; awk -v d="$d" -v l="$1" 'BEGIN { exit !(d > l) }' || { echo "max difference $d, want > $1"; return 1; }; }
# same_after_shift SKIN.obj OUT.obj DX DY DZ: OUT's vertices are SKIN's moved by (DX,DY,DZ) within 1e-5,
# same vertex count, and the face lines are unchanged
same_after_shift() {
  awk -v dx="$3" -v dy="$4" -v dz="$5" '
    function abs(x) { return x < 0 ? -x : x }
    FNR == NR { if ($1 == "v") { n++; x[n] = $2; y[n] = $3; z[n] = $4 } else if ($1 == "f") f[++nf] = $0; next }
    $1 == "v" { m++; if (abs($2 - x[m] - dx) > 1e-5 || abs($3 - y[m] - dy) > 1e-5 || abs($4 - z[m] - dz) > 1e-5) {
                  bad++; if (bad <= 3) printf "  vertex %d: (%s %s %s), want (%s %s %s) + (%s %s %s)\n", m, $2, $3, $4, x[m], y[m], z[m], dx, dy, dz } }
    $1 == "f" { g++; if ($0 != f[g]) { bad++; print "  face line " g " changed: " $0 } }
    END { if (m != n || g != nf) print "  counts: " m " vertices (want " n "), " g " faces (want " nf ")"
          exit !(bad == 0 && m == n && n > 0 && g == nf) }' "$1" "$2"
}

# need_demo_assets: DEMO and CAGE, the bundled demo character and cage; skips the script (77) without them
need_demo_assets() {
  local root
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
  DEMO="$root/assets/demo_character.glb"
  CAGE="$root/assets/demo_cage.obj"
  [ -f "$DEMO" ] && [ -f "$CAGE" ] || { echo "skipped: $DEMO or $CAGE not found"; exit 77; }
}

cmp_close() {  # cmp_close A B TOL: two float32 files (pose --out .bin) of the same length, every float within TOL
  python3 - "$1" "$2" "$3" <<'PY'
import struct, sys
a = open(sys.argv[1], 'rb').read(); b = open(sys.argv[2], 'rb').read()
assert len(a) == len(b), (len(a), len(b))
fa = struct.unpack('%df' % (len(a) // 4), a); fb = struct.unpack('%df' % (len(b) // 4), b)
worst = max(abs(x - y) for x, y in zip(fa, fb))
sys.exit(0 if worst <= float(sys.argv[3]) else 1)
PY
}
