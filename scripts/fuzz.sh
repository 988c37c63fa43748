#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/) with clang, ASan and UBSan in their own build folder
# (or in a clang sanitizer tree BUILD already configured: make test uses build-sanitize, whose CMake
# configuration instruments it for libFuzzer too) and runs each for a bounded time. Seeds are made fresh by the project's own writers
# (cagewrap_fuzz_seeds); what the fuzzer adds stays in BUILD/corpus/<harness>, crashes go to
# BUILD/artifacts/<harness>/ and fail the run.
# Usage: fuzz.sh [BUILD (build-fuzz)] [SECONDS per harness (60)] [JOBS]
# FUZZ_RUNS=N runs N inputs per harness (fuzz_assimp: FUZZ_RUNS_ASSIMP, 600) instead of SECONDS, and FUZZ_SEED=S fixes libFuzzer's seed:
# together they make a run that does the same on every machine (make test uses them, so that a green
# run here is a green run in CI; open-ended exploration is make fuzz).
# Exits 77 (skipped) when clang is not installed.
set -euo pipefail
BUILD=${1:-build-fuzz}
SECONDS_EACH=${2:-60}
JOBS=${3:-$(nproc)}
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ is not installed (scripts/setup.sh installs it); skipped"
  exit 77
fi
# -O1 -g1 (line tables for the reports' stack traces): the level the sanitizers and libFuzzer are usually
# run at; the build is about a third quicker than RelWithDebInfo's -O2 -g, and make test builds it each time
if [ ! -f "$BUILD/build.ninja" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCAGEWRAP_FUZZ=ON -DCAGEWRAP_GUI=OFF >/dev/null
fi
cmake --build "$BUILD" --target fuzzers -j "$JOBS"

rm -rf "$BUILD/seeds"
"$BUILD/cagewrap_fuzz_seeds" "$BUILD/seeds"
# Each harness runs alone (one process, one core): JOBS of them at a time, each into its own log; the
# summaries are printed in harness order once all are done.
run_harness() {
  local harness=$1
  local corpus="$BUILD/corpus/$harness"
  # a fixed run (FUZZ_RUNS) starts from the seeds alone, as on a clean checkout: what earlier runs added
  # to the corpus would make this machine's run differ from CI's (a mesh OOM CI found was missed here)
  [ -n "${FUZZ_RUNS:-}" ] && corpus="$BUILD/corpus-fixed/$harness" && rm -rf "$corpus"
  local artifacts="$BUILD/artifacts/$harness"
  mkdir -p "$corpus" "$artifacts"
  # checked-in regression inputs (crashes found before) run first, as seeds
  local extra=()
  [ -d "$ROOT/tests/fuzz/corpus/$harness" ] && extra+=("$ROOT/tests/fuzz/corpus/$harness")
  local budget=(-max_total_time="$SECONDS_EACH")
  # fuzz_assimp forks a child per input (a few inputs a second under ASan): FUZZ_RUNS_ASSIMP of them (600)
  [ -n "${FUZZ_RUNS:-}" ] && budget=(-runs="$([ "$harness" = assimp ] && echo "${FUZZ_RUNS_ASSIMP:-600}" || echo "$FUZZ_RUNS")")
  [ -n "${FUZZ_SEED:-}" ] && budget+=(-seed="$FUZZ_SEED")
  # -malloc_limit_mb: a single allocation above 64 MB is a crash (no input of at most 64 KiB needs one;
  # a loader that trusts a count in the file does: issue 19), -rss_limit_mb bounds the whole process
  # fuzz_assimp: the importer runs in a child process (core/io/assimp_loader.h), given 5 s (under the -timeout of
  # 10); leaks inside libassimp and the zlib it calls are not this project's (tests/fuzz/assimp_lsan.supp)
  local lsan=()
  [ "$harness" = assimp ] && lsan=(LSAN_OPTIONS="suppressions=$ROOT/tests/fuzz/assimp_lsan.supp")
  env "${lsan[@]}" CAGEWRAP_IMPORT_SECONDS=5 \
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$BUILD/fuzz_$harness" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=64 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" "$BUILD/seeds/$harness" "${extra[@]}" \
    >"$BUILD/fuzz_$harness.log" 2>&1
}

# fuzz_assimp first: its runs are the longest, and overlap the others
harnesses=(assimp gltf gltf_rig mesh project set_edits patch binding)
declare -A pid_of
running=0
for harness in "${harnesses[@]}"; do
  if [ "$running" -ge "$JOBS" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  if [ -n "${FUZZ_RUNS:-}" ]; then
    echo "fuzz: $harness, -runs=$([ "$harness" = assimp ] && echo "${FUZZ_RUNS_ASSIMP:-600}" || echo "$FUZZ_RUNS")${FUZZ_SEED:+ -seed=$FUZZ_SEED}"
  else echo "fuzz: $harness, -max_total_time=$SECONDS_EACH${FUZZ_SEED:+ -seed=$FUZZ_SEED}"; fi
  run_harness "$harness" &
  pid_of[$harness]=$!
  running=$((running + 1))
done
status=0
for harness in "${harnesses[@]}"; do
  artifacts="$BUILD/artifacts/$harness"
  if ! wait "${pid_of[$harness]}"; then
    echo "fuzz: $harness FAILED; see $BUILD/fuzz_$harness.log and $artifacts/"
    grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$BUILD/fuzz_$harness.log" | head -20 || true
    status=1
  else
    echo "fuzz: $harness passed"
    grep -E "stat::number_of_executed_units|cov:" "$BUILD/fuzz_$harness.log" | tail -2 || true
  fi
done
exit $status
