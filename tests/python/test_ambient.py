# SPDX-License-Identifier: Apache-2.0
"""Output-only identification (okid identify --inputs 0, docs/ambient.md) of a simulated ambient
record against the exact modes: the paper's 2-DOF system (M, R, K of its eq. 1-9, as in
tests/reference/make_reference.py) driven by unmeasured unit white forces on both masses, the two
accelerations with 5 % white sensor noise, simulated here with SciPy (exact zero-order hold), the
exact modes from NumPy's eigenvalues of the continuous model.

Tolerances are statistical (tests/test_ambient.c and bench/ambient_spread.c): the frequency's
standard deviation is about c sqrt(zeta / (omega T)) and the damping ratio's relative one
c' / sqrt(zeta omega T), T the record's duration, with c <= 3.6 and c' <= 4.2 measured over 30
seeds; the checks allow 4 c and 4 c'.
"""
import json
import math
import os
import subprocess

import numpy as np
import pytest
import scipy.linalg
import scipy.signal

OKID = os.environ.get("OKID_CLI", "okid")
DT = 0.05
SAMPLES = 40000
FREQ_FACTOR, DAMP_FACTOR = 4 * 3.7, 4 * 4.2


def paper_model():
    """Continuous state space of the paper's plant with a force on each mass, accelerations out."""
    mass = np.diag([2.0, 3.0])
    damping = np.array([[6.0, -4.0], [-4.0, 7.0]])
    stiffness = np.array([[60.0, -40.0], [-40.0, 70.0]])
    minv = np.linalg.inv(mass)
    ac = np.block([[np.zeros((2, 2)), np.eye(2)], [-minv @ stiffness, -minv @ damping]])
    bc = np.vstack([np.zeros((2, 2)), minv])
    c = np.hstack([-minv @ stiffness, -minv @ damping])
    d = minv
    return ac, bc, c, d


def exact_modes():
    """(frequency [Hz], damping ratio) of each pair, by increasing frequency."""
    poles = np.linalg.eigvals(paper_model()[0])
    poles = sorted((p for p in poles if p.imag > 0), key=abs)
    return [(abs(p) / (2 * math.pi), -p.real / abs(p)) for p in poles]


def ambient_record(samples=SAMPLES, seed=11, noise=0.05):
    ac, bc, c, d = paper_model()
    a, b, _, _, _ = scipy.signal.cont2discrete((ac, bc, c, d), DT, method="zoh")
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 2))
    x = np.zeros(4)
    y = np.empty((samples, 2))
    for t in range(samples):  # y = C x + D u, x+ = A x + B u (scipy's dlsim, written out)
        y[t] = c @ x + d @ u[t]
        x = a @ x + b @ u[t]
    y += noise * y.std(axis=0) * rng.standard_normal(y.shape)
    return y


def assert_exact_modes(modes, duration):
    pairs = [m for m in modes if m["is_pair"]]
    assert len(pairs) == 2, modes
    for got, (f, zeta) in zip(pairs, exact_modes()):
        omega = 2 * math.pi * f
        assert got["frequency_hz"] == pytest.approx(f, rel=FREQ_FACTOR * math.sqrt(zeta / (omega * duration)))
        assert got["damping_ratio"] == pytest.approx(zeta, rel=DAMP_FACTOR / math.sqrt(zeta * omega * duration))


@pytest.fixture(scope="module")
def ambient_csv(tmp_path_factory):
    y = ambient_record()
    path = tmp_path_factory.mktemp("ambient") / "ambient.csv"
    t = DT * np.arange(len(y))
    np.savetxt(path, np.column_stack([t, y]), delimiter=",", header="t,acc1,acc2", comments="", fmt="%.17g")
    return path


def run(*args):
    return subprocess.run([OKID, *map(str, args)], capture_output=True, text=True, timeout=120)


def test_exact_modes_from_numpy_match_the_reference():
    """The model here is the paper's (tests/reference/reference_data.h: 0.50329, 1.04769 Hz)."""
    (f1, z1), (f2, z2) = exact_modes()
    assert f1 == pytest.approx(0.5032921210448703, rel=1e-12) and f2 == pytest.approx(1.0476860961782999, rel=1e-12)
    assert z1 == pytest.approx(0.15811388300841872, rel=1e-12) and z2 == pytest.approx(0.3291402943021918, rel=1e-12)


