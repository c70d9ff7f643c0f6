# SPDX-License-Identifier: Apache-2.0
"""Identification quality through the CLI: diagnostics, modal indicators and the stabilization
diagram against numpy (an ERA and the indicators of okid/modal_indicators.h written again here from
the Markov parameters the CLI prints, and the exact paper model), and the diagram's PNG."""
import json

import numpy as np
import pytest
from scipy.linalg import expm

from okid.tools.stabilization import main as stabilization_main
from okid.tools.stabilization import plot_stabilization, poles
from test_cli import PAPER, PAPER_SETTINGS, chain_matrices, continuous_matrix, exact_eigenvalues, run

NOISY = ("--observer-order", 60, "--hankel-rows", 100, "--hankel-cols", 100, "--zero-initial-state")


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    folder = tmp_path_factory.mktemp("quality")
    run("simulate", "--output", folder / "clean.csv")
    run("simulate", "--noise", 0.02, "--seed", 3, "--output", folder / "noisy.csv")
    return folder


def identify(path, *extra):
    return json.loads(run("identify", "--json", *extra, path).stdout)


# ---- an independent ERA and the indicators' definitions, in numpy ----

def coherence(p, q):
    big, small = max(abs(p), abs(q)), min(abs(p), abs(q))
    phase = abs(np.angle(q * np.conj(p)))
    return 0.0 if big == 0 or phase >= np.pi / 4 else small / big * (1 - phase / (np.pi / 4))


def numpy_indicators(res, m, r):
    """EMAC (output, input), MPC and MSV of each mode (Im lambda > 0) of an ERA on res["markov"]."""
    alpha, beta, n = res["config"]["hankel_rows"], res["config"]["hankel_cols"], res["order"]
    Y = np.array(res["markov"])
    block = lambda k: Y[:, k * r:(k + 1) * r]  # noqa: E731
    H0 = np.block([[block(i + j + 1) for j in range(beta)] for i in range(alpha)])
    H1 = np.block([[block(i + j + 2) for j in range(beta)] for i in range(alpha)])
    U, s, Vt = np.linalg.svd(H0)
    root = np.sqrt(s[:n])
    P, Q = U[:, :n] * root, root[:, None] * Vt[:n]
    A = (U[:, :n] / root).T @ H1 @ (Vt[:n].T / root)
    lam, psi = np.linalg.eig(A)
    inv = np.linalg.inv(psi)
    c, o = P[:m] @ psi, P[-m:] @ psi
    b, g = inv @ Q[:, :r], inv @ Q[:, -r:]
    out = []
    for i in np.flatnonzero(lam.imag > 0):
        w_out, w_in = np.abs(c[:, i]) ** 2, np.abs(b[i]) ** 2
        e_out = sum(w * coherence(c[a, i] * lam[i] ** (alpha - 1), o[a, i]) for a, w in enumerate(w_out)) / w_out.sum()
        e_in = sum(w * coherence(b[i, l] * lam[i] ** (beta - 1), g[i, l]) for l, w in enumerate(w_in)) / w_in.sum()
        phi = c[:, i]
        mpc = abs(phi @ phi) ** 2 / np.vdot(phi, phi).real ** 2
        msv = np.sqrt(np.linalg.norm(c[:, i]) * np.linalg.norm(b[i]) * sum(abs(lam[i]) ** np.arange(alpha + beta - 1)))
        out.append((lam[i], e_out, e_in, mpc, msv))
    return out


def paper_exact_msv(alpha, beta):
    """MSV of the exact ZOH model of the paper (acceleration outputs, force on mass 1), Im lambda > 0."""
    masses, dampers, springs, dt = PAPER
    M, R, K = chain_matrices(masses, dampers, springs)
    Ac = continuous_matrix(masses, dampers, springs)
    Bc = np.concatenate([np.zeros(2), np.linalg.inv(M)[:, 0]])[:, None]
    Ad = expm(Ac * dt)
    Bd = np.linalg.solve(Ac, (Ad - np.eye(4)) @ Bc)
    C = Ac[2:]  # accelerations: the second block row of Ac
    lam, psi = np.linalg.eig(Ad)
    c, b = C @ psi, np.linalg.solve(psi, Bd)
    keep = np.flatnonzero(lam.imag > 0)
    return {lam[i]: np.sqrt(np.linalg.norm(c[:, i]) * np.linalg.norm(b[i]) *
                            sum(abs(lam[i]) ** np.arange(alpha + beta - 1))) for i in keep}


def match(modes, lam):
    return min(modes, key=lambda md: abs(complex(*md["eigenvalue"]) - lam))


# ---- item 3: diagnostics ----

