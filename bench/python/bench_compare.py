# SPDX-License-Identifier: Apache-2.0
"""Side-by-side benchmark: okid (CLI, C API and the Python package) against a plain numpy/scipy
OKID/ERA, mdof (OKID + ERA, SRIM) and python-control (markov + eigensys_realization), on identical
data made by okid's simulator, plus okid's C speed benchmark with the reference BLAS and with
OpenBLAS, the Python package's overhead and speed-up on the paper and the 5 % case, and every
method's RMS error as a multiple of the Cramer-Rao bound (okid crlb) against okid --refine,
SIPPY's subspace methods (N4SID, MOESP, CVA, PARSIM-K) and nfoursid.

    .venv/bin/python bench/python/bench_compare.py [--quick] [--build build] [--out docs] [--python-only]
        [--crlb-only] [--crlb-seeds N]        (scripts/bench.sh runs it after a build)

Writes docs/benchmarks.md, docs/img/benchmark.png and bench/results.json (--python-only: only the
Python figures, into the existing files).
"""
import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import okid

# the numpy/scipy oracle of the tests (tests/python/reference.py), independent of the C code
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from reference import paper_reference  # noqa: E402

ARCH_LIB = Path("/usr/lib/x86_64-linux-gnu")
BLAS_DIRS = {"reference": [ARCH_LIB / "blas", ARCH_LIB / "lapack"], "OpenBLAS": [ARCH_LIB / "openblas-pthread"]}

# Data sets: (name, dt, samples, output noise as a fraction of each channel's RMS).
CASES = [("paper, noise-free", 0.01, 1001, 0.0), ("paper dt, 2 % noise", 0.01, 1001, 0.02),
         ("dt 0.05 s, 100 s, 2 % noise", 0.05, 2001, 0.02), ("dt 0.05 s, 100 s, 5 % noise", 0.05, 2001, 0.05)]

# Parameter grids, tuned per case on a tuning seed (the best of the grid is then run on fresh seeds).
# The most accurate setting wins; among settings within 1.5x of its error (or below 1e-9), the fastest.
# okid and the numpy OKID/ERA get the same grid; the Hankel span reaches one period of the slowest
# mode at the paper's dt (h = 100), which noisy oversampled data needs (docs/design.md, numerical decisions).
OKID_GRID = [dict(p=p, h=h) for p in (2, 5, 10, 20, 40, 60, 80, 100) for h in (10, 20, 40, 60, 100)]
# okid's options of docs/quality.md: decimation (k: --decimation) and the instrumental-variable
# estimator (iv: --estimator instrumental); p and h then count decimated samples.
DECIMATED_GRID = [dict(p=p, h=h, k=k) for k in (2, 5, 10) for p in (2, 5, 10, 20, 40) for h in (10, 20, 40, 60)]
GRIDS = {
    "okid (CLI)": OKID_GRID,
    "okid + decimation": DECIMATED_GRID,
    "okid + IV": [dict(g, iv=1) for g in OKID_GRID],
    "okid + decimation + IV": [dict(g, iv=1) for g in DECIMATED_GRID],
    "numpy OKID/ERA": OKID_GRID,
    "mdof OKID+ERA": [dict(m=m, h=h) for m in (60, 120, 200, 300) for h in (10, 20, 40, 60)],
    "mdof SRIM": [dict(h=h) for h in (5, 10, 20, 40, 60)],
    "python-control": [dict(m=m, h=h) for m in (60, 120, 200, 300) for h in (10, 20, 40, 60)],
}

# Accuracy at the physical limit (docs/refinement.md): the two configurations, each method's
# RMS error over the seeds divided by the RMS Cramer-Rao bound of the same records (okid crlb).
CRLB_CASES = [("dt 0.05 s, 2001 samples, 5 % noise", 0.05, 2001, 0.05),
              ("dt 0.01 s, 10001 samples, 2 % noise", 0.01, 10001, 0.02)]
SUBSPACE_GRID = [dict(f=f) for f in (10, 20, 40)]
CRLB_GRIDS = {
    "okid (CLI)": [dict(p=p, h=h) for p in (10, 20, 40, 80) for h in (20, 50, 100)],
    "okid --refine": [dict()],  # the newcomer's call: no horizons, the start is chosen from the data
    "SIPPY N4SID": SUBSPACE_GRID, "SIPPY MOESP": SUBSPACE_GRID, "SIPPY CVA": SUBSPACE_GRID,
    "SIPPY PARSIM-K": SUBSPACE_GRID, "nfoursid": SUBSPACE_GRID,
}

# Every method's time is the fastest of a few calls on the same data (at most PEER_REPEATS, and no
# more once TIME_BUDGET seconds are spent), then the median over the evaluation seeds; okid's C API
# figure is the fastest of 20 identifications inside the process (okid identify --timing --repeat 20).
PEER_REPEATS, TIME_BUDGET = 5, 0.5

# Relative errors below this are round-off for every method (noise-free data): they count as equal.
ROUND_OFF = 1e-9


def modal(A, dt):
    """Frequencies [Hz] and damping ratios of the complex pairs of A, by frequency."""
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag > 1e-12]
    s = np.log(lam) / dt
    order = np.argsort(np.abs(s))
    return np.abs(s[order]) / (2 * np.pi), -s[order].real / np.abs(s[order])


def era_A(Y, alpha, beta, n):
    """ERA (eq. 57-61, Juang's form) from Markov parameters Y[k] (m x r), k = 0 .. alpha + beta."""
    m, r = Y[1].shape
    H0 = np.block([[Y[i + j + 1] for j in range(beta)] for i in range(alpha)])
    H1 = np.block([[Y[i + j + 2] for j in range(beta)] for i in range(alpha)])
    U, S, Vt = np.linalg.svd(H0, full_matrices=False)
    Sr = np.diag(S[:n] ** -0.5)
    return Sr @ U[:, :n].T @ H1 @ Vt[:n].T @ Sr


