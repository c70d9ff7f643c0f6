# SPDX-License-Identifier: Apache-2.0
"""The okid command-line tool end to end, against exact values computed here with numpy/scipy.

The reference never goes through the library: the chain's M, R, K are assembled by reference.py, the ZOH
transition matrix is scipy's expm, and the eigenvalues and eigenvectors come from numpy.
"""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy.linalg import expm

from reference import chain_matrices, mac  # the oracle (tests/python/reference.py): the chain's M, R, K; the MAC

OKID = os.environ.get("OKID_CLI", "okid")


def run(*args, check=True, stdin=None):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, timeout=120, input=stdin)
    proc.stdout, proc.stderr = proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8", "replace")
    if check and proc.returncode != 0:
        raise AssertionError(f"okid {' '.join(map(str, args))} failed: {proc.stderr}")
    return proc


def assert_one_error(proc, code):
    """Exit status code (not a signal), nothing on stdout, exactly one 'okid: ' line on stderr."""
    assert proc.returncode == code, (proc.returncode, proc.stderr)
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
    assert "Traceback" not in proc.stderr and "Sanitizer" not in proc.stderr
    assert proc.stdout == ""
    return lines[0]


# ---- independent reference (paper eq. 6, 13; chain_matrices from reference.py) ----

def continuous_matrix(masses, dampers, springs):
    M, R, K = chain_matrices(masses, dampers, springs)
    n = len(masses)
    Mi = np.linalg.inv(M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ R]])


def exact_modes(masses, dampers, springs, dt):
    """Discrete eigenvalues with Im > 0, by frequency, and the Ac eigenvectors [x; dx/dt] of each."""
    lam, vec = np.linalg.eig(expm(continuous_matrix(masses, dampers, springs) * dt))
    keep = lam.imag > 0
    lam, vec = lam[keep], vec[:, keep]
    order = np.argsort(np.abs(np.log(lam)))
    return lam[order], vec[:, order]


def exact_eigenvalues(masses, dampers, springs, dt):
    return exact_modes(masses, dampers, springs, dt)[0]


PAPER = ([2, 3], [2, 4, 3], [20, 40, 30], 0.01)
# The settings the CLI otherwise chooses from the data, fixed at okid_config_default()'s values:
# the tests of the core's exactness on noise-free data (decimation's filter would bias them).
LIBRARY_DEFAULTS = ("--decimation", 1, "--observer-order", 20, "--hankel-rows", 20, "--hankel-cols", 20)
PAPER_SETTINGS = ("--observer-order", 20, "--order", 4, "--hankel-rows", 20, "--hankel-cols", 20,
                  "--zero-initial-state")


def test_reference_matrices_are_the_papers():
    M, R, K = chain_matrices(*PAPER[:3])
    assert np.array_equal(M, np.diag([2.0, 3.0]))
    assert np.array_equal(R, [[6, -4], [-4, 7]])
    assert np.array_equal(K, [[60, -40], [-40, 70]])


@pytest.fixture(scope="module")
def paper_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "paper.csv"
    run("simulate", "--output", path)
    return path


def identify_json(path, *extra):
    return json.loads(run("identify", "--json", *extra, path).stdout)


def eigenvalues(result):
    return np.array([complex(*m["eigenvalue"]) for m in result["modes"]])


# ---- the paper's case ----

def test_simulate_writes_the_documented_columns(paper_csv):
    lines = paper_csv.read_text().splitlines()
    assert lines[0] == "t,force,acc1,acc2"
    assert len(lines) == 1 + 1001
    data = np.loadtxt(paper_csv, delimiter=",", skiprows=1)
    assert np.allclose(np.diff(data[:, 0]), 0.01, rtol=1e-9, atol=0)
    assert 0.8 < np.std(data[:, 1]) < 1.2  # unit-variance white noise
    # Same seed, same file; another seed, another force.
    assert run("simulate").stdout == paper_csv.read_text()
    assert run("simulate", "--seed", 2).stdout != paper_csv.read_text()


