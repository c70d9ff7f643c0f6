#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# valgrind memcheck over the default build (build/): every C test, the fuzz corpus replays, the
# example, the CLI (simulate, identify, identify --refine, crlb), and the FMUs (FMI 2, FMI 3 and one
# written by okid-fmu) through the C importers of tests/. Fails on any error or definite/indirect leak.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
# Each run is one process on one core: $jobs of them at a time, each with its own log (shown when it
# fails); what a run needs (the simulated CSV, the generated FMU) is made before the runs start.
vg=(valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite,indirect -q)
vg_dir=$(mktemp -d)
trap 'rm -rf "$vg_dir"' EXIT
vg_count=0
vg_run() {  # vg_run PROGRAM ARGS...: in the background, at most $jobs at once
    while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
    local log=$vg_dir/$((vg_count++))
    echo "$*" > "$log.cmd"
    ( rc=0; "${vg[@]}" "$@" > /dev/null 2> "$log.err" || rc=$?; echo $rc > "$log.rc" ) &
}
csv=$vg_dir/paper.csv
"${vg[@]}" build/host_tools/cli/okid simulate --output "$csv"
# an FMI 2 FMU written by okid-fmu: the binary reads its configuration from resources/
rm -rf build/fmu-generated
.venv/bin/okid-fmu --base build/fmu/fmi2/okid_identifier.fmu --inputs 1 --outputs 2 --max-modes 4 --hankel-rows 20 \
    -o build/fmu-generated/paper.fmu >/dev/null
.venv/bin/python -m zipfile -e build/fmu-generated/paper.fmu build/fmu-generated/paper
# test_refine: 3 noise realisations, not 200; test_mode_selection: one seed per case, not 6
export OKID_MONTE_CARLO_DRAWS=3 OKID_SELECTION_SEEDS=1
for test in build/tests/test_*; do vg_run "$test"; done
vg_run build/tests/fuzz_replay_api fuzz/corpus/api/*
vg_run build/tests/fuzz_replay_csv fuzz/corpus/csv/*
vg_run build/examples/paper_2dof/paper_2dof
vg_run build/host_tools/cli/okid identify --json --order 4 "$csv"
vg_run build/host_tools/cli/okid identify --json --order 4 --refine --observer-order 20 "$csv"
vg_run build/host_tools/cli/okid crlb --noise 0.02
vg_run build/tests/fmu_cosim build/fmu/fmi2/okid_plant_2dof build/fmu/fmi2/okid_identifier
vg_run build/tests/fmu_cosim build/fmu/fmi2/okid_plant_2dof build/fmu/fmi2/okid_identifier linux64 select
vg_run build/tests/fmu3_chain build/fmu/fmi3/okid_identifier
vg_run build/tests/fmu_cosim build/fmu/fmi2/okid_plant_2dof build/fmu-generated/paper
wait
unset OKID_MONTE_CARLO_DRAWS OKID_SELECTION_SEEDS
failed=0
for rc in "$vg_dir"/*.rc; do
    if [[ $(cat "$rc") != 0 ]]; then
        echo "valgrind: FAILED: $(cat "${rc%.rc}.cmd")"; cat "${rc%.rc}.err"; failed=1
    fi
done
echo "valgrind: $vg_count runs, $(grep -L '^0$' "$vg_dir"/*.rc | wc -l) failed"
((failed == 0))