def test_cli_identifies_the_exact_modes(ambient_csv):
    proc = run("identify", "--inputs", 0, "--order", 4, "--hankel-rows", 20, "--json", ambient_csv)
    assert proc.returncode == 0, proc.stderr
    res = json.loads(proc.stdout)
    assert res["inputs"] == [] and res["outputs"] == ["acc1", "acc2"] and res["references"] == ["acc1", "acc2"]
    assert res["config"] == {"num_inputs": 0, "num_outputs": 2, "num_references": 0, "hankel_rows": 20, "order": 4,
                             "dt": DT, "sensing": "acceleration", "segments": 0, "segment_samples": 0}
    assert res["segments_used"] == 0 and "frequency_std" not in res
    assert res["order"] == 4 and res["samples"] == SAMPLES and res["pairs"] == SAMPLES - 40
    assert np.array(res["correlations"]).shape == (2, 2 * 41)
    assert_exact_modes(res["modes"], SAMPLES * DT)


def test_cli_correlations_are_numpys(ambient_csv):
    """R(k) = sum y(t+k) y(t)' / (N - k) of the mean-removed record, against NumPy."""
    res = json.loads(run("identify", "--inputs", 0, "--order", 4, "--hankel-rows", 3, "--json", ambient_csv).stdout)
    data = np.loadtxt(ambient_csv, delimiter=",", skiprows=1)[:, 1:]
    y = data - data.mean(axis=0)
    r = np.array(res["correlations"])
    n = len(y)
    for k in range(7):
        want = y[k:].T @ y[:n - k] / (n - k)
        np.testing.assert_allclose(r[:, 2 * k:2 * k + 2], want, rtol=1e-10, atol=1e-12 * np.abs(want).max())


def assert_physical_modes(res_modes, poles, order):
    """Without an order: the physical modes are the first exact mode alone (16 %; the second, 33 %,
    is under the damping limit 1/sqrt(2) of the input-output path, but its EMAC is below 0.5 at
    these Hankel sizes: it has decayed within them), the model of order 4 holds both, the first
    with the verdict physical, the second rejected for its EMAC."""
    assert_exact_modes_first(res_modes)
    assert order == 4
    pairs = [p for p in poles if p["is_pair"]]
    assert [p["verdict"] for p in pairs] == ["physical", "rejected"]
    assert "EMAC below" in pairs[1]["reason"]
    assert_exact_modes(pairs, SAMPLES * DT)


def assert_exact_modes_first(modes):
    (f, zeta), _ = exact_modes()
    omega, duration = 2 * math.pi * f, SAMPLES * DT
    assert len(modes) == 1, modes
    assert modes[0]["frequency_hz"] == pytest.approx(f, rel=FREQ_FACTOR * math.sqrt(zeta / (omega * duration)))
    assert modes[0]["damping_ratio"] == pytest.approx(zeta, rel=DAMP_FACTOR / math.sqrt(zeta * omega * duration))


@pytest.fixture(scope="module")
def chosen_json(ambient_csv):
    """okid identify --inputs 0 --json with nothing chosen by the user."""
    return json.loads(run("identify", "--inputs", 0, "--json", ambient_csv).stdout)


def test_cli_chooses_the_hankel_size_and_the_physical_modes(ambient_csv, chosen_json):
    """Without --hankel-rows, L dt is one period at the band's 5 % frequency, checked at 2/3 and 4/3
    of it; without --order, the physical modes stable across orders and two of the three sizes."""
    res = chosen_json
    L = res["config"]["hankel_rows"]
    assert 20 <= L <= 60  # the slowest period is 2 s: about 40 samples
    chosen = res["chosen"]
    assert chosen["hankel_rows"]["value"] == L and chosen["hankel_rows"]["chosen"] is True
    assert chosen["hankel_windows"] == [L, round(2 * L / 3), round(4 * L / 3)] and chosen["max_order"] == 60
    assert chosen["order"] == {"value": 4, "chosen": True,
                               "reason": "the lowest order whose poles hold every physical mode"}
    assert res["config"]["order"] == 0 and res["order"] == 4  # as given; the model's order at the top
    assert_physical_modes(res["modes"], res["poles"], res["order"])
    assert res["modes"][0]["windows"] >= 2 and res["modes"][0]["of_windows"] == 3
    table = run("identify", "--inputs", 0, ambient_csv)
    assert table.returncode == 0 and "output-only" in table.stdout and "chosen: one period" in table.stdout
    assert "physical modes: 1" in table.stdout


