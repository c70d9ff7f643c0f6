#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Flash and RAM a program takes per archive, from its GNU ld map file (after --gc-sections).

Usage: map_sizes.py PROGRAM.map [ARCHIVE_NAME ...]
Prints "<archive> flash <bytes> ram <bytes>" for each archive named (e.g. libokid.a, libm.a,
libc.a), flash = .text* + .rodata* (+ .ARM.exidx/extab, RISC-V .srodata), ram = .data* + .bss* (+ .sdata,
.sbss), as linked.
"""
import re
import sys

# An input section: name, then (on the same or the next line) address, size and the object.
SECTION = re.compile(r"^ (\.[\w.$]+)\s*\n?\s+0x[0-9a-f]+\s+0x([0-9a-f]+)\s+(\S+)", re.M)
FLASH = (".text", ".rodata", ".srodata", ".ARM.exidx", ".ARM.extab")  # .s*: RISC-V small data
RAM = (".data", ".bss", ".sdata", ".sbss")


def main():
    text = open(sys.argv[1]).read()
    # Only what was linked: the map lists discarded input sections before "Memory Configuration".
    text = text[text.find("Linker script and memory map"):]
    wanted = sys.argv[2:]
    totals = {name: [0, 0] for name in wanted}
    for section, size, obj in SECTION.findall(text):
        archive = re.sub(r"\(.*", "", obj).rsplit("/", 1)[-1]
        if archive not in totals:
            continue
        if section.startswith(FLASH):
            totals[archive][0] += int(size, 16)
        elif section.startswith(RAM):
            totals[archive][1] += int(size, 16)
    for name in wanted:
        print(f"{name} flash {totals[name][0]} ram {totals[name][1]}")


if __name__ == "__main__":
    main()
