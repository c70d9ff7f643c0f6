# SPDX-License-Identifier: Apache-2.0
"""Coverage study of the refinement's error bars (docs/refinement.md), end to end through the CLI.

For each record: `okid simulate` (the paper's 2-DOF chain, unit white force on mass 1) and, for
the unmeasured-force case, a second `okid simulate` with a white force on mass 2 (another seed)
scaled to --unmeasured x the measured force's RMS and added (the chain is linear); a drift case
adds an offset and a ramp to output 2; then white output noise of --noise x each output's RMS;
then `okid identify --order 4 --refine --refine-model M --json` (the start search included). Prints per quantity
(f1, f2, zeta1, zeta2) the RMS error, the RMS stated sigma and the +-2 sigma coverage against the
exact modes (`okid crlb` prints them), and how often the residual and mode-split warnings fired.

    .venv/bin/python scripts/refine_coverage.py --case unmeasured --records 50
    .venv/bin/python scripts/refine_coverage.py --case white --records 200      # false alarms
    .venv/bin/python scripts/refine_coverage.py --case white --records 50 --order 2  # a mode missed
    .venv/bin/python scripts/refine_coverage.py --case unmeasured --records 50 --refine-model innovation --max-passes 100
    .venv/bin/python scripts/refine_coverage.py --case unmeasured --records 50 --method "SIPPY PARSIM-K"

--method "SIPPY N4SID" | "SIPPY PARSIM-K" identifies the same records with SIPPY instead (order 4,
D estimated, horizons f = p = --sippy-horizon, bench/python/bench_compare.py's call): RMS errors
only, since SIPPY states no standard deviations.
"""
from __future__ import annotations

import argparse
import csv
import io
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

# OKID_CLI: another build of the CLI (a copy, so that a rebuild does not change a long run midway)
OKID = os.environ.get("OKID_CLI") or os.path.join(os.path.dirname(__file__), "..", "build", "host_tools", "cli", "okid")
SIPPY_METHODS = ("SIPPY N4SID", "SIPPY PARSIM-K")


def simulate(args, seed, force_dof):
    out = subprocess.run([OKID, "simulate", "--samples", str(args.samples), "--dt", str(args.dt), "--noise", "0",
                          "--seed", str(seed), "--force-dof", str(force_dof)], check=True, capture_output=True,
                         text=True).stdout
    rows = list(csv.reader(io.StringIO(out)))
    return rows[0], np.array(rows[1:], dtype=float)


def exact_modes(args):
    out = subprocess.run([OKID, "crlb", "--samples", "101", "--dt", str(args.dt), "--noise", "0.01"], check=True,
                         capture_output=True, text=True).stdout.splitlines()
    rows = [line.split(",") for line in out if line[:1].isdigit()]
    return np.array([[float(r[1]) for r in rows], [float(r[3]) for r in rows]])  # (freq, zeta) x mode


def record(args, k):
    header, a = simulate(args, 1000 + k, 1)
    y = a[:, 2:].copy()
    if args.case == "unmeasured":
        _, b = simulate(args, 50000 + k, 2)
        y += args.unmeasured * np.sqrt(np.mean(a[:, 1] ** 2)) / np.sqrt(np.mean(b[:, 1] ** 2)) * b[:, 2:]
    if args.case == "drift":
        t = np.arange(len(y)) / len(y)
        y[:, 1] += np.sqrt(np.mean(y[:, 1] ** 2)) * (0.5 + 1.5 * t)
    rng = np.random.default_rng(777 + k)
    y += args.noise * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape)
    return header, np.column_stack([a[:, :2], y])


def parse(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=["white", "unmeasured", "drift"], default="unmeasured")
    ap.add_argument("--records", type=int, default=50)
    ap.add_argument("--samples", type=int, default=2001)
    ap.add_argument("--dt", type=float, default=0.05)
    ap.add_argument("--noise", type=float, default=0.02)
    ap.add_argument("--unmeasured", type=float, default=0.3)
    ap.add_argument("--refine-model", choices=["output_error", "innovation", "auto"], default="output_error")
    ap.add_argument("--max-passes", type=int, default=100)  # okid_refine_config_default()
    ap.add_argument("--order", type=int, default=4, help="model order refined (2: too low, one mode missed)")
    ap.add_argument("--method", choices=("okid",) + SIPPY_METHODS, default="okid")
    ap.add_argument("--sippy-horizon", type=int, default=20, help="SIPPY's f = p (bench_compare.py's tuned 20 at dt 0.05 s)")
    return ap.parse_args(argv)


def sippy_errors(args, data, truth):
    """SIPPY's f1, f2, zeta1, zeta2 minus the truth on one record (None: fewer than two pairs)."""
    import warnings
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "bench", "python"))
    from bench_compare import sippy_subspace
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        freq, zeta = sippy_subspace(data[:, 1:2], data[:, 2:], args.dt, args.method.split()[1], args.sippy_horizon,
                                    n=args.order)
    if len(freq) != 2:
        return None
    return (np.array([freq, zeta]) - truth).ravel()


def study_sippy(args):
    """The records of args through SIPPY: errors as (records, 4), and the records without two pairs."""
    truth = exact_modes(args)
    err, missed = [], 0
    for k in range(args.records):
        e = sippy_errors(args, record(args, k)[1], truth)
        if e is None:
            missed += 1
        else:
            err.append(e)
    return np.array(err), missed


