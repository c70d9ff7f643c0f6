# SPDX-License-Identifier: Apache-2.0
"""The fit of each output (host_tools/common/output_fit.c) and the warning of a model that explains
nothing (issue 27: OKID/ERA on pure noise returned modes without a word).

fit = 100 (1 - |y - yhat| / |y - mean y|), yhat the model's response to u from rest, as MATLAB's
compare(). The reference here is numpy's own simulation of the identified (A, B, C, D)."""
import json
import os
import subprocess
import warnings

import numpy as np
import pytest

import okid

OKID = os.environ.get("OKID_CLI", "okid")
DT = 0.01


def numpy_fit(result, u, y):
    """The fit by a plain numpy simulation x(k+1) = A x + B u, yhat = C x + D u from x = 0."""
    x = np.zeros(result.order)
    yhat = np.empty_like(y)
    for k in range(len(u)):
        yhat[k] = result.C @ x + result.D @ u[k]
        x = result.A @ x + result.B @ u[k]
    return 100 * (1 - np.linalg.norm(y - yhat, axis=0) / np.linalg.norm(y - y.mean(axis=0), axis=0))


@pytest.fixture(scope="module")
def noise():
    """A force and two 'responses' that are independent white noise: nothing to explain."""
    rng = np.random.default_rng(27)
    return rng.standard_normal((1000, 1)), rng.standard_normal((1000, 2))


@pytest.fixture(scope="module")
def paper():
    """The paper's two-mass case (okid.model.paper_system), noise-free and with 2 % output noise."""
    u = np.random.default_rng(3).standard_normal((1001, 1))
    y, _ = okid.model.simulate(*okid.model.paper_system(DT), u)
    noisy = y + 0.02 * y.std(axis=0) * np.random.default_rng(4).standard_normal(y.shape)
    return u, y, noisy


def test_pure_noise_warns(noise):
    u, y = noise
    for kw in ({}, {"order": 4, "observer_order": 20, "hankel_rows": 20, "hankel_cols": 20, "decimation": 1}):
        with pytest.warns(okid.NoOutputExplainedWarning, match=r"^the model explains less than half of every output "
                                                                r"\(fit_percent -?[0-9.]+ %, -?[0-9.]+ %, each below 50 %\)"):
            res = okid.identify(u, y, DT, **kw)
        assert res.decimation == 1
        # the same numbers as numpy's simulation: the sums of 1000 squares differ in order only
        # (relative round-off ~ N eps = 2e-13 of |y|, far below 1e-9 of the fit)
        np.testing.assert_allclose(res.fit_percent, numpy_fit(res, u, y), rtol=1e-9, atol=1e-9)
        assert np.all(res.fit_percent < 50)                       # explains nothing: a few percent
        assert res.warnings & okid.WarningFlag.NO_OUTPUT_EXPLAINED
        assert res.to_dict()["fit_percent"] == res.fit_percent.tolist()


def test_paper_case_is_quiet(paper):
    u, y, noisy = paper
    # noise-free: the exact model, 100 % to round-off; 2 % noise: |y - yhat| is at least about the
    # noise's 2 % of |y|, so the fit stays below about 98 %, and well above the warning's 50 %
    for record, least, most in ((y, 99.999, 100.0), (noisy, 50.0, 98.5)):
        for kw in ({}, {"order": 4, "observer_order": 20, "hankel_rows": 40, "hankel_cols": 40, "decimation": 1}):
            with warnings.catch_warnings():
                warnings.simplefilter("error", okid.OkidWarning)  # a model that explains: no warning
                res = okid.identify(u, record, DT, **kw)
            if res.fit_percent is None:  # the data chose decimation > 1: no fit
                assert res.decimation > 1
                continue
            np.testing.assert_allclose(res.fit_percent, numpy_fit(res, u, record), rtol=1e-9, atol=1e-9)
            assert np.all((res.fit_percent > least) & (res.fit_percent <= most)), res.fit_percent
            assert not res.warnings & okid.WarningFlag.NO_OUTPUT_EXPLAINED


def test_streaming_result_has_no_fit(paper):
    u, y, _ = paper
    idf = okid.Identifier(1, 2, DT, order=4)
    idf.push(u, y)
    res = idf.identify()
    assert res.fit_percent is None  # no record kept: nothing to compare, and the result says so
    assert res.fit_note == ("no fit: no record came with this model (okid.Identifier keeps none: fixed memory, the "
                            "regressor's sums only); okid.identify(u, y) computes it over the record it is given")
    assert okid.identify(u, y, DT, order=4, decimation=1).fit_note == ""


