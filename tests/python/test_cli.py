"""The okid command-line tool end to end, against exact values computed here with numpy/scipy."""
import json
import os
import subprocess

import numpy as np
import pytest
from scipy.linalg import expm

OKID = os.environ.get("OKID_CLI", "okid")


def run(*args, check=True):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, text=True, timeout=120)
    if check and proc.returncode != 0:
        raise AssertionError(f"okid {' '.join(map(str, args))} failed: {proc.stderr}")
    return proc


def exact_eigenvalues(masses, dampers, springs, dt):
    """Discrete eigenvalues (Im >= 0, by frequency) of a chain between two walls, from eq. 6 and 13."""
    n = len(masses)

    def links(values):
        A = np.zeros((n, n))
        for i, v in enumerate(values):
            for a in (i - 1, i):
                if 0 <= a < n:
                    A[a, a] += v
            if 0 <= i - 1 and i < n:
                A[i - 1, i] -= v
                A[i, i - 1] -= v
        return A

    Mi = np.linalg.inv(np.diag(masses))
    Ac = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ links(springs), -Mi @ links(dampers)]])
    lam = np.linalg.eigvals(expm(Ac * dt))
    lam = lam[lam.imag > 0]
    return lam[np.argsort(np.abs(np.log(lam)))]


PAPER = ([2, 3], [2, 4, 3], [20, 40, 30], 0.01)


@pytest.fixture(scope="module")
def paper_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "paper.csv"
    run("simulate", "--output", path)
    return path


def identify_json(path, *extra):
    return json.loads(run("identify", "--json", *extra, path).stdout)


def eigenvalues(result):
    return np.array([complex(*m["eigenvalue"]) for m in result["modes"]])


def test_paper_round_trip_matches_exact(paper_csv):
    res = identify_json(paper_csv, "--observer-order", 20, "--order", 4, "--hankel-rows", 20,
                        "--hankel-cols", 20, "--zero-initial-state")
    want = exact_eigenvalues(*PAPER)
    got = eigenvalues(res)
    assert np.max(np.abs(got - want) / np.abs(want)) < 1e-9
    # The paper's printed digits (eq. 94).
    assert np.allclose(sorted(got, key=abs)[::-1], [0.9767 + 0.0608j, 0.9945 + 0.0311j][::-1], atol=6e-5) or \
        np.allclose(np.sort_complex(got), np.sort_complex([0.9767 + 0.0608j, 0.9945 + 0.0311j]), atol=6e-5)
    for key in ("order", "observer_order", "samples", "dt", "singular_values", "A", "B", "C", "D", "modes",
                "warnings", "regressor_rank"):
        assert key in res
    assert res["order"] == 4 and res["observer_order"] == 20 and res["samples"] == 1001
    assert res["dt"] == pytest.approx(0.01, rel=1e-12)
    assert len(res["A"]) == 4 and all(len(row) == 4 for row in res["A"])
    assert len(res["B"]) == 4 and len(res["B"][0]) == 1
    assert len(res["C"]) == 2 and len(res["D"]) == 2
    for mode in res["modes"]:
        assert len(mode["shape"]) == 4 and all(len(z) == 2 for z in mode["shape"])
        assert isinstance(mode["frequency_hz"], float) and isinstance(mode["damping_ratio"], float)
    freqs = [m["frequency_hz"] for m in res["modes"]]
    assert freqs == sorted(freqs)


def test_columns_by_name_count_and_dt(paper_csv):
    by_count = identify_json(paper_csv, "--inputs", 1, "--outputs", 2, "--order", 4, "--zero-initial-state")
    by_name = identify_json(paper_csv, "--inputs", "force", "--outputs", "acc1,acc2", "--order", 4,
                            "--zero-initial-state", "--dt", 0.01)
    assert np.allclose(eigenvalues(by_count), eigenvalues(by_name), rtol=1e-12)
    # Outputs in the other order: same poles, shapes with swapped components.
    swapped = identify_json(paper_csv, "--inputs", "force", "--outputs", "acc2,acc1", "--order", 4,
                            "--zero-initial-state")
    assert np.allclose(eigenvalues(swapped), eigenvalues(by_name), rtol=1e-9)


def test_automatic_order_and_combined(paper_csv):
    auto = identify_json(paper_csv, "--zero-initial-state")
    assert auto["order"] == 4
    comb = identify_json(paper_csv, "--realization", "combined", "--observer-order", 2, "--order", 4,
                         "--zero-initial-state")
    assert "G" in comb and len(comb["G"]) == 4 and len(comb["G"][0]) == 2
    assert np.max(np.abs(eigenvalues(comb) - exact_eigenvalues(*PAPER))) < 1e-9


