#!/usr/bin/env bash
# The README opens with exactly the two set-up commands, `make run` and `make test`, in one code
# block (the `make run` line was lost once in an unrelated commit), and both targets exist in the
# Makefile. Usage: readme.sh <cagewrap binary> [shared assets dir].
set -u

source "$(dirname "$0")/harness.bash"
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
rc=0
last="(none: the README is read)"

# the first fenced block of the README, without its fences
awk '/^```/{n++; next} n==1{print} n>1{exit}' "$ROOT/README.md" >"$T/block"
check "the first block has exactly two lines" [ "$(wc -l <"$T/block")" -eq 2 ]
check "its first line is make run" has "$T/block" '^make run  *#'
check "its second line is make test" bash -c "sed -n 2p '$T/block' | grep -q '^make test  *#'"
check "make run comes first" bash -c "sed -n 1p '$T/block' | grep -q '^make run  *#'"
check "nothing comes before the block but the title" bash -c "awk '/^\`\`\`/{exit} NF{print}' '$ROOT/README.md' | grep -qx '# cagewrap'"
check "the Makefile has a run target" has "$ROOT/Makefile" '^run:'
check "the Makefile has a test target" has "$ROOT/Makefile" '^test:'
check ".ci/run runs make test" has "$ROOT/.ci/run" '^make test$'
finish