def numpy_conditions(csv, p):
    """1-norm condition numbers of the column-equilibrated triangular factor of the regressor (row
    k = [u(k), u(k-1..k-p), y(k-1..k-p)], from rest) and of its input columns, by numpy's QR
    (the factor is unique up to row signs, which the 1-norm condition ignores)."""
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    u, y = data[:, 1], data[:, 2:]
    past = lambda x, j: np.concatenate([np.zeros((j,) + x.shape[1:]), x[:len(x) - j]])  # noqa: E731
    phi = np.column_stack([u] + [past(u, j) for j in range(1, p + 1)] + [past(y, j) for j in range(1, p + 1)])
    R = np.linalg.qr(phi / np.linalg.norm(phi, axis=0), mode="r")
    kappa = lambda T: np.linalg.norm(T, 1) * np.linalg.norm(np.linalg.inv(T), 1)  # noqa: E731
    return kappa(R), kappa(R[:p + 1, :p + 1])


@pytest.mark.parametrize("name, p", [("clean.csv", 2), ("noisy.csv", 60)])
def test_condition_numbers_match_numpy(data, name, p):
    res = identify(data / name, "--observer-order", p, "--order", 4, "--zero-initial-state")
    lsq, inputs = numpy_conditions(data / name, p)
    assert res["lsq_condition"] == pytest.approx(lsq, rel=1e-6)
    assert res["input_condition"] == pytest.approx(inputs, rel=1e-9)


def test_noise_free_diagnostics(data):
    res = identify(data / "clean.csv", *PAPER_SETTINGS)
    assert res["regressor_rank"] == res["regressor_rank_expected"] == 1 * 21 + 4
    assert any("noise-free" in w for w in res["warnings"])
    assert any("Hankel span" in w for w in res["warnings"])  # 0.4 s against a 2 s period
    assert res["input_condition"] < 3 and res["lsq_condition"] > 1e12
    sv = res["singular_values"]
    assert res["realization_condition"] == pytest.approx(sv[0] / sv[3], rel=1e-12)


def test_noisy_recommended_settings_have_no_warning(data):
    res = identify(data / "noisy.csv", *NOISY, "--order", 4)
    assert res["warnings"] == [] and res["warning_bits"] == 0
    assert res["regressor_rank"] == res["regressor_columns"] == 181


# ---- item 4: modal indicators ----

def test_indicator_contract_and_noise_free_values(data):
    res = identify(data / "clean.csv", *PAPER_SETTINGS)
    exact_msv = paper_exact_msv(res["config"]["hankel_rows"], res["config"]["hankel_cols"])
    for lam, want in exact_msv.items():
        md = match(res["modes"], lam)
        for key in ("emac", "mpc", "cmi"):
            assert md[key] == pytest.approx(1, abs=1e-6), key
        assert md["msv"] == pytest.approx(want, rel=1e-6)  # similarity-invariant: exact model = realization


def test_indicators_match_numpy_on_overstated_noisy_model(data):
    res = identify(data / "noisy.csv", *NOISY, "--order", 8)
    ref = numpy_indicators(res, m=2, r=1)
    assert len(ref) == sum(md["is_pair"] for md in res["modes"]) == 4
    for lam, e_out, e_in, mpc, msv in ref:
        md = match(res["modes"], lam)
        assert abs(complex(*md["eigenvalue"]) - lam) < 1e-9
        assert md["emac_output"] == pytest.approx(e_out, abs=1e-7)
        assert md["emac_input"] == pytest.approx(e_in, abs=1e-7)
        assert md["mpc"] == pytest.approx(mpc, abs=1e-9)
        assert md["msv"] == pytest.approx(msv, rel=1e-7)
        assert md["cmi"] == pytest.approx(e_out * e_in * mpc, abs=1e-7)
    # The two physical modes are consistent, the computational ones are not.
    exact = exact_eigenvalues(*PAPER)
    for md in res["modes"]:
        physical = min(abs(complex(*md["eigenvalue"]) - exact)) < 1e-3
        assert (md["cmi"] > 0.9) if physical else (md["cmi"] < 0.1), md


# ---- item 5: stabilization diagram ----

