#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what is missing, and only that: Debian packages (apt, as root or through sudo) and the
# Python packages of host_tools/requirements.txt and the okid package (pip install .) in .venv. Safe to run again.
#   bash scripts/setup.sh          everything scripts/test.sh needs
#   bash scripts/setup.sh --demo   only what scripts/demo.sh needs: a C compiler, CMake, Ninja, LAPACKE
set -euo pipefail
cd "$(dirname "$0")/.."

mode=all
case "${1:-}" in
    "") ;;
    --demo) mode=demo ;;
    *) echo "usage: bash scripts/setup.sh [--demo]" >&2; exit 2 ;;
esac

# The library and examples/paper_2dof (the demo preset): compiler, build tools, LAPACKE.
DEMO_PACKAGES=(build-essential cmake ninja-build pkg-config liblapacke-dev liblapack-dev libblas-dev)
# The rest of the test suite: OpenBLAS (the CLI links it statically), Eigen, cmocka, Python, memory checkers, fuzzing, the firmware targets.
TEST_PACKAGES=(libopenblas-dev libeigen3-dev libcmocka-dev python3-venv python3-pip valgrind clang libclang-rt-dev llvm time
               # the firmware targets: Cortex-M (newlib) and RISC-V (picolibc; the Eigen backend takes
               # its C++ headers from the Arm toolchain's libstdc++), QEMU for both
               gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib libstdc++-arm-none-eabi-dev
               qemu-system-arm gcc-riscv64-unknown-elf picolibc-riscv64-unknown-elf qemu-system-misc
               # the FMUs' other platforms (fmu/platforms) and the importers that run them
               gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64 wine64 qemu-user lld
               libc6-dev-arm64-cross libgcc-12-dev-arm64-cross libstdc++-12-dev-arm64-cross
               libtbb12
               # the m32 preset (gcc -m32): the 32-bit C library, LAPACKE and cmocka
               gcc-multilib libcmocka-dev:i386 liblapacke-dev:i386)
APT_PACKAGES=("${DEMO_PACKAGES[@]}")
if [[ $mode == all ]]; then APT_PACKAGES+=("${TEST_PACKAGES[@]}"); fi

missing=()
for pkg in "${APT_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$pkg")
    fi
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}"
    if [[ $(id -u) -eq 0 ]]; then SUDO=(); else SUDO=(sudo); fi
    if [[ $mode == all ]] && ! dpkg --print-foreign-architectures | grep -qx i386; then   # multiarch, for the :i386 packages
        "${SUDO[@]}" dpkg --add-architecture i386
    fi
    # a list that fails to download (a mirror in mid-sync) need not stop the install: it says itself
    # when a package is really missing
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q || echo "setup: apt-get update had errors; installing anyway"
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

if [[ $mode == demo ]]; then exit 0; fi  # the demo needs no Python

if [[ ! -x .venv/bin/python ]]; then
    echo "setup: creating .venv"
    python3 -m venv .venv
fi
stamp=.venv/.requirements.sha256
want=$(cat host_tools/requirements.txt | sha256sum | cut -d' ' -f1)
# The okid package (pyproject.toml: the C core, its binding, okid.tools and the console scripts),
# rebuilt when a file it is built from changes.
package_stamp=.venv/.okid-package.sha256
package_want=$(find pyproject.toml CMakeLists.txt cmake lib python host_tools/cli host_tools/common -type f -not -name '*.pyc' -print0 \
       | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)
need_requirements=0 need_package=0
[[ -f $stamp && $(cat "$stamp") == "$want" ]] || need_requirements=1
[[ -f $package_stamp && $(cat "$package_stamp") == "$package_want" ]] || need_package=1
if ((need_requirements)); then .venv/bin/python -m pip install -q --upgrade pip; fi
# The package's wheel compiles (in pip's own build environment, not in .venv) while the requirements
# download and install: the two overlap; the wheel goes into .venv once both are done.
if ((need_package)); then
    echo "setup: building the okid Python package"
    wheel_dir=$(mktemp -d)
    trap 'rm -rf "$wheel_dir"' EXIT
    .venv/bin/python -m pip wheel -q --no-deps -w "$wheel_dir" . > "$wheel_dir/build.log" 2>&1 &
    wheel_pid=$!
fi
if ((need_requirements)); then
    echo "setup: installing Python packages into .venv"
    .venv/bin/python -m pip install -q -r host_tools/requirements.txt
    echo "$want" > "$stamp"
fi
if ((need_package)); then
    wait "$wheel_pid" || { cat "$wheel_dir/build.log"; echo "setup: building the okid Python package failed" >&2; exit 1; }
    echo "setup: installing the okid Python package into .venv"
    # the same version may be installed already: pip would then keep it, not this build
    .venv/bin/python -m pip uninstall -q -y okid 2>/dev/null || true
    .venv/bin/python -m pip install -q "$wheel_dir"/okid-*.whl
    echo "$package_want" > "$package_stamp"
fi
