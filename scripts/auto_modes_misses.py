#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Why the automatic identification misses three real records' consensus and the damping target
on the 5-mass chain (issue 23; docs/quality.md section 8, "Why the three records miss"). Prints the
measurements that section quotes:

- observer: each real record with every setting chosen from the data except the observer order,
  p = 0.5, 0.625, 0.75, 0.875 and 1 slowest period T (the data's choice is 0.5 T);
- meloland: the Meloland record cut into 20 s windows, its mode at fixed settings per window, with
  the deck's peak acceleration (a softening structure's frequency falls while it shakes hardest);
- gws261: the stabilization table of GWS 261 deg between 4.6 and 5.3 Hz at the chosen settings, in
  each of the three Hankel windows (tests/mode_selection_run, the selection of section 7);
- chain: the damping errors of the 5-mass chain and the unexcited-mode chain at the chosen settings
  and at larger observer orders.

    .venv/bin/python scripts/auto_modes_misses.py [observer|meloland|gws261|chain ...]
        [--runner build/tests/mode_selection_run]
"""
import argparse
import json
import pathlib
import subprocess
import sys
import warnings

import numpy as np

import okid

ROOT = pathlib.Path(__file__).resolve().parents[1]
REAL = ROOT / "tests" / "data" / "real"
CONSENSUS = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())["records"]
sys.path.insert(0, str(ROOT / "bench" / "python"))


def modes_text(result, lo=0.0, hi=np.inf):
    return " ".join(f"{m.frequency_hz:.3f}/{m.damping_ratio:.3f}" for m in result.modes if lo <= m.frequency_hz <= hi)


def record(stem):
    spec = CONSENSUS[stem]
    return okid.read_record(REAL / f"{stem}.csv", inputs=spec["inputs"], outputs=spec["outputs"])


def observer(_args):
    print("observer order as a fraction of the slowest period T, every other setting from the data (f/zeta)")
    for stem, spec in CONSENSUS.items():
        r = record(stem)
        chosen = okid.identify(r.u, r.y, r.dt).chosen
        period, k = chosen["slowest_period_seconds"], chosen["decimation"]["value"]
        consensus = " ".join(f"{m['frequency_hz']:.3f}" for m in spec["modes"])
        print(f"{stem}: consensus {consensus} Hz; T {period:.2f} s, K {k}")
        for share in (0.5, 0.625, 0.75, 0.875, 1.0):
            p = int(round(share * period / (k * r.dt)))
            print(f"  p {p:3d} ({share:.3g} T): {modes_text(okid.identify(r.u, r.y, r.dt, observer_order=p))}")


def meloland(_args):
    r = record("meloland_transverse")
    t = np.arange(r.u.shape[0]) * r.dt
    deck = np.abs(r.y).max(axis=1)
    print("Meloland, 20 s windows, K 7, Hankel 30, modes between 2 and 4 Hz (f/zeta); deck peak in cm/s^2")
    for start in range(0, 70, 10):
        s = (t >= start) & (t < start + 20)
        cells = []
        for p in (5, 7, 10):
            res = okid.identify(r.u[s], r.y[s], r.dt, decimation=7, observer_order=p, hankel_rows=30, hankel_cols=30)
            cells.append(f"p {p}: {modes_text(res, 2, 4) or '-'}")
        print(f"  {start:2d}-{start + 20:2d} s, peak {deck[s].max():3.0f}: " + " | ".join(cells))


def gws261(args):
    path = REAL / "gws_building_261.csv"
    print("GWS 261 deg at the chosen K 7, p 15, orders 2..44: poles in 4.6..5.3 Hz (f/zeta EMAC)")
    for window in (88, 58, 117):
        out = subprocess.run([args.runner, "--inputs", "2", "--outputs", "3", "--observer-order", "15", "--hankel",
                              str(window), "--decimation", "7", "--max-order", "44", "--damping-max", "0.7071", "--table",
                              str(path)], capture_output=True, text=True, check=True)
        run = json.loads(out.stdout)
        picked = " ".join(f"{m['frequency_hz']:.3f} ({m['num_orders']} orders)" for m in run["modes"])
        print(f"  window {window}: selected {picked}; a mode needs {run['min_orders']} of {run['num_orders']} orders")
        rows = {}
        for pole in run["table"]:
            if pole["is_pair"] and 4.6 <= pole["frequency_hz"] <= 5.3:
                rows.setdefault(pole["order"], []).append(
                    f"{pole['frequency_hz']:.3f}/{pole['damping_ratio']:.3f} {pole['emac']:.2f}")
        for order in sorted(rows):
            print(f"    {order:2d}: " + " | ".join(rows[order]))


def chain(_args):
    from mode_selection_bench import SIMULATED, match  # the benchmark's data sets and matching
    for name in ("5-mass chain, 5 % noise", "unexcited mode, 5 % noise"):
        print(f"{name}: relative damping error of each mode, from the data's p and larger p")
        for seed in (1, 2, 3):
            (u, y, dt), truth = SIMULATED[name](seed)
            for settings in ({}, {"observer_order": 40}, {"observer_order": 60}, {"observer_order": 80},
                             {"estimator": "instrumental"}):
                res = okid.identify(u, y, dt, **settings)
                pairs, spurious = match([(m.frequency_hz, m.damping_ratio) for m in res.modes], truth, 0.05)
                errors = " ".join(f"{abs(g[1] - t[1]) / t[1]:.3f}" for t, g in pairs)
                print(f"  seed {seed}, p {res.chosen['observer_order']['value']:2d} {settings or ''}: {len(pairs)} found, "
                      f"{spurious} spurious, damping errors {errors}")


def main():
    parts = {"observer": observer, "meloland": meloland, "gws261": gws261, "chain": chain}
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("parts", nargs="*", help=f"any of {', '.join(parts)} (default: all)")
    ap.add_argument("--runner", default=str(ROOT / "build" / "tests" / "mode_selection_run"))
    args = ap.parse_args()
    warnings.simplefilter("ignore")  # the identifications' warnings are not the measurement
    unknown = [name for name in args.parts if name not in parts]
    if unknown:
        ap.error(f"unknown part {unknown[0]}: one of {', '.join(parts)}")
    for name in args.parts or parts:
        parts[name](args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