def test_paper_round_trip_matches_exact(paper_csv):
    res = identify_json(paper_csv, *PAPER_SETTINGS)
    want, vectors = exact_modes(*PAPER)
    got = eigenvalues(res)
    got = np.where(got.imag < 0, got.conj(), got)
    assert np.max(np.abs(got - want) / np.abs(want)) < 1e-9
    # The paper's printed digits: 0.9945 +/- 0.0311i and 0.9767 +/- 0.0608i (4 decimals).
    assert np.allclose(got.real, [0.9945, 0.9767], rtol=0, atol=5e-5)
    assert np.allclose(got.imag, [0.0311, 0.0608], rtol=0, atol=5e-5)
    # Poles, frequencies and damping follow from the eigenvalues (s = ln(lambda) / dt).
    s = np.log(want) / 0.01
    for mode, s_exact, vec in zip(res["modes"], s, vectors.T):
        pole = complex(*mode["pole"])
        pole = pole.conjugate() if pole.imag < 0 else pole
        assert abs(pole - s_exact) / abs(s_exact) < 1e-9
        assert mode["frequency_hz"] == pytest.approx(abs(s_exact) / (2 * np.pi), rel=1e-9)
        assert mode["damping_ratio"] == pytest.approx(-s_exact.real / abs(s_exact), rel=1e-8)
        assert mode["is_pair"] is True
        # eq. 64: displacements then velocities at both masses = the Ac eigenvector (all states measured).
        shape = np.array([complex(*z) for z in mode["shape"]])
        assert mac(shape, vec) > 1 - 1e-9
        assert np.linalg.norm(shape) == pytest.approx(1, rel=1e-9)


def test_json_keys_and_types(paper_csv):
    res = identify_json(paper_csv, *PAPER_SETTINGS)
    types = {"order": int, "config": dict, "samples": int, "dt": float, "singular_values": list,
             "A": list, "B": list, "C": list, "D": list, "regressor_rank": int, "regressor_columns": int,
             "warnings": list, "modes": list, "inputs": list, "outputs": list}
    for key, kind in types.items():
        assert isinstance(res[key], kind), key
    assert "G" not in res  # system realization: no observer gain
    assert res["order"] == 4 and res["config"]["observer_order"] == 20 and res["samples"] == 1001
    assert res["inputs"] == ["force"] and res["outputs"] == ["acc1", "acc2"]
    assert res["dt"] == pytest.approx(0.01, rel=1e-12)
    assert res["regressor_columns"] == 1 + 3 * 20
    assert 0 < res["regressor_rank"] <= res["regressor_columns"]
    assert all(isinstance(w, str) for w in res["warnings"])
    sv = res["singular_values"]
    assert all(isinstance(v, float) for v in sv) and sv == sorted(sv, reverse=True)
    for name, rows, cols in (("A", 4, 4), ("B", 4, 1), ("C", 2, 4), ("D", 2, 1)):
        assert len(res[name]) == rows and all(len(row) == cols for row in res[name]), name
        assert all(isinstance(v, float) for row in res[name] for v in row), name
    assert len(res["modes"]) == 2
    for mode in res["modes"]:
        for key in ("eigenvalue", "pole"):
            assert len(mode[key]) == 2 and all(isinstance(v, float) for v in mode[key])
        assert isinstance(mode["frequency_hz"], float) and isinstance(mode["damping_ratio"], float)
        assert isinstance(mode["is_pair"], bool)
        assert len(mode["sensor_shape"]) == 2 and all(len(z) == 2 for z in mode["sensor_shape"])
        assert len(mode["shape"]) == 4 and all(len(z) == 2 for z in mode["shape"])
    freqs = [m["frequency_hz"] for m in res["modes"]]
    assert freqs == sorted(freqs)
    # The identified A has the exact eigenvalues too (values printed with %.17g round-trip).
    lam = np.linalg.eigvals(np.array(res["A"]))
    lam = np.sort_complex(lam[lam.imag > 0])
    assert np.max(np.abs(lam - np.sort_complex(exact_eigenvalues(*PAPER)))) < 1e-9