def numpy_okid_markov(u, y, p, count):
    """OKID (eq. 49-51) by numpy least squares: Markov parameters Y_0 .. Y_count, written here from the
    paper's equations."""
    N, r = u.shape
    m = y.shape[1]
    v = np.hstack([u, y])
    Phi = np.hstack([u[p:]] + [v[p - i:N - i] for i in range(1, p + 1)])
    X = np.linalg.lstsq(Phi, y[p:], rcond=None)[0].T
    D = X[:, :r]
    Y1 = [X[:, r + (i - 1) * (r + m): r + (i - 1) * (r + m) + r] for i in range(1, p + 1)]
    G = [X[:, r + (i - 1) * (r + m) + r: r + i * (r + m)] for i in range(1, p + 1)]
    Y = [D]
    for k in range(1, count + 1):
        Yk = Y1[k - 1].copy() if k <= p else np.zeros((m, r))
        for i in range(1, min(k, p) + 1):
            Yk += G[i - 1] @ Y[k - i]
        Y.append(Yk)
    return Y


def numpy_okid_era(u, y, dt, p, h, n=4):
    """numpy OKID, then ERA."""
    return modal(era_A(numpy_okid_markov(u, y, p, 2 * h + 1), h, h, n), dt)


def mdof_okid_era(u, y, dt, m, h, n=4):
    import mdof.markov
    import mdof.realize
    Y = mdof.markov.okid(u.T, y.T, m=m)
    A = mdof.realize.era(Y, horizon=h, nc=h, order=n)[0]
    return modal(A, dt)


def mdof_srim(u, y, dt, h, n=4):
    import mdof.realize
    A = mdof.realize.srim(u.T, y.T, horizon=h, order=n, find="AC", threads=1)[0]
    return modal(A, dt)


def control_era(u, y, dt, m, h, n=4):
    import control
    H = control.markov(y.T, u.T, m)
    sys_, _ = control.eigensys_realization(H, n, m=h, n=h, dt=dt)
    return modal(sys_.A, dt)


def sippy_subspace(u, y, dt, method, f, n=4):
    """SIPPY (sippy-unipi): past and future horizons f, fixed order n, with feedthrough."""
    from sippy_unipi import system_identification
    sys_ = system_identification(y.T, u.T, method, SS_fixed_order=n, SS_f=f, SS_p=f, SS_D_required=True, tsample=dt)
    return modal(sys_.A, dt)


def nfoursid_subspace(u, y, dt, f, n=4):
    """nfoursid's N4SID with f block rows."""
    import pandas as pd
    from nfoursid.nfoursid import NFourSID
    columns = [f"u{i}" for i in range(u.shape[1])] + [f"y{i}" for i in range(y.shape[1])]
    frame = pd.DataFrame(np.hstack([u, y]), columns=columns)
    n4 = NFourSID(frame, output_columns=columns[u.shape[1]:], input_columns=columns[:u.shape[1]], num_block_rows=f)
    n4.subspace_identification()
    state_space, _ = n4.system_identification(rank=n)
    return modal(state_space.a, dt)


def okid_refine(cli, path):
    """okid identify --refine with nothing else but the order: the refined modes."""
    out = subprocess.run([cli, "identify", "--json", "--order", "4", "--refine", path], capture_output=True, text=True,
                         env=best_blas_env())
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    modes = [mm for mm in json.loads(out.stdout)["refinement"]["modes"] if mm["is_pair"]]
    return np.array([mm["frequency_hz"] for mm in modes]), np.array([mm["damping_ratio"] for mm in modes])


def okid_crlb(cli, dt, samples, noise, seed):
    """The bound (std of f1, f2, zeta1, zeta2) of the record okid simulate writes with these options."""
    out = subprocess.run([cli, "crlb", "--dt", str(dt), "--samples", str(samples), "--noise", str(noise), "--seed",
                          str(seed)], capture_output=True, text=True, check=True)
    rows = [line.split(",") for line in out.stdout.splitlines() if line[:1].isdigit()]
    return np.array([float(rows[0][2]), float(rows[1][2]), float(rows[0][4]), float(rows[1][4])])


def signed_errors(result, ref):
    """f1, f2, zeta1, zeta2 minus the exact values; inf when the method did not return two pairs."""
    freq, zeta = result
    if len(freq) != 2:
        return np.full(4, np.inf)
    exact = [m.frequency_hz for m in ref.modes] + [m.damping_ratio for m in ref.modes]
    return np.array([freq[0], freq[1], zeta[0], zeta[1]]) - np.array(exact)


def crlb_method(name, params, cli, path, u, y, dt):
    """One identification of the CRLB comparison and its seconds (okid: the whole CLI process)."""
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "okid (CLI)":
            result = okid_cli(cli, path, dt, params)[0]
        elif name == "okid --refine":
            result = okid_refine(cli, path)
        elif name == "nfoursid":
            result = nfoursid_subspace(u, y, dt, params["f"])
        else:
            result = sippy_subspace(u, y, dt, name.split()[1], params["f"])
    return result, time.perf_counter() - t0


