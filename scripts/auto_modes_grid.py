#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The grid of issue 23's acceptance for `okid identify` with nothing but the channel counts:
the four real records of tests/data/real against tests/data/real_consensus.json and the simulated
newcomer case (the paper's plant, 10001 samples, 2 % output noise, seeds 1-5, no --order) against
its exact modes, and a 3-mass chain with velocity sensors at 5 % noise (seeds 1-3) against its
closed-form modes. Prints one line per case: what was reported, what was missed, what was extra.

    .venv/bin/python scripts/auto_modes_grid.py [--okid build/host_tools/cli/okid] [--data DIR]
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "reference"))
from make_reference import chain  # noqa: E402  (M, R, K of the chain, written from the paper's equations)
TOL = 0.02  # the acceptance: every consensus mode within 2 %
CHAIN = ["--masses", "1,1,1", "--dampers", "0.1,0.1,0.1,0", "--springs", "100,80,60,0", "--force-dof", "2",
         "--sensing", "velocity", "--samples", "3000", "--noise", "0.05"]


def chain_hz(masses, dampers, springs):
    """Frequencies [Hz] of masses in a chain between two walls (okid simulate's model), closed form."""
    mass, damping, stiffness = chain(masses, dampers, springs)
    n = len(masses)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(mass, stiffness), -np.linalg.solve(mass, damping)]])
    s = np.linalg.eigvals(a)
    return sorted(np.abs(s[s.imag > 0]) / (2 * np.pi))


PAPER_HZ = chain_hz([2, 3], [2, 4, 3], [20, 40, 30])  # the paper's plant
CHAIN_HZ = chain_hz([1, 1, 1], [0.1, 0.1, 0.1, 0], [100, 80, 60, 0])


def identify(okid, path, *args):
    out = subprocess.run([okid, "identify", "--json", *args, str(path)], capture_output=True, text=True, timeout=300)
    if out.returncode != 0:
        return None, out.stderr.strip().splitlines()[-1:]
    return json.loads(out.stdout), None


def verdict(want, modes):
    got = [m["frequency_hz"] for m in modes]
    missed = [w for w in want if not any(abs(g - w) <= TOL * w for g in got)]
    extra = [g for g in got if not any(abs(g - w) <= TOL * w for w in want)]
    return missed, extra


def line(name, res, err, want):
    if res is None:
        return f"{name:22s} FAILED {err}", False
    modes = res["modes"]
    missed, extra = verdict(want, modes)
    c = res["chosen"]
    settings = f"K {c['decimation']['value']}, p {c['observer_order']['value']}, a {c['hankel_rows']['value']}"
    rep = ", ".join(f"{m['frequency_hz']:.3f} ({m['damping_ratio']:.3f})" for m in modes) or "none"
    ok = not missed and not extra
    text = f"{name:22s} {'ok  ' if ok else 'MISS'} [{settings}] {rep}"
    if missed:
        text += "; missed " + ", ".join(f"{w:.3f}" for w in missed)
    if extra:
        text += "; extra " + ", ".join(f"{g:.3f}" for g in extra)
    return text, ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--okid", default=str(ROOT / "build" / "host_tools" / "cli" / "okid"))
    ap.add_argument("--data", default=str(ROOT / "tests" / "data" / "real"))
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args()
    consensus = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())["records"]
    passed = total = 0
    for stem in sorted(consensus):
        rec = consensus[stem]
        res, err = identify(args.okid, pathlib.Path(args.data) / (stem + ".csv"), "--inputs", str(rec["inputs"]),
                            "--outputs", str(rec["outputs"]))
        text, ok = line(stem, res, err, [m["frequency_hz"] for m in rec["modes"]])
        print(text, flush=True)
        passed, total = passed + ok, total + 1
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.seeds + 1):
            path = pathlib.Path(tmp) / f"paper_{seed}.csv"
            subprocess.run([args.okid, "simulate", "--samples", "10001", "--noise", "0.02", "--seed", str(seed),
                            "--output", str(path)], check=True)
            res, err = identify(args.okid, path)
            text, ok = line(f"newcomer seed {seed}", res, err, PAPER_HZ)
            print(text, flush=True)
            passed, total = passed + ok, total + 1
        for seed in range(1, 4):
            path = pathlib.Path(tmp) / f"chain_{seed}.csv"
            subprocess.run([args.okid, "simulate", *CHAIN, "--seed", str(seed), "--output", str(path)], check=True)
            res, err = identify(args.okid, path)
            text, ok = line(f"chain 5 % seed {seed}", res, err, CHAIN_HZ)
            print(text, flush=True)
            passed, total = passed + ok, total + 1
    print(f"{passed} of {total} cases exact")
    return 0


if __name__ == "__main__":
    sys.exit(main())
