#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# One hash of `okid identify --json` over a grid of records and configurations: a refactoring that
# must not change a single bit of the results compares this line before and after.
#   bash scripts/json_hash.sh [path/to/okid]     (default build/host_tools/cli/okid)
# No --timing, so the JSON holds no elapsed time; each run's exit status is hashed with its output
# (a refusal must stay a refusal). OKID_JSON_HASH_VERBOSE=1 prints one hash per run.
set -euo pipefail
cd "$(dirname "$0")/.."
cli=$(realpath "${1:-build/host_tools/cli/okid}")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

"$cli" simulate --output "$dir/paper.csv"
"$cli" simulate --noise 0.02 --seed 7 --output "$dir/noisy.csv"
"$cli" simulate --sensing displacement --samples 2000 --output "$dir/disp.csv"
"$cli" simulate --masses 1,1,1 --dampers 0.1,0.1,0.1,0 --springs 100,80,60,0 --force-dof 2 --sensing velocity \
    --samples 3000 --dt 0.01 --noise 0.01 --seed 3 --output "$dir/chain.csv"

runs=()
for record in paper noisy disp chain; do
    runs+=("$record|")
    for order in 2 4 6; do runs+=("$record|--order $order"); done
    for p in 5 20 40; do runs+=("$record|--order 4 --observer-order $p"); done
    for h in "10 10" "20 30" "40 20"; do
        set -- $h; runs+=("$record|--order 4 --hankel-rows $1 --hankel-cols $2")
    done
    for k in 2 4; do runs+=("$record|--order 4 --decimation $k"); done
    for s in none auto; do runs+=("$record|--order 4 --scaling $s"); done
    for f in 0.999 0.9999; do runs+=("$record|--order 4 --forgetting-factor $f"); done
    runs+=("$record|--order 4 --realization combined")
    runs+=("$record|--order 4 --estimator instrumental")
    runs+=("$record|--order 4 --block-rows 1")
    runs+=("$record|--order 4 --block-rows 7 --zero-initial-state")
    runs+=("$record|--order 4 --stabilization 10")
    runs+=("$record|--order 4 --refine --observer-order 20")
    # the correlation form: the Toeplitz Gram, and xSYRK (forgetting keeps it)
    runs+=("$record|--order 4 --estimator correlation" "$record|--order 4 --estimator correlation --forgetting-factor 0.999")
    # output-only (@OUTPUTS: the record's sensor columns, every one but t and force)
    runs+=("$record|--inputs 0 --outputs @OUTPUTS" "$record|--inputs 0 --outputs @OUTPUTS --order 4 --hankel-rows 20"
           "$record|--inputs 0 --outputs @OUTPUTS --order 4 --hankel-rows 20 --segments 4")
done
# chain: six states
runs+=("chain|--order 6 --refine --observer-order 20" "chain|--order 6 --realization combined --scaling auto")

all=""
for run in "${runs[@]}"; do
    record=${run%%|*}; args=${run#*|}
    outputs=$(head -1 "$dir/$record.csv" | tr -d '\r' | tr ',' '\n' | grep -vx -e t -e force | paste -sd,)
    args=${args//@OUTPUTS/$outputs}
    rc=0
    # shellcheck disable=SC2086
    out=$("$cli" identify --json $args "$dir/$record.csv" 2>&1) || rc=$?
    one=$(printf '%s\nexit %d\n' "$out" "$rc" | sha256sum | cut -c1-16)
    if [[ ${OKID_JSON_HASH_VERBOSE:-0} == 1 ]]; then echo "$one $record $args"; fi
    all+="$one $record $args"$'\n'
done
echo "${#runs[@]} runs: $(printf '%s' "$all" | sha256sum | cut -d' ' -f1)"
