#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Information criteria for the observer order on the real records (docs/quality.md section 8,
rule 3): for p = 2 .. 2 T (T the slowest period the automatic settings find), the least squares
of the observer's ARX form y(k) = D u(k) + sum_i [u(k-i); y(k-i)] Y_i at the decimation the
defaults choose (scipy's FIR decimation here, not okid's Butterworth), and the p where AIC, BIC
and FPE of its residual covariance are smallest, as a share of T.

    .venv/bin/python scripts/observer_criteria.py
"""
import pathlib

import numpy as np
from scipy import signal

ROOT = pathlib.Path(__file__).resolve().parents[1]
# inputs, outputs, the decimation and the slowest period [s] the defaults choose (okid identify --json: chosen)
RECORDS = {"hayward_transverse": (4, 4, 5, 1.024), "meloland_transverse": (3, 3, 7, 0.931),
           "gws_building_351": (2, 5, 4, 0.853), "gws_building_261": (2, 3, 7, 1.024)}


def criteria(u, y, p):
    n_rows = len(y) - p
    x = np.hstack([u[p:]] + [np.hstack([u[p - i:len(y) - i], y[p - i:len(y) - i]]) for i in range(1, p + 1)])
    theta, *_ = np.linalg.lstsq(x, y[p:], rcond=None)
    e = y[p:] - x @ theta
    logdet = np.linalg.slogdet(e.T @ e / n_rows)[1]
    k = x.shape[1] * y.shape[1]
    fpe = logdet + y.shape[1] * np.log((n_rows + x.shape[1]) / (n_rows - x.shape[1]))
    return n_rows * logdet + 2 * k, n_rows * logdet + k * np.log(n_rows), fpe


def main():
    for stem, (r, m, k, period) in RECORDS.items():
        d = np.loadtxt(ROOT / "tests" / "data" / "real" / f"{stem}.csv", delimiter=",", skiprows=1)
        dt = d[1, 0] - d[0, 0]
        u = signal.decimate(d[:, 1:1 + r], k, axis=0, ftype="fir")
        y = signal.decimate(d[:, 1 + r:1 + r + m], k, axis=0, ftype="fir")
        u, y = u - u.mean(0), y - y.mean(0)
        t = period / (k * dt)
        ps = np.arange(2, int(2 * t) + 1)
        values = np.array([criteria(u, y, p) for p in ps])
        best = [ps[values[:, c].argmin()] for c in range(3)]
        print(f"{stem:22s} T = {t:5.1f} samples: AIC p {best[0]} ({best[0] / t:.2f} T), "
              f"BIC p {best[1]} ({best[1] / t:.2f} T), FPE p {best[2]} ({best[2] / t:.2f} T)")


if __name__ == "__main__":
    main()
