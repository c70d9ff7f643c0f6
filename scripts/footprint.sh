#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Footprint and cost of okid on every firmware target (docs/firmware.md), for the paper
# configuration (r = 1, m = 2, p = 20, n = 4, alpha = beta = 20):
# - flash (text + rodata) and RAM (data + bss): libokid.a whole, and as linked into examples/firmware;
# - worst stack depth of okid_push and okid_identify from -fstack-usage/-fcallgraph-info, and as
#   measured at run time by stack painting;
# - workspace bytes, instructions per pushed sample and per identify: bench/firmware/cost_report.c
#   under QEMU with -icount (deterministic: QEMU counts instructions, not host time);
# - the same library and costs at -O2 on the presets of O2_PRESETS (the presets build -Os), and on
#   the Cortex-M55 without Helium (MVE) to show what the compiler's auto-vectorisation gives;
# then the table of every target side by side with the Cortex-M4F's budgets applied to each float
# target. Prints figures; fails only if a build or run fails.
# PRESETS="cortex-m4f riscv32" bash scripts/footprint.sh measures a subset.
set -euo pipefail
cd "$(dirname "$0")/.."
shift_=5   # -icount shift: 2^5 ns per instruction
presets=(${PRESETS:-$(bash scripts/firmware_presets.sh)})  # every firmware preset of CMakePresets.json
O2_PRESETS=" cortex-m4f cortex-m7 cortex-m55 "

run_cost() {   # machine elf: the cost report's "key value" lines (picolibc's console is QEMU's stderr)
    local qemu=(qemu-system-arm -M "$1")
    [[ $1 == virt ]] && qemu=(qemu-system-riscv32 -M virt -bios none)
    timeout 600 "${qemu[@]}" -nographic -semihosting-config enable=on,target=native \
        -icount shift=$shift_,align=off -kernel "$2" 2>&1
}

cache() {  # build-dir variable
    sed -n "s/^$2:[A-Z]*=//p" "$1/CMakeCache.txt"
}

archive_size() {  # size-tool archive: prints "flash ram" of all members
    "$1" -t "$2" | awk 'END { print $1, $2 + $3 }'
}

# A variant build of a preset: build dir, then extra cache arguments.
configure_variant() {
    local preset=$1 dir=$2; shift 2
    if [[ ! -f $dir/build.ninja ]]; then
        cmake --preset "$preset" -B "$dir" --no-warn-unused-cli -DBUILD_TESTING=OFF "$@" >/dev/null
    fi
}

# Phase 1, the builds: each preset and its variants (-O2, the M55 without MVE). Most of a build's
# time is one translation unit (the Eigen backend) on one core, so two builds run side by side.
variants_of() {  # preset: its build "dir:label" entries, the preset's own first
    local dir=build-$1
    echo "$dir:-Os"
    [[ $O2_PRESETS == *" $1 "* ]] && echo "$dir-o2:-O2"
    [[ $1 == cortex-m55 ]] && echo "$dir-nomve:-Os without MVE"  # the same core without Helium
    return 0
}
build_preset() {  # preset: configures (when needed) and builds it and its variants (variants_of)
    local preset=$1 variant dir
    [[ -f build-$preset/build.ninja ]] || cmake --preset "$preset" >/dev/null
    cmake --build --preset "$preset" >/dev/null
    while read -r variant; do
        dir=${variant%%:*}
        case $dir in
            *-o2) configure_variant "$preset" "$dir" -DCMAKE_BUILD_TYPE=Release \
                      "-DCMAKE_C_FLAGS_RELEASE=-O2 -DNDEBUG" "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" ;;
            *-nomve) configure_variant "$preset" "$dir" \
                         "-DOKID_TARGET_CPU_FLAGS=-mcpu=cortex-m55+nomve -mfloat-abi=hard" ;;  # scalar FPU only
        esac
        cmake --build "$dir" --target okid okid_cost_report >/dev/null
    done < <(variants_of "$preset" | tail -n +2)
}
# pool WIDTH COMMAND ARGS...: runs COMMAND ARG for each ARG, WIDTH at a time; fails if any failed
# (`wait PID` gives each one's status, also of one that `wait -n` already reaped)
pool() {
    local width=$1 cmd=$2 failed=0 pids=() pid; shift 2
    for arg in "$@"; do
        while (($(jobs -rp | wc -l) >= width)); do wait -n || true; done
        "$cmd" "$arg" &
        pids+=($!)
    done
    for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
    return $failed
}
pool 2 build_preset "${presets[@]}"