def main_sippy(args):
    err, missed = study_sippy(args)
    print(f"case {args.case}, {args.method} (f = p = {args.sippy_horizon}, order {args.order}): {len(err)} records "
          f"of {args.samples} samples at dt {args.dt} s, noise {args.noise:g}"
          + (f", unmeasured force {args.unmeasured:g}" if args.case == "unmeasured" else "")
          + f"; {missed} without two pairs; no sigma stated")
    if len(err):
        rms = np.sqrt(np.mean(err ** 2, axis=0))
        print("  rms error f1, f2 [Hz], zeta1, zeta2: " + ", ".join(f"{v:.3e}" for v in rms))


def study(args):
    """The records of args through `okid identify --refine`: (errors, sigmas) as (records, 4)
    arrays of f1, f2, zeta1, zeta2, the warning counts and the outputs flagged not white."""
    truth = exact_modes(args)
    err, sig, flags = [], [], {"not_white": 0, "not_explained": 0, "sandwich": 0, "converged": 0,
                                "passes": [], "records": 0, "chose_innovation": 0, "input_correlated": 0,
                                "input_correlated_outputs": np.zeros(2, dtype=int), "reasons": {}, "mode_split": 0}
    outputs_flagged = np.zeros(2, dtype=int)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "record.csv")
        for k in range(args.records):
            header, data = record(args, k)
            np.savetxt(path, data, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
            run = subprocess.run([OKID, "identify", "--order", str(args.order), "--refine", "--refine-model", args.refine_model,
                                  "--max-passes", str(args.max_passes), "--json", path], capture_output=True, text=True)
            if run.returncode != 0:
                print(f"record {k}: exit {run.returncode}: {run.stderr.strip()}", file=sys.stderr)
                continue
            d = json.loads(run.stdout)
            flags["records"] += 1
            flags["passes"].append(d["refinement"]["passes"])
            flags["chose_innovation"] += d.get("refine_model_choice", {}).get("chosen") == "innovation"
            reason = d.get("refine_model_choice", {}).get("reason")
            if reason:
                flags["reasons"][reason] = flags["reasons"].get(reason, 0) + 1
            tests = d["refinement"]["residual_tests"]["outputs"]
            # OKID_W_RESIDUAL_INPUT_CORRELATED (1 << 13): counted before the modes, which order 2 lacks
            flags["input_correlated"] += bool(d["warning_bits"] & (1 << 13))
            flags["input_correlated_outputs"] += [bool(o["warning_bits"] & (1 << 13)) for o in tests]
            flags["mode_split"] += bool(d["warning_bits"] & (1 << 15))  # OKID_W_MODE_SPLIT
            pairs = [m for m in d["modes"] if m["is_pair"]][:2]
            if len(pairs) < 2:
                flags["not_white"] += bool(d["warning_bits"] & (1 << 9))
                flags["not_explained"] += bool(d["warning_bits"] & (1 << 10))
                flags["converged"] += d["refinement"]["state"] == "converged"
                outputs_flagged += [not o["white"] for o in tests]
                continue
            got = np.array([[m["frequency_hz"] for m in pairs], [m["damping_ratio"] for m in pairs]])
            sd = np.array([[m["frequency_std"] for m in pairs], [m["damping_std"] for m in pairs]])
            err.append((got - truth).ravel())
            sig.append(sd.ravel())
            outputs_flagged += [not o["white"] for o in tests]
            flags["not_white"] += bool(d["warning_bits"] & (1 << 9))
            flags["not_explained"] += bool(d["warning_bits"] & (1 << 10))
            flags["sandwich"] += d["std_covariance"] == "sandwich"
            flags["converged"] += d["refinement"]["state"] == "converged"
    return np.array(err), np.array(sig), flags, outputs_flagged


def main():
    args = parse()
    if args.method != "okid":
        return main_sippy(args)
    err, sig, flags, outputs_flagged = study(args)
    n = len(err)
    print(f"case {args.case}, refine_model {args.refine_model}: {n} records of {args.samples} samples at dt "
          f"{args.dt} s, noise {args.noise:g}"
          + (f", unmeasured force {args.unmeasured:g}" if args.case == "unmeasured" else ""))
    print(f"  converged {flags['converged']}, residual not white {flags['not_white']} (per output "
          f"{outputs_flagged.tolist()}), output not explained {flags['not_explained']}, sandwich stds {flags['sandwich']}")
    print(f"  residual correlated with the input {flags['input_correlated']} (per output "
          f"{flags['input_correlated_outputs'].tolist()})")
    print(f"  one mode split in two {flags['mode_split']}")
    if args.refine_model == "auto":
        print(f"  refine_model auto chose the innovation form in {flags['chose_innovation']} of {flags['records']}"
              f" (reasons {flags['reasons']})")
    print(f"  passes: median {np.median(flags['passes']):g}, largest {max(flags['passes'])} (max_passes {args.max_passes})")
    if n == 0:
        return
    print("  quantity  rms error   rms sigma   error/sigma  +-2 sigma coverage")
    for q, name in enumerate(["f1", "f2", "zeta1", "zeta2"]):
        rms_e, rms_s = np.sqrt(np.mean(err[:, q] ** 2)), np.sqrt(np.mean(sig[:, q] ** 2))
        cover = np.mean(np.abs(err[:, q]) <= 2 * sig[:, q])
        print(f"  {name:8s}  {rms_e:.3e}   {rms_s:.3e}   {rms_e / rms_s:9.2f}    {100 * cover:5.1f} %")
    print(f"  all four: +-2 sigma coverage {100 * np.mean(np.abs(err) <= 2 * sig):.1f} % of {err.size} checks")


if __name__ == "__main__":
    main()