def test_stabilization_json_and_plot(data, tmp_path):
    res = identify(data / "noisy.csv", *NOISY, "--order", 4, "--stabilization", 16)
    st = res["stabilization"]
    assert st["max_order"] == 16 and st["step"] == 2 and [o["order"] for o in st["orders"]] == list(range(2, 17, 2))
    exact_f = np.abs(np.log(exact_eigenvalues(*PAPER))) / (2 * np.pi * PAPER[3])
    for entry in st["orders"]:
        assert len(entry["modes"]) <= entry["order"]
        for md in entry["modes"]:
            assert 0 <= md["cmi"] <= 1 and 0 <= md["emac"] <= 1 and 0 <= md["mpc"] <= 1
        if entry["order"] >= 4:  # both physical modes at every order, within 1 % (2 % noise)
            freqs = np.array([md["frequency_hz"] for md in entry["modes"]])
            assert all(np.min(np.abs(freqs - f)) < 0.01 * f for f in exact_f), entry["order"]
    stable = [p for p in poles(res) if p[3] == "stable"]
    assert stable and all(min(abs(p[1] - f) / f for f in exact_f) < 0.01 for p in stable if p[4] > 0.5)
    png = plot_stabilization(res, tmp_path / "diagram.png", max_frequency=50)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10000
    (tmp_path / "res.json").write_text(json.dumps(res))
    assert stabilization_main([str(tmp_path / "res.json"), "--output", str(tmp_path / "cli.png")]) == 0
    assert (tmp_path / "cli.png").exists()


def test_stabilization_usage(data, tmp_path):
    plain = identify(data / "clean.csv", *PAPER_SETTINGS)
    (tmp_path / "plain.json").write_text(json.dumps(plain))
    assert stabilization_main([str(tmp_path / "plain.json"), "--output", str(tmp_path / "x.png")]) == 1
    proc = run("identify", "--stabilization", 41, *PAPER_SETTINGS, data / "clean.csv", check=False)
    assert proc.returncode == 2 and "at most the Hankel size" in proc.stderr
    table = run("identify", *NOISY, "--order", 4, "--stabilization", 8, data / "noisy.csv").stdout
    assert "EMAC    MPC    CMI" in table and "condition numbers: least squares" in table
    rows = [line for line in table.splitlines() if line.strip().startswith(("6:", "8:"))]
    assert len(rows) == 2 and all(line.count("s") >= 2 for line in rows), table  # both modes stable
    # Noise-free: the Hankel rank (4) caps the diagram.
    st = identify(data / "clean.csv", *PAPER_SETTINGS, "--stabilization", 10)["stabilization"]
    assert st["rank_limit"] == 4 and [o["order"] for o in st["orders"]] == [2, 4]


# ---- items 1, 2, 6: decimation, scaling, instrumental variables ----

def exact_frequencies():
    return np.sort(np.abs(np.log(exact_eigenvalues(*PAPER))) / (2 * np.pi * PAPER[3]))


def frequency_error(res):
    f = np.sort([md["frequency_hz"] for md in res["modes"] if md["is_pair"]])
    return np.max(np.abs(f - exact_frequencies()) / exact_frequencies()) if len(f) == 2 else np.inf


def write_csv(path, t, u, y):
    np.savetxt(path, np.column_stack([t, u, y]), delimiter=",", header="t,force,acc1,acc2", comments="",
               fmt="%.17g")
    return path


def test_decimation_equals_scipy_filter_then_identify(data, tmp_path):
    """--decimation K = scipy's Butterworth (order 2, edge 0.5/K of the Nyquist frequency) on every
    column, every K-th row kept, then plain identification at K dt."""
    import scipy.signal as ss
    K = 2
    raw = np.loadtxt(data / "noisy.csv", delimiter=",", skiprows=1)
    filtered = ss.sosfilt(ss.butter(2, 0.5 / K, output="sos"), raw[:, 1:], axis=0)[::K]
    path = write_csv(tmp_path / "decimated.csv", raw[::K, 0], filtered[:, :1], filtered[:, 1:])
    settings = ("--observer-order", 30, "--hankel-rows", 50, "--hankel-cols", 50, "--order", 4, "--zero-initial-state")
    ours = identify(data / "noisy.csv", *settings, "--decimation", K)
    ref = identify(path, *settings)
    assert ours["decimation"] == K and ours["config"]["dt"] == pytest.approx(0.01) and ours["dt"] == pytest.approx(0.02)
    assert ours["samples"] == len(raw) and ours["rows"] == ref["rows"] == len(filtered)
    np.testing.assert_allclose(ours["markov"], ref["markov"], rtol=1e-7, atol=1e-9 * np.max(np.abs(ref["markov"])))
    # the claim on this record: same p, alpha, beta, K = 1 biased, K = 2 within 1 %
    assert frequency_error(ours) < 0.01
    assert frequency_error(identify(data / "noisy.csv", *settings)) > 0.02
    # horizons in seconds give the same counts: p = 0.6 s / 0.02 s, alpha = beta = 1 s / 0.02 s
    seconds = identify(data / "noisy.csv", "--decimation", K, "--observer-seconds", 0.6, "--hankel-seconds", 1.0,
                       "--order", 4, "--zero-initial-state")
    assert tuple(seconds["config"][k] for k in ("observer_order", "hankel_rows", "hankel_cols")) == (30, 50, 50)
    assert seconds["markov"] == ours["markov"]


