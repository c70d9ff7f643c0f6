# SPDX-License-Identifier: Apache-2.0
"""Automatic modes against the truth (issue 23, item 7): per data set, the physical modes found,
the spurious modes reported, and the frequency and damping errors, for

- okid with no setting (`okid.identify(u, y, dt)`: settings from the data, the physical modes);
- okid tuned (simulated sets only): the best of a grid of observer orders and Hankel sizes at the
  true order, scored by its worst relative error (on the real records the consensus itself comes
  from such a grid, tests/data/real_consensus.json);
- mdof SRIM with its own defaults (horizon min(300, N), order min(20, horizon / 2)) and its
  documented filter of the modes (MPC and EMAC in [0.5, 1], damping in [0, 0.2]);
- python-control (`markov` + `eigensys_realization`): it selects nothing, so the stable complex
  poles of an order-20 model with damping in [0, 0.2] are its modes (120 Markov parameters, Hankel 50 x 50).

A reported mode matches a true one within 5 % in frequency on the simulated sets and 2 % (the
issue's acceptance) on the real records; a reported mode matching none, or a second one matching
the same, is spurious. The errors are relative, over the modes found (damping: |dzeta| / zeta).
CPU seconds of the call, one BLAS thread.

    .venv/bin/python bench/python/mode_selection_bench.py [--markdown] [--seeds N]

The simulated sets (white force, output noise as a fraction of each output's RMS, seeds 1..N):
the paper's system at 2 % and 5 % (the second mode is damped 33 %), a 5-mass chain at 5 %,
closely spaced modes (1.592 and 1.615 Hz, 1.5 % apart), a chain whose force sits on the node of
its middle mode (that mode is not excited: not to be reported), the cases of tests/test_mode_selection.c.
"""
import argparse
import json
import os
import pathlib
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import okid  # noqa: E402
from okid import model  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
REAL = ROOT / "tests" / "data" / "real"
CONSENSUS = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())


def continuous_modes(ac):
    """(frequency [Hz], damping ratio) of the complex pairs of Ac, by frequency."""
    s = np.linalg.eigvals(ac)
    s = s[s.imag > 0]
    w = np.abs(s)
    order = np.argsort(w)
    return [(float(w[i] / (2 * np.pi)), float(-s[i].real / w[i])) for i in order]


def chain_case(masses, springs, beta, input_dof, dt, samples, noise, seed, excited=None):
    """A chain of masses between walls, stiffness-proportional dampers r_i = beta k_i, one force on
    mass input_dof, accelerations of every mass; truth: the continuous modes (those in `excited`)."""
    springs = np.asarray(springs, float)
    mass, damping, stiffness = model.chain_model(masses, beta * springs, springs)
    b2 = np.zeros((len(masses), 1))
    b2[input_dof] = 1
    ac, bc, c, d = model.state_space(mass, damping, stiffness, b2, acceleration=np.eye(len(masses)))
    a, b = model.discretize_zoh(ac, bc, dt)
    truth = continuous_modes(ac)
    if excited is not None:
        truth = [truth[i] for i in excited]
    return simulated(a, b, c, d, dt, samples, noise, seed), truth


def simulated(a, b, c, d, dt, samples, noise, seed):
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, b.shape[1]))
    y, _ = model.simulate(a, b, c, d, u)
    y = y + noise * y.std(axis=0) * rng.standard_normal(y.shape)
    return u, y, dt


def paper_case(noise, seed):
    a, b, c, d = model.paper_system(0.01)
    ac, _, _, _ = model._paper_continuous()
    return simulated(a, b, c, d, 0.01, 10001, noise, seed), continuous_modes(ac)


SIMULATED = {
    "paper, 2 % noise": lambda seed: paper_case(0.02, seed),
    "paper, 5 % noise": lambda seed: paper_case(0.05, seed),
    "5-mass chain, 5 % noise": lambda seed: chain_case([1] * 5, [100] * 6, 0.004, 0, 0.02, 6001, 0.05, seed),
    "close modes, 5 % noise": lambda seed: chain_case([1, 1], [100, 1.5, 100], 0.004, 0, 0.02, 3001, 0.05, seed),
    "unexcited mode, 5 % noise": lambda seed: chain_case([1, 1, 1], [100] * 4, 0.004, 1, 0.02, 3001, 0.05, seed,
                                                         excited=[0, 2]),
}


def okid_defaults(u, y, dt):
    return [(m.frequency_hz, m.damping_ratio) for m in okid.identify(u, y, dt).modes]


def okid_tuned(u, y, dt, truth):
    """The grid's best at the true order, scored against the truth (an oracle, as an expert tunes):
    the most modes found, then the fewest spurious, then the smallest worst relative error."""
    best, best_score = [], (np.inf,)
    n = 2 * len(truth)
    for p in (10, 20, 40, 80):
        for h in (20, 40, 100):
            try:
                res = okid.identify(u, y, dt, observer_order=p, hankel_rows=h, hankel_cols=h, order=n)
            except okid.OkidError:
                continue
            modes = [(m.frequency_hz, m.damping_ratio) for m in res.modes]
            pairs, spurious = match(modes, truth, 0.05)
            score = (len(truth) - len(pairs), spurious, worst_error((pairs, spurious)))  # all found, none extra, then accuracy
            if score < best_score:
                best, best_score = modes, score
    return best