def test_table_output(paper_csv):
    out = run("identify", "--order", 4, "--zero-initial-state", paper_csv).stdout
    assert "0.50329212" in out and "1.04768610" in out
    assert "frequency [Hz]" in out


def test_three_dof_velocity_from_command_line_model(tmp_path):
    path = tmp_path / "chain3.csv"
    model = ([1, 1.5, 2], [0.4, 0.3, 0.2, 0.1], [40, 30, 20, 10], 0.02)
    run("simulate", "--masses", "1,1.5,2", "--dampers", "0.4,0.3,0.2,0.1", "--springs", "40,30,20,10",
        "--sensing", "velocity", "--dt", 0.02, "--samples", 2000, "--output", path)
    assert path.read_text().splitlines()[0] == "t,force,vel1,vel2,vel3"
    res = identify_json(path, "--order", 6, "--sensing", "velocity", "--zero-initial-state")
    want = exact_eigenvalues(*model)
    assert np.max(np.abs(eigenvalues(res) - want) / np.abs(want)) < 1e-9


def test_output_noise_two_percent(tmp_path):
    path = tmp_path / "noisy.csv"
    run("simulate", "--noise", 0.02, "--samples", 5001, "--seed", 3, "--output", path)
    res = identify_json(path, "--order", 4, "--observer-order", 40, "--hankel-rows", 60, "--hankel-cols", 60)
    s = np.log(exact_eigenvalues(*PAPER)) / 0.01
    want = np.abs(s) / (2 * np.pi)
    got = np.array([m["frequency_hz"] for m in res["modes"]])
    assert np.max(np.abs(got - want) / want) < 0.02


BAD_FILES = {
    "empty.csv": "",
    "header_only.csv": "t,force,acc1,acc2\n",
    "nan.csv": "t,force,acc1\n0,1,2\n0.01,nan,3\n",
    "ragged.csv": "t,force,acc1\n0,1,2\n0.01,1\n",
    "text_cell.csv": "t,force,acc1\n0,1,2\n0.01,abc,3\n",
    "non_uniform.csv": "t,force,acc1\n0,1,2\n0.01,1,2\n0.03,1,2\n",
    "no_header.csv": "0,1,2\n0.01,1,2\n",
    "binary.csv": "t,force\x00,acc1\n\xff\xfe,1,2\n",
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_bad_files_give_one_clear_message(tmp_path, name):
    path = tmp_path / name
    path.write_bytes(BAD_FILES[name].encode("latin-1"))
    proc = run("identify", path, check=False)
    assert proc.returncode == 1, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
    assert proc.stdout == ""


@pytest.mark.parametrize("args,code", [
    (["identify", "/nonexistent/file.csv"], 1),
    (["identify", "--bogus", "x.csv"], 2),
    (["identify"], 2),
    (["identify", "--order"], 2),
    (["identify", "--order", "four", "x.csv"], 2),
    (["identify", "--sensing", "jerk", "x.csv"], 2),
    (["frobnicate"], 2),
    (["simulate", "--masses", "1,2", "--springs", "1,2"], 2),
    (["simulate", "--dt", "-1"], 2),
])
def test_usage_errors(args, code):
    proc = run(*args, check=False)
    assert proc.returncode == code, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr


def test_unknown_column_and_bad_settings(paper_csv):
    proc = run("identify", "--inputs", "forse", paper_csv, check=False)
    assert proc.returncode == 2 and "forse" in proc.stderr
    proc = run("identify", "--observer-order", 1, "--order", 4, paper_csv, check=False)
    assert proc.returncode == 2 and proc.stderr.startswith("okid: invalid settings")


def test_too_few_rows(tmp_path):
    path = tmp_path / "short.csv"
    run("simulate", "--samples", 30, "--output", path)
    proc = run("identify", "--order", 4, path, check=False)
    assert proc.returncode == 1 and "not enough data" in proc.stderr


def test_constant_force_is_rank_deficient(tmp_path):
    path = tmp_path / "constant.csv"
    rows = ["t,force,acc1,acc2"] + [f"{0.01 * k},1.0,{np.sin(0.1 * k)},{np.cos(0.1 * k)}" for k in range(500)]
    path.write_text("\n".join(rows) + "\n")
    proc = run("identify", "--order", 4, path, check=False)
    assert proc.returncode == 1 and "rank deficient" in proc.stderr
