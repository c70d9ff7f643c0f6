#!/usr/bin/env bash
# Footprint and cost of okid on Cortex-M (README "Use in firmware"), for the paper configuration
# (r = 1, m = 2, p = 20, n = 4, alpha = beta = 20) on the two target presets:
# - flash (text + rodata) and RAM (data + bss): libokid.a whole, and as linked into examples/firmware;
# - worst stack depth of okid_push and okid_identify from -fstack-usage/-fcallgraph-info, and as
#   measured at run time by stack painting;
# - workspace bytes, instructions per pushed sample and per identify: bench/firmware/cost_report.c
#   under qemu-system-arm -icount (deterministic: QEMU counts instructions, not host time);
# - the same library and costs at -O2 (the presets build -Os);
# then the budgets of the Cortex-M4F float build. Prints figures; fails only if a build or run fails.
set -euo pipefail
cd "$(dirname "$0")/.."
shift_=5   # -icount shift: 2^5 ns per instruction, the 25 MHz board timer then resolves 1.25 instructions

run_cost() {   # machine elf
    timeout 600 qemu-system-arm -M "$1" -nographic -semihosting-config enable=on,target=native \
        -icount shift=$shift_,align=off -kernel "$2"
}

archive_size() {  # prints "flash ram" of an archive, all members
    arm-none-eabi-size -t "$1" | awk 'END { print $1, $2 + $3 }'
}

declare -A figure
for preset in cortex-m4f cortex-m7; do
    dir=build-$preset
    [[ -f $dir/build.ninja ]] || cmake --preset $preset >/dev/null
    cmake --build --preset $preset >/dev/null
    o2=build-$preset-o2
    if [[ ! -f $o2/build.ninja ]]; then
        cmake --preset $preset -B $o2 --no-warn-unused-cli -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
            "-DCMAKE_C_FLAGS_RELEASE=-O2 -DNDEBUG" "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" >/dev/null
    fi
    machine=$(sed -n 's/^OKID_QEMU_MACHINE:STRING=//p' $dir/CMakeCache.txt)
    # Without a linear-algebra backend only the library's size and the call graph can be reported.
    backend=$(sed -n 's/^OKID_BACKEND:STRING=//p' $dir/CMakeCache.txt)
    if [[ $backend == none ]]; then o2_targets=(okid); else o2_targets=(okid okid_cost_report); fi
    cmake --build $o2 --target "${o2_targets[@]}" >/dev/null

    echo "=== $preset ($machine, $(sed -n 's/^OKID_REAL:STRING=//p' $dir/CMakeCache.txt)) ==="
    read -r flash ram < <(archive_size $dir/lib/libokid.a)
    read -r flash_o2 ram_o2 < <(archive_size $o2/lib/libokid.a)
    echo "libokid.a whole archive: flash $flash bytes (-O2: $flash_o2), RAM $ram bytes"
    figure[$preset.lib_flash]=$flash
    python3 scripts/stack_depth.py $dir/lib okid_push okid_identify | tee $dir/stack_report.txt
    figure[$preset.stack_static]=$(awk '/^stack.okid_(push|identify) / { if ($2 > m) m = $2 } END { print m }' $dir/stack_report.txt)
    if [[ $backend == none ]]; then
        echo "OKID_BACKEND=none: no okid_identify on the target, so no example and no cost report"
        echo; continue
    fi
    python3 scripts/map_sizes.py $dir/examples/firmware/okid_firmware.map libokid.a libm.a libc.a \
        libstdc++.a libgcc.a | sed 's/^/as linked into okid_firmware: /'
    arm-none-eabi-size $dir/examples/firmware/okid_firmware | sed 's/^/okid_firmware (Berkeley, text includes rodata): /'

    for variant in "$dir:-Os" "$o2:-O2"; do
        build=${variant%%:*} opt=${variant##*:}
        run_cost "$machine" $build/bench/firmware/okid_cost_report > $build/cost_report.txt
        sed "s/^/cost $opt: /" $build/cost_report.txt
    done
    get() { awk -v k="$1" '$1 == k { print $2 }' $dir/cost_report.txt; }
    figure[$preset.workspace]=$(get block_rows_1.workspace_bytes)
    figure[$preset.push]=$(get block_rows_1.push_instructions_worst)
    figure[$preset.identify]=$(get block_rows_1.identify_instructions)
    figure[$preset.stack_run]=$(get block_rows_1.identify_stack_bytes)
    echo
done

# The budgets of issue 4 (Cortex-M4F, float, paper configuration, block_rows 1 as in the example).
verdict() {  # name measured budget unit
    local state=met
    (( $2 <= $3 )) || state="MISSED by $(( $2 - $3 )) $4"
    printf '%-34s %10s %-6s budget %10s  %s\n' "$1" "$2" "$4" "$3" "$state"
}
echo "=== budgets: Cortex-M4F, float, paper configuration, -Os ==="
if [[ -z ${figure[cortex-m4f.workspace]:-} ]]; then
    echo "library flash ${figure[cortex-m4f.lib_flash]} bytes (budget 65536) without a backend; the rest needs one"
    exit 0
fi
verdict "library flash (whole libokid.a)" "${figure[cortex-m4f.lib_flash]}" 65536 bytes
verdict "workspace (block_rows 1)" "${figure[cortex-m4f.workspace]}" 24576 bytes
verdict "stack (call graph, worst path)" "${figure[cortex-m4f.stack_static]}" 2048 bytes
verdict "stack (measured, identify)" "${figure[cortex-m4f.stack_run]}" 2048 bytes
verdict "push, worst sample" "${figure[cortex-m4f.push]}" 20000 instructions
verdict "identify" "${figure[cortex-m4f.identify]}" 5000000 instructions
