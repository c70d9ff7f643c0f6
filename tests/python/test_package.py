# SPDX-License-Identifier: Apache-2.0
"""The Python package okid: the paper's case against the independent numpy/scipy reference, the
CLI's JSON against Result.to_dict() on the same data, property tests (hypothesis), the caller's
arrays, threads, NaN rows and the memory of a long stream.

Needs the package installed in the interpreter (scripts/setup.sh) and OKID_CLI (ctest sets it).
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import okid

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "reference"))
import make_reference as ref  # noqa: E402  (numpy/scipy, independent of the C code)

OKID_CLI = os.environ.get("OKID_CLI", str(ROOT / "build" / "host_tools" / "cli" / "okid"))


def paper_data(samples=1001, dt=0.01, noise=0.0, seed=2024):
    """The paper's 2-DOF system from the reference's own equations, simulated in numpy from rest."""
    M, R, K = ref.chain([2.0, 3.0], [2.0, 4.0, 3.0], [20.0, 40.0, 30.0])
    Ac, Bc, C, D = ref.state_space(M, R, K, np.array([[1.0], [0.0]]), Ca=np.eye(2))
    A, B = ref.zoh(Ac, Bc, dt)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    x = np.zeros(4)
    y = np.empty((samples, 2))
    for k in range(samples):
        y[k] = C @ x + D @ u[k]
        x = A @ x + B @ u[k]
    if noise:
        y = y + noise * y.std(axis=0) * rng.standard_normal(y.shape)
    return (A, B, C, D, Ac), u, y


# ---- the paper's case ----

def test_paper_case_to_1e9_against_the_reference():
    (A, B, C, D, Ac), u, y = paper_data()
    res = okid.identify(u, y, 0.01, observer_order=20, order=4, hankel_rows=20, hankel_cols=20,
                        zero_initial_state=1)
    exact = ref.modes(Ac, 0.01)
    assert res.order == 4 and len(res.modes) == 2
    for mode, (lam, s, f, zeta, _) in zip(res.modes, exact):
        assert abs(mode.eigenvalue - lam) <= 1e-9 * abs(lam)
        assert abs(mode.frequency_hz - f) <= 1e-9 * f
        assert abs(mode.damping_ratio - zeta) <= 1e-9 * zeta
    Y = ref.markov(A, B, C, D, 40)
    assert res.markov.shape == Y.shape
    assert np.max(np.abs(res.markov - Y)) <= 1e-9 * np.max(np.abs(Y))
    sv = ref.hankel_singular_values(Y, 1, 2, 20, 20)
    np.testing.assert_allclose(res.singular_values[:4], sv[:4], rtol=1e-9)
    np.testing.assert_allclose(res.frequencies_hz, [e[2] for e in exact], rtol=1e-9)
    assert res.warnings & okid.WarningFlag.REGRESSOR_RANK_DEFICIENT  # p = 20 on noise-free data


def test_model_side_matches_the_reference():
    (A, B, C, D, Ac), u, y = paper_data(samples=200)
    a, b, c, d = okid.model.paper_system(0.01)
    np.testing.assert_allclose(a, A, rtol=0, atol=1e-13)
    np.testing.assert_allclose(b, B, rtol=0, atol=1e-13)
    np.testing.assert_allclose(c, C, rtol=0, atol=1e-12)
    y_sim, _ = okid.model.simulate(a, b, c, d, u)
    np.testing.assert_allclose(y_sim, y, rtol=0, atol=1e-11 * np.abs(y).max())


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ldd")
def test_the_extension_needs_no_system_lapack():
    """The extension's LAPACK is scipy-openblas32's, loaded by `import okid`: ldd lists only libc, libm
    and the loader, and the LAPACK symbols it uses are the prefixed scipy_LAPACKE_* ones."""
    extension = okid._core.__file__
    libraries = subprocess.run(["ldd", extension], capture_output=True, text=True, check=True).stdout
    assert not re.search(r"lapack|blas|gfortran|libstdc\+\+", libraries), libraries
    undefined = subprocess.run(["nm", "-D", "--undefined-only", extension], capture_output=True, text=True).stdout
    lapack = re.findall(r"\b\w*LAPACKE_\w+", undefined)
    assert lapack and all(name.startswith("scipy_LAPACKE_d") for name in lapack), lapack


# ---- the vocabulary: keywords from the C header, warning bits from status.h ----

def header_with(pattern):
    for path in sorted((ROOT / "lib" / "include" / "okid").rglob("*.h")):
        text = path.read_text()
        if re.search(pattern, text):
            return text
    raise AssertionError(f"no header under lib/include/okid matches {pattern}")


def test_keywords_are_the_okid_config_fields():
    import inspect
    text = header_with(r"typedef struct okid_config\s*\{")
    body = re.search(r"typedef struct okid_config\s*\{(.*?)\}\s*okid_config;", text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    fields = re.findall(r"(\w+)\s*;", body)
    params = inspect.signature(okid.identify).parameters
    keyword_only = [n for n, p in params.items() if p.kind is p.KEYWORD_ONLY]
    assert [f for f in fields if f not in ("num_inputs", "num_outputs", "dt")] == keyword_only[:len(fields) - 3]
    assert list(params)[:3] == ["u", "y", "dt"]
    # the okid_config fields, then okid_refine_config's behind refine (docs/cli.md), then the
    # progress callback of a long call and decimation_method (the CLI's, before okid_lift; no C field)
    refine_fields = ["max_passes", "step_tolerance", "refine_model"]
    assert keyword_only == list(okid.OPTION_NAMES) + ["refine", *refine_fields, "progress", "decimation_method"]
    text = header_with(r"typedef struct okid_refine_config\s*\{")
    body = re.search(r"typedef struct okid_refine_config\s*\{(.*?)\}\s*okid_refine_config;", text, re.S).group(1)
    assert re.findall(r"(\w+)\s*;", re.sub(r"/\*.*?\*/", "", body, flags=re.S)) == refine_fields
    assert {k: params[k].default for k in refine_fields} == okid.REFINE_DEFAULTS


def test_warning_flags_are_the_c_bits():
    text = header_with(r"enum okid_warning")
    bits = dict(re.findall(r"OKID_W_(\w+)\s*=\s*1u\s*<<\s*(\d+)", text))
    assert {name: 1 << int(shift) for name, shift in bits.items()} == {f.name: f.value for f in okid.WarningFlag}


def test_every_status_of_the_data_has_its_exception():
    """Each okid_status that data or settings can cause maps to its own exception class; the rest
    (pointers, workspace, state, backend arguments: the binding's own contract) to InternalError."""
    from okid import _errors
    text = header_with(r"typedef enum okid_status")
    statuses = {name: int(value) for name, value in re.findall(r"OKID_(E_\w+)\s*=\s*(-\d+)", text)}
    assert {name: getattr(_errors, name) for name in statuses} == statuses  # the Python constants
    internal = {"E_NULL_POINTER", "E_WORKSPACE_TOO_SMALL", "E_WORKSPACE_ALIGNMENT", "E_NOT_INITIALIZED",
                "E_BACKEND_ARGUMENT"}
    for name, value in statuses.items():
        cls = type(_errors.error_for(value))
        assert (cls is okid.InternalError) == (name in internal), (name, cls)


def test_channels_beyond_the_arithmetic_raise_data_range_error():
    a, b, c, d = okid.model.paper_system(dt=0.05)
    u = np.random.default_rng(3).standard_normal((600, 1))
    y, _ = okid.model.simulate(a, b, c, d, u)
    with pytest.raises(okid.DataRangeError) as info:
        okid.identify(u, y * 1e-160, 0.05, order=4)
    assert isinstance(info.value, ValueError) and info.value.status == -14
    res = okid.identify(u * 1e155, y * 1e155, 0.05, order=4, scaling="auto")  # what scaling is for
    assert np.allclose(sorted(res.frequencies_hz), sorted(okid.identify(u, y, 0.05, order=4).frequencies_hz),
                       rtol=1e-6)


# ---- the CLI's JSON ----

CLI_FLAGS = {  # the CLI spellings of main (the vocabulary branch keeps them as aliases)
    "forgetting_factor": "--forgetting", "decimation": "--decimate", "scaling": "--scale",
    "observer_order": "--observer-order", "order": "--order", "hankel_rows": "--hankel-rows",
    "hankel_cols": "--hankel-cols", "rank_tolerance": "--rank-tolerance", "sensing": "--sensing",
    "realization": "--realization", "estimator": "--estimator", "instrument_lags": "--instrument-lags",
}
CLI_ONLY = ("inputs", "outputs", "elapsed_seconds")


def cli_json(u, y, dt, options):
    if not Path(OKID_CLI).exists():
        pytest.skip(f"no okid CLI at {OKID_CLI} (set OKID_CLI)")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "data.csv"
        names = [f"u{i}" for i in range(u.shape[1])] + [f"y{i}" for i in range(y.shape[1])]
        np.savetxt(path, np.hstack([u, y]), delimiter=",", fmt="%.17g", header=",".join(names), comments="")
        args = [OKID_CLI, "identify", "--json", "--dt", repr(dt), "--inputs", str(u.shape[1])]
        for name, value in options.items():
            if name == "zero_initial_state":
                args += ["--zero-initial-state"] if value else []
            elif name == "estimator":
                args += ["--estimator", value.replace("_", "-")]
            else:
                args += [CLI_FLAGS[name], str(value)]
        proc = subprocess.run(args + [str(path)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    return {k: v for k, v in out.items() if k not in CLI_ONLY}


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def numeric(values):
    """The numbers of a (nested) list of numbers, or None when it holds anything else."""
    flat = np.array(values, dtype=object).ravel() if values else np.array([])
    return np.array(flat, dtype=float) if all(is_number(v) for v in flat) else None


INDICATORS = {"emac", "emac_input", "emac_output", "mpc", "cmi", "cmi_min"}


def assert_same_json(a, b, path="$", kappa=1.0):
    """Equal structure, equal integers and strings; reals to 1e-7 kappa of their array's scale: the
    CLI links the system's LAPACK, the package scipy-openblas32, so round-off differs (kappa: how
    much the problem's conditioning magnifies it)."""
    if is_number(a) and is_number(b):
        tol = (1e-4 if "condition" in path else 1e-7) * kappa  # condition numbers amplify round-off by themselves
        if isinstance(a, int) and isinstance(b, int):
            assert a == b, (path, a, b)
        # the modal indicators lie in [0, 1]: round-off is relative to that range, not to a value near 0
        scale = 1.0 if path.rsplit(".", 1)[-1] in INDICATORS else max(abs(a), abs(b), 1e-300)
        assert abs(a - b) <= tol * scale, (path, a, b)
        return
    assert type(a) is type(b), (path, a, b)
    if isinstance(a, dict):
        assert list(a) == list(b), (path, list(a), list(b))
        for k in a:
            assert_same_json(a[k], b[k], f"{path}.{k}", kappa)
    elif isinstance(a, list):
        assert len(a) == len(b), (path, len(a), len(b))
        fa, fb = numeric(a), numeric(b)
        if fa is not None and fb is not None and fa.shape == fb.shape:
            scale = max(np.max(np.abs(fa), initial=0), np.max(np.abs(fb), initial=0), 1e-300)
            assert np.all(np.abs(fa - fb) <= 1e-7 * kappa * scale), (path, a, b)
        else:
            for i, (x, z) in enumerate(zip(a, b)):
                assert_same_json(x, z, f"{path}[{i}]", kappa)
    else:
        assert a == b, (path, a, b)


GRID = [
    dict(observer_order=20, order=4, zero_initial_state=1),
    dict(observer_order=10, order=0),
    dict(),  # every setting chosen: the observer orders combined (docs/quality.md section 8, rule 5b)
    dict(observer_order=20, order=4, realization="combined", sensing="velocity"),
    dict(observer_order=20, order=4, estimator="instrumental"),
    dict(observer_order=10, order=4, decimation=2, hankel_rows=15, hankel_cols=15),
    dict(observer_order=20, order=4, scaling="auto", forgetting_factor=0.9995),
    dict(observer_order=8, order=4, hankel_rows=30, hankel_cols=10, sensing="displacement",
         rank_tolerance=1e-8),
]


@pytest.mark.parametrize("options", GRID, ids=lambda o: ",".join(f"{k}={v}" for k, v in o.items()))
def test_to_dict_equals_the_cli_json(options):
    _, u, y = paper_data(samples=1500, noise=0.02, seed=5)
    res = okid.identify(u, y, 0.01, **options)
    ours, theirs = res.to_dict(), cli_json(u, y, 0.01, options)
    if "poles" in ours:  # order chosen: the rejected poles include noise poles of a high order
        assert_same_rejected_poles(ours, theirs)
    assert_same_json(ours, theirs)
    config = res.to_dict().get("config")  # the JSON's settings object (docs/cli.md), where the CLI writes one
    if config is not None:
        assert list(config) == ["num_inputs", "num_outputs", "observer_order", "order", "hankel_rows", "hankel_cols",
                                "block_rows", "dt", *okid.OPTION_NAMES[5:]]
        assert all(config[k] == res.config[k] for k in okid.OPTION_NAMES), (config, res.config)


def assert_same_rejected_poles(ours, theirs):
    """The verdicts agree; a rejected pole's frequency, damping and eigenvalue agree within the
    realization's conditioning, and its indicators are left out (a noise pole's EMAC moves by 0.4
    between two LAPACKs: it measures round-off). Removes those indicators from both documents."""
    assert [p["verdict"] for p in ours["poles"]] == [p["verdict"] for p in theirs["poles"]]
    kappa = max(ours["realization_condition"], 1.0)
    for a, b in zip(ours["poles"], theirs["poles"]):
        if a["verdict"] == "rejected":
            for key in ("emac", "emac_input", "emac_output", "mpc", "cmi", "msv", "sensor_shape", "shape", "reason"):
                a.pop(key), b.pop(key)
            assert_same_json(a, b, "$.poles[rejected]", kappa)


# ---- property tests ----

@st.composite
def valid_cases(draw):
    r = draw(st.integers(1, 2))
    m = draw(st.integers(1, 3))
    p = draw(st.integers(2, 12))
    alpha = draw(st.integers(4, 15))
    beta = draw(st.integers(4, 15))
    realization = draw(st.sampled_from(["system", "combined"]))
    columns = r + m if realization == "combined" else r
    order = draw(st.integers(0, min(alpha * m, beta * columns, m * p, 6)))
    options = dict(observer_order=p, order=order, hankel_rows=alpha, hankel_cols=beta, realization=realization,
                   sensing=draw(st.sampled_from(["acceleration", "velocity", "displacement"])),
                   zero_initial_state=draw(st.integers(0, 1)))
    samples = draw(st.integers(8 * (r + (r + m) * p), 1200))
    seed = draw(st.integers(0, 2 ** 31))
    return r, m, samples, seed, options


def chain_data(r, m, samples, seed, noise=0.01):
    """Three masses, r forces and m sensors from the library's own model side, plus noise."""
    mass, damping, stiffness = okid.model.chain_model([1.0, 2.0, 1.5], [1, 2, 1, 1], [30, 50, 40, 20])
    ac, bc, c, d = okid.model.state_space(mass, damping, stiffness, np.eye(3)[:, :r], acceleration=np.eye(3)[:m])
    a, b = okid.model.discretize_zoh(ac, bc, 0.02)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, r))
    y, _ = okid.model.simulate(a, b, c, d, u)
    return u, y + noise * y.std(axis=0) * rng.standard_normal(y.shape)


# derandomized: the same 12 cases every run, so that CI judges the code, not the draw (two LAPACKs
# are compared; a case hypothesis finds can be added to GRID above)
@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(valid_cases())
def test_random_valid_cases_agree_with_the_cli(case):
    r, m, samples, seed, options = case
    u, y = chain_data(r, m, samples, seed)
    try:
        res = okid.identify(u, y, 0.02, **options)
    except okid.NotPersistentlyExcitingError:
        with pytest.raises(AssertionError):  # the CLI fails on the same data too
            cli_json(u, y, 0.02, options)
        return
    assert_agree_within_conditioning(res.to_dict(), cli_json(u, y, 0.02, options))


def assert_agree_within_conditioning(a, b):
    """Random cases include ill-conditioned ones (automatic orders of 20 and more states): there two
    LAPACKs may realize the model in another basis (A, B, C, G differ by a similarity where singular
    values are close) and round-off grows with the realization's condition number sigma_1 / sigma_n.
    So the basis-free numbers (Markov parameters, D, singular values, modes, diagnostics) are
    compared, to 1e-7 times that condition number."""
    kappa = max(1.0, a["realization_condition"], b["realization_condition"])
    basis = ("A", "B", "C", "G")
    assert_same_json({k: v for k, v in a.items() if k not in basis}, {k: v for k, v in b.items() if k not in basis},
                     kappa=kappa)


INVALID = st.sampled_from([
    ("observer_order", 0), ("observer_order", 1001), ("hankel_rows", 0), ("hankel_cols", 1001),
    ("order", -1), ("order", 10 ** 4), ("forgetting_factor", 1.5), ("forgetting_factor", -0.1),
    ("rank_tolerance", 1e-20), ("decimation", 65), ("instrument_lags", -1), ("sensing", "strain"),
    ("realization", "full"), ("scaling", "rms"), ("estimator", "least-squares"), ("zero_initial_state", 2),
    ("block_rows", -3), ("observer_order", 2.5),
])


@settings(max_examples=40, deadline=None)
@given(INVALID, st.integers(1, 3), st.integers(1, 3))
def test_invalid_options_raise_a_value_error_naming_the_setting(bad, r, m):
    name, value = bad
    u, y = np.zeros((50, r)), np.zeros((50, m))
    with pytest.raises(okid.ConfigurationError) as info:
        okid.identify(u, y, 0.01, **{name: value})
    assert isinstance(info.value, ValueError)
    assert name in str(info.value)


@pytest.mark.parametrize("dt", [0.0, -0.01, float("nan"), float("inf")])
def test_invalid_dt(dt):
    with pytest.raises(okid.BadParameterError, match="dt"):
        okid.Identifier(1, 2, dt)


def test_sizes_and_shapes():
    with pytest.raises(okid.BadSizeError, match="num_inputs = 65 is outside 1..64"):
        okid.Identifier(65, 1, 0.01)
    with pytest.raises(okid.BadSizeError, match="time along axis 0"):
        okid.identify(np.zeros((100, 1)), np.zeros((90, 2)), 0.01)
    with okid.Identifier(1, 2, 0.01) as idf:
        with pytest.raises(okid.BadSizeError):
            idf.push(np.zeros((10, 2)), np.zeros((10, 2)))
    with pytest.raises(TypeError, match="unknown okid option"):
        okid.Identifier(1, 1, 0.01, hankel=20)


def test_errors_from_the_library():
    _, u, y = paper_data(samples=300)
    with pytest.raises(okid.NotPersistentlyExcitingError, match="not persistently exciting"):
        okid.identify(np.zeros_like(u), y, 0.01, observer_order=5, order=4)
    with pytest.raises(okid.NotEnoughDataError, match="needed"):
        okid.identify(u[:40], y[:40], 0.01, observer_order=20)
    with okid.Identifier(1, 2, 0.01, observer_order=5) as idf:
        with pytest.raises(okid.NotAvailableError):
            idf.predict([0.0])


# ---- streaming, NaN rows, the caller's arrays ----

def without_record_fit(doc):
    """okid.identify()'s to_dict() without what needs the record, which an Identifier does not keep:
    the fit of each output and its warning (a model with a pole on or outside the unit circle has
    no fit: p = 10 on 800 samples, or p = 20 with a 20 x 20 Hankel on 3000 samples of seed 1)."""
    bit = int(okid.WarningFlag.NO_OUTPUT_EXPLAINED)
    out = {k: v for k, v in doc.items() if k != "fit_percent"}
    out["warning_bits"] = doc["warning_bits"] & ~bit
    out["warnings"] = [w for w in doc["warnings"] if w != okid.WarningFlag(bit).describe()[0]]
    return out


def test_samples_blocks_and_one_shot_agree_bit_for_bit():
    _, u, y = paper_data(samples=800, noise=0.01)
    # every setting given: identify() then chooses nothing from the data, as an Identifier
    options = dict(observer_order=10, order=4, hankel_rows=20, hankel_cols=20, decimation=1)
    one_shot = okid.identify(u, y, 0.01, **options).to_dict()
    with okid.Identifier(1, 2, 0.01, **options) as idf:
        for k in range(300):
            idf.push(u[k], y[k])
        idf.push(u[300:550], y[300:550])
        idf.push(u[550:], y[550:])
        assert idf.progress.samples == 800
        # its pole outside the unit circle leaves the one-shot result without a fit, so the two agree whole
        assert "fit_percent" not in one_shot and one_shot["warning_bits"] & int(okid.WarningFlag.UNSTABLE_POLE)
        assert idf.identify().to_dict() == one_shot


def test_predict_is_the_next_sample_on_noise_free_data():
    _, u, y = paper_data(samples=1001)
    with okid.Identifier(1, 2, 0.01, observer_order=20, order=4, zero_initial_state=1) as idf:
        idf.push(u[:900], y[:900])
        idf.identify()
        for k in range(900, 1001):
            np.testing.assert_allclose(idf.predict(u[k]), y[k], rtol=0, atol=1e-9 * np.abs(y).max())
            idf.push(u[k], y[k])


def test_nan_rows_are_rejected_and_nothing_learned_is_lost():
    _, u, y = paper_data(samples=900, noise=0.01)
    y_bad = y.copy()
    y_bad[400, 1] = np.nan
    options = dict(observer_order=10, order=4)
    with okid.Identifier(1, 2, 0.01, **options) as idf:
        idf.push(u[:400], y[:400])
        before = idf.identify()
        with pytest.warns(okid.NonFiniteSampleWarning, match="1 of 500"):
            assert idf.push(u[400:], y_bad[400:]) == 499
        p = idf.progress
        assert (p.samples, p.rejected) == (899, 1)
        after = idf.identify()
    with okid.Identifier(1, 2, 0.01, **options) as ref_idf:  # the same with the gap pushed apart
        ref_idf.push(u[:400], y[:400])
        ref_idf.identify()  # folds the pending rows, as above
        with pytest.warns(okid.NonFiniteSampleWarning):
            ref_idf.push(u[400], y_bad[400])
        ref_idf.push(u[401:], y[401:])
        assert ref_idf.identify().to_dict() == after.to_dict()
    assert after.rows > before.rows
    assert np.all(np.isfinite(after.A))


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(0, 599), min_size=1, max_size=6, unique=True), st.sampled_from([np.nan, np.inf, -np.inf]),
       st.integers(0, 2))
