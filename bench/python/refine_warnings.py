# SPDX-License-Identifier: Apache-2.0
"""How often the refinement's residual warnings fire, and how many passes it takes, for both
refine models (docs/refinement.md, "Residual tests" and "Passes"), end to end through the CLI
(`okid identify --order 4 --refine --json`, the start search included) on the records of
scripts/refine_coverage.py: white output noise (the false-alarm rate: the issue's target is at
most 5 % of records), an unmeasured white force of 30 % on mass 2 and a drift on output 2 (where
they should fire).

    .venv/bin/python bench/python/refine_warnings.py [--white 200] [--records 50] [--max-passes 100]

Per case and model: records, converged, passes (median, largest), records with
RESIDUAL_NOT_WHITE (and per output), with RESIDUAL_INPUT_CORRELATED (and per output), with
OUTPUT_NOT_EXPLAINED, and the rate of each; last, white records refined at order 2 (a mode
missed, where the input-residual cross-correlation test should fire). About 1 s of
CPU per record and model.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import refine_coverage  # noqa: E402  (the records and the runs)

NOISE = {"white": 0.05, "unmeasured": 0.02, "drift": 0.02}


def row(case, model, records, max_passes, order=4):
    args = refine_coverage.parse(["--case", case, "--records", str(records), "--noise", str(NOISE[case]),
                                  "--refine-model", model, "--max-passes", str(max_passes), "--order", str(order)])
    _, _, flags, outputs = refine_coverage.study(args)
    n, passes = flags["records"], np.array(flags["passes"])
    label = case if order == 4 else f"{case}, order {order}"
    print(f"| {label} | {model} | {n} | {flags['converged']} | {np.median(passes):g}, {passes.max()} | "
          f"{flags['not_white']} {outputs.tolist()} ({100 * flags['not_white'] / n:.1f} %) | "
          f"{flags['input_correlated']} {flags['input_correlated_outputs'].tolist()} "
          f"({100 * flags['input_correlated'] / n:.1f} %) | "
          f"{flags['not_explained']} ({100 * flags['not_explained'] / n:.1f} %) |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--white", type=int, default=200, help="white-noise records (the false-alarm rate)")
    ap.add_argument("--records", type=int, default=50, help="records of the unmeasured-force and drift cases")
    ap.add_argument("--max-passes", type=int, default=100)
    ap.add_argument("--cases", default="white,unmeasured,drift")
    ap.add_argument("--models", default="output_error,innovation")
    ap.add_argument("--low-order", type=int, default=50, help="white-noise records refined at order 2 (0: none)")
    args = ap.parse_args()
    print(f"max_passes {args.max_passes}")
    print("| case | refine_model | records | converged | passes (median, largest) | residual not white (per output) "
          "| residual correlated with the input (per output) | output not explained |")
    print("|---|---|---|---|---|---|---|---|")
    for case in args.cases.split(","):
        for model in args.models.split(","):
            row(case, model, args.white if case == "white" else args.records, args.max_passes)
    for model in args.models.split(",") if args.low_order > 0 else []:
        row("white", model, args.low_order, args.max_passes, order=2)  # a mode missed: the input correlation fires


if __name__ == "__main__":
    main()