def test_decimated_result_says_why_it_has_no_fit(paper, tmp_path):
    """A decimated model describes the identifier's filtered record of every K-th sample, which the
    identifier keeps to itself: no fit, and Result.fit_note and the CLI's table say why (issue 27:
    they said nothing)."""
    u, y, _ = paper
    why = ("no fit: the model (decimation 2) describes the identifier's anti-alias-filtered record, one sample kept "
           "in 2, which the identifier keeps to itself; compared with the record given it would measure the filter, "
           "not the model")
    res = okid.identify(u, y, DT, order=4, observer_order=10, hankel_rows=20, hankel_cols=20, decimation=2)
    assert res.decimation == 2 and res.fit_percent is None
    assert res.fit_note == why
    path = tmp_path / "paper.csv"
    np.savetxt(path, np.column_stack([np.arange(len(u)) * DT, u, y]), delimiter=",", header="t,force,acc1,acc2",
               comments="", fmt="%.17g")
    proc = subprocess.run([OKID, "identify", str(path), "--order", "4", "--observer-order", "10", "--hankel-rows", "20",
                           "--hankel-cols", "20", "--decimation", "2"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert f"fit of each output: {why}\n" in proc.stdout


def test_unstable_model_says_why_it_has_no_fit():
    """A model with a pole outside the unit circle grows from rest without bound: its "fit" was the
    growth (-8e38 % on a weak Hayward event, or NaN after an overflow) and set
    NO_OUTPUT_EXPLAINED. Now there is no fit and fit_note says why. The record is noise-free
    x(k+1) = 1.001 x + u, y = x: its one pole, 1.001, is identified to round-off."""
    u = np.random.default_rng(5).standard_normal((3000, 1))
    x, y = 0.0, np.empty((3000, 1))
    for k in range(3000):
        y[k, 0] = x
        x = 1.001 * x + u[k, 0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the unstable pole's own warning
        res = okid.identify(u, y, DT, order=1, observer_order=5, hankel_rows=10, hankel_cols=10, decimation=1)
    radius = abs(res.modes[0].eigenvalue)
    # noise-free, one state: the pole is exact to round-off (0 to 4.4e-16 measured under OpenBLAS's
    # Prescott, Haswell and SkylakeX kernels); 1e-9 leaves room for the rank-deficient observer least
    # squares (p = 5 > n / m, condition 1e16), whose solution differs by kernel while the system
    # Markov parameters that carry the pole do not
    assert abs(radius - 1.001) < 1e-9 and okid.WarningFlag.UNSTABLE_POLE in res.warnings
    assert res.fit_percent is None and okid.WarningFlag.NO_OUTPUT_EXPLAINED not in res.warnings
    assert res.fit_note.startswith("no fit: the model has a pole on or outside the unit circle (|z| up to 1.001)")


def test_warning_classes_share_one_base():
    """okid.OkidWarning is the base of every okid warning: one filter for all of them."""
    for cls in (okid.NoOutputExplainedWarning, okid.NonFiniteSampleWarning, okid.RefinementWarning,
                okid.ResidualWarning):
        assert issubclass(cls, okid.OkidWarning) and issubclass(cls, UserWarning)
    assert issubclass(okid.RefinementWarning, RuntimeWarning)  # as before


def test_cli_reports_the_same_fit(noise, tmp_path):
    u, y = noise
    path = tmp_path / "noise.csv"
    t = np.arange(len(u)) * DT
    np.savetxt(path, np.column_stack([t, u, y]), delimiter=",", header="t,force,acc1,acc2", comments="", fmt="%.17g")
    args = ["--order", "4", "--observer-order", "20", "--hankel-rows", "20", "--hankel-cols", "20", "--decimation", "1"]
    proc = subprocess.run([OKID, "identify", str(path), *args, "--json"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    with pytest.warns(okid.NoOutputExplainedWarning):
        res = okid.identify(u, y, DT, order=4, observer_order=20, hankel_rows=20, hankel_cols=20, decimation=1)
    # one rule: the same number up to the round-off of the two builds' LAPACK (the CLI links the
    # system's, the package scipy-openblas32: the models differ in the last bits), test_package's 1e-7
    np.testing.assert_allclose(doc["fit_percent"], res.to_dict()["fit_percent"], rtol=1e-7, atol=1e-7)
    assert "the model explains less than half of every output" in " ".join(doc["warnings"])
    table = subprocess.run([OKID, "identify", str(path), *args], capture_output=True, text=True, timeout=120).stdout
    assert "warning: the model explains less than half of every output" in table
    assert "fit of each output" in table