def test_columns_by_name_count_and_dt(paper_csv, tmp_path):
    by_count = identify_json(paper_csv, "--inputs", 1, "--outputs", 2, *PAPER_SETTINGS)
    by_name = identify_json(paper_csv, "--inputs", "force", "--outputs", "acc1,acc2", *PAPER_SETTINGS)
    assert np.array_equal(eigenvalues(by_count), eigenvalues(by_name))
    # --dt equal to the time column's step: the same result.
    with_dt = identify_json(paper_csv, "--dt", 0.01, *PAPER_SETTINGS)
    assert np.array_equal(eigenvalues(with_dt), eigenvalues(by_name))
    # --dt wins over the time column with --ignore-time-column (without it, refused: test_hostile_round3.py):
    # same eigenvalues, poles and frequencies scaled by 0.01 / 0.02.
    slower = identify_json(paper_csv, "--dt", 0.02, "--ignore-time-column", *PAPER_SETTINGS)
    assert slower["dt"] == 0.02
    assert np.allclose(eigenvalues(slower), eigenvalues(by_name), rtol=1e-12)
    assert np.allclose([m["frequency_hz"] for m in slower["modes"]],
                       [m["frequency_hz"] / 2 for m in by_name["modes"]], rtol=1e-12)
    # Outputs in the other order: same poles.
    swapped = identify_json(paper_csv, "--inputs", "force", "--outputs", "acc2,acc1", *PAPER_SETTINGS)
    assert np.allclose(eigenvalues(swapped), eigenvalues(by_name), rtol=1e-9)
    assert swapped["outputs"] == ["acc2", "acc1"]
    # No time column: counts start at the first column, and dt must be given.
    untimed = tmp_path / "untimed.csv"
    untimed.write_text("\n".join(",".join(line.split(",")[1:]) for line in paper_csv.read_text().splitlines()) + "\n")
    assert untimed.read_text().startswith("force,acc1,acc2\n")
    res = identify_json(untimed, "--dt", 0.01, "--inputs", 1, "--outputs", 2, *PAPER_SETTINGS)
    assert np.array_equal(eigenvalues(res), eigenvalues(by_name))
    message = assert_one_error(run("identify", *PAPER_SETTINGS, untimed, check=False), 2)
    assert "--dt" in message


def test_other_csv_dialects_and_stdin(paper_csv, tmp_path):
    """Semicolons, CRLF, comments and blank lines, a 'Time' header, and '-' for standard input."""
    reference = eigenvalues(identify_json(paper_csv, *PAPER_SETTINGS))
    lines = paper_csv.read_text().splitlines()
    dialect = tmp_path / "dialect.csv"
    body = ["# recorded by a test", "Time;force;acc1;acc2"] + [line.replace(",", ";") for line in lines[1:]] + [""]
    dialect.write_bytes("\r\n".join(body).encode())
    assert np.array_equal(eigenvalues(identify_json(dialect, *PAPER_SETTINGS)), reference)
    proc = run("identify", "--json", *PAPER_SETTINGS, "-", stdin=paper_csv.read_bytes())
    assert np.array_equal(eigenvalues(json.loads(proc.stdout)), reference)


def test_automatic_order_and_combined(paper_csv):
    auto = identify_json(paper_csv, "--zero-initial-state")
    assert auto["order"] == 4
    comb = identify_json(paper_csv, "--realization", "combined", "--observer-order", 2, "--order", 4,
                         "--zero-initial-state")
    assert comb["config"]["realization"] == "combined"
    assert "G" in comb and len(comb["G"]) == 4 and len(comb["G"][0]) == 2
    assert np.max(np.abs(eigenvalues(comb) - exact_eigenvalues(*PAPER))) < 1e-9


def test_table_output(paper_csv):
    out = run("identify", *PAPER_SETTINGS, paper_csv).stdout
    want = np.abs(np.log(exact_eigenvalues(*PAPER)) / 0.01) / (2 * np.pi)
    for f in want:
        assert f"{f:.8f}" in out  # 0.50329212 and 1.04768610
    assert "frequency [Hz]" in out and "damping ratio" in out
    assert "singular values:" in out and "regressor rank" in out
    assert "0.9945274" in out and "0.9766764" in out
    assert "inputs: force; outputs: acc1 acc2" in out


def test_three_dof_velocity_from_command_line_model(tmp_path):
    path = tmp_path / "chain3.csv"
    model = ([1, 1.5, 2], [0.4, 0.3, 0.2, 0.1], [40, 30, 20, 10], 0.02)
    run("simulate", "--masses", "1,1.5,2", "--dampers", "0.4,0.3,0.2,0.1", "--springs", "40,30,20,10",
        "--sensing", "velocity", "--force-dof", 2, "--dt", 0.02, "--samples", 2000, "--output", path)
    assert path.read_text().splitlines()[0] == "t,force,vel1,vel2,vel3"
    res = identify_json(path, "--order", 6, "--sensing", "velocity", "--zero-initial-state", *LIBRARY_DEFAULTS)
    want = exact_eigenvalues(*model)
    got = eigenvalues(res)
    got = np.where(got.imag < 0, got.conj(), got)
    assert np.max(np.abs(got - want) / np.abs(want)) < 1e-9