def mdof_srim(u, y, dt):
    import mdof
    real = mdof.system(u.T, y.T, dt=dt, method="srim")
    modes = real.modes(filter_by=["MPC", "EMAC", "damping"], filter_lim=[(0.5, 1.0), (0.5, 1.0), (0.0, 0.2)])
    return sorted((float(v["freq"]), float(v["damp"])) for v in modes.values())


def control_era(u, y, dt):
    import control
    h = control.markov(y.T, u.T, 120)  # the Hankel's 50 + 50 blocks and one more
    sys_, _ = control.eigensys_realization(h, 20, m=50, n=50, dt=dt)
    lam = np.linalg.eigvals(np.asarray(sys_.A))
    out = []
    for z in lam[lam.imag > 0]:
        s = np.log(z) / dt
        f, zeta = abs(s) / (2 * np.pi), -s.real / abs(s)
        if abs(z) < 1 and 0 <= zeta <= 0.2:
            out.append((float(f), float(zeta)))
    return sorted(out)


def match(modes, truth, tol):
    """For each true mode the closest reported one within tol (relative frequency), each reported
    mode used once; returns (pairs, spurious count)."""
    used, pairs = set(), []
    for f, z in truth:
        cands = [(abs(m[0] - f) / f, i) for i, m in enumerate(modes) if i not in used and abs(m[0] - f) <= tol * f]
        if cands:
            _, i = min(cands)
            used.add(i)
            pairs.append(((f, z), modes[i]))
    return pairs, len(modes) - len(used)


def worst_error(matched):
    pairs, _ = matched
    if not pairs:
        return np.inf
    return max(max(abs(g[0] - t[0]) / t[0], abs(g[1] - t[1]) / t[1]) for t, g in pairs)


def timed(fn, *args):
    t0 = time.process_time()
    try:
        out = fn(*args)
    except Exception as exc:  # a peer's failure is a row, not the end of the benchmark
        out = exc
    return out, time.process_time() - t0


def score(modes, truth, tol):
    if isinstance(modes, Exception):
        return dict(found=0, truth=len(truth), spurious=0, freq=np.inf, damping=np.inf, error=type(modes).__name__)
    pairs, spurious = match(modes, truth, tol)
    return dict(found=len(pairs), truth=len(truth), spurious=spurious,
                freq=max((abs(g[0] - t[0]) / t[0] for t, g in pairs), default=np.inf),
                damping=max((abs(g[1] - t[1]) / t[1] for t, g in pairs), default=np.inf))


def real_records():
    for stem, rec in CONSENSUS["records"].items():
        path = REAL / f"{stem}.csv"
        if not path.exists():
            continue
        r = okid.read_record(path, inputs=rec["inputs"], outputs=rec["outputs"])
        truth = [(m["frequency_hz"], m["damping_ratio"]) for m in rec["modes"]]
        yield stem, r.u, r.y, r.dt, truth


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=3, help="seeds per simulated set (default 3)")
    ap.add_argument("--markdown", action="store_true", help="a markdown table (docs/benchmarks.md)")
    args = ap.parse_args(argv)
    methods = {"okid, no setting": okid_defaults, "mdof SRIM + its filter": mdof_srim,
               "python-control ERA": control_era}
    rows = []
    for name, make in SIMULATED.items():
        per = {}
        for seed in range(1, args.seeds + 1):
            (u, y, dt), truth = make(seed)
            runs = {m: timed(fn, u, y, dt) for m, fn in methods.items()}
            runs["okid tuned (grid's best)"] = timed(okid_tuned, u, y, dt, truth)
            for m, (modes, sec) in runs.items():
                per.setdefault(m, []).append((score(modes, truth, 0.05), sec))
        for m, results in per.items():
            rows.append(summary(name, m, results))
    for stem, u, y, dt, truth in real_records():
        for m, fn in methods.items():
            modes, sec = timed(fn, u, y, dt)
            rows.append(summary(stem, m, [(score(modes, truth, 0.02), sec)]))
    print_rows(rows, args.markdown, args.seeds)
    return 0


def summary(data, method, results):
    scores = [s for s, _ in results]
    return dict(data=data, method=method, runs=len(results),
                found=f"{sum(s['found'] for s in scores)}/{sum(s['truth'] for s in scores)}",
                spurious=sum(s["spurious"] for s in scores),
                freq=max(s["freq"] for s in scores), damping=max(s["damping"] for s in scores),
                seconds=float(np.median([sec for _, sec in results])),
                error=next((s["error"] for s in scores if "error" in s), ""))


def print_rows(rows, markdown, seeds):
    head = ["data", "method", "modes found", "spurious", "max freq. error", "max damping error", "CPU s"]
    if markdown:
        print(f"| {' | '.join(head)} |")
        print("|" + "---|" * len(head))
    for r in rows:
        cells = [r["data"], r["method"] + (f" ({r['error']})" if r["error"] else ""), r["found"], str(r["spurious"]),
                 f"{r['freq']:.3g}", f"{r['damping']:.3g}", f"{r['seconds']:.3f}"]
        print(f"| {' | '.join(cells)} |" if markdown else "  ".join(cells))
    print(f"\n(simulated sets: {seeds} seeds each, counts summed, errors the worst, time the median)")


if __name__ == "__main__":
    sys.exit(main())
