# SPDX-License-Identifier: Apache-2.0
"""okid identify on hostile recordings (issue 17, docs/robustness.md): CSV files that lie about their
columns (class 2), numbers at the edge of the floating-point range (class 5), memory that must not
grow with the file (class 6), and refusals that give the numbers (class 7, library side).

The references are the CLI's own result on the plain paper recording (whose accuracy test_cli.py
checks against numpy/scipy): a file that differs only in how it is written must give the same
modes, or a refusal that says why.
"""
import csv
import io
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

OKID = os.environ.get("OKID_CLI", "okid")
TIME = "/usr/bin/time"  # GNU time (Debian package time)
# every setting given: the streaming path in fixed memory (settings chosen from the data read the record into memory)
SETTINGS = ("--decimation", 1, "--observer-order", 20, "--order", 4, "--hankel-rows", 20, "--hankel-cols", 20)


def run(*args, stdin=None):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, timeout=300, input=stdin)
    proc.stdout, proc.stderr = proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8", "replace")
    return proc


def identify(path, *extra):
    proc = run("identify", "--json", *SETTINGS, *extra, path)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def refusal(path, *extra, code=1):
    """One 'okid: ' line on stderr, nothing on stdout, the documented exit status."""
    proc = run("identify", *SETTINGS, *extra, path)
    assert proc.returncode == code, (proc.returncode, proc.stderr)
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: ") and proc.stdout == "", proc.stderr
    assert "internal error" not in lines[0]
    return lines[0]


def frequencies(result):
    return np.array([m["frequency_hz"] for m in result["modes"]])


def dampings(result):
    return np.array([m["damping_ratio"] for m in result["modes"]])


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    """The plain paper recording (t, force, acc1, acc2 at 0.01 s), its rows and its result."""
    path = tmp_path_factory.mktemp("data") / "paper.csv"
    proc = run("simulate", "--output", path)
    assert proc.returncode == 0, proc.stderr
    rows = list(csv.reader(io.StringIO(path.read_text())))
    return path, rows, identify(path)


def write_rows(path, header, rows, prefix=b""):
    text = "\n".join(",".join(r) for r in [header, *rows]) + "\n"
    path.write_bytes(prefix + text.encode("utf-8"))
    return path


def assert_same_modes(got, want, tol=1e-12):
    np.testing.assert_allclose(frequencies(got), frequencies(want), rtol=tol)
    np.testing.assert_allclose(dampings(got), dampings(want), rtol=tol)


# ---- class 2: CSV files that lie about their columns ----

def test_utf8_byte_order_mark_is_skipped(paper, tmp_path):
    path, rows, want = paper
    bom = write_rows(tmp_path / "bom.csv", rows[0], rows[1:], prefix=b"\xef\xbb\xbf")
    got = identify(bom)
    assert got["inputs"] == ["force"] and got["outputs"] == ["acc1", "acc2"] and got["dt"] == want["dt"]
    assert got["modes"] == want["modes"]  # the same bits: the mark changes nothing else
    # with --dt the time column stays the time column (it used to become the input: 28.8 Hz modes)
    got = identify(bom, "--dt", 0.01)
    assert got["inputs"] == ["force"] and got["outputs"] == ["acc1", "acc2"]
    assert_same_modes(got, want)


def test_utf16_is_refused_with_the_reason(paper, tmp_path):
    path, rows, _ = paper
    utf16 = tmp_path / "utf16.csv"
    utf16.write_bytes(("\n".join(",".join(r) for r in rows[:50]) + "\n").encode("utf-16"))
    assert "UTF-16" in refusal(utf16)


def test_a_column_is_never_both_input_and_output(paper):
    path, _, _ = paper
    got = identify(path, "--inputs", "acc1", "--outputs", 2, "--order", 2)
    assert got["inputs"] == ["acc1"] and "acc1" not in got["outputs"] and "t" not in got["outputs"]
    assert got["outputs"] == ["force", "acc2"]  # the next columns not taken, in file order