def test_scaling_makes_units_irrelevant(data, tmp_path):
    raw = np.loadtxt(data / "noisy.csv", delimiter=",", skiprows=1)
    mm = write_csv(tmp_path / "mm.csv", raw[:, 0], raw[:, 1:2] / 1000, raw[:, 2:] * 1000)  # kN and mm
    settings = (*NOISY, "--order", 4, "--scaling", "auto", "--realization", "combined")
    si, other = identify(data / "noisy.csv", *settings), identify(mm, *settings)
    assert si["config"]["scaling"] == "auto"
    for a, b in zip(si["modes"], other["modes"]):
        assert b["frequency_hz"] == pytest.approx(a["frequency_hz"], rel=1e-10)
        assert b["damping_ratio"] == pytest.approx(a["damping_ratio"], rel=1e-10)
    np.testing.assert_allclose(other["C"], 1000 * np.array(si["C"]), rtol=1e-8)
    np.testing.assert_allclose(other["B"], 1000 * np.array(si["B"]), rtol=1e-8)
    np.testing.assert_allclose(other["D"], 1e6 * np.array(si["D"]), rtol=1e-8)
    np.testing.assert_allclose(other["G"], np.array(si["G"]) / 1000, rtol=1e-8)


def numpy_iv_markov(csv, p, lags, count):
    """Extended IV estimate of eq. 50 written here: min |Z'Phi X - Z'y| with z(k) = u(k .. k-L), rows from
    rest (zero history), then eq. 51."""
    d = np.loadtxt(csv, delimiter=",", skiprows=1)
    u, y = d[:, 1], d[:, 2:]
    past = lambda x, j: np.concatenate([np.zeros((j,) + x.shape[1:]), x[:len(x) - j]])  # noqa: E731
    phi = np.column_stack([u] + [past(u, j) for j in range(1, p + 1)] + [past(y, j) for j in range(1, p + 1)])
    z = np.column_stack([past(u, j) for j in range(lags + 1)])
    X = np.linalg.lstsq(z.T @ phi, z.T @ y, rcond=None)[0]  # rows: D, Ybar1_1..p, -Ybar2_1..p
    ybar1, ybar2 = X[1:p + 1].T, -X[p + 1:].reshape(p, 2, 2).transpose(0, 2, 1)
    Y = [X[0][:, None]]
    for k in range(1, count):
        Yk = (ybar1[:, k - 1][:, None] if k <= p else np.zeros((2, 1)))
        Yk = Yk - sum(ybar2[i - 1] @ Y[k - i] for i in range(1, min(k, p) + 1))
        Y.append(Yk)
    return np.hstack(Y)


def test_instrumental_estimator_matches_numpy(tmp_path):
    csv = tmp_path / "bench20.csv"
    run("simulate", "--dt", 0.05, "--samples", 2001, "--noise", 0.2, "--seed", 11, "--output", csv)
    settings = ("--observer-order", 10, "--order", 4, "--zero-initial-state")
    iv = identify(csv, *settings, "--estimator", "instrumental")
    assert iv["config"]["estimator"] == "instrumental" and iv["instrument_lags"] == 31 + 20  # ceil(q/r) + 2p
    ref = numpy_iv_markov(csv, 10, iv["instrument_lags"], len(iv["markov"][0]))
    np.testing.assert_allclose(iv["markov"], ref, rtol=1e-6, atol=1e-8 * np.max(np.abs(ref)))
    ls = identify(csv, *settings)
    assert ls["config"]["estimator"] == "least_squares" and "instrument_lags" not in ls
    f = exact_frequencies()  # the frequencies do not depend on dt
    err = lambda res: np.max(np.abs(np.sort([m["frequency_hz"] for m in res["modes"] if m["is_pair"]]) - f) / f)  # noqa: E731
    assert err(iv) < 0.3 * err(ls)


@pytest.mark.parametrize("args", [["--decimation", 0], ["--decimation", 65], ["--scaling", "si"],
                                  ["--estimator", "iv"], ["--instrument-lags", -1], ["--observer-seconds", 0],
                                  ["--hankel-seconds", "nan"], ["--hankel-seconds", 1e6]])
def test_quality_option_usage_errors(data, args):
    proc = run("identify", *args, data / "clean.csv", check=False)
    assert proc.returncode == 2 and proc.stdout == "" and proc.stderr.startswith("okid: ")
