# SPDX-License-Identifier: Apache-2.0
"""The least-squares fold at its automatic block size and the correlation-form estimator (issue 29)
against numpy's lstsq of the same regressor, and the correlation form's fallback to the QR fold in
okid.identify() and the CLI."""
import json
import os
import subprocess

import numpy as np
import pytest

import okid

OKID = os.environ.get("OKID_CLI", "okid")
EPS = np.finfo(float).eps


def record(samples=4000, outputs=10, seed=3, noise=0.02):
    """A lightly damped 5-mass chain, 1 force, two noisy accelerometers per mass (outputs = 10)."""
    from okid import model
    n = 5
    masses, springs = np.ones(n), np.full(n + 1, 4000.0)
    m_, r_, k_ = model.chain_model(masses, 5e-4 * springs, springs)
    b2 = np.zeros((n, 1))
    b2[0, 0] = 1
    ac, bc, c, d = model.state_space(m_, r_, k_, b2, acceleration=np.vstack([np.eye(n)] * (outputs // n)))
    a, b = model.discretize_zoh(ac, bc, 0.01)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    y, _ = model.simulate(a, b, c, d, u)
    return u, y + noise * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape)


def numpy_markov(u, y, p, count):
    """Markov parameters Y_0 .. Y_count from numpy's lstsq of the OKID regressor (eq. 49-51), the
    record's first p samples as history, and the condition number of the column-equilibrated regressor."""
    N, r = u.shape
    m = y.shape[1]
    v = np.hstack([u, y])
    phi = np.hstack([u[p:]] + [v[p - i:N - i] for i in range(1, p + 1)])
    scale = np.linalg.norm(phi, axis=0)
    x = np.linalg.lstsq(phi / scale, y[p:], rcond=None)[0] / scale[:, None]
    X = x.T
    D = X[:, :r]
    Y1 = [X[:, r + (i - 1) * (r + m): r + (i - 1) * (r + m) + r] for i in range(1, p + 1)]
    G = [X[:, r + (i - 1) * (r + m) + r: r + i * (r + m)] for i in range(1, p + 1)]
    Y = [D]
    for k in range(1, count + 1):
        Yk = Y1[k - 1].copy() if k <= p else np.zeros((m, r))
        for i in range(1, min(k, p) + 1):
            Yk += G[i - 1] @ Y[k - i]
        Y.append(Yk)
    return np.hstack(Y), np.linalg.cond(phi / scale)


@pytest.mark.parametrize("estimator", ["least_squares", "correlation"])
def test_markov_parameters_match_numpy_lstsq(estimator):
    """q = 221 (w = 231: 256-row blocks), 4000 samples. Both solutions are backward stable, so they
    differ by about kappa^2 eps (the normal equations' error; the QR fold's is kappa eps + kappa^2
    eps times residual / (|Phi| |x|)), kappa the equilibrated regressor's 2-norm condition; the
    Markov recursion then mixes 2 p of them: 4 p w kappa^2 eps relative to the largest."""
    p = 20
    u, y = record()
    res = okid.identify(u, y, 0.01, observer_order=p, order=10, estimator=estimator)
    assert not res.warnings & okid.WarningFlag.CORRELATION_FALLBACK
    count = res.markov.shape[1] - 1
    want, kappa = numpy_markov(u, y, p, count)
    tol = 4 * p * 231 * kappa ** 2 * EPS
    assert tol < 1e-3  # the comparison means something
    err = np.max(np.abs(res.markov - want)) / np.max(np.abs(want))
    assert err <= tol, (err, tol, kappa)


def test_noise_free_record_falls_back_to_the_qr_fold():
    """Noise-free data with p above the minimum: the regressor is rank deficient, the guard refuses,
    okid.identify() identifies again with least squares: the same numbers, and says so."""
    u, y = record(samples=3000, noise=0.0)
    qr = okid.identify(u, y, 0.01, observer_order=10, order=10)
    co = okid.identify(u, y, 0.01, observer_order=10, order=10, estimator="correlation")
    assert co.warnings & okid.WarningFlag.CORRELATION_FALLBACK
    assert co.warnings & ~okid.WarningFlag.CORRELATION_FALLBACK == qr.warnings
    assert co.config["estimator"] == "least_squares"
    np.testing.assert_array_equal(co.markov, qr.markov)
    np.testing.assert_array_equal(co.A, qr.A)
    with okid.Identifier(1, 10, 0.01, observer_order=10, order=10, estimator="correlation") as ident:
        ident.push(u, y)
        with pytest.raises(okid.DecompositionError):
            ident.identify()


def test_cli_falls_back_and_says_so(tmp_path):
    csv = tmp_path / "paper.csv"
    subprocess.run([OKID, "simulate", "--output", str(csv)], check=True, capture_output=True)

    def run(*args):
        out = subprocess.run([OKID, "identify", str(csv), "--json", "--order", "4", *args], capture_output=True,
                             text=True, check=True)
        return json.loads(out.stdout)
    qr, co = run(), run("--estimator", "correlation")
    assert co["config"]["estimator"] == "least_squares"
    assert co["warning_bits"] == qr["warning_bits"] | int(okid.WarningFlag.CORRELATION_FALLBACK)
    assert co["modes"] == qr["modes"]