def test_nan_rows_anywhere_are_rejected_as_sample_by_sample(bad_rows, bad_value, column):
    """A block with non-finite rows anywhere: those rows are rejected, the others accepted, and the
    identifier ends as if the block had been pushed one sample at a time (okid_push_block's contract)."""
    _, u, y = paper_data(samples=600, noise=0.01, seed=9)
    u, y = u.copy(), y.copy()
    (u if column == 0 else y)[bad_rows, max(column - 1, 0)] = bad_value
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", okid.NonFiniteSampleWarning)
        with okid.Identifier(1, 2, 0.01, observer_order=4, order=4, block_rows=8) as block:
            assert block.push(u, y) == 600 - len(bad_rows)
            p = block.progress
            assert (p.samples, p.rejected) == (600 - len(bad_rows), len(bad_rows))
            try:
                expected = block.identify().to_dict()
            except okid.NotEnoughDataError:
                expected = None
        with okid.Identifier(1, 2, 0.01, observer_order=4, order=4, block_rows=8) as single:
            for k in range(600):
                single.push(u[k], y[k])
            try:
                got = single.identify().to_dict()
            except okid.NotEnoughDataError:
                got = None
    assert got == expected
    assert expected is None or all(np.isfinite(v) for row in expected["A"] for v in row)


