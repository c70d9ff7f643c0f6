#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Error against record length (docs/accuracy.md) from runs of tests/target/test_float_convergence.

Usage: accuracy_plot.py OUT.png LABEL=RUN.txt [LABEL=RUN.txt ...]
Each RUN.txt is a program's output ("error <samples> <mode> <frequency error> <damping error>"
lines); the plot has the frequency and damping errors of both modes against the record length,
one line per run, and the same numbers are printed as a Markdown table.
"""
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LINE = re.compile(r"^error (\d+) (\d) (\S+) (\S+)", re.M)


def load(path):
    runs = {}
    for samples, mode, freq, damp in LINE.findall(open(path).read()):
        runs.setdefault(int(mode), []).append((int(samples), float(freq), float(damp)))
    return runs


def main():
    out, runs = sys.argv[1], [arg.split("=", 1) for arg in sys.argv[2:]]
    data = [(label, load(path)) for label, path in runs]
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    for (label, modes), style in zip(data, ("o-", "s--", "^-", "x:", "d-.")):
        for mode in (1, 2):
            rows = modes.get(mode, [])
            for col, name in ((0, "frequency"), (1, "damping ratio")):
                ax = axes[mode - 1][col]
                ax.loglog([r[0] for r in rows], [r[1 + col] for r in rows], style, label=label)
                ax.set_title(f"mode {mode}: relative {name} error")
    for ax in axes.flat:
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("record length (samples at 100 Hz)")
    axes[0][0].legend(fontsize=8)
    fig.suptitle("2-DOF paper structure, 2 % output noise, p = 40, 40 x 40 Hankel, block_rows 1")
    fig.tight_layout()
    fig.savefig(out, dpi=90)

    print("| samples | mode | " + " | ".join(f"{label}: frequency / damping" for label, _ in data) + " |")
    print("|---|---|" + "---|" * len(data))
    lengths = sorted({r[0] for _, modes in data for rows in modes.values() for r in rows})
    for n in lengths:
        for mode in (1, 2):
            cells = []
            for _, modes in data:
                row = next((r for r in modes.get(mode, []) if r[0] == n), None)
                cells.append(f"{row[1]:.2e} / {row[2]:.2e}" if row else "")
            print(f"| {n} | {mode} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