def crlb_compare(cli, quick, seeds_count):
    """Each method tuned on seed 1 (least sum of squared error/bound), then run on fresh seeds."""
    seeds = list(range(11, 11 + (3 if quick else seeds_count)))
    rows = []
    for case, dt, samples, noise in CRLB_CASES[:1] if quick else CRLB_CASES:
        ref = paper_reference(dt)
        bounds = {seed: okid_crlb(cli, dt, samples, noise, seed) for seed in [1] + seeds}
        crlb = np.sqrt(np.mean([bounds[s] ** 2 for s in seeds], axis=0))
        rows.append(dict(case=case, method="Cramer-Rao bound", params={}, rms=crlb.tolist(), ratio=[1.0] * 4,
                         seconds=None))
        tune_path, tu, ty = simulate(cli, dt, samples, noise, seed=1)
        for name, grid in CRLB_GRIDS.items():
            scored = []
            for params in grid[::3] if quick else grid:
                try:
                    result, seconds = crlb_method(name, params, cli, tune_path, tu, ty, dt)
                    scored.append((float(np.sum((signed_errors(result, ref) / bounds[1]) ** 2)), seconds, params))
                except Exception:  # a setting a method cannot run is simply not chosen
                    pass
            finite = [t for t in scored if np.isfinite(t[0])]
            best = min(finite, key=lambda t: t[0])[2] if finite else grid[0]
            errs, times = [], []
            for seed in seeds:
                path, u, y = simulate(cli, dt, samples, noise, seed)
                try:
                    result, seconds = crlb_method(name, best, cli, path, u, y, dt)
                    errs.append(signed_errors(result, ref))
                    times.append(seconds)
                except Exception:
                    errs.append(np.full(4, np.inf))
                os.unlink(path)
            rms = np.sqrt(np.mean(np.square(errs), axis=0))
            rows.append(dict(case=case, method=name, params=best, rms=rms.tolist(), ratio=(rms / crlb).tolist(),
                             seconds=float(np.median(times)) if times else None))
            print(f"{case:38s} {name:16s} " + " ".join(f"{x:6.2f}" for x in rms / crlb) +
                  (f"  {np.median(times):.3f} s" if times else "") + f"  {best}", flush=True)
        os.unlink(tune_path)
    return rows, len(seeds)


