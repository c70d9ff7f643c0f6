#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The firmware targets, as CMakePresets.json defines them (the one list): every visible configure
# preset whose toolchain file, its own or inherited, is a bare-metal one (cmake/arm-none-eabi.cmake,
# cmake/riscv-unknown-elf.cmake), in the file's order. scripts/test.sh and scripts/footprint.sh read it.
#   bash scripts/firmware_presets.sh      prints: cortex-m4f cortex-m7 cortex-m33 cortex-m55 riscv32
set -euo pipefail
cd "$(dirname "$0")/.."
python3 - <<'PY'
import json
presets = {p["name"]: p for p in json.load(open("CMakePresets.json"))["configurePresets"]}

def toolchain(p):
    if "toolchainFile" in p:
        return p["toolchainFile"]
    parents = p.get("inherits", [])
    for parent in [parents] if isinstance(parents, str) else parents:
        found = toolchain(presets[parent])
        if found:
            return found
    return None

bare_metal = ("/arm-none-eabi.cmake", "/riscv-unknown-elf.cmake")
print(" ".join(name for name, p in presets.items()
               if not p.get("hidden") and (toolchain(p) or "").endswith(bare_metal)))
PY
