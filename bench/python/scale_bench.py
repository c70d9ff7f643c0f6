# SPDX-License-Identifier: Apache-2.0
"""okid on large records against numpy OKID/ERA and mdof SRIM (issue 29), one BLAS thread, CPU time.

    .venv/bin/python bench/python/scale_bench.py [--repeats 3] [--quick] [--results bench/scale_results.json]

Cases, on the same data for every method (okid's simulator, okid.model, 2 % output noise of each
channel's RMS, white force):
- "5-DOF, 10 acc.": a 5-mass chain (record() below), 1 force on mass 1, two accelerometers
  on every mass (10 channels, independent noise), 100 000 samples at 0.01 s, p = 20, n = 10,
  20 x 20 Hankel (SRIM: horizon 20);
- "24-ch. fleet, p = 4" and "p = 20": the shape of the fleet's sizing record (docs/fleet.md): a
  lightly damped 24-mass chain, 1 force, 24 accelerometers, 10 minutes at 100 Hz, n = 48, 20 x 80
  Hankel (SRIM: horizon 20).
Prints one row per case and method: the median CPU time (time.process_time, the whole call: regressor
rows, fold, solve, ERA, modes) and the largest relative error of the frequencies and damping ratios
of the exact modes (each matched to the nearest identified frequency). okid runs with its defaults
(block_rows 0: the block size from w and the cache), with block_rows 32 (the old default) and with
the correlation-form estimator.
No number is asserted. --results keeps the table (key "markdown"), which bench_compare.py copies into
docs/benchmarks.md ("Large records"), as it does bench/stream_results.json.
"""
import os

# one BLAS thread for every method: set before numpy loads its BLAS
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import okid  # noqa: E402
from okid import model  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_compare import mdof_srim, numpy_okid_era  # noqa: E402


def record(masses_count, sensors_per_mass, samples, seed):
    """u (N, 1), y (N, masses_count * sensors_per_mass) and the exact (frequency [Hz], damping) pairs.
    A lightly damped chain between two walls: 1 kg masses, 4000 N/m springs, dampers 5e-4 s times
    the springs (stiffness-proportional: 0.8-3 % damping for 5 masses, 5.2-19 Hz; 0.2-3 % for 24,
    1.3-20 Hz), sampled at 100 Hz."""
    masses = np.ones(masses_count)
    springs = np.full(masses_count + 1, 4000.0)
    dampers = 5e-4 * springs
    m_, r_, k_ = model.chain_model(masses, dampers, springs)
    b2 = np.zeros((masses_count, 1))
    b2[0, 0] = 1
    sensors = np.vstack([np.eye(masses_count)] * sensors_per_mass)
    ac, bc, c, d = model.state_space(m_, r_, k_, b2, acceleration=sensors)
    a, b = model.discretize_zoh(ac, bc, 0.01)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    y, _ = model.simulate(a, b, c, d, u)
    y = y + 0.02 * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape)
    s = np.linalg.eigvals(ac)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    return u, y, np.abs(s) / (2 * np.pi), -s.real / np.abs(s)


def largest_error(found, exact_f, exact_z):
    """Largest relative error of frequency and damping over the exact modes, each matched to the
    nearest identified frequency (inf when nothing was identified)."""
    freq, zeta = (np.asarray(v, dtype=float) for v in found)
    if freq.size == 0:
        return float("inf")
    worst = 0.0
    for f, z in zip(exact_f, exact_z):
        i = int(np.argmin(np.abs(freq - f)))
        worst = max(worst, abs(freq[i] - f) / f, abs(zeta[i] - z) / z)
    return worst


def okid_modes(u, y, p, n, h, block_rows, estimator="least_squares"):
    res = okid.identify(u, y, 0.01, observer_order=p, order=n, hankel_rows=h[0], hankel_cols=h[1],
                        block_rows=block_rows, estimator=estimator)
    if res.warnings & okid.WarningFlag.CORRELATION_FALLBACK:
        print(f"(p = {p}: the correlation form fell back to the QR fold)", file=sys.stderr)
    pairs = [md for md in res.modes if md.is_pair]
    return [md.frequency_hz for md in pairs], [md.damping_ratio for md in pairs]


def timed(call, repeats):
    """(median CPU seconds, the last call's value)."""
    times, value = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        value = call()
        times.append(time.process_time() - t0)
    return statistics.median(times), value


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="calls per method (median CPU time)")
    parser.add_argument("--quick", action="store_true", help="a tenth of the samples (a smoke run)")
    parser.add_argument("--results", default=None, help="write the table here (JSON, key markdown)")
    a = parser.parse_args(argv)
    scale = 10 if a.quick else 1
    cases = [("5-DOF, 10 acc., 100 000 samples", 5, 2, 100_000 // scale, 20, 10, (20, 20)),
             ("24-ch. fleet record, p = 4", 24, 1, 60_000 // scale, 4, 48, (20, 80)),
             ("24-ch. fleet record, p = 20", 24, 1, 60_000 // scale, 20, 48, (20, 80))]
    lines = ["| case | method | CPU time [s] | largest relative error |", "|---|---|---|---|"]
    print("\n".join(lines))
    for name, masses, per_mass, samples, p, n, h in cases:
        u, y, exact_f, exact_z = record(masses, per_mass, samples, seed=1)
        methods = [("okid.identify (defaults: block_rows 0)", lambda: okid_modes(u, y, p, n, h, 0)),
                   ("okid.identify, block_rows 32 (the old default)", lambda: okid_modes(u, y, p, n, h, 32)),
                   ('okid.identify, estimator="correlation"', lambda: okid_modes(u, y, p, n, h, 0, "correlation")),
                   ("mdof SRIM (horizon 20)", lambda: mdof_srim(u, y, 0.01, 20, n)),
                   (f"numpy OKID/ERA (p = {p})", lambda: numpy_okid_era(u, y, 0.01, p, max(h), n))]
        for label, call in methods:
            try:
                seconds, found = timed(call, a.repeats)
                lines.append(f"| {name} | {label} | {seconds:.3f} | {largest_error(found, exact_f, exact_z):.2g} |")
            except Exception as exc:  # a peer that fails on a case is reported, not fatal
                lines.append(f"| {name} | {label} | failed: {type(exc).__name__}: {exc} | |")
            print(lines[-1], flush=True)
    if a.results:
        header = ["## Large records (issue 29)", "",
                  f"`.venv/bin/python bench/python/scale_bench.py` on {platform.processor() or platform.machine()}, "
                  f"{os.cpu_count()} cores, one BLAS thread, median CPU time of {a.repeats} calls "
                  "(the whole identification; the script's docstring describes the cases).", ""]
        with open(a.results, "w") as f:
            json.dump({"markdown": header + lines + [""]}, f, indent=1)
            f.write("\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