@pytest.mark.parametrize("name,factor", [
    ("time", 1), ("Time [s]", 1), ("TIME (s)", 1), ("t_s", 1), ("timestamp", 1), ("Zeit", 1),
    ("time_ms", 1e3), ("t [ms]", 1e3), ("Time (us)", 1e6), ("time/s", 1), ("elapsed_time [min]", 1 / 60),
])
def test_time_column_names_and_units(paper, tmp_path, name, factor):
    path, rows, want = paper
    stamped = [[repr(float(r[0]) * factor)] + r[1:] for r in rows[1:]]
    got = identify(write_rows(tmp_path / "named.csv", [name, *rows[0][1:]], stamped))
    assert got["inputs"] == ["force"] and got["outputs"] == ["acc1", "acc2"]
    assert got["dt"] == pytest.approx(0.01, rel=1e-12)
    assert_same_modes(got, want, tol=1e-9)


def test_time_column_anywhere_is_never_a_channel(paper, tmp_path):
    path, rows, want = paper
    moved = write_rows(tmp_path / "last.csv", rows[0][1:] + ["time"], [r[1:] + [r[0]] for r in rows[1:]])
    got = identify(moved)
    assert got["inputs"] == ["force"] and got["outputs"] == ["acc1", "acc2"]
    assert got["modes"] == want["modes"]
    assert "time column" in refusal(moved, "--inputs", "time", code=2)


def test_two_time_columns_are_refused(paper, tmp_path):
    path, rows, _ = paper
    two = write_rows(tmp_path / "two.csv", ["t"] + rows[0][1:] + ["time_ms"],
                     [r + [repr(float(r[0]) * 1e3)] for r in rows[1:]])
    message = refusal(two)
    assert "two time columns" in message and "'t'" in message and "'time_ms'" in message


def test_unix_epoch_stamps_at_1khz(tmp_path):
    """A 1 kHz record stamped in Unix epoch seconds: uniform to the stamps' resolution, not 'not uniform'."""
    plain = tmp_path / "plain.csv"
    assert run("simulate", "--dt", 0.001, "--samples", 6000, "--output", plain).returncode == 0
    rows = list(csv.reader(io.StringIO(plain.read_text())))
    epoch = write_rows(tmp_path / "epoch.csv", rows[0],
                       [[f"{1700000000 + k * 0.001:.3f}"] + r[1:] for k, r in enumerate(rows[1:])])
    want, got = identify(plain), identify(epoch)
    # the mean step is as good as the end stamps: 2 ulp(1.7e9) / 6 s = 8e-8 relative
    assert got["dt"] == pytest.approx(0.001, rel=1e-7)
    assert_same_modes(got, want, tol=1e-6)
    # a real gap is still found: one step of 2 ms in a 1 ms record
    gapped = [[f"{1700000000 + (k + (k > 3000)) * 0.001:.3f}"] + r[1:] for k, r in enumerate(rows[1:])]
    assert "not uniform" in refusal(write_rows(tmp_path / "gap.csv", rows[0], gapped))


# ---- class 5: numbers at the edge of the floating-point range ----

def scaled(rows, tmp_path, name, factors):
    """rows with column j multiplied by factors.get(j, 1)."""
    out = [[repr(float(x) * factors.get(j, 1)) if j in factors else x for j, x in enumerate(r)] for r in rows[1:]]
    return write_rows(tmp_path / name, rows[0], out)


@pytest.mark.parametrize("dt", ["1e-320", "1e-80", "1e300"])
def test_dt_outside_the_range_names_it(paper, dt):
    path, _, _ = paper
    message = refusal(path, "--dt", dt, code=2)
    assert "'%s'" % dt in message and "okid_config.dt" in message and "[1e-75, 1e+75]" in message


