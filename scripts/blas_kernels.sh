#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The LAPACKE backend's C suites, double (build/) and float (build-float/), each under reference
# BLAS/LAPACK and under Debian's OpenBLAS with forced kernels, so that no tolerance holds on one
# machine's kernel only. The binaries are the ones scripts/test.sh built: the library is chosen at
# load time (LD_LIBRARY_PATH to Debian's blas/, lapack/ or openblas-pthread/ folders; they all
# provide libblas.so.3 and liblapack.so.3). OpenBLAS emulates nothing: a kernel whose instructions
# this CPU lacks is skipped and named. Every check's worst error over all runs, against its
# tolerance, goes to build/tolerance-report.md (scripts/tolerance_report.py).
#   bash scripts/blas_kernels.sh [SUITE_DIR...]      default: build build-float
set -euo pipefail
cd "$(dirname "$0")/.."

suites=("$@")
((${#suites[@]})) || suites=(build build-float)
arch=$(gcc -print-multiarch)
libdir=/usr/lib/$arch
flags=$(grep -m1 '^flags' /proc/cpuinfo)
has() { for f in "$@"; do [[ " $flags " == *" $f "* ]] || return 1; done; }

# The C programs only (cmocka tests, the backend agreement and the float convergence test):
# the pytest suites run through the CLI and Python, whose LAPACK is linked statically.
tests='^(test_|backend_values_lapacke$|float_convergence$)'

# backend name -> environment
declare -A env_of
env_of[reference]="LD_LIBRARY_PATH=$libdir/blas:$libdir/lapack"
backends=(reference)
# OpenBLAS kernel families of x86-64, oldest first, with the CPU features each one executes (pni is SSE3; Zen
# runs the Haswell kernels, Cooperlake the SkylakeX ones with bf16 added: nothing new for LAPACK).
declare -A needs=([Prescott]="pni" [Sandybridge]="avx" [Haswell]="avx2 fma"
                  [SkylakeX]="avx512f avx512dq avx512bw avx512vl")
skipped=()
if [[ $arch == x86_64-linux-gnu && -e $libdir/openblas-pthread/liblapack.so.3 ]]; then
    for kernel in Prescott Sandybridge Haswell SkylakeX; do
        # shellcheck disable=SC2086
        if has ${needs[$kernel]}; then
            env_of[openblas-$kernel]="LD_LIBRARY_PATH=$libdir/openblas-pthread OPENBLAS_CORETYPE=$kernel"
            backends+=("openblas-$kernel")
        else
            skipped+=("$kernel (needs ${needs[$kernel]})")
        fi
    done
elif [[ -e $libdir/openblas-pthread/liblapack.so.3 ]]; then
    env_of[openblas-auto]="LD_LIBRARY_PATH=$libdir/openblas-pthread"   # the kernel OpenBLAS picks here
    backends+=(openblas-auto)
fi
[[ -e $libdir/blas/libblas.so.3 && -e $libdir/lapack/liblapack.so.3 ]] \
    || { echo "blas_kernels: reference BLAS/LAPACK not found in $libdir/blas, $libdir/lapack" >&2; exit 1; }

out=build/blas-kernels
rm -rf "$out"   # this script's own output folder
mkdir -p "$out"

# The kernel OpenBLAS really runs (OPENBLAS_VERBOSE=2 prints it when the library loads).
probe=${suites[0]}/tests/test_random
for b in "${backends[@]}"; do
    [[ $b == openblas-* ]] || continue
    # shellcheck disable=SC2086
    core=$(env ${env_of[$b]} OPENBLAS_VERBOSE=2 "$probe" 2>&1 >/dev/null | sed -n 's/^Core: //p' | head -1)
    want=${b#openblas-}
    if [[ $want != auto && $core != "$want" ]]; then
        echo "blas_kernels: OpenBLAS ran '$core' when $want was forced" >&2; exit 1
    fi
    echo "$b: OpenBLAS kernel $core"
done
((${#skipped[@]} == 0)) || echo "skipped (this CPU lacks their instructions): ${skipped[*]}"

# One run per (suite, backend), as many at a time as there are cores (a new one starts when any
# ends); each test program writes its checks' worst err / tol to the run's tolerance log when it exits.
run() {
    local suite=$1 backend=$2 name=$1@$2
    # shellcheck disable=SC2086
    env ${env_of[$backend]} OKID_TOLERANCE_LOG="$PWD/$out/$name.tsv" \
        ctest --test-dir "$suite" -R "$tests" --output-on-failure > "$out/$name.log" 2>&1
}
pids=(); names=()
for suite in "${suites[@]}"; do
    for backend in "${backends[@]}"; do
        while (($(jobs -rp | wc -l) >= $(nproc))); do wait -n || true; done
        run "$suite" "$backend" & pids+=($!); names+=("$suite@$backend")
    done
done
failed=0
for i in "${!pids[@]}"; do   # `wait PID` gives each one's status, also after `wait -n` reaped it
    if wait "${pids[$i]}"; then status=ok; else status=FAILED; failed=1; fi
    summary=$(grep -E 'tests passed|tests failed' "$out/${names[$i]}.log" | tail -1)
    echo "${names[$i]}: $status ($summary)"
    [[ $status == ok ]] || cat "$out/${names[$i]}.log"
done
python3 scripts/tolerance_report.py "$out" > build/tolerance-report.md
echo "closest to their tolerances (all of them: build/tolerance-report.md):"
awk '/^[|] check/ {shown = 1} shown && /^$/ {exit} shown && n++ < 14' build/tolerance-report.md  # the first table
((failed == 0))
