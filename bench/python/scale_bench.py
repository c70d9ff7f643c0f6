# SPDX-License-Identifier: Apache-2.0
"""okid on small and large records against mdof SRIM, numpy OKID/ERA, python-control and SIPPY
(issue 29), one BLAS thread, CPU time, and the fold's rate against the same run's DGEMM.

    .venv/bin/python bench/python/scale_bench.py [--repeats 3] [--seeds 10] [--quick] [--results bench/scale_results.json]

Cases, on the same data for every method (okid.model's simulation, white force, output noise as a
fraction of each channel's RMS):
- "paper, noise-free": the paper's 2-DOF system (okid.model.paper_system), 1 force, 2 accelerometers,
  1001 samples at 0.01 s, p = 20, n = 4, 20 x 20 Hankel (the paper case of docs/benchmarks.md);
- "5 % noise": the same system at 0.05 s, 2001 samples, 5 % noise, p = 20, n = 4, 40 x 40 Hankel;
- "5-DOF, 10 acc.": a 5-mass chain (record() below), 1 force on mass 1, two accelerometers
  on every mass (10 channels, independent noise), 100 000 samples at 0.01 s, p = 20, n = 10,
  20 x 20 Hankel;
- "24-ch. lightly damped": fleet_bench.py --lightly-damped's record (24-mass chain, modes 1.26-20 Hz,
  damping 0.19-3 %, 24 accelerometers, 2 % noise, 60 000 samples at 0.01 s), n = 48, at the
  cheapest settings found to recover all its modes (LIGHT below; docs/benchmarks.md says how).
Peers get the same model order; mdof SRIM a horizon of the Hankel's block rows, python-control
markov + eigensys_realization with the Hankel's sizes, SIPPY N4SID with past = future horizon F.
Prints one row per case and method: the median CPU time (time.process_time, the whole call) and the
largest relative error of the frequencies and damping ratios of the exact modes (each matched to the
nearest identified frequency). A method whose first call takes over 10 s runs once; one under 20 ms
is timed in batches (timed()). Then the accuracy of okid, SRIM and python-control over --seeds
records of each noisy case (seed_spread()), and
build/bench/okid_fold_rate_bench (when built) for q = 61, 221, 501 at 50 000 samples.
No number is asserted. --results keeps the tables (key "markdown") for docs/benchmarks.md
("Large records").
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
from pathlib import Path  # noqa: E402

import subprocess  # noqa: E402

import numpy as np  # noqa: E402

import okid  # noqa: E402
from okid import model  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_compare import era_A, mdof_srim, modal, numpy_okid_markov, sippy_subspace  # noqa: E402
from fleet_bench import _chain_record  # noqa: E402
from cpu_timing import timed  # noqa: E402

#: the 24-channel record's settings: the cheapest found that recover all 24 modes (docs/benchmarks.md)
LIGHT = dict(p=20, h=(20, 300))


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


def paper_record(dt, samples, noise, seed):
    """The paper's 2-DOF system (okid.model.paper_system), white force, noise on both outputs."""
    a, b, c, d = model.paper_system(dt)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    y, _ = model.simulate(a, b, c, d, u)
    y = y + noise * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape)
    ac = model._paper_continuous()[0]
    s = np.linalg.eigvals(ac)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    return u, y, np.abs(s) / (2 * np.pi), -s.real / np.abs(s)


def light_record(samples, seed=1):
    """fleet_bench.py --lightly-damped's record (seed 1): (u, y, exact frequencies [Hz], damping ratios)."""
    springs = np.full(25, 3969.0)
    u, y, ac = _chain_record(np.ones(24), 4.77e-4 * springs, springs, samples, seed)
    s = np.linalg.eigvals(ac)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    return u, y, np.abs(s) / (2 * np.pi), -s.real / np.abs(s)


def numpy_okid_era_rect(u, y, dt, p, h, n):
    """numpy OKID, then ERA with an alpha x beta Hankel."""
    return modal(era_A(numpy_okid_markov(u, y, p, h[0] + h[1] + 1), h[0], h[1], n), dt)


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


_FELL_BACK = set()


def okid_modes(u, y, dt, p, n, h, block_rows, estimator="least_squares"):
    res = okid.identify(u, y, dt, observer_order=p, order=n, hankel_rows=h[0], hankel_cols=h[1],
                        block_rows=block_rows, estimator=estimator)
    if res.warnings & okid.WarningFlag.CORRELATION_FALLBACK and p not in _FELL_BACK:
        _FELL_BACK.add(p)  # said once, not at every timed call
        print(f"(p = {p}: the correlation form fell back to the QR fold)", file=sys.stderr)
    pairs = [md for md in res.modes if md.is_pair]
    return [md.frequency_hz for md in pairs], [md.damping_ratio for md in pairs]


def control_era_rect(u, y, dt, m, h, n):
    """python-control: markov (m Markov parameters by least squares), then ERA with an h[0] x h[1] Hankel."""
    import control
    H = control.markov(y.T, u.T, m)
    sys_, _ = control.eigensys_realization(H, n, m=h[0], n=h[1], dt=dt)
    return modal(sys_.A, dt)