def test_displacement_sensing_header(tmp_path):
    out = run("simulate", "--sensing", "displacement", "--samples", 3).stdout.splitlines()
    assert out[0] == "t,force,disp1,disp2" and len(out) == 4


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_output_noise_two_percent(tmp_path, seed):
    """2 % output noise on the default record (1001 samples): a long observer and Hankel window keep
    the frequencies within 2 % (the design notes: p against the noise bias, alpha and beta spanning
    a period of the slowest mode)."""
    path = tmp_path / "noisy.csv"
    run("simulate", "--noise", 0.02, "--seed", seed, "--output", path)
    clean = run("simulate", "--seed", seed).stdout.splitlines()
    noisy = path.read_text().splitlines()
    assert clean[0] == noisy[0] and clean[1].split(",")[:2] == noisy[1].split(",")[:2]  # same force
    res = identify_json(path, "--order", 4, "--observer-order", 60, "--hankel-rows", 100, "--hankel-cols", 100)
    want = np.abs(np.log(exact_eigenvalues(*PAPER)) / 0.01) / (2 * np.pi)
    got = np.array([m["frequency_hz"] for m in res["modes"]])
    assert got.shape == want.shape
    assert np.max(np.abs(got - want) / want) < 0.02


# ---- bad input: one clear line, the documented exit status, never a crash ----

