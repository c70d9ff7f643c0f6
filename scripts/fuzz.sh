#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Bounded fuzzing: builds the libFuzzer targets with clang (ASan + UBSan), runs each for
# FUZZ_SECONDS (default 60) from the seed corpus and fails on any finding (the crashing input is
# kept in build-fuzz/findings/); then replays the corpus in a coverage build and prints the line
# coverage of lib/ that the fuzzers reach.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-60}
python=$PWD/.venv/bin/python
common=(-G Ninja -DBUILD_TESTING=OFF -DOKID_BUILD_FMU=OFF -DOKID_BUILD_EXAMPLES=OFF -DOKID_BUILD_BENCH=OFF
        -DOKID_BUILD_CLI=OFF -DOKID_PYTHON="$python" -DOKID_FUZZ=ON)

CC=clang cmake -S . -B build-fuzz "${common[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz
mkdir -p build-fuzz/findings
# The three fuzzers run side by side (each is one process on one core; 2 cores here), each for
# $seconds of wall time; a finding fails the step with its log's tail.
targets=(api csv fmu)
pids=()
for target in "${targets[@]}"; do
    work=build-fuzz/corpus/$target
    mkdir -p "$work"
    build-fuzz/fuzz/fuzz_$target -max_total_time="$seconds" -print_final_stats=1 -timeout=20 \
        -artifact_prefix=build-fuzz/findings/$target- "$work" fuzz/corpus/$target 2>build-fuzz/fuzz_$target.log &
    pids+=($!)
done
failed=0
for i in "${!targets[@]}"; do
    target=${targets[$i]}
    echo "=== fuzz_$target for ${seconds}s"
    if ! wait "${pids[$i]}"; then
        tail -40 build-fuzz/fuzz_$target.log; echo "fuzz_$target found a problem: build-fuzz/findings/"; failed=1; continue
    fi
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" build-fuzz/fuzz_$target.log | sed 's/^/  /'
    grep -E "^#[0-9]+.*DONE" build-fuzz/fuzz_$target.log | tail -1 | sed 's/^/  /'
done
((failed == 0))

# Coverage of lib/ by the corpus the fuzzers built (seeds included).
CC=clang cmake -S . -B build-fuzz-cov "${common[@]}" -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_C_FLAGS="-fprofile-instr-generate -fcoverage-mapping" \
    -DCMAKE_EXE_LINKER_FLAGS="-fprofile-instr-generate" -DCMAKE_SHARED_LINKER_FLAGS="-fprofile-instr-generate" >/dev/null
cmake --build build-fuzz-cov >/dev/null
rm -f build-fuzz-cov/*.profraw
for target in api fmu; do
    LLVM_PROFILE_FILE=$PWD/build-fuzz-cov/$target-%p.profraw \
        build-fuzz-cov/fuzz/fuzz_$target -runs=0 build-fuzz/corpus/$target fuzz/corpus/$target >/dev/null 2>&1
done
llvm-profdata merge -sparse build-fuzz-cov/*.profraw -o build-fuzz-cov/fuzz.profdata
echo "=== line coverage of lib/ reached by fuzz_api and fuzz_fmu"
llvm-cov report build-fuzz-cov/fuzz/fuzz_api -object build-fuzz-cov/fuzz/libokid_identifier_fuzz.so \
    -instr-profile=build-fuzz-cov/fuzz.profdata "$PWD"/lib/src/*.c "$PWD"/lib/src/*/*.c | sed 's|'"$PWD"'/||'
