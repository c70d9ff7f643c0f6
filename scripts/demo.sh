#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job: the paper's 2-DOF identification end to end, identified against exact values.
# Installs only what it needs (scripts/setup.sh --demo) and builds only the library and the example.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --demo
cmake --preset demo >/dev/null
cmake --build --preset demo
exec build-demo/examples/paper_2dof/paper_2dof
