# SPDX-License-Identifier: Apache-2.0
"""Output error against the innovation form (--refine-model, docs/refinement.md) on the same
records, end to end through the CLI: for each case of scripts/refine_coverage.py (the paper's
system; an unmeasured white force of 30 % on mass 2 with 2 % output noise, white 5 % noise, a
drift on output 2) the RMS error of f1, f2, zeta1, zeta2, the RMS error over the RMS stated sigma
(each estimate against its own bound) and the +-2 sigma coverage, as the rows of docs/refinement.md's
table. Both run with the default max_passes (100; the innovation form takes up to 85 passes).

    .venv/bin/python bench/python/refine_models.py [--records 50] [--cases unmeasured,white,drift]

About 2 s of CPU per record and model (the start search included).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import refine_coverage  # noqa: E402  (the records, the runs and the exact modes)

NOISE = {"unmeasured": 0.02, "white": 0.05, "drift": 0.02}


def row(case, model, records):
    args = refine_coverage.parse(["--case", case, "--records", str(records), "--noise", str(NOISE[case]),
                                  "--refine-model", model])
    err, sig, flags, outputs = refine_coverage.study(args)
    rms_e, rms_s = np.sqrt(np.mean(err ** 2, axis=0)), np.sqrt(np.mean(sig ** 2, axis=0))
    cover = 100 * np.mean(np.abs(err) <= 2 * sig)
    print(f"| {case} | {model} | {len(err)} | {flags['converged']} | {flags['not_white']} {outputs.tolist()} | "
          f"{', '.join(f'{v:.3g}' for v in rms_e)} | {', '.join(f'{v:.2f}' for v in rms_e / rms_s)} | {cover:.1f} % |",
          flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--records", type=int, default=50)
    ap.add_argument("--cases", default="unmeasured,white,drift")
    args = ap.parse_args()
    print("| case | model | records | converged | flagged not white (per output) | RMS error f1, f2 [Hz], zeta1, zeta2 "
          "| RMS error / RMS sigma | +-2 sigma coverage |")
    print("|---|---|---|---|---|---|---|---|")
    for case in args.cases.split(","):
        for model in ("output_error", "innovation"):
            row(case, model, args.records)


if __name__ == "__main__":
    main()
