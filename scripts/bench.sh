#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The benchmark: okid's C core (reference BLAS and OpenBLAS) and okid against numpy/scipy, mdof and
# python-control on identical data, and every method's RMS error over the Cramer-Rao bound against
# SIPPY and nfoursid (docs/refinement.md). Writes docs/benchmarks.md, docs/img/benchmark.png and
# bench/results.json (about 5 minutes on 2 cores, plus about 20 for the bound's 20-seed comparison,
# which --crlb-only runs alone). --quick: a smoke run of seconds.
# Installs libopenblas-dev when missing (it becomes the system's default BLAS through the Debian
# alternatives; okid's tests pass with either).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if ! dpkg-query -W -f='${Status}' libopenblas-dev 2>/dev/null | grep -q "install ok installed"; then
    if [[ $(id -u) -eq 0 ]]; then SUDO=(); else SUDO=(sudo); fi
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends libopenblas-dev
fi
cmake --preset default >/dev/null
cmake --build --preset default
exec .venv/bin/python bench/python/bench_compare.py "$@"