def test_the_callers_arrays_are_never_written():
    _, u, y = paper_data(samples=600, noise=0.01)
    inputs = [u, np.asfortranarray(np.hstack([u, u]))[:, :1], u.astype(np.float32), u[::1].copy()]
    for uu in inputs:
        keep_u, keep_y = uu.copy(), y.copy()
        res = okid.identify(uu, y, 0.01, observer_order=10, order=4)
        with okid.Identifier(1, 2, 0.01, observer_order=10, order=4) as idf:
            idf.push(uu, y)
            idf.identify()
        assert np.array_equal(uu, keep_u) and np.array_equal(y, keep_y)
    with pytest.raises(ValueError):
        res.A[0, 0] = 1.0  # results are read-only
    with pytest.raises(Exception):
        res.order = 3


# ---- threads ----

def test_two_identifiers_in_two_threads_give_the_sequential_results():
    cases = [paper_data(samples=3000, noise=0.02, seed=s)[1:] for s in (1, 2)]
    options = dict(observer_order=20, order=4, hankel_rows=20, hankel_cols=20, decimation=1)  # nothing chosen
    sequential = [without_record_fit(okid.identify(u, y, 0.01, **options).to_dict()) for u, y in cases]
    results = [None, None]

    def work(i):
        with okid.Identifier(1, 2, 0.01, **options) as idf:
            u, y = cases[i]
            for k in range(0, len(u), 100):
                idf.push(u[k:k + 100], y[k:k + 100])
            results[i] = idf.identify().to_dict()

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == sequential


