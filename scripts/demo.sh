#!/usr/bin/env bash
# The main job: the paper's 2-DOF identification end to end, identified against exact values.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset default >/dev/null
cmake --build --preset default
exec build/examples/paper_2dof/paper_2dof