# Phase 2, the cost reports under QEMU (one host thread each, deterministic): all side by side.
cost_runs=()
for preset in "${presets[@]}"; do
    while read -r variant; do cost_runs+=("$preset:${variant%%:*}"); done < <(variants_of "$preset")
done
cost_run() {  # preset:build-dir
    local machine; machine=$(cache "build-${1%%:*}" OKID_QEMU_MACHINE)
    run_cost "$machine" "${1#*:}/bench/firmware/okid_cost_report" > "${1#*:}/cost_report.txt"
}
pool "$(nproc)" cost_run "${cost_runs[@]}"

# Phase 3, the report of each preset in turn.
declare -A figure
for preset in "${presets[@]}"; do
    dir=build-$preset
    real=$(cache $dir OKID_REAL)
    machine=$(cache $dir OKID_QEMU_MACHINE)
    size_tool=$(cache $dir CMAKE_NM); size_tool=${size_tool%-nm}-size
    figure[$preset.real]=$real
    mapfile -t variants < <(variants_of "$preset")

    echo "=== $preset ($machine, $real) ==="
    read -r flash ram < <(archive_size "$size_tool" $dir/lib/libokid.a)
    echo "libokid.a whole archive: flash $flash bytes, RAM $ram bytes"
    for variant in "${variants[@]:1}"; do
        read -r vflash _ < <(archive_size "$size_tool" "${variant%%:*}/lib/libokid.a")
        echo "libokid.a whole archive (${variant#*:}): flash $vflash bytes"
    done
    figure[$preset.lib_flash]=$flash
    figure[$preset.lib_ram]=$ram
    python3 scripts/stack_depth.py $dir/lib okid_push okid_identify | tee $dir/stack_report.txt
    figure[$preset.stack_static]=$(awk '/^stack.okid_(push|identify) / { if ($2 > m) m = $2 } END { print m }' $dir/stack_report.txt)
    python3 scripts/map_sizes.py $dir/examples/firmware/okid_firmware.map libokid.a libm.a libc.a \
        libstdc++.a libgcc.a | tee $dir/map_sizes.txt | sed 's/^/as linked into okid_firmware: /'
    figure[$preset.linked_flash]=$(awk '$1 == "libokid.a" { print $3 }' $dir/map_sizes.txt)
    "$size_tool" $dir/examples/firmware/okid_firmware | sed 's/^/okid_firmware (Berkeley, text includes rodata): /'

    for variant in "${variants[@]}"; do
        sed "s/^/cost ${variant#*:}: /" "${variant%%:*}/cost_report.txt"
    done
    get() { awk -v k="$1" '$1 == k { print $2 }' "$2/cost_report.txt"; }
    figure[$preset.workspace]=$(get block_rows_1.workspace_bytes $dir)
    figure[$preset.push]=$(get block_rows_1.push_instructions_worst $dir)
    figure[$preset.identify]=$(get block_rows_1.identify_instructions $dir)
    figure[$preset.stack_run]=$(get block_rows_1.identify_stack_bytes $dir)
    echo
done

# Every target side by side; the budgets of issue 4 (Cortex-M4F, float, paper configuration,
# block_rows 1 as in the example) applied to each float target.
verdict() {  # preset key budget ("-": none)
    local v=${figure[$1.$2]}
    if [[ ${figure[$1.real]} != float || $3 == - ]]; then printf '%10s  ' "$v"
    elif (( v <= $3 )); then printf '%10s ok' "$v"
    else printf '%10s !!' "$v"; fi
}
echo "=== every target, paper configuration, block_rows 1, -Os (ok / !!: within / over the M4F budget) ==="
printf '%-36s' ""; for p in "${presets[@]}"; do printf '%14s' "$p"; done; printf '%12s\n' budget
row() {  # label key budget
    printf '%-36s' "$1"
    for p in "${presets[@]}"; do printf '  '; verdict "$p" "$2" "$3"; done
    printf '%12s\n' "$3"
}
printf '%-36s' "okid_real"; for p in "${presets[@]}"; do printf '%14s' "${figure[$p.real]}"; done; echo
# The flash budget is what the paper configuration links (--gc-sections); the whole archive also
# holds what only some firmware calls (the refinement, lifting, the stabilization diagram).
row "library flash, whole libokid.a (B)" lib_flash -
row "library flash as linked (B)" linked_flash 65536
row "library RAM, data + bss (B)" lib_ram 0
row "workspace (B)" workspace 24576
row "stack, call graph, worst path (B)" stack_static 2048
row "stack, measured, identify (B)" stack_run 2048
row "push, worst sample (instructions)" push 20000
row "identify (instructions)" identify 5000000
