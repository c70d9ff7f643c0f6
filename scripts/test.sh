#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Every test: the default build (-Werror; it cross-builds the FMUs' win64 and aarch64-linux binaries
# too) with ctest (C, CLI, FMUs in fmpy, ecospy, libcosimpy, and under Wine and qemu-user, the
# Python package, the fleet on a local Dask cluster, install, both linear-algebra backends
# compared), the float build, the double and float C suites again under reference BLAS and each
# OpenBLAS kernel this CPU runs, the Eigen-backend build, the 32-bit (gcc -m32) build, the firmware
# cross-builds (Cortex-M4F, M7, M33, M55, RISC-V) with their tests under QEMU and the footprint
# report, the C and CLI suites again under ASan + UBSan, valgrind memcheck, and bounded fuzzing. Stops at
# the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

# Each step's header also reports how long the previous one took (CI has 90 minutes for all of it)
# and the CPU time its processes used: CPU/wall below the core count is room for more parallelism.
# `times` runs in this shell itself (not in $(...): a subshell's children start at zero).
times_file=$(mktemp); trap 'rm -f "$times_file"' EXIT
step_name=""; step_start=$SECONDS; step_cpu=0
step() {
    local cpu
    times > "$times_file"
    cpu=$(awk 'NR == 2 { n = 0; for (i = 1; i <= 2; i++) { split($i, t, "m"); n += t[1] * 60 + t[2] } printf "%d", n }' "$times_file")
    if [[ -n $step_name ]]; then echo "--- $step_name: $((SECONDS - step_start)) s (CPU $((cpu - step_cpu)) s)"; fi
    step_name=$*; step_start=$SECONDS; step_cpu=$cpu
    echo; echo "=== $* ==="
}

step "setup (installs only what is missing)"
bash scripts/setup.sh

step "default build and tests"
cmake --preset default
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs"

step "float build (okid_real = float): the C tests with the float tolerances"
cmake --preset float
cmake --build --preset float -j "$jobs"
ctest --preset float -j "$jobs"

step "BLAS kernels: the double and float C suites under reference BLAS/LAPACK and forced OpenBLAS kernels"
bash scripts/blas_kernels.sh

step "eigen build (the firmware's heap-free Eigen backend on the host): the C tests"
cmake --preset eigen
cmake --build --preset eigen -j "$jobs"
ctest --preset eigen -j "$jobs"

step "m32 build (gcc -m32: the firmware targets' 32-bit size_t on the host): the C tests"
cmake --preset m32
cmake --build --preset m32 -j "$jobs"
ctest --preset m32 -j "$jobs"

targets=($(bash scripts/firmware_presets.sh))  # the firmware presets of CMakePresets.json
# Most of a cross-build's time is one translation unit (the Eigen backend) on one core: two targets
# build side by side, each to its own log, printed when it is done.
step "firmware cross-builds: ${targets[*]} (two at a time)"
logs=$(mktemp -d)
cross_build() { cmake --preset "$1" && cmake --build --preset "$1" -j "$jobs"; }
pids=()
for target in "${targets[@]}"; do
    while (($(jobs -rp | wc -l) >= 2)); do wait -n || true; done
    cross_build "$target" > "$logs/$target.log" 2>&1 &
    pids+=($!)
done
failed=0
for i in "${!targets[@]}"; do   # `wait PID` gives each one's status, also after `wait -n` reaped it
    echo "--- ${targets[$i]}"
    if wait "${pids[$i]}"; then tail -n 1 "$logs/${targets[$i]}.log"; else cat "$logs/${targets[$i]}.log"; failed=1; fi
done
rm -rf "$logs"
((failed == 0))

# QEMU runs one program on one host thread: the five targets' tests run side by side (the
# Cortex-M4F's float convergence test alone takes some 40 s, the others a few seconds), and beside
# them the footprint report (its builds are other directories; its QEMU cost runs count
# instructions, -icount, so the load does not move a figure). The test logs are printed after the report.
step "firmware target tests under QEMU (the five targets in parallel) beside the footprint and cost report"
logs=$(mktemp -d)
pids=()
for target in "${targets[@]}"; do
    ctest --preset $target -j "$jobs" > "$logs/$target.log" 2>&1 &
    pids+=($!)
done
failed=0
bash scripts/footprint.sh || failed=1
for i in "${!targets[@]}"; do
    wait "${pids[$i]}" || failed=1
    echo "--- ${targets[$i]}"; cat "$logs/${targets[$i]}.log"
done
rm -rf "$logs"
((failed == 0))

step "benchmark smoke run (figures only; nothing is timed against a limit)"
.venv/bin/python bench/python/bench_compare.py --quick --out build/bench-smoke --results build/bench-smoke/results.json

step "AddressSanitizer + UndefinedBehaviorSanitizer"
cmake --preset asan
cmake --build --preset asan -j "$jobs"
ctest --preset asan -j "$jobs"

step "valgrind memcheck: every C test, the example, the CLI, the FMUs through a C importer"
bash scripts/valgrind.sh

step "bounded fuzzing (libFuzzer, ASan + UBSan), ${FUZZ_SECONDS:-60} s per target"
bash scripts/fuzz.sh

step "done"
echo "all tests passed in $SECONDS s"