def fold_rate(samples):
    """okid_fold_rate_bench's table (one BLAS thread), or a line saying it is not built."""
    bench = Path(__file__).resolve().parents[2] / "build" / "bench" / "okid_fold_rate_bench"
    if not bench.exists():
        return [f"({bench} not built: no fold rate)"]
    out = subprocess.run([str(bench), str(samples)], capture_output=True, text=True, env=dict(os.environ))
    return [f"`OPENBLAS_NUM_THREADS=1 build/bench/okid_fold_rate_bench {samples}` (the same run):", ""] \
        + out.stdout.strip().splitlines()


def seed_spread(cases, seeds):
    """The accuracy over seeds 1..seeds of each case (one record says little: the paper case at 5 %
    noise ranks SRIM first on seed 1): per method the median and the worst of the largest relative
    error. okid's QR fold and correlation form give the same estimates (the tables' digits), so
    okid runs once, as the correlation form; SIPPY is left out (its horizon fails on the 24-channel
    record and it is the slowest by 20x)."""
    lines = [f"Accuracy over seeds 1-{seeds} (the largest relative error of a record; median, worst):", "",
             "| case | okid (correlation) | mdof SRIM | python-control |", "|---|---|---|---|"]
    for name, make, dt, p, n, h, _ in cases:
        errors = {"okid": [], "srim": [], "control": []}
        for seed in range(1, seeds + 1):
            u, y, exact_f, exact_z = make(seed)
            for key, call in (("okid", lambda: okid_modes(u, y, dt, p, n, h, 0, "correlation")),
                              ("srim", lambda: mdof_srim(u, y, dt, h[0], n)),
                              ("control", lambda: control_era_rect(u, y, dt, sum(h) + 1, h, n))):
                try:
                    errors[key].append(largest_error(call(), exact_f, exact_z))
                except Exception:  # a peer that fails on a seed counts as no identification
                    errors[key].append(float("inf"))
        cells = [f"{statistics.median(v):.2g}, {max(v):.2g}" for v in errors.values()]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="calls per method (median CPU time)")
    parser.add_argument("--quick", action="store_true", help="a tenth of the samples (a smoke run)")
    parser.add_argument("--results", default=None, help="write the table here (JSON, key markdown)")
    parser.add_argument("--seeds", type=int, default=10, help="records per case of the accuracy table (0: none)")
    a = parser.parse_args(argv)
    scale = 10 if a.quick else 1
    # (name, record of a seed, p, n, Hankel blocks, SIPPY's horizon)
    cases = [("paper, noise-free", lambda seed: paper_record(0.01, 1001, 0.0, seed), 0.01, 20, 4, (20, 20), 20),
             ("dt 0.05 s, 5 % noise", lambda seed: paper_record(0.05, 2001, 0.05, seed), 0.05, 20, 4, (40, 40), 20),
             ("5-DOF, 10 acc., 100 000 samples", lambda seed: record(5, 2, 100_000 // scale, seed), 0.01, 20, 10,
              (20, 20), 10),
             ("24-ch. lightly damped, 60 000 samples", lambda seed: light_record(60_000 // scale, seed), 0.01,
              LIGHT["p"], 48, LIGHT["h"], 10)]
    lines = ["| case | method | CPU time [s] | largest relative error |", "|---|---|---|---|"]
    print("\n".join(lines))
    for name, make, dt, p, n, h, f in cases:
        u, y, exact_f, exact_z = make(1)
        methods = [("okid.identify (defaults: block_rows 0)", lambda: okid_modes(u, y, dt, p, n, h, 0)),
                   ('okid.identify, estimator="correlation"', lambda: okid_modes(u, y, dt, p, n, h, 0, "correlation")),
                   (f"mdof SRIM (horizon {h[0]})", lambda: mdof_srim(u, y, dt, h[0], n)),
                   (f"numpy OKID/ERA (p = {p})", lambda: numpy_okid_era_rect(u, y, dt, p, h, n)),
                   (f"python-control (markov {sum(h) + 1}, ERA {h[0]} x {h[1]})",
                    lambda: control_era_rect(u, y, dt, sum(h) + 1, h, n)),
                   (f"SIPPY N4SID (horizon {f})", lambda: sippy_subspace(u, y, dt, "N4SID", f, n))]
        for label, call in methods:
            try:
                seconds, found = timed(call, a.repeats)
                lines.append(f"| {name} | {label} | {seconds:.3g} | {largest_error(found, exact_f, exact_z):.2g} |")
            except Exception as exc:  # a peer that fails on a case is reported, not fatal
                lines.append(f"| {name} | {label} | failed: {type(exc).__name__}: {exc} | |")
            print(lines[-1], flush=True)
    spread = seed_spread(cases[1:], a.seeds) if a.seeds > 0 else []
    fold = fold_rate(50_000 // scale)
    print("\n".join(fold))
    if a.results:
        header = ["## Large records (issue 29)", "",
                  f"`.venv/bin/python bench/python/scale_bench.py` on {platform.processor() or platform.machine()}, "
                  f"{os.cpu_count()} cores, one BLAS thread, median CPU time of {a.repeats} calls (of batches "
                  "of calls under 20 ms; the whole identification; the script's docstring describes the "
                  "cases).", ""]
        with open(a.results, "w") as f:
            json.dump({"markdown": header + lines + [""] + spread + [""] + fold + [""]}, f, indent=1)
            f.write("\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