BAD_FILES = {
    "empty.csv": b"",
    "blank_lines.csv": b"\n\n  \n",
    "header_only.csv": b"t,force,acc1,acc2\n",
    "nan.csv": b"t,force,acc1\n0,1,2\n0.01,nan,3\n",
    "inf.csv": b"t,force,acc1\n0,1,2\n0.01,1,-inf\n",
    "ragged.csv": b"t,force,acc1\n0,1,2\n0.01,1\n",
    "long_row.csv": b"t,force,acc1\n0,1,2\n0.01,1,2,3\n",
    "text_cell.csv": b"t,force,acc1\n0,1,2\n0.01,abc,3\n",
    "empty_cell.csv": b"t,force,acc1\n0,1,2\n0.01,,3\n",
    "non_uniform.csv": b"t,force,acc1\n0,1,2\n0.01,1,2\n0.03,1,2\n",
    "decreasing_time.csv": b"t,force,acc1\n0.02,1,2\n0.01,1,2\n0.0,1,2\n",
    "no_header.csv": b"0,1,2\n0.01,1,2\n",
    "duplicate_names.csv": b"t,force,force\n0,1,2\n",
    "empty_name.csv": b"t,,acc1\n0,1,2\n",
    "control_in_name.csv": b"t,for\rce,acc1\n0,1,2\n",
    "binary.csv": b"t,force\x00,acc1\n\xff\xfe,1,2\n",
    "not_utf8.csv": b"t,f\xf6rce,acc1\n0,1,2\n0.01,\xe9,3\n",
    "huge_field.csv": b"t,force,acc1\n0,1," + b"9" * 100000 + b"\n",
    "huge_name.csv": b"t,force," + b"a" * 100000 + b"\n0,1,2\n",
    "too_few_rows.csv": b"t,force,acc1,acc2\n0,1,2,3\n0.01,2,3,4\n0.02,3,4,5\n",
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_bad_files_give_one_clear_message(tmp_path, name):
    path = tmp_path / name
    path.write_bytes(BAD_FILES[name])
    assert_one_error(run("identify", path, check=False), 1)


def test_messages_name_the_row_and_column(tmp_path):
    path = tmp_path / "nan.csv"
    path.write_bytes(BAD_FILES["nan.csv"])
    message = assert_one_error(run("identify", path, check=False), 1)
    assert "line 3" in message and "'force'" in message and "NaN" in message
    path.write_bytes(BAD_FILES["text_cell.csv"])
    message = assert_one_error(run("identify", path, check=False), 1)
    assert "line 3" in message and "'force'" in message and "not a number" in message
    path.write_bytes(BAD_FILES["ragged.csv"])
    assert "line 3" in assert_one_error(run("identify", path, check=False), 1)
    path.write_bytes(BAD_FILES["non_uniform.csv"])
    assert "not uniform" in assert_one_error(run("identify", path, check=False), 1)
    path.write_bytes(BAD_FILES["empty.csv"])
    assert "empty" in assert_one_error(run("identify", path, check=False), 1)


@pytest.mark.parametrize("args,code", [
    (["identify", "/nonexistent/file.csv"], 1),
    (["identify", "--bogus", "x.csv"], 2),
    (["identify", "-x", "x.csv"], 2),
    (["identify", "x.csv", "--bogus"], 2),
    (["simulate", "--bogus"], 2),
    (["simulate", "--samples"], 2),
    (["identify"], 2),
    (["identify", "--order"], 2),
    (["identify", "--order", "four", "x.csv"], 2),
    (["identify", "--order", "4.5", "x.csv"], 2),
    (["identify", "--dt", "0", "x.csv"], 2),
    (["identify", "--dt", "nan", "x.csv"], 2),
    (["identify", "--forgetting-factor", "x", "x.csv"], 2),
    (["identify", "--sensing", "jerk", "x.csv"], 2),
    (["identify", "--realization", "both", "x.csv"], 2),
    (["identify", "a.csv", "b.csv"], 2),
    ([], 2),
    (["frobnicate"], 2),
    (["simulate", "--masses", "1,2", "--springs", "1,2"], 2),
    (["simulate", "--masses", "1,x"], 2),
    (["simulate", "--masses", "-1,3"], 2),
    (["simulate", "--masses", ",".join(["1"] * 17), "--dampers", ",".join(["1"] * 18),
      "--springs", ",".join(["1"] * 18)], 2),
    (["simulate", "--dt", "-1"], 2),
    (["simulate", "--samples", "0"], 2),
    (["simulate", "--force-dof", "3"], 2),
    (["simulate", "--noise", "-0.1"], 2),
    (["simulate", "--sensing", "strain"], 2),
    (["simulate", "extra"], 2),
    (["simulate", "--output", "/nonexistent/dir/x.csv"], 1),
])
def test_usage_errors(args, code):
    assert_one_error(run(*args, check=False), code)


def test_help_documents_exit_status():
    for args in ([], ["identify"], ["simulate"]):
        proc = run(*args, "--help")
        assert proc.stdout.startswith("usage: okid") and proc.stderr == ""
        assert "Exit status: 0 success" in proc.stdout
    assert run("--version").stdout.startswith("okid ")


@pytest.mark.parametrize("args,needle", [
    (["--inputs", "forse"], "forse"),
    (["--outputs", "acc1,acc3"], "acc3"),
    (["--inputs", "force", "--outputs", "force,acc1"], "force"),
    (["--inputs", "t"], "'t'"),
    (["--inputs", "force", "--outputs", "acc1,acc1"], "acc1"),
    (["--inputs", 3], "no output columns"),
    (["--inputs", 1, "--outputs", 2147483647], "--outputs"),
    (["--inputs", 100], "--inputs 100"),
    (["--observer-order", 1, "--order", 4], "invalid settings"),
    (["--observer-order", 5000], "valid: 1..1000"),
    (["--hankel-rows", 0], "valid: 1..1000"),
    (["--forgetting-factor", 2], "valid: (0, 1]"),
    (["--rank-tolerance", -1], "valid: 0 or ["),
])
def test_bad_column_choice_and_settings(paper_csv, args, needle):
    message = assert_one_error(run("identify", *args, paper_csv, check=False), 2)
    assert needle in message


def test_unreadable_inputs(tmp_path):
    assert "directory" in assert_one_error(run("identify", tmp_path, check=False), 1)
    assert "standard input" in assert_one_error(run("identify", "-", stdin=b"", check=False), 1)
    message = assert_one_error(run("identify", tmp_path / "missing.csv", check=False), 1)
    assert "missing.csv" in message and "cannot open" in message


def test_too_few_rows(tmp_path):
    path = tmp_path / "short.csv"
    run("simulate", "--samples", 30, "--output", path)
    message = assert_one_error(run("identify", "--order", 4, path, check=False), 1)
    assert "not enough data" in message


@pytest.mark.parametrize("force", ["0.0", "1.0"])
def test_constant_force_is_rank_deficient(tmp_path, force):
    path = tmp_path / "constant.csv"
    rows = ["t,force,acc1,acc2"] + [f"{0.01 * k},{force},{np.sin(0.1 * k)},{np.cos(0.1 * k)}" for k in range(500)]
    path.write_text("\n".join(rows) + "\n")
    for extra in ([], ["--order", 4]):
        message = assert_one_error(run("identify", *extra, path, check=False), 1)
        assert "rank deficient" in message


def test_odd_column_names_stay_valid_json(tmp_path, paper_csv):
    """Column names come from the file: quotes, backslashes and non-UTF-8 bytes must not break the JSON."""
    lines = paper_csv.read_bytes().split(b"\n")
    lines[0] = b't,F\\1,"a\xe9",\xc3\xa4cc2'
    path = tmp_path / "names.csv"
    path.write_bytes(b"\n".join(lines))
    res = identify_json(path, *PAPER_SETTINGS)
    assert res["inputs"] == ["F\\1"] and res["outputs"] == ["a\ufffd", "\u00e4cc2"]


def test_write_error_is_reported(paper_csv):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    with open("/dev/full", "w") as full:
        proc = subprocess.run([OKID, "identify", "--json", paper_csv], stdout=full, stderr=subprocess.PIPE,
                              text=True, timeout=60)
    assert proc.returncode == 1 and proc.stderr.startswith("okid: ")
