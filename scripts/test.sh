#!/usr/bin/env bash
# Every test: the default build (-Werror) with ctest, the whole suite again under ASan + UBSan,
# and valgrind memcheck on the paper example. Stops at the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)

step() { echo; echo "=== $* ==="; }

step "default build and tests"
cmake --preset default
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs"

step "AddressSanitizer + UndefinedBehaviorSanitizer"
cmake --preset asan
cmake --build --preset asan -j "$jobs"
ctest --preset asan -j "$jobs"

step "valgrind memcheck"
vg=(valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite,indirect -q)
"${vg[@]}" build/examples/paper_2dof/paper_2dof >/dev/null
"${vg[@]}" build/tests/test_identifier_api >/dev/null
csv=$(mktemp --suffix=.csv)
trap 'rm -f "$csv"' EXIT
"${vg[@]}" build/host_tools/cli/okid simulate --output "$csv"
"${vg[@]}" build/host_tools/cli/okid identify --json --order 4 "$csv" >/dev/null

echo; echo "all tests passed"