def test_cli_one_reference(ambient_csv):
    res = json.loads(run("identify", "--inputs", 0, "--order", 4, "--hankel-rows", 20, "--references", "acc2",
                         "--json", ambient_csv).stdout)
    assert res["references"] == ["acc2"] and res["config"]["num_references"] == 1
    assert len(res["G"][0]) == 1
    pairs = [m for m in res["modes"] if m["is_pair"]]
    # one reference (the second mass): measured spread 9.8 and 8.4 times the figures (tests/test_ambient.c)
    for got, (f, zeta) in zip(pairs, exact_modes()):
        omega = 2 * math.pi * f
        assert got["frequency_hz"] == pytest.approx(f, rel=4 * 9.8 * math.sqrt(zeta / (omega * SAMPLES * DT)))


@pytest.mark.parametrize("args,says", [
    (("--observer-order", 10), "--observer-order/--observer-seconds does not apply to output-only"),
    (("--refine",), "--refine does not apply"),
    (("--estimator", "instrumental"), "--estimator does not apply"),
    (("--order", 99, "--hankel-rows", 20), "--order 99: valid 0..40"),
    (("--references", "acc3"), "'acc3' is not one of the output columns"),
    (("--references", 3), "--references 3: 1..2"),
    (("--hankel-rows", 30000), "for --hankel-rows (okid_config.hankel_rows): out of range; valid: 1..1000"),
])
def test_cli_refusals_are_one_line(ambient_csv, args, says):
    proc = run("identify", "--inputs", 0, *args, ambient_csv)
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: ") and says in lines[0], proc.stderr


def test_cli_references_need_inputs_zero(ambient_csv):
    proc = run("identify", "--references", "acc1", ambient_csv)
    assert proc.returncode == 2 and "--references applies to output-only" in proc.stderr
    proc = run("identify", "--segments", 4, ambient_csv)
    assert proc.returncode == 2 and "--segments applies to output-only" in proc.stderr


def test_segments_give_each_mode_a_calibrated_std(ambient_csv):
    """16 segments: within 92-98 % of 100 seeds the exact value lay within 2 std (tests/test_ambient.c);
    one record: within 4 std, and the CLI and Python give the same std (one library call)."""
    import okid
    cli = json.loads(run("identify", "--inputs", 0, "--order", 4, "--hankel-rows", 20, "--segments", 16, "--json",
                         ambient_csv).stdout)
    assert cli["config"]["segments"] == 16 and cli["segments_used"] == 16
    data = np.loadtxt(ambient_csv, delimiter=",", skiprows=1)[:, 1:]
    res = okid.identify_ambient(data, DT, order=4, hankel_rows=20, segments=16)
    assert res.segments_used == 16 and res.frequency_std.shape == (2,)
    np.testing.assert_allclose(cli["frequency_std"], res.frequency_std, rtol=1e-9)
    np.testing.assert_allclose(cli["damping_std"], res.damping_std, rtol=1e-9)
    for mode, sf, sz, (f, zeta) in zip(res.modes, res.frequency_std, res.damping_std, exact_modes()):
        assert abs(mode.frequency_hz - f) <= 4 * sf and abs(mode.damping_ratio - zeta) <= 4 * sz
    assert okid.identify_ambient(data, DT, order=4, hankel_rows=20).frequency_std is None


def test_cli_too_short_a_record(tmp_path):
    path = tmp_path / "short.csv"
    y = ambient_record(samples=30)
    np.savetxt(path, np.column_stack([DT * np.arange(30), y]), delimiter=",", header="t,a,b", comments="")
    proc = run("identify", "--inputs", 0, "--hankel-rows", 20, path)
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.splitlines() == ["okid: not enough data: 30 samples, at least 2 L + 1 = 41 for L = 20"]


# ---- Python: okid.identify_ambient, the same library call and the same names ----

