# SPDX-License-Identifier: Apache-2.0
"""The refinement on the real records of tests/data/real (docs/refinement.md, "The real records"),
both refine models, through the CLI:

    okid identify --inputs R --outputs M --order N --decimation K --decimation-method lift
                  --refine --refine-model MODEL --json FILE
                  [--observer-order 20 --hankel-rows 50 --hankel-cols 50]   (--horizons fixed)

(K: the decimation of the record's mode selection in tests/data/real_consensus.json, 4 where it
has none; lifting, since the refinement needs the record the model describes) at three orders per record (2c, 2c + 2, 2c + 4 for the c modes of tests/data/real_consensus.json).
Per run: the state, passes, the decrement, the fit and the largest Ljung-Box Q over the outputs,
the CPU seconds (of the okid process), and how many refined modes lie within 5 % of each consensus
mode (2 or more: the refinement split one physical mode). Per record, model and consensus mode:
the statistical sigma (the refinement's frequency_std: its median over the orders) and the spread
across model orders (the sample std of the nearest refined frequency over the orders), named so.

    .venv/bin/python bench/python/refine_real.py [--horizons fixed|search] [--records a,b] [--models ...]
                                                 [--orders auto] [--decimation-method lift|none]

--orders auto gives no --order: the refinement's order and start come from the physical-mode
selection (host_tools/common/refine_selection.c; the "order" column then shows the chosen one).
--decimation-method none runs the record at its own dt (no --decimation).

With --horizons search the CLI's start search chooses p and the Hankel size (minutes per run on
these records: every start is refined).
"""
import argparse
import json
import os
import pathlib
import resource
import subprocess

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
OKID = os.environ.get("OKID_CLI") or str(ROOT / "build" / "host_tools" / "cli" / "okid")
CONSENSUS = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())["records"]
FIXED = ["--observer-order", "20", "--hankel-rows", "50", "--hankel-cols", "50"]
NEAR = 0.05  # a refined mode within 5 % of a consensus mode is that mode


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(stem, rec, order, model, horizons, decimation_method):
    k = (rec["selection_settings"] or {}).get("decimation", 4)
    cmd = [OKID, "identify", "--inputs", str(rec["inputs"]), "--outputs", str(rec["outputs"]),
           *(["--order", str(order)] if order else []),
           *(["--decimation", str(k), "--decimation-method", "lift"] if decimation_method == "lift" else []),
           "--refine", "--refine-model", model, "--json", *(FIXED if horizons == "fixed" else []),
           str(ROOT / "tests" / "data" / "real" / (stem + ".csv"))]
    t0 = cpu_children()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    seconds = cpu_children() - t0
    if proc.returncode != 0:
        return None, seconds, proc.stderr.strip()
    return json.loads(proc.stdout), seconds, ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--horizons", choices=["fixed", "search"], default="fixed")
    ap.add_argument("--records", default=",".join(sorted(CONSENSUS)))
    ap.add_argument("--models", default="output_error,innovation")
    ap.add_argument("--orders", default="", help="orders to run instead of 2c, 2c + 2, 2c + 4 (comma-separated), or "
                    "'auto': no --order, the order chosen from the mode selection")
    ap.add_argument("--decimation-method", choices=["lift", "none"], default="lift")
    args = ap.parse_args()
    print(f"horizons: {'p 20, alpha = beta = 50' if args.horizons == 'fixed' else 'the start search'}")
    print("| record | refine_model | order | state | passes | decrement | fit % (outputs) | largest Q | CPU s "
          "| refined modes near each consensus mode [Hz] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    summary = []
    for stem in args.records.split(","):
        rec = CONSENSUS[stem]
        want = [m["frequency_hz"] for m in rec["modes"]]
        c = len(want)
        for model in args.models.split(","):
            near = {w: [] for w in want}
            orders = ([0] if args.orders == "auto" else [int(v) for v in args.orders.split(",")] if args.orders
                      else [2 * c, 2 * c + 2, 2 * c + 4])
            for order in orders:
                d, seconds, err = run(stem, rec, order, model, args.horizons, args.decimation_method)
                if d is None:
                    print(f"| {stem} | {model} | {order} | refused: {err} | | | | | {seconds:.1f} | |", flush=True)
                    continue
                r = d["refinement"]
                tests = r["residual_tests"]["outputs"]
                fits = [o["fit_percent"] for o in tests]
                cells = []
                for w in want:
                    hits = [m for m in d["modes"] if m["is_pair"] and abs(m["frequency_hz"] - w) <= NEAR * w]
                    cells.append(f"{w:.3f}: " + (", ".join(f"{m['frequency_hz']:.3f} ± {m['frequency_std']:.2g}"
                                                           for m in hits) or "none")
                                 + (" (SPLIT)" if len(hits) > 1 else ""))
                    if hits:
                        best = min(hits, key=lambda m: abs(m["frequency_hz"] - w))
                        near[w].append((best["frequency_hz"], best["frequency_std"]))
                shown = order or f"{d.get('chosen', {}).get('order', {}).get('value')} (chosen)"
                print(f"| {stem} | {model} | {shown} (K {d.get('lift_factor', 1)}) | {r['state']} | {r['passes']} | {r['decrement']:.3g} | "
                      f"{min(fits):.0f}–{max(fits):.0f} | {max(o['whiteness'] for o in tests):.3g} | {seconds:.1f} | "
                      f"{'; '.join(cells)} |", flush=True)
            for w, found in near.items():
                f = np.array([v[0] for v in found])
                s = np.array([v[1] for v in found if v[1] >= 0])  # -1: not computable (singular)
                spread = np.std(f, ddof=1) if len(f) > 1 else float("nan")
                summary.append(f"| {stem} | {model} | {w:.3f} | {len(f)} of {len(orders)} | "
                               + (f"{np.mean(f):.4f} | {np.median(s) if len(s) else float('nan'):.3g} | {spread:.3g} | "
                                  f"{spread / np.median(s) if len(s) else float('nan'):.3g} |" if len(f) else " | | | |"))
    print()
    print("| record | refine_model | consensus mode [Hz] | orders with it | mean refined f [Hz] "
          "| statistical sigma (median frequency_std) | spread across orders (std) | spread / sigma |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(summary))


if __name__ == "__main__":
    main()