def test_one_identifier_refuses_a_second_thread():
    """While one thread is inside push() (the GIL released), a call from this thread is refused."""
    rng = np.random.default_rng(3)
    u, y = rng.standard_normal((400_000, 1)), rng.standard_normal((400_000, 2))
    idf = okid.Identifier(1, 2, 0.01, observer_order=20)
    pusher = threading.Thread(target=idf.push, args=(u, y))
    refused = 0
    pusher.start()
    while pusher.is_alive():
        try:
            idf.progress
        except okid.ConcurrentUseError:
            refused += 1
    pusher.join()
    assert refused > 0  # this thread ran while the other pushed, and was refused
    assert idf.progress.samples == 400_000


# ---- memory ----

def resident_bytes():
    return int(Path("/proc/self/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="needs /proc")
def test_ten_million_samples_leave_the_resident_memory_flat():
    rng = np.random.default_rng(4)
    u, y = rng.standard_normal((100_000, 1)), rng.standard_normal((100_000, 2))
    with okid.Identifier(1, 2, 0.01, observer_order=4, order=2) as idf:
        idf.push(u, y)
        start = resident_bytes()
        for _ in range(99):
            idf.push(u, y)
        grown = resident_bytes() - start
        assert idf.progress.samples == 10_000_000
        idf.identify()
    assert grown < 4 << 20, f"resident memory grew by {grown} bytes over 10^7 samples"


def test_to_frame_and_stabilization():
    pd = pytest.importorskip("pandas")
    _, u, y = paper_data(samples=1500, noise=0.01)
    with okid.Identifier(1, 2, 0.01, observer_order=20, order=4) as idf:
        idf.push(u, y)
        res = idf.identify()
        frame = res.to_frame()
        assert isinstance(frame, pd.DataFrame) and list(frame["frequency_hz"]) == list(res.frequencies_hz)
        st_ = res.stabilization(12)
        assert [o.order for o in st_.orders] == list(range(2, 13, 2))[:len(st_.orders)]
        assert st_.to_dict()["max_order"] == 12
        idf.identify()
        with pytest.raises(okid.NotAvailableError):
            res.stabilization(12)  # the identifier has moved on


# ---- the package's import graph and what it installs (docs/design.md, "Layers") ----

# The modules of python/okid, lowest first: a module imports only modules of a lower rank (at the
# top of the file or inside a function alike), so the graph has no cycle and no arrow back up.
PACKAGE_LAYERS = {
    "_core": 0,
    "_errors": 1, "_document": 1, "_progress": 1, "_stays_here": 1,
    "_config": 2, "model": 2, "_mode": 2,
    "_statespace": 3,
    "_refine": 4, "_record": 4, "_ambient": 4,
    "_result": 5,
    "_identifier": 6, "plot": 6,
    "__init__": 7,
    "tools": 8, "fleet": 8,  # the user tools, on top of the package
}


def _package_imports():
    """(importer, imported) pairs between the package's modules, from the source (ast)."""
    import ast
    src = ROOT / "python" / "okid"
    pairs = []
    for path in sorted(src.rglob("*.py")):
        rel = path.relative_to(src).with_suffix("")
        module = ".".join(rel.parts)
        package = rel.parts[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
                names = [node.module] if node.module else [a.name for a in node.names]
                pairs += [(module, ".".join(base + tuple(n.split(".")))) for n in names]
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                pairs += [(module, n[len("okid."):]) for n in names if n.startswith("okid.")]
    return pairs


def _layer(module):
    top = module.split(".")[0]  # "_refine", "__init__", "tools" of "tools.plots"
    return PACKAGE_LAYERS[top], top


def test_import_graph_runs_down():
    """_refine <-> _result imported each other through Mode (a late import); now every import of the
    package goes to a lower layer, the subpackages' own imports among themselves aside."""
    problems = []
    for importer, imported in _package_imports():
        (li, ti), (lt, tt) = _layer(importer), _layer(imported)
        if ti == tt and ti in ("tools", "fleet"):
            continue  # inside a user tool's subpackage
        if not lt < li:
            problems.append(f"{importer} imports {imported} (layer {li} -> {lt})")
    assert not problems, problems


def test_no_development_harness_is_installed():
    """The benchmark, the ERA/DC study, the fleet benchmark and the test oracle live in bench/python
    and tests/python, not in the installed package; the user tools stay."""
    import importlib.util
    for gone in ("okid.tools.bench_compare", "okid.tools.era_dc_study", "okid.fleet.bench", "okid.tools.reference",
                 "okid.tools.verify_fmu", "okid.tools.fmu_runs"):
        assert importlib.util.find_spec(gone) is None, gone
    for kept in ("okid.tools.fmu_generator", "okid.tools.stabilization", "okid.tools.plots", "okid.fleet.cli"):
        assert importlib.util.find_spec(kept) is not None, kept