def test_python_identifies_the_exact_modes_and_agrees_with_the_cli(ambient_csv):
    import okid
    data = np.loadtxt(ambient_csv, delimiter=",", skiprows=1)[:, 1:]
    before = data.copy()
    res = okid.identify_ambient(data, DT, order=4, hankel_rows=20)
    assert np.array_equal(data, before)  # the caller's array is never written
    assert res.order == 4 and res.samples == SAMPLES and res.pairs == SAMPLES - 40 and res.references == (0, 1)
    assert res.correlations.shape == (2, 82) and res.G.shape == (4, 2) and not res.correlations.flags.writeable
    assert_exact_modes([{"is_pair": m.is_pair, "frequency_hz": m.frequency_hz, "damping_ratio": m.damping_ratio}
                        for m in res.modes], SAMPLES * DT)
    cli = json.loads(run("identify", "--inputs", 0, "--order", 4, "--hankel-rows", 20, "--json", ambient_csv).stdout)
    # the CSV holds the record to the last bit (%.17g): the sums (plain loops) are the same bits; the
    # SVD runs in two LAPACK builds (the CLI's OpenBLAS archive, the wheel's scipy-openblas), whose
    # rounding differs: eps times the realization's condition (about 4 here), with a wide margin
    np.testing.assert_array_equal(np.array(cli["correlations"]), res.correlations)
    np.testing.assert_allclose([m["frequency_hz"] for m in cli["modes"]], res.frequencies_hz, rtol=1e-12)
    with pytest.raises(Exception):
        res.order = 3  # frozen


def test_python_chooses_the_settings_and_the_modes_as_the_cli_does(ambient_csv, chosen_json):
    import okid
    data = np.loadtxt(ambient_csv, delimiter=",", skiprows=1)[:, 1:]
    res = okid.identify_ambient(data, DT)
    cli = chosen_json
    assert res.hankel_rows == cli["config"]["hankel_rows"] and res.band_hz > 0 and res.order == cli["order"]
    assert isinstance(res.modes[0], okid.SelectedMode) and isinstance(res.poles[0], okid.Pole)
    assert dict(res.chosen["order"]) == cli["chosen"]["order"]
    assert list(res.chosen["hankel_windows"]) == cli["chosen"]["hankel_windows"]
    assert_physical_modes([{"frequency_hz": m.frequency_hz, "damping_ratio": m.damping_ratio} for m in res.modes],
                          [{"is_pair": p.is_pair, "frequency_hz": p.frequency_hz, "damping_ratio": p.damping_ratio,
                            "verdict": p.verdict, "reason": p.reason} for p in res.poles], res.order)
    # the same sums and the same selection: the CLI's figures to the SVD backends' rounding
    np.testing.assert_allclose(res.frequencies_hz, [m["frequency_hz"] for m in cli["modes"]], rtol=1e-9)
    with_order = okid.identify_ambient(data, DT, order=4, hankel_rows=res.hankel_rows)
    assert with_order.poles is None and with_order.chosen is None


def test_python_one_reference_and_a_gap():
    import okid
    y = ambient_record(samples=8000)
    y[100, 1] = np.nan
    with pytest.warns(okid.NonFiniteSampleWarning):
        res = okid.identify_ambient(y, DT, order=4, hankel_rows=10, references=[1])
    assert res.references == (1,) and res.G.shape == (4, 1)
    assert res.samples == 7999 and res.pairs == (100 - 20) + (8000 - 101 - 20)


@pytest.mark.parametrize("kwargs,error,says", [
    ({"order": 99, "hankel_rows": 20}, "BadOrderError", "order = 99: valid 0..40"),
    ({"references": [2]}, "BadParameterError", "reference_channels = 2: valid 0..1"),
    ({"hankel_rows": 5000}, "BadSizeError", "hankel_rows = 5000: valid 1..1000"),
    ({"sensing": "strain"}, "BadParameterError", "sensing = 'strain'"),
    ({"segments": 65}, "BadSizeError", "segments = 65: valid 0..64"),
])
def test_python_refusals_name_the_setting(kwargs, error, says):
    import okid
    with pytest.raises(getattr(okid, error)) as info:
        okid.identify_ambient(ambient_record(samples=2000), DT, **kwargs)
    assert says in str(info.value)


def test_python_too_short_and_bad_shapes():
    import okid
    with pytest.raises(okid.NotEnoughDataError):
        okid.identify_ambient(np.zeros((30, 2)), DT, hankel_rows=20)
    with pytest.raises(okid.BadSizeError):
        okid.identify_ambient(np.zeros(30), DT)
