#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Consensus of the physical modes of the real records in tests/data/real (README there), by
three independent routes, written to tests/data/real_consensus.json:

1. okid at fixed orders over a grid of settings (observer order p, Hankel size alpha = beta,
   decimation K, model order n; the Python package's okid.identify, not the automatic selection
   under test): in each run the poles that are stable complex pairs with 0 < zeta <= 0.2,
   MPC >= 0.5 and EMAC >= 0.5; poles of all runs are grouped by frequency (a pole joins the group
   whose median is within 3 %), and a group that holds a pole in at least half of the runs is an
   okid mode (frequency, damping: medians over the group; spread: the group's std and range).
2. The multi-input H1 estimate H(f) = S_yu(f) S_uu(f)^-1 (scipy.signal.csd, Hann windows of
   H1_SEGMENT_SECONDS, half overlap) and its complex mode indicator function: the peaks of the
   first and second singular values of H(f), each with a prominence of at least a tenth of that
   curve's largest value. Resolution 1 / segment length.
3. mdof (PyPI, the records' own source project, Chern et al.), SRIM at orders 12 and 20 with the
   same hard criteria (mdof gives no EMAC) and the same grouping: a mode in both runs.

A consensus mode is found by at least two of the three routes (the okid grid and mdof within 3 %
of each other, an H1 peak within one frequency bin of either: the H1 peaks are many, 10-13 on the
bridges, so a looser match would confirm almost anything); its frequency and damping are the
okid grid's medians when the grid found it, else mdof's. "found_by" lists the routes.

Then the automatic selection under test (tests/mode_selection_run, okid_select_modes with its
default criteria) runs over a grid of settings, and the settings at which it gives every
consensus mode within 2 % and nothing else are counted ("selection_matches"); the one with the
smallest worst frequency error is recorded as "selection_settings" for
tests/python/test_mode_selection_real.py.

    .venv/bin/python scripts/real_consensus.py [--data tests/data/real] [--no-mdof]
"""
import argparse
import json
import os
import sys
import warnings

import numpy as np
from scipy import signal

RECORDS = {
    # file stem: inputs, outputs, band of interest [Hz] (above the CGS/USGS high-pass corner, below
    # 15 Hz: the global modes), decimations of the okid grid
    "hayward_transverse": dict(inputs=4, outputs=4, band=(0.5, 15.0), decimations=(4, 8)),
    "meloland_transverse": dict(inputs=3, outputs=3, band=(0.5, 15.0), decimations=(2, 4)),
    "gws_building_351": dict(inputs=2, outputs=5, band=(0.5, 15.0), decimations=(4, 8)),
    "gws_building_261": dict(inputs=2, outputs=3, band=(0.5, 15.0), decimations=(4, 8)),
}
OBSERVER_SECONDS = (0.5, 1.0)      # p K dt
HANKEL_SECONDS = (2.0, 4.0)        # alpha K dt
ORDERS = (12, 20, 30)
H1_SEGMENT_SECONDS = 10.24
GROUP_TOL = 0.03
ZETA_MAX, MPC_MIN, EMAC_MIN = 0.2, 0.5, 0.5


def load(path, r, m):
    d = np.loadtxt(path, delimiter=",", skiprows=1)
    dt = float(np.median(np.diff(d[:, 0])))
    return d[:, 1:1 + r], d[:, 1 + r:1 + r + m], dt


def group(poles, runs, min_share=0.5):
    """poles: (run, f, zeta). Greedy grouping by frequency; groups present in >= min_share of runs."""
    groups = []
    for run, f, z in sorted(poles, key=lambda p: p[1]):
        for g in groups:
            if abs(f - np.median(g["f"])) <= GROUP_TOL * np.median(g["f"]):
                g["f"].append(f); g["z"].append(z); g["runs"].add(run)
                break
        else:
            groups.append({"f": [f], "z": [z], "runs": {run}})
    out = []
    for g in groups:
        if len(g["runs"]) >= min_share * runs:
            f, z = np.array(g["f"]), np.array(g["z"])
            out.append(dict(frequency_hz=float(np.median(f)), damping_ratio=float(np.median(z)),
                            frequency_std=float(f.std()), frequency_range=[float(f.min()), float(f.max())],
                            damping_std=float(z.std()), runs=len(g["runs"]), of_runs=runs))
    return out


def okid_grid(u, y, dt, spec):
    import okid
    poles, runs, settings = [], 0, []
    lo, hi = spec["band"]
    for K in spec["decimations"]:
        for ps in OBSERVER_SECONDS:
            for hs in HANKEL_SECONDS:
                p = max(1, round(ps / (K * dt)))
                a = max(1, round(hs / (K * dt)))
                for n in ORDERS:
                    try:
                        res = okid.identify(u, y, dt, order=n, observer_order=p, hankel_rows=a, hankel_cols=a,
                                            decimation=K, scaling="auto", sensing="acceleration")
                    except Exception as e:  # a setting the data cannot support: not a run
                        print(f"  okid K={K} p={p} a={a} n={n}: {e}", file=sys.stderr)
                        continue
                    runs += 1
                    settings.append(dict(decimation=K, observer_order=p, hankel=a, order=n))
                    for md in res.modes:
                        if (md.is_pair and abs(md.eigenvalue) < 1 and 0 < md.damping_ratio <= ZETA_MAX
                                and md.mpc >= MPC_MIN and md.emac >= EMAC_MIN and lo <= md.frequency_hz <= hi):
                            poles.append((runs, md.frequency_hz, md.damping_ratio))
    return group(poles, runs), settings


def h1_peaks(u, y, dt, band):
    nper = int(round(H1_SEGMENT_SECONDS / dt))
    r, m = u.shape[1], y.shape[1]
    f, _ = signal.csd(u[:, 0], u[:, 0], fs=1 / dt, nperseg=nper)
    suu = np.zeros((len(f), r, r), complex)
    syu = np.zeros((len(f), m, r), complex)
    for i in range(r):
        for j in range(r):
            suu[:, i, j] = signal.csd(u[:, i], u[:, j], fs=1 / dt, nperseg=nper)[1]
        for a in range(m):
            syu[:, a, i] = signal.csd(y[:, a], u[:, i], fs=1 / dt, nperseg=nper)[1]
    h = syu @ np.linalg.pinv(suu, rcond=1e-8)
    sv = np.linalg.svd(h, compute_uv=False)
    sel = (f >= band[0]) & (f <= band[1])
    fb = f[sel]
    peaks = []
    for curve in range(min(2, sv.shape[1])):
        cb = sv[sel, curve]
        idx, _ = signal.find_peaks(cb, prominence=0.1 * cb.max())
        peaks += interpolate_peaks(fb, cb, idx)
    return sorted(peaks), float(f[1] - f[0])


def interpolate_peaks(fb, cb, idx):
    """Parabolic interpolation of each peak on the log magnitude."""
    peaks = []
    for i in idx:
        if 0 < i < len(cb) - 1:
            l0, l1, l2 = np.log(cb[i - 1:i + 2])
            den = l0 - 2 * l1 + l2
            off = 0.5 * (l0 - l2) / den if den != 0 else 0.0
            peaks.append(float(fb[i] + off * (fb[1] - fb[0])))
        else:
            peaks.append(float(fb[i]))
    return peaks


def mdof_modes(u, y, dt, spec):
    import mdof
    import mdof.modal
    poles, runs = [], 0
    lo, hi = spec["band"]
    K = spec["decimations"][-1]
    for n in (12, 20):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            real = mdof.sysid(u.T, y.T, dt=dt, method="srim", order=n, horizon=round(1.0 / (K * dt)),
                              decimation=K)
            modes = mdof.modal.system_modes(real, K * dt)
        runs += 1
        for md in modes.values():
            f, z, mpc = float(md["freq"]), float(md["damp"]), float(md.get("mpc", 1.0))
            if 0 < z <= ZETA_MAX and mpc >= MPC_MIN and lo <= f <= hi:
                poles.append((runs, f, z))
    return group(poles, runs, 1.0), dict(method="srim", orders=[12, 20], horizon_seconds=1.0, decimation=K)


def near(f, values, tol):
    return [v for v in values if abs(v - f) <= tol]


def consensus(grid, peaks, res, md):
    """Every mode any route found, with the routes that agree; consensus when two or more do."""
    found = []
    for g in grid:
        f = g["frequency_hz"]
        routes = ["okid grid %d/%d runs" % (g["runs"], g["of_runs"])]
        h = near(f, peaks, res)
        if h:
            routes.append("H1 peak %.3f Hz" % h[0])
        mm = [x for x in md if abs(x["frequency_hz"] - f) <= GROUP_TOL * f]
        if mm:
            routes.append("mdof SRIM %.3f Hz (%d/%d runs)" % (mm[0]["frequency_hz"], mm[0]["runs"], mm[0]["of_runs"]))
        found.append(dict(g, source="okid grid", found_by=routes))
    for x in md:  # mdof modes the grid did not find
        f = x["frequency_hz"]
        if any(abs(g["frequency_hz"] - f) <= GROUP_TOL * g["frequency_hz"] for g in grid):
            continue
        routes = ["mdof SRIM %.3f Hz (%d/%d runs)" % (f, x["runs"], x["of_runs"])]
        h = near(f, peaks, res)
        if h:
            routes.append("H1 peak %.3f Hz" % h[0])
        found.append(dict(x, source="mdof", found_by=routes))
    for g in found:
        g["consensus"] = len(g["found_by"]) >= 2
    return sorted(found, key=lambda g: g["frequency_hz"])


SELECTION_GRID = [dict(decimation=K, observer_seconds=ps, hankel_seconds=hs, max_order=n)
                  for n in (40, 60) for hs in (2.0, 4.0) for ps in (0.5, 1.0) for K in (0, 1)]


def selection_search(runner, path, spec, dt, modes):
    """The selection over SELECTION_GRID (K: index into the record's decimations); each run's modes and
    whether they match the consensus (every mode within 2 %, nothing else in the band)."""
    import subprocess
    runs = []
    want = [g["frequency_hz"] for g in modes]
    lo, hi = spec["band"]
    for s in SELECTION_GRID:
        K = spec["decimations"][s["decimation"]]
        p = max(1, round(s["observer_seconds"] / (K * dt)))
        a = max(1, round(s["hankel_seconds"] / (K * dt)))
        cmd = [runner, "--inputs", str(spec["inputs"]), "--outputs", str(spec["outputs"]), "--decimation", str(K),
               "--observer-order", str(p), "--hankel", str(a), "--max-order", str(s["max_order"]),
               "--frequency-min", str(lo), "--frequency-max", str(hi), path]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            runs.append(dict(decimation=K, observer_order=p, hankel=a, max_order=s["max_order"], error=out.stderr.strip()))
            continue
        got = [m["frequency_hz"] for m in json.loads(out.stdout)["modes"]]
        match = len(got) == len(want) and all(any(abs(g - w) <= 0.02 * w for g in got) for w in want)
        worst = max((min(abs(g - w) / w for g in got) for w in want), default=0.0) if got else None
        runs.append(dict(decimation=K, observer_order=p, hankel=a, max_order=s["max_order"],
                         selected_hz=[round(g, 4) for g in got], matches=match,
                         worst_error=None if worst is None else round(worst, 5)))
    return runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=os.path.join(os.path.dirname(__file__), "..", "tests", "data", "real"))
    ap.add_argument("--output", default=os.path.join(os.path.dirname(__file__), "..", "tests", "data",
                                                     "real_consensus.json"))
    ap.add_argument("--no-mdof", action="store_true")
    ap.add_argument("--runner", default=os.path.join(os.path.dirname(__file__), "..", "build", "tests",
                                                     "mode_selection_run"))
    ap.add_argument("--only")
    ap.add_argument("--reuse", help="a previous output: its okid grid, H1 peaks and mdof modes (the slow part)")
    args = ap.parse_args()
    out = {"procedure": __doc__.split("\n\n")[0] + " See scripts/real_consensus.py.",
           "criteria": dict(zeta_max=ZETA_MAX, mpc_min=MPC_MIN, emac_min=EMAC_MIN, group_tolerance=GROUP_TOL,
                            observer_seconds=OBSERVER_SECONDS, hankel_seconds=HANKEL_SECONDS, orders=ORDERS,
                            h1_segment_seconds=H1_SEGMENT_SECONDS),
           "records": {}}
    for stem, spec in RECORDS.items():
        if args.only and stem != args.only:
            continue
        u, y, dt = load(os.path.join(args.data, stem + ".csv"), spec["inputs"], spec["outputs"])
        if args.reuse:
            old = json.load(open(args.reuse))["records"][stem]
            keep = ("frequency_hz", "damping_ratio", "frequency_std", "frequency_range", "damping_std", "runs", "of_runs")
            grid = [{k: g[k] for k in keep} for g in old["modes"] + old["not_confirmed"] if g["source"] == "okid grid"]
            settings = [None] * old["okid_runs"]
            peaks, res, md, md_settings = old["h1_peaks_hz"], old["h1_resolution_hz"], old["mdof_modes"], old["mdof_settings"]
        else:
            grid, settings = okid_grid(u, y, dt, spec)
            peaks, res = h1_peaks(u, y, dt, spec["band"])
            md, md_settings = ([], None) if args.no_mdof else mdof_modes(u, y, dt, spec)
        modes = consensus(grid, peaks, res, md)
        out["records"][stem] = dict(
            inputs=spec["inputs"], outputs=spec["outputs"], dt=dt, band_hz=list(spec["band"]),
            modes=[g for g in modes if g["consensus"]],
            not_confirmed=[g for g in modes if not g["consensus"]],
            h1_peaks_hz=peaks, h1_resolution_hz=res, mdof_modes=md, mdof_settings=md_settings,
            okid_runs=len(settings))
        rec = out["records"][stem]
        rec["selection_runs"] = selection_search(args.runner, os.path.join(args.data, stem + ".csv"), spec, dt,
                                                 rec["modes"])
        ok = [r for r in rec["selection_runs"] if r.get("matches")]
        rec["selection_settings"] = min(ok, key=lambda r: r["worst_error"]) if ok else None
        rec["selection_matches"] = "%d of %d settings" % (len(ok), len(rec["selection_runs"]))
        print(stem, file=sys.stderr)
        for g in modes:
            print("  %s %.3f Hz zeta %.3f std %.3f  %s" % ("*" if g["consensus"] else " ", g["frequency_hz"],
                  g["damping_ratio"], g["frequency_std"], "; ".join(g["found_by"])), file=sys.stderr)
        for r in rec["selection_runs"]:
            print("  selection", r, file=sys.stderr)
        print("  H1 peaks:", ", ".join("%.3f" % p for p in peaks), "res %.3f" % res, file=sys.stderr)
        print("  mdof:", ", ".join("%.3f" % x["frequency_hz"] for x in md), file=sys.stderr)
    if not args.only:
        os.makedirs(os.path.dirname(args.output), exist_ok=True)
        with open(args.output, "w") as fh:
            json.dump(out, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