def crlb_markdown(rows, seeds):
    lines = ["## RMS error as a multiple of the Cramer-Rao bound", "",
             f"The paper's system, white force, {seeds} seeds per configuration; each method tuned on a separate "
             "seed (least sum of squared error/bound over the grid: okid p and h, the subspace methods' horizon f), "
             "then run on the seeds. The bound is `okid crlb` of the same records (the RMS over the seeds); "
             "`okid --refine` is called with `--order 4` and nothing else. Seconds: the median per "
             "identification (okid: the whole CLI process; Python peers: the call on arrays). "
             "Method: [refinement.md](refinement.md).", "",
             "| data | method | parameters | f1 | f2 | zeta1 | zeta2 | seconds |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        params = ", ".join(f"{k}={v}" for k, v in (r["params"] or {}).items())
        if r["method"] == "Cramer-Rao bound":
            cells = " | ".join(f"{x:.2e}" for x in r["rms"])
            lines.append(f"| {r['case']} | **bound** (std) | | {cells} | |")
        else:
            cells = " | ".join(f"{x:.2f}x" if np.isfinite(x) else "failed" for x in r["ratio"])
            seconds = f"{r['seconds']:.3f}" if r["seconds"] is not None else ""
            lines.append(f"| {r['case']} | {r['method']} | {params} | {cells} | {seconds} |")
    return lines


def best_blas_env():
    """The environment that runs okid with OpenBLAS (one thread) when it is installed: numpy, hence
    every Python peer, runs on the OpenBLAS it bundles, so okid gets the same BLAS."""
    dirs = BLAS_DIRS["OpenBLAS"]
    if not all(d.exists() for d in dirs):
        return None
    return dict(os.environ, LD_LIBRARY_PATH=":".join(map(str, dirs)), OPENBLAS_NUM_THREADS="1")


def simulate(cli, dt, samples, noise, seed):
    with tempfile.NamedTemporaryFile(suffix=".csv", delete=False) as f:
        path = f.name
    subprocess.run([cli, "simulate", "--dt", str(dt), "--samples", str(samples), "--noise", str(noise), "--seed",
                    str(seed), "--output", path], check=True)
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return path, data[:, 1:2], data[:, 2:]


def okid_cli(cli, path, dt, params, timing=False, repeat=20):
    h = str(params["h"])
    args = [cli, "identify", "--json", "--order", "4", "--observer-order", str(params["p"]), "--hankel-rows", h,
            "--hankel-cols", h, "--zero-initial-state", path]
    if params.get("k", 1) > 1:
        args[2:2] = ["--decimation", str(params["k"])]
    if params.get("iv"):
        args[2:2] = ["--estimator", "instrumental"]
    if timing:
        args[2:2] = ["--timing", "--repeat", str(repeat)]
    t0 = time.perf_counter()
    out = subprocess.run(args, capture_output=True, text=True, env=best_blas_env())
    wall = time.perf_counter() - t0
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    res = json.loads(out.stdout)
    freq = np.array([mm["frequency_hz"] for mm in res["modes"] if mm["is_pair"]])
    zeta = np.array([mm["damping_ratio"] for mm in res["modes"] if mm["is_pair"]])
    return (freq, zeta), wall, res.get("elapsed_seconds")


def okid_python(u, y, dt, params):
    """okid in-process through the Python package, with the CLI's settings for params."""
    res = okid.identify(u, y, dt, observer_order=params["p"], order=4, hankel_rows=params["h"],
                        hankel_cols=params["h"], zero_initial_state=1, decimation=params.get("k", 1),
                        estimator="instrumental" if params.get("iv") else "least_squares")
    pairs = [md for md in res.modes if md.is_pair]
    return np.array([md.frequency_hz for md in pairs]), np.array([md.damping_ratio for md in pairs])


def errors(result, ref):
    freq, zeta = result
    if len(freq) != len(ref.modes):
        return np.inf, np.inf
    f_err = max(abs(f - m.frequency_hz) / m.frequency_hz for f, m in zip(freq, ref.modes))
    z_err = max(abs(z - m.damping_ratio) / m.damping_ratio for z, m in zip(zeta, ref.modes))
    return f_err, z_err


def call_method(name, params, cli, path, u, y, dt, in_process=False):
    """One identification: (frequencies, damping ratios) and the seconds it took (okid with in_process:
    the C API's time inside the CLI process, without the process start and the CSV parsing)."""
    t0 = time.perf_counter()
    if name.startswith("okid") and in_process:  # the C core in this process, through the Python package
        return okid_python(u, y, dt, params), time.perf_counter() - t0
    if name.startswith("okid"):
        result, wall, _ = okid_cli(cli, path, dt, params)
        return result, wall
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "numpy OKID/ERA":
            result = numpy_okid_era(u, y, dt, params["p"], params["h"])
        elif name == "mdof OKID+ERA":
            result = mdof_okid_era(u, y, dt, params["m"], params["h"])
        elif name == "mdof SRIM":
            result = mdof_srim(u, y, dt, params["h"])
        else:
            result = control_era(u, y, dt, params["m"], params["h"])
    return result, time.perf_counter() - t0


def run_method(name, params, cli, path, u, y, dt, repeats=1, in_process=False):
    """The result and the fastest of up to `repeats` calls (fewer once TIME_BUDGET is spent)."""
    result, best = call_method(name, params, cli, path, u, y, dt, in_process)
    spent = best
    for _ in range(repeats - 1):
        if spent > TIME_BUDGET:
            break
        _, seconds = call_method(name, params, cli, path, u, y, dt, in_process)
        best, spent = min(best, seconds), spent + seconds
    return result, best


def compare(cli, quick):
    seeds = [11, 12] if quick else [11, 12, 13, 14, 15]
    rows = []
    for case, dt, samples, noise in CASES[:2] if quick else CASES:
        ref = paper_reference(dt)
        tune_path, tu, ty = simulate(cli, dt, samples, noise, seed=1)
        for name, grid in GRIDS.items():
            tried = []
            for params in (grid[::4] if quick else grid):  # tuning on seed 1
                try:
                    # okid is tuned on its in-process time: a process start would drown sub-ms differences
                    result, seconds = run_method(name, params, cli, tune_path, tu, ty, dt, in_process=True)
                    tried.append((max(errors(result, ref)), seconds, params))
                except Exception:  # a setting a method cannot run is simply not chosen
                    pass
            finite = [t for t in tried if np.isfinite(t[0])]
            best = None
            if finite:
                best_err = min(t[0] for t in finite)
                good = [t for t in finite if t[0] <= max(1.5 * best_err, ROUND_OFF)]
                best = min(good, key=lambda t: t[1])[2]
            best = best or grid[0]
            f_errs, z_errs, times = [], [], []
            for seed in seeds:  # evaluation on fresh data
                path, u, y = simulate(cli, dt, samples, noise, seed)
                try:
                    result, seconds = run_method(name, best, cli, path, u, y, dt, PEER_REPEATS)
                    f, z = errors(result, ref)
                except Exception:
                    f, z, seconds = np.inf, np.inf, np.nan
                f_errs.append(f), z_errs.append(z), times.append(seconds)
                os.unlink(path)
            rows.append(dict(case=case, method=name, params=best, freq_error=float(np.mean(f_errs)),
                             damping_error=float(np.mean(z_errs)), seconds=float(np.nanmedian(times)),
                             freq_errors=[float(e) for e in f_errs], damping_errors=[float(e) for e in z_errs]))
            if name.startswith("okid"):  # the same settings through the C API, timed inside the process
                api_times = []
                for seed in seeds:
                    path, _, _ = simulate(cli, dt, samples, noise, seed)
                    _, _, elapsed = okid_cli(cli, path, dt, best, timing=True)
                    api_times.append(elapsed)
                    os.unlink(path)
                api = dict(rows[-1], seconds=float(np.median(api_times)))
                if name == "okid (CLI)":
                    rows.append(dict(api, method="okid (C API)"))
                    python_times = []
                    for seed in seeds:  # the same settings from Python, on arrays in memory
                        path, u, y = simulate(cli, dt, samples, noise, seed)
                        python_times.append(run_method(name, best, cli, path, u, y, dt, PEER_REPEATS,
                                                       in_process=True)[1])
                        os.unlink(path)
                    rows.append(dict(api, method="okid (Python)", seconds=float(np.median(python_times))))
                else:  # the options' rows give the C API time only
                    rows[-1] = api
        os.unlink(tune_path)
    return rows


# The Python package's figures (issue 14): its overhead over the C API on the paper case and the 5 %
# case, and `okid identify` as a whole process against the numpy OKID/ERA in process on the 5 % case.
SPEED_CASES = {"paper": (CASES[0], dict(p=20, h=20)), "5pct": (CASES[3], dict(p=20, h=40))}


def children_cpu():
    """User + system CPU seconds of the finished child processes."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def python_speed(cli, quick):
    """Per case, on the same data in one run: the fastest of interleaved calls of the numpy OKID/ERA
    and okid.identify (in process) and `okid identify --json` (the whole process, CSV parsing
    included); okid.identify also back to back, as okid's C API time inside the CLI is measured
    (init to modes, fastest of 20)."""
    repeats = 5 if quick else 30
    out = {}
    for key, ((case, dt, samples, noise), params) in SPEED_CASES.items():
        path, u, y = simulate(cli, dt, samples, noise, seed=11)
        ref = paper_reference(dt)
        methods = {"numpy": lambda: numpy_okid_era(u, y, dt, params["p"], params["h"]),
                   "python": lambda: okid_python(u, y, dt, params),
                   "cli_process": lambda: okid_cli(cli, path, dt, params)[0]}
        best = {name: np.inf for name in methods}
        cpu = dict(best)  # CPU seconds (this process's, or the child's): what a loaded machine does not inflate
        found = {}
        for _ in range(repeats):
            for name, call in methods.items():
                t0, c0, k0 = time.perf_counter(), time.process_time(), children_cpu()
                found[name] = call()
                best[name] = min(best[name], time.perf_counter() - t0)
                used = children_cpu() - k0 if name == "cli_process" else time.process_time() - c0
                cpu[name] = min(cpu[name], used)
        # The C API figure is the fastest of 20 back to back (warm caches): so is the Python one here.
        for _ in range(20):
            t0 = time.perf_counter()
            methods["python"]()
            best["python"] = min(best["python"], time.perf_counter() - t0)
        c_api = okid_cli(cli, path, dt, params, timing=True)[2]
        os.unlink(path)
        out[key] = dict(case=case, params=params, numpy_seconds=best["numpy"], python_seconds=best["python"],
                        cli_process_seconds=best["cli_process"], c_api_seconds=c_api,
                        python_overhead=best["python"] / c_api,
                        speedup_vs_numpy_inprocess=best["numpy"] / best["cli_process"],
                        python_speedup_vs_numpy=best["numpy"] / best["python"],
                        numpy_cpu_seconds=cpu["numpy"], cli_process_cpu_seconds=cpu["cli_process"],
                        speedup_vs_numpy_inprocess_cpu=cpu["numpy"] / cpu["cli_process"],
                        numpy_error=max(errors(found["numpy"], ref)), okid_error=max(errors(found["python"], ref)),
                        openblas_num_threads=os.environ.get("OPENBLAS_NUM_THREADS", "OpenBLAS's default"))
    return out


def c_benchmark(bench, quick):
    out = {}
    for blas, dirs in BLAS_DIRS.items():
        if not all(d.exists() for d in dirs):
            continue
        env = dict(os.environ, LD_LIBRARY_PATH=":".join(map(str, dirs)), OPENBLAS_NUM_THREADS="1")
        with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
            path = f.name
        text = subprocess.run([bench, "--json", path] + (["--quick"] if quick else []), env=env, check=True,
                              capture_output=True, text=True).stdout
        out[blas] = dict(json.loads(Path(path).read_text()), text=text)
        os.unlink(path)
    return out


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = list(dict.fromkeys(r["method"] for r in rows))
    cases = list(dict.fromkeys(r["case"] for r in rows))
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for method in methods:
        errs = [next((r["freq_error"] for r in rows if r["method"] == method and r["case"] == c), np.nan)
                for c in cases]
        ax[0].semilogy(range(len(cases)), np.maximum(errs, 1e-16), "o-", label=method)
    ax[0].set_xticks(range(len(cases)), [c.replace(", ", "\n") for c in cases], fontsize=8)
    ax[0].set_ylabel("max relative frequency error")
    ax[0].set_title("Accuracy (mean over seeds)")
    ax[0].legend(fontsize=8)
    paper = [r for r in rows if r["case"] == cases[0]]
    ax[1].barh([r["method"] for r in paper], [r["seconds"] for r in paper])
    ax[1].set_xscale("log")
    ax[1].set_xlabel("seconds, paper case (log)")
    ax[1].set_title("Time from data to modes")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def worst(r):
    return max(r["freq_error"], r["damping_error"])


def best_okid(rows, case, key=worst):
    """okid's most accurate row of a case (by `key`): plain OKID (C API) or one of its options."""
    mine = [r for r in rows if r["case"] == case and r["method"].startswith("okid") and r["method"] != "okid (CLI)"]
    return min(mine, key=key)


def best_peer(rows, case, key=worst):
    return min((r for r in rows if r["case"] == case and not r["method"].startswith("okid")), key=key)


def no_worse(mine, peer, key):
    """Is mine[key] no worse than peer[key]? Both ran on the same seeds' data, so the test is paired:
    the mean of the per-seed differences must not exceed twice its standard error (round-off counts
    as equal). Returns (verdict, how it was decided)."""
    if mine[key] <= max(peer[key], ROUND_OFF):
        return True, ""
    diff = np.array(mine[key + "s"]) - np.array(peer[key + "s"])
    if not np.all(np.isfinite(diff)) or len(diff) < 2:
        return False, ""
    bound = 2 * diff.std(ddof=1) / np.sqrt(len(diff))
    if diff.mean() <= bound:
        return True, f" (within the seed scatter: {diff.mean():.1e} <= {bound:.1e})"
    return False, ""


def targets(rows, results):
    """The targets of the benchmark issue, each with the measured figure and met / missed (by how much)."""
    out = []

    def add(what, measured, goal, met, margin):
        out.append((what, measured, goal, "met" if met else f"missed: {margin}"))

    push, frac = results["push_samples_per_s"], results["dgemm_fraction"]
    add(f"push r=1 m=2 p=20 ({results['blas']})", f"{push:,.0f} samples/s", ">= 1,000,000 samples/s",
        push >= 1e6, f"{push / 1e6:.2f}x of it")
    add("push as a fraction of the same run's DGEMM", f"{100 * frac:.1f} %", ">= 25 %", frac >= 0.25,
        f"{frac / 0.25:.2f}x of it")
    paper = [r for r in rows if r["case"] == CASES[0][0]]
    ours = next(r for r in paper if r["method"] == "okid (C API)")
    peer = min((r for r in paper if not r["method"].startswith("okid")), key=lambda r: r["seconds"])
    speedup = peer["seconds"] / ours["seconds"]
    accurate = max(ours["freq_error"], ours["damping_error"], ROUND_OFF) <= max(peer["freq_error"],
                                                                             peer["damping_error"], ROUND_OFF)
    add(f"paper end to end vs the fastest peer ({peer['method']})", f"{speedup:.2f}x the peer's speed"
        f"{'' if accurate else ' (less accurate)'}", ">= 50x at equal or better accuracy", speedup >= 50 and accurate,
        f"{speedup / 50:.2f} of the factor")
    for case in dict.fromkeys(r["case"] for r in rows):
        others = [r for r in rows if r["case"] == case and not r["method"].startswith("okid")]
        for key, label in (("freq_error", "frequency"), ("damping_error", "damping")):
            best = min(others, key=lambda r: r[key])
            mine = best_okid(rows, case, key=lambda r: r[key])
            ok, how = no_worse(mine, best, key)
            add(f"{case}: {label} error vs the best peer", f"{mine[key]:.2e} ({mine['method']}; best peer "
                f"{best['method']} {best[key]:.2e}){how}", "no worse (paired over the seeds; round-off is equal)",
                ok, f"{mine[key] / best[key]:.2f}x the best peer's error")
        if case == CASES[3][0]:
            for key, label, bound in (("freq_error", "frequency", 1e-3), ("damping_error", "damping", 1e-2)):
                mine = best_okid(rows, case, key=lambda r: r[key])
                add(f"{case}: {label} error", f"{100 * mine[key]:.3f} % ({mine['method']})",
                    f"<= {100 * bound:g} %", mine[key] <= bound, f"{mine[key] / bound:.2f}x the bound")
    return out


def behind(rows, cbench):
    """Where okid is behind its targets or a peer, with the arithmetic that says why (from this run)."""
    out = []
    paper = [r for r in rows if r["case"] == CASES[0][0]]
    ours = next(r for r in paper if r["method"] == "okid (C API)")
    peer = min((r for r in paper if not r["method"].startswith("okid")), key=lambda r: r["seconds"])
    dgemm = max(d["dgemm_gflops"] for d in cbench.values()) * 1e9
    p = ours["params"]["p"]
    q = 1 + 3 * p  # r + (r + m) p rows of the regressor for r = 1, m = 2
    budget = peer["seconds"] / 50
    floor = 2 * q * q * CASES[0][2] / dgemm
    if ours["seconds"] * 50 > peer["seconds"]:
        out.append(
            f"- **Paper case end to end, 50x the fastest peer.** {peer['method']} takes {1e3 * peer['seconds']:.2f} ms "
            f"on arrays already in memory; 50x faster is {1e6 * budget:.1f} µs for the 1001 samples, "
            f"{1e9 * budget / CASES[0][2]:.1f} ns per sample. okid's tuned setting (p = {p}, q = {q}) costs at least "
            f"2q² = {2 * q * q} flops per sample to fold, {1e6 * floor:.1f} µs for the record at this run's best "
            f"single-core DGEMM rate ({dgemm / 1e9:.1f} GFlop/s), before the observer-Markov solve, the Hankel SVD and "
            f"the eigen-analysis; it measures {1e6 * ours['seconds']:.0f} µs "
            f"({peer['seconds'] / ours['seconds']:.2f}x the peer's speed), {ours['seconds'] / floor:.0f}x that floor. "
            f"At this width the cost is not flops: the fold is bound by per-call overhead (a blocked QR update "
            f"of a {q}-column factor every 32 samples; Givens rotations row by row measured twice as slow on "
            "this CPU), and identify does fixed work whatever the record length (the rank-revealing solve and "
            "the diagnostics' second one, the Hankel SVD, the eigen-analysis, the modal indicators: 0.34 M "
            "instructions at p = 2, h = 10 under callgrind). The peer's cost is itself a handful of LAPACK calls "
            "on a 1001-row matrix, so a 50x lead is out of reach for this method; what okid adds is the same "
            "order of speed in fixed memory, sample by sample, on a microcontroller.")
    def behind_peer(mine, best):
        return not all(no_worse(mine, best, key)[0] for key in ("freq_error", "damping_error"))

    for case, dt, _, noise in CASES:
        if not any(r["case"] == case for r in rows):
            continue
        plain = next(r for r in rows if r["case"] == case and r["method"] == "okid (C API)")
        mine, best = best_okid(rows, case), best_peer(rows, case)
        if behind_peer(plain, best) and not behind_peer(mine, best):
            out.append(
                f"- **{case}: plain OKID is behind {best['method']}** (worst relative error {worst(plain):.2e} "
                f"against {worst(best):.2e}); {mine['method']} ({worst(mine):.2e}) is not: that option is the "
                "remedy for this kind of data (docs/quality.md).")
        if behind_peer(mine, best):
            srim = (" SRIM takes the observability subspace from the data's correlation matrices, where white "
                    "output noise adds a nearly block-diagonal term that barely moves the leading singular "
                    "vectors." if best["method"] == "mdof SRIM" else "")
            same = (" The numpy OKID/ERA is the same estimator written from the equations; with equal p and h "
                    "the two differ only in the first p samples (okid, told the record starts at rest, uses them "
                    "with zero history; the script drops them) and in the rank tolerance, and the setting each "
                    "uses is tuned on one seed." if best["method"] == "numpy OKID/ERA" else "")
            period = 1 / min(m.frequency_hz for m in paper_reference(dt).modes)
            out.append(
                f"- **{case}: {best['method']} is more accurate** (frequency {best['freq_error']:.2e}, damping "
                f"{best['damping_error']:.2e}; okid's best, {mine['method']} with "
                f"{', '.join(f'{k}={v}' for k, v in mine['params'].items())}: {mine['freq_error']:.2e} and "
                f"{mine['damping_error']:.2e}). With noise on the outputs only, the regressor's past outputs are "
                "noisy too and OKID's least-squares observer-Markov parameters are biased (errors-in-variables); "
                f"at Δt = {dt:g} s the slow period is {period / dt:.0f} samples, so a Hankel window of h blocks "
                f"sees h/{period / dt:.0f} of it. Decimation and the instrumental-variable estimator "
                f"(docs/quality.md) trade that bias for variance.{same}{srim}")
        mine = best_okid(rows, case, key=lambda r: r["freq_error"])
        if case == CASES[3][0] and mine["freq_error"] > 1e-3:
            low = best_okid(rows, CASES[2][0], key=lambda r: r["freq_error"])
            out.append(
                f"- **{case}: frequencies within 0.1 %** is missed: {100 * mine['freq_error']:.3f} % "
                f"({mine['freq_error'] / 1e-3:.1f}x the bound; the best peer, {best['method']}, "
                f"{100 * best['freq_error']:.3f} %). From 2 % to 5 % noise okid's error grows "
                f"{mine['freq_error'] / low['freq_error']:.1f}x for 2.5x the noise: proportional to the noise, so "
                "the error is the estimate's variance, not a bias (a bias grows with the noise power, 6.25x). "
                "Variance falls as 1/√N: the bound needs about "
                f"{(mine['freq_error'] / 1e-3) ** 2:.1f}x the record ({100 * (mine['freq_error'] / 1e-3) ** 2:.0f} s "
                "instead of 100 s) or that many averaged experiments. No peer does better on these data (the best "
                f"is at {100 * best_peer(rows, case, key=lambda r: r['freq_error'])['freq_error']:.2f} %).")
    return out


def python_section(speed):
    """The markdown section of python_speed()'s figures, with the arithmetic of a missed target."""
    lines = ["## okid from Python", "",
             "The same data and settings, one run, the fastest of interleaved calls: numpy OKID/ERA and "
             "`okid.identify` on arrays in memory, `okid identify --json` as a whole process (start, CSV "
             "parsing, JSON); okid's C API time inside that process (init to modes, fastest of 20 back to "
             "back) and `okid.identify` also back to back for python_overhead. OPENBLAS_NUM_THREADS: "
             f"{next(iter(speed.values()))['openblas_num_threads']} (numpy's OpenBLAS and okid's alike; the "
             "CLI runs with one thread).", "",
             "| case | settings | numpy OKID/ERA | okid.identify (Python) | okid C API | `okid identify` process "
             "| python_overhead (goal <= 1.2) | speedup_vs_numpy_inprocess (goal >= 5), wall / CPU "
             "| max error numpy / okid |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in speed.values():
        lines.append(f"| {s['case']} | p={s['params']['p']}, h={s['params']['h']} | {1e3 * s['numpy_seconds']:.2f} ms "
                     f"(CPU {1e3 * s['numpy_cpu_seconds']:.2f}) | {1e3 * s['python_seconds']:.2f} ms |"
                     f" {1e3 * s['c_api_seconds']:.2f} ms | {1e3 * s['cli_process_seconds']:.2f} ms (CPU "
                     f"{1e3 * s['cli_process_cpu_seconds']:.2f}) | {s['python_overhead']:.2f} |"
                     f" {s['speedup_vs_numpy_inprocess']:.2f} / {s['speedup_vs_numpy_inprocess_cpu']:.2f} |"
                     f" {s['numpy_error']:.1e} / {s['okid_error']:.1e} |")
    five = speed["5pct"]
    if five["speedup_vs_numpy_inprocess"] < 5:
        rest = five["cli_process_seconds"] - five["c_api_seconds"]
        lines += ["", f"The whole `okid identify` process on the 5 % case is {five['speedup_vs_numpy_inprocess']:.2f}x "
                  f"the numpy OKID/ERA ({five['speedup_vs_numpy_inprocess_cpu']:.2f}x in CPU time), short of 5x: 5x "
                  f"leaves the process {1e3 * five['numpy_seconds'] / 5:.2f} ms, and the identification alone (C API) "
                  f"takes {1e3 * five['c_api_seconds']:.2f} ms; the other {1e3 * rest:.2f} ms of the process are its "
                  "start, reading the CSV and writing the JSON. "
                  f"In process, from Python, okid is {five['python_speedup_vs_numpy']:.1f}x the numpy OKID/ERA "
                  "(docs/python.md, \"Performance\")."]
    return lines


def update_python_figures(cli, quick, results_path, markdown_path):
    """--python-only: measure python_speed() again and replace its figures in results.json and its
    section of benchmarks.md, leaving the rest of an earlier full run as it was."""
    speed = python_speed(cli, quick)
    results = json.loads(Path(results_path).read_text()) if Path(results_path).exists() else {}
    results.update(python_overhead={k: v["python_overhead"] for k, v in speed.items()},
                   speedup_vs_numpy_inprocess=speed["5pct"]["speedup_vs_numpy_inprocess"], python=speed)
    Path(results_path).write_text(json.dumps(results, indent=2) + "\n")
    text = Path(markdown_path).read_text()
    section = "\n".join(python_section(speed)) + "\n\n"
    if "## okid from Python" in text:
        start = text.index("## okid from Python")
        end = text.index("\n## ", start + 1) + 1
        text = text[:start] + section + text[end:]
    else:
        end = text.index("## Where okid is behind")
        text = text[:end] + section + text[end:]
    Path(markdown_path).write_text(text)
    for s in speed.values():
        print(json.dumps(s))


def markdown(rows, cbench, results, quick, crlb_lines=()):
    lines = ["# Benchmarks", "", f"Generated by `.venv/bin/python bench/python/bench_compare.py{' --quick' if quick else ''}` "
             f"on {platform.node() or 'this machine'}: {platform.processor() or platform.machine()}, "
             f"{os.cpu_count()} cores, {platform.platform()}.", "",
             "## Accuracy and time against the peers (identical data from okid's simulator)", "",
             "| data | method | parameters (tuned on a separate seed) | max freq. error | max damping error | seconds |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        params = ", ".join(f"{k}={v}" for k, v in (r["params"] or {}).items())
        lines.append(f"| {r['case']} | {r['method']} | {params} | {r['freq_error']:.2e} | {r['damping_error']:.2e} |"
                     f" {r['seconds']:.2e} |")
    lines += ["", "Errors are the largest relative error over the two modes, averaged over the evaluation seeds; "
              "times are medians (okid CLI: the whole process, CSV parsing included; okid C API: init to modes "
              "inside the process, fastest of 20; Python peers: the identification call on arrays in memory; "
              "okid runs on OpenBLAS when it is installed, as numpy does). "
              "p is the observer order, h the Hankel block rows = columns, m the number of Markov parameters "
              "(python-control, mdof). Every method's A goes through the same eigen-analysis.", "",
              "![benchmark](img/benchmark.png)", "", "## Targets of the benchmark issue", "",
              "| target | measured | goal | verdict |", "|---|---|---|---|"]
    lines += [f"| {what} | {measured} | {goal} | {verdict} |" for what, measured, goal, verdict in targets(rows, results)]
    lines += [""] + python_section(results["python"])
    lines += [""] + list(crlb_lines)
    notes = behind(rows, cbench)
    lines += ["", "## Where okid is behind, and why", ""] + (notes or ["- Nowhere in this run."])
    lines += ["", "## Speed of the C core", ""]
    for blas, data in cbench.items():
        lines += [f"### {blas} BLAS (one thread)", "", "```", data["text"].rstrip(), "```", ""]
    stream = Path("bench/stream_results.json")  # scripts/bench_stream.py: the CLI on a 1 GB CSV, kept here
    if stream.exists():
        lines += json.loads(stream.read_text())["markdown"]
    scale = Path("bench/scale_results.json")  # bench/python/scale_bench.py: large records, kept here
    if scale.exists():
        lines += json.loads(scale.read_text())["markdown"]
    lines += ["## Machine-readable", "", "```json", json.dumps(results, indent=2), "```", ""]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run of seconds (fewer cases and seeds)")
    parser.add_argument("--build", default="build", help="the CMake build folder (default build)")
    parser.add_argument("--out", default="docs", help="where benchmarks.md and img/benchmark.png go")
    parser.add_argument("--results", default="bench/results.json")
    parser.add_argument("--python-only", action="store_true",
                        help="only the Python package's figures, into the existing results and benchmarks.md")
    parser.add_argument("--crlb-only", action="store_true",
                        help="only the comparison with the Cramer-Rao bound, printed as markdown (no files)")
    parser.add_argument("--crlb-seeds", type=int, default=20, help="seeds per configuration of that comparison")
    args = parser.parse_args(argv)
    cli = str(Path(args.build) / "host_tools/cli/okid")
    if args.python_only:
        update_python_figures(cli, args.quick, args.results, Path(args.out) / "benchmarks.md")
        return 0
    if args.crlb_only:
        crlb_rows, seeds = crlb_compare(cli, args.quick, args.crlb_seeds)
        print("\n".join(crlb_markdown(crlb_rows, seeds)))
        return 0
    bench = str(Path(args.build) / "bench/okid_bench")
    t0 = time.perf_counter()
    cbench = c_benchmark(bench, args.quick)
    rows = compare(cli, args.quick)
    speed = python_speed(cli, args.quick)
    crlb_rows, crlb_seeds = crlb_compare(cli, args.quick, args.crlb_seeds)
    paper = [r for r in rows if r["case"] == CASES[0][0]]
    ours = next(r for r in paper if r["method"] == "okid (C API)")
    peers = [r for r in paper if not r["method"].startswith("okid")]
    best_blas = cbench.get("OpenBLAS") or cbench.get("reference")
    best_push = max((p for p in best_blas["push"] if p["r"] == 1 and p["m"] == 2 and p["p"] == 20),
                    key=lambda p: p["samples_per_s"])
    results = dict(push_samples_per_s=best_push["samples_per_s"], push_block_rows=best_push["block_rows"],
                   dgemm_fraction=best_push["dgemm_fraction"], blas="OpenBLAS" if "OpenBLAS" in cbench else "reference",
                   paper_e2e_seconds=ours["seconds"],
                   paper_e2e_seconds_best_peer=min(r["seconds"] for r in peers),
                   python_overhead={k: v["python_overhead"] for k, v in speed.items()},
                   speedup_vs_numpy_inprocess=speed["5pct"]["speedup_vs_numpy_inprocess"],
                   python=speed, rows=rows, crlb_rows=crlb_rows)
    for r in rows:
        print(f"{r['case']:30s} {r['method']:16s} f {r['freq_error']:.2e}  zeta {r['damping_error']:.2e}  "
              f"{r['seconds']:.2e} s  {r['params']}")
    Path(args.results).parent.mkdir(parents=True, exist_ok=True)
    if Path(args.results).exists():  # the fleet benchmark's figures (bench/python/fleet_bench.py) are its own
        earlier = json.loads(Path(args.results).read_text())
        results.update({k: earlier[k] for k in ("fleet",) if k in earlier})
    Path(args.results).write_text(json.dumps(results, indent=2) + "\n")
    out = Path(args.out)
    (out / "img").mkdir(parents=True, exist_ok=True)
    plot(rows, out / "img" / "benchmark.png")
    (out / "benchmarks.md").write_text(markdown(rows, cbench,
                                                {k: v for k, v in results.items() if k not in ("rows", "crlb_rows")},
                                                args.quick, crlb_markdown(crlb_rows, crlb_seeds)))
    print(f"\nwrote {out / 'benchmarks.md'}, {out / 'img/benchmark.png'}, {args.results} "
          f"in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
