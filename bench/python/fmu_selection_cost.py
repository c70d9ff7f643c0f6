# SPDX-License-Identifier: Apache-2.0
"""What the identifier FMU's mode selection costs (docs/fmu.md): memory and time per identification.

The record of docs/quality.md section 8's newcomer case (`okid simulate --samples 10001 --noise 0.02
--seed 1`: the paper's plant, 2 % output noise) fed to the FMI 3 identifier through fmpy with
identify_every 200 (50 identifications), once with all_poles false (the stabilization table and
the selection after each identification) and once with all_poles true (the model's poles, as
before). fmpy's per-step overhead is the same in both runs, so their difference over the 50
identifications is the table and the selection. CPU seconds of this process (the FMU runs in it,
single-threaded), best of --repeat runs each. The memory is the
FMU's own logEvents line at initialization (the table's and the selection's bytes).

Output-only (num_inputs 0, okid identify --inputs 0's path): tests/python/test_ambient.py's
record (the paper's plant under unmeasured white forces, 40000 samples at 0.05 s, its mean
removed) with L = hankel_rows 20, fed once with identify_every 40000 (one identification) and
once with identify_every 200 (200); the difference over the 199 more identifications is the time
of one (identify, table and selection), the same fmpy steps in both.

    .venv/bin/python bench/python/fmu_selection_cost.py [--fmu build/fmu/fmi3/okid_identifier.fmu]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from fmu_runs import Slave  # noqa: E402

CONFIGS = [("paper: p 20, alpha = beta 20", dict(observer_order=20, hankel_rows=20, hankel_cols=20)),
           ("p 50, alpha = beta 100", dict(observer_order=50, hankel_rows=100, hankel_cols=100))]


def run(path, data, settings, output_only=False):
    """data: rows (t, force, acc1, acc2), or with output_only rows of y alone (num_inputs 0)."""
    log = []
    s = Slave(path, "identifier", logger=lambda st, cat, msg: log.append(msg)).instantiate(logging_on=True)
    if output_only:
        s.configure(num_inputs=0)
    s.set(**settings)
    s.initialize()
    dt = settings["dt"]
    start = time.process_time()  # CPU seconds of this process (the FMU runs in it): not the other jobs'
    for k in range(len(data)):
        if output_only:
            s.set_array("y", data[k])
        else:
            s.set_inputs(data[k, 1], data[k, 2:])
        s.step(k * dt, dt)
    elapsed = time.process_time() - start
    count, modes = s.get("identifications", "num_modes")
    s.close()
    return elapsed, count, modes, [m for m in log if m.startswith(("mode selection", "output-only"))]


def output_only_cost(path, repeat):
    from test_ambient import DT, ambient_record
    y = ambient_record()
    y = y - y.mean(axis=0)
    settings = dict(dt=DT, hankel_rows=20)
    best = {}
    for every in (len(y), 200):
        for _ in range(repeat):
            elapsed, count, modes, memory = run(path, y, {**settings, "identify_every": every}, output_only=True)
            if every not in best or elapsed < best[every][0]:
                best[every] = (elapsed, count, modes, memory)
    (once, n1, modes, memory), (often, n200, _, _) = best[len(y)], best[200]
    print("output-only, L 20 (m 2): " + "; ".join(memory))
    print(f"  {len(y)} steps: {once:.3f} s with {n1} identification ({modes} modes), {often:.3f} s with {n200}: "
          f"{1e3 * (often - once) / (n200 - n1):.2f} ms per identification (identify, table and selection)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default="build/fmu/fmi3/okid_identifier.fmu")
    parser.add_argument("--cli", default=os.environ.get("OKID_CLI", "build/host_tools/cli/okid"))
    parser.add_argument("--repeat", type=int, default=3)
    a = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "record.csv"
        subprocess.run([a.cli, "simulate", "--samples", "10001", "--noise", "0.02", "--seed", "1", "--output", str(csv)],
                       check=True)
        data = np.loadtxt(csv, delimiter=",", skiprows=1)
    for name, config in CONFIGS:
        settings = dict(dt=0.01, identify_every=200, **config)
        times = {}
        for all_poles in (False, True):
            best = None
            for _ in range(a.repeat):
                elapsed, count, modes, memory = run(a.fmu, data, {**settings, "all_poles": all_poles})
                best = elapsed if best is None else min(best, elapsed)
            times[all_poles] = (best, count, modes, memory)
        (sel, count, modes, memory), (raw, _, raw_modes, _) = times[False], times[True]
        print(f"{name}: {memory[0] if memory else 'no selection memory'}")
        print(f"  {count} identifications: {sel:.3f} s with the selection ({modes} modes), {raw:.3f} s with all_poles "
              f"({raw_modes} poles): {1e3 * (sel - raw) / count:.2f} ms per identification for the table and the selection")
    output_only_cost(a.fmu, a.repeat)


if __name__ == "__main__":
    main()
