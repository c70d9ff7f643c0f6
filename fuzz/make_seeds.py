#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes the seed corpus of the fuzz targets (fuzz/corpus/): inputs that reach deep paths at once
(a valid configuration, a few hundred samples, identifications), which random bytes rarely do.
    python3 fuzz/make_seeds.py
"""
import math
import random
from pathlib import Path

HERE = Path(__file__).parent / "corpus"


def i(value, lo, hi):
    v = value - lo
    assert 0 <= v <= hi - lo
    return bytes([v & 255, v >> 8])


def real(x):
    """fuzz_real's ordinary branch: ((v % 65536) - 32768) / 4096."""
    v = max(0, min(65535, int(round(x * 4096)) + 32768))
    return bytes([200]) + i(v, 0, 65535)


def api_seed(rng, realization, block_rows, zero_state, samples):
    out = bytearray()
    out += i(1, -1, 3) + i(2, -1, 3) + i(4, -1, 12) + i(4, -1, 8) + i(6, -1, 14) + i(6, -1, 14)
    out += i(block_rows, -1, 9) + i(realization, 0, 2) + i(2, -1, 3) + i(zero_state, 0, 1)
    out += bytes([0, 0, 0]) + i(0, -64, 64) + bytes([255])   # dt 0.01, defaults, no workspace change
    x1 = x2 = 0.0
    for k in range(samples):
        u = rng.gauss(0, 1)
        x1, x2 = 0.9 * x1 - 0.3 * x2 + u, 0.8 * x2 + 0.2 * x1
        out += bytes([0]) + real(u) + real(x1) + real(x2)      # push
        if k % 60 == 59:
            out += bytes([4])                                  # identify
            out += bytes([5]) + real(rng.gauss(0, 1))          # predict
    out += bytes([7]) + bytes([6, 0])                          # bad calls, reset
    return bytes(out)


def main():
    rng = random.Random(1)
    for n, (realization, block_rows, zero_state) in enumerate([(0, 3, 1), (1, 0, 0), (0, 8, 0), (1, 1, 1)]):
        (HERE / "api" / f"seed{n}.bin").write_bytes(api_seed(rng, realization, block_rows, zero_state, 190))
    rows = ["t,force,acc1,acc2"] + [f"{0.01 * k:.2f},{math.sin(k):.6f},{math.cos(k):.6f},{k % 7}" for k in range(40)]
    (HERE / "csv" / "paper.csv").write_text("\n".join(rows) + "\n")
    (HERE / "csv" / "semicolon.csv").write_text("time;u;y\r\n0;1;2\r\n# comment\r\n0.5;1e-3;-2.5E+2\r\n")
    (HERE / "csv" / "ragged.csv").write_text("a,b,c\n1,2\n")
    # FMU: instantiate with the right token, logging on; set defaults; init; steps with inputs.
    out = bytearray([200, 200]) + i(1, 0, 1)
    out += bytes([5]) + i(0, 0, 130) + bytes([6]) + i(0, 0, 130)      # enter, exit initialization
    for k in range(250):
        out += bytes([7]) + i(0, 0, 130) + bytes([0, 0])               # step at the right time and size
        for _ in range(3):
            out += bytes([0]) + i(int(1000 + 900 * math.sin(0.7 * k + _)), 0, 2000)
    (HERE / "fmu" / "steps.bin").write_bytes(bytes(out))


if __name__ == "__main__":
    main()
