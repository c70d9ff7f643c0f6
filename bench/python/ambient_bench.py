# SPDX-License-Identifier: Apache-2.0
"""Output-only identification against its peers on identical simulated ambient records
(docs/ambient.md, "Against the peers"): frequency and damping RMS errors over seeds and the time
per identification of okid.identify_ambient, of an independent SSI-COV written here in NumPy
(correlations by matrix products, block Hankel of R(1..2L), SVD, shift of the observability
matrix), and of koma-python's covssi when it is installed (pip install koma-python); every method
at the same Hankel size L and order n, one BLAS thread (OPENBLAS_NUM_THREADS=1 unless set).

  .venv/bin/python bench/python/ambient_bench.py [--seeds 20] [--cases paper,chain10]

Records: the paper's 2-DOF plant (dt 0.05 s, 40000 samples) and a 10-mass chain fixed at one end
(springs 1000, unit masses, Rayleigh damping 2 % at modes 1 and 10, dt 0.01 s, 40000 samples),
unit white forces on every mass, every acceleration with 5 % white sensor noise (SciPy, exact ZOH).
"""
import argparse
import math
import os

# one BLAS thread for every method: time.process_time counts every thread's CPU, and OpenBLAS's
# idle threads spin (okid's chain10 call took 363 ms of CPU with the default threads, 61 ms with one)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np
import scipy.signal

from cpu_timing import timed


def chain(n, k, zeta):
    M = np.eye(n)
    K = np.zeros((n, n))
    for i in range(n):  # spring i joins mass i-1 (or the wall) and mass i
        K[i, i] += k
        if i > 0:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    w = np.sqrt(np.sort(np.linalg.eigvalsh(K)))
    a0, a1 = np.linalg.solve([[1 / (2 * w[0]), w[0] / 2], [1 / (2 * w[-1]), w[-1] / 2]], [zeta, zeta])
    return M, a0 * M + a1 * K, K


def state_space(M, C, K):
    n = len(M)
    Mi = np.linalg.inv(M)
    ac = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ C]])
    bc = np.vstack([np.zeros((n, n)), Mi])
    return ac, bc, np.hstack([-Mi @ K, -Mi @ C]), Mi


def exact_modes(ac):
    poles = sorted((p for p in np.linalg.eigvals(ac) if p.imag > 0), key=abs)
    return np.array([abs(p) / (2 * math.pi) for p in poles]), np.array([-p.real / abs(p) for p in poles])


CASES = {
    "paper": dict(M=np.diag([2.0, 3.0]), C=np.array([[6.0, -4], [-4, 7]]), K=np.array([[60.0, -40], [-40, 70]]),
                  dt=0.05, samples=40000, L=20, order=4),
    "chain10": dict(**dict(zip("MCK", chain(10, 1000.0, 0.02))), dt=0.01, samples=40000, L=20, order=20),
}


def record(case, seed):
    ac, bc, c, d = state_space(case["M"], case["C"], case["K"])
    a, b, _, _, _ = scipy.signal.cont2discrete((ac, bc, c, d), case["dt"], method="zoh")
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((case["samples"], bc.shape[1]))
    _, y, _ = scipy.signal.dlsim((a, b, c, d, case["dt"]), u)
    return y + 0.05 * y.std(axis=0) * rng.standard_normal(y.shape)


def modes_of(a, dt):
    lam = np.log(np.linalg.eigvals(a).astype(complex)) / dt
    lam = lam[lam.imag > 0]
    return np.abs(lam) / (2 * math.pi), -lam.real / np.abs(lam)


def ssi_cov_numpy(y, dt, L, n):
    """Covariance-driven SSI, written independently of okid: R(k) = sum y(t+k) y(t)' / (N - k)."""
    y = y - y.mean(axis=0)
    N, m = y.shape
    R = [y[k:].T @ y[:N - k] / (N - k) for k in range(1, 2 * L + 1)]
    H = np.block([[R[i + j] for j in range(L)] for i in range(L)])
    U, S, _ = np.linalg.svd(H)
    O = U[:, :n] * np.sqrt(S[:n])
    A = np.linalg.lstsq(O[:-m], O[m:], rcond=None)[0]
    return modes_of(A, dt)


def okid_ambient(y, dt, L, n):
    import okid
    res = okid.identify_ambient(y, dt, hankel_rows=L, order=n)
    pairs = [md for md in res.modes if md.is_pair]
    return np.array([md.frequency_hz for md in pairs]), np.array([md.damping_ratio for md in pairs])


def koma_covssi(y, dt, L, n):
    from koma import oma
    lam, _ = oma.covssi(y, 1 / dt, L, [n], showinfo=False, return_flat=False)
    lam = np.asarray(lam[0])  # continuous-time poles of order n, one of each conjugate pair
    lam = lam[np.abs(lam.imag) > 0]
    return np.abs(lam) / (2 * math.pi), -lam.real / np.abs(lam)


def matched_errors(f, z, f_exact, z_exact):
    """Relative errors of the nearest identified pair to each exact mode (NaN when none)."""
    ef, ez = [], []
    for fe, ze in zip(f_exact, z_exact):
        if len(f) == 0:
            ef.append(np.nan), ez.append(np.nan)
            continue
        i = int(np.argmin(np.abs(f - fe)))
        ef.append((f[i] - fe) / fe)
        ez.append((z[i] - ze) / ze)
    return np.array(ef), np.array(ez)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--cases", default="paper,chain10")
    args = ap.parse_args()
    methods = {"okid": okid_ambient, "numpy SSI-COV": ssi_cov_numpy}
    try:
        import koma.oma  # noqa: F401
        methods["koma covssi"] = koma_covssi
    except ImportError:
        print("koma-python not installed: its column is left out")
    for name in args.cases.split(","):
        case = CASES[name]
        f_exact, z_exact = exact_modes(state_space(case["M"], case["C"], case["K"])[0])
        print(f"\n{name}: {len(f_exact)} modes {np.round(f_exact, 3).tolist()} Hz, m = {len(case['M'])}, "
              f"N = {case['samples']}, L = {case['L']}, n = {case['order']}, {args.seeds} seeds")
        errors = {k: ([], []) for k in methods}
        times = {k: [] for k in methods}
        for seed in range(1, args.seeds + 1):
            y = record(case, seed)
            for key, method in methods.items():
                seconds, (f, z) = timed(lambda: method(y, case["dt"], case["L"], case["order"]))
                times[key].append(seconds)
                ef, ez = matched_errors(f, z, f_exact, z_exact)
                errors[key][0].append(ef)
                errors[key][1].append(ez)
        print(f"{'method':16s} {'freq rms (worst mode)':>22s} {'damp rms (worst mode)':>22s} {'CPU s / id (median)':>20s} {'koma / method':>14s}")
        for key in methods:
            ef, ez = np.array(errors[key][0]), np.array(errors[key][1])
            rf = np.sqrt(np.nanmean(ef ** 2, axis=0)).max()
            rz = np.sqrt(np.nanmean(ez ** 2, axis=0)).max()
            ratio = np.median(times["koma covssi"]) / np.median(times[key]) if "koma covssi" in times else math.nan
            print(f"{key:16s} {rf:22.3e} {rz:22.3e} {np.median(times[key]):20.5f} {ratio:14.2f}")


if __name__ == "__main__":
    main()