def test_huge_channels(paper, tmp_path):
    path, rows, want = paper
    big = scaled(rows, tmp_path, "big.csv", {2: 1e155, 3: 1e155})
    message = refusal(big)
    assert "'acc1'" in message and "e+154" in message and "--scale auto" in message
    assert_same_modes(identify(big, "--scale", "auto"), want, tol=1e-9)  # scaling is what rescues this
    force = scaled(rows, tmp_path, "big_force.csv", {1: 1e155})
    assert "'force'" in refusal(force)
    assert_same_modes(identify(force, "--scale", "auto"), want, tol=1e-9)


def test_tiny_channels(paper, tmp_path):
    path, rows, _ = paper
    for name, factors, column in (("tiny_out.csv", {2: 1e-160, 3: 1e-160}, "'acc1'"), ("tiny_in.csv", {1: 1e-160}, "'force'")):
        tiny = scaled(rows, tmp_path, name, factors)
        for scale in ("none", "auto"):
            message = refusal(tiny, "--scale", scale)
            assert column in message and "e-16" in message and "rescale" in message


def test_wide_but_inside_the_range(paper, tmp_path):
    path, rows, want = paper
    assert_same_modes(identify(scaled(rows, tmp_path, "wide.csv", {2: 1e60, 3: 1e60})), want, tol=1e-9)


# ---- class 7 (library side): the refusal gives the numbers ----

def test_forgetting_factor_memory_not_excitation(paper):
    path, _, _ = paper
    message = refusal(path, "--forgetting", "1e-12")
    assert "forgetting factor 1e-12" in message and "remembers 2 regressor rows" in message
    assert "61 needed" in message and "0.464159" in message and "excit" not in message


def test_order_error_names_the_order_and_its_range(paper):
    path, _, _ = paper
    message = refusal(path, "--observer-order", 1, code=2)  # --order 4 > m p = 2
    assert "order = 4 is outside 0..2" in message and "workspace" not in message
    message = refusal(path, "--rank-tolerance", "1e-300", code=2)
    assert "'1e-300'" in message and "rank_tolerance" in message and "2.220446049250313e-16" in message


# ---- class 6: memory out of proportion ----

def peak_rss_kib(*args, stdin_path=None, code=0):
    """Peak resident memory of one okid run in KiB, from GNU time (wait4 of its child). A child of
    this Python process itself would start from the interpreter's resident size (fork and exec keep it)."""
    proc = subprocess.Popen([TIME, "-f", "peak %M", OKID, *map(str, args)], stdin=subprocess.PIPE,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if stdin_path is not None:  # through a pipe, not a seekable file
        with open(stdin_path, "rb") as f:
            shutil.copyfileobj(f, proc.stdin)
    proc.stdin.close()
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait() == code, err
    return int(err.splitlines()[-1].split()[-1])


def test_resident_memory_does_not_grow_with_the_file(tmp_path):
    small, large = tmp_path / "small.csv", tmp_path / "large.csv"
    assert run("simulate", "--samples", 100_000, "--output", small).returncode == 0
    assert run("simulate", "--samples", 800_000, "--output", large).returncode == 0
    assert large.stat().st_size > 7 * small.stat().st_size > 40e6
    rss_small = peak_rss_kib("identify", *SETTINGS, small)
    rss_large = peak_rss_kib("identify", *SETTINGS, large)
    # reading the whole file (the old way) costs more than the file itself: 80 MB more here
    assert rss_large < rss_small + 4096, (rss_small, rss_large)
    # standard input through a pipe: the same
    rss_pipe = peak_rss_kib("identify", *SETTINGS, "-", stdin_path=large)
    assert rss_pipe < rss_small + 4096, (rss_small, rss_pipe)


def test_sufficiency_before_the_workspace(paper):
    """p = 1000 over 1001 samples: refused from the row count, not after a 0.7 GB workspace."""
    path, _, _ = paper
    message = refusal(path, "--observer-order", 1000, "--hankel-rows", 1000)
    assert "not enough data" in message and "3001 needed" in message
    assert peak_rss_kib("identify", "--observer-order", 1000, "--hankel-rows", 1000, path, code=1) < 32 * 1024
