# SPDX-License-Identifier: Apache-2.0
"""Hostile input, round three (issue 27): wrong answers with a success status, each now a correct
answer or a refusal that names the value and why.

1. okid crlb / okid.crlb: a bound that cannot be computed was printed as -1 with exit 0; a huge
   noise overflowed the weights 1 / sigma^2 into that -1 (the bound is linear in the noise).
2. okid crlb --dt 1: the chain's modes alias above Nyquist, and a finite bound of another "mode"
   (0.345 Hz, damping 0.9995) came out without a word.
3. okid identify with a header t,1,2,3: --outputs 2 took columns "2" and "3" (a name read as a count).
4. okid identify --dt 0.02 on stamps 0.01 s apart halved every frequency without a word.
5. Python: dt=True ran at 1 s, bool and complex arrays were cast (True -> 1, imaginary parts
   dropped), refine="no" refined, and copy.copy(identifier) shared the C core.
"""
import json
import copy
import os
import subprocess

import numpy as np
import pytest

import okid

OKID = os.environ.get("OKID_CLI", "okid")


def run(*args):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, timeout=300)
    proc.stdout, proc.stderr = proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8", "replace")
    return proc


def refused(proc, code=1):
    """A refusal: the exit status, nothing on stdout, one 'okid: ' line on stderr."""
    assert proc.returncode == code, (proc.returncode, proc.stdout, proc.stderr)
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
    return lines[0]


def crlb_table(proc):
    assert proc.returncode == 0, proc.stderr
    rows = [line.split(",") for line in proc.stdout.splitlines()[2:]]
    return np.array([[float(v) for v in row[1:]] for row in rows])


# --- 1. the Cramer-Rao bound ---------------------------------------------------------------------

def test_crlb_cli_huge_noise_is_linear():
    unit = crlb_table(run("crlb", "--noise", 1))
    huge = crlb_table(run("crlb", "--noise", 1e200))
    assert unit.shape == (2, 4) and np.all(unit[:, [1, 3]] > 0)
    np.testing.assert_allclose(huge[:, [0, 2]], unit[:, [0, 2]], rtol=0)       # the modes
    np.testing.assert_allclose(huge[:, [1, 3]], 1e200 * unit[:, [1, 3]], rtol=1e-5)  # 6 printed digits
    assert huge[0, 1] == pytest.approx(1.35e198, rel=0.01)


def test_crlb_cli_singular_fisher_is_refused():
    # 12 samples of 2 outputs for 18 parameters: the Fisher information is singular at working precision
    line = refused(run("crlb", "--noise", 0.05, "--samples", 12))
    assert "cannot compute the bound: the Fisher information is singular" in line
    assert line.endswith("the record spans 0.12 s, less than one period of the chain's fastest mode (0.954484 s at 1.04769 Hz)")


def test_crlb_python_huge_noise_is_linear():
    u = np.random.default_rng(1).standard_normal(1001)
    unit = okid.crlb(u, 0.01, noise=1.0)
    huge = okid.crlb(u, 0.01, noise=1e200)
    np.testing.assert_allclose(huge.frequency_std, 1e200 * unit.frequency_std, rtol=1e-12)
    np.testing.assert_allclose(huge.damping_std, 1e200 * unit.damping_std, rtol=1e-12)
    small = okid.crlb(u, 0.01, noise_std=1e-200)
    assert np.all(np.isfinite(small.frequency_std)) and np.all(small.frequency_std > 0)


def _zero_a():
    return np.zeros((4, 4)), np.ones((4, 1)), np.ones((2, 4)), np.zeros((2, 1))


@pytest.mark.parametrize("case", ["constant force", "zero A", "dt 10"])
def test_crlb_python_singular_fisher_is_refused(case):
    u = np.random.default_rng(1).standard_normal(1001)
    # dt 10 with the paper system's discrete model at dt 10 given (not aliasing-checked: a discrete model)
    args = {"constant force": (np.ones(1001), 0.01, {}), "zero A": (u, 0.01, {"model": _zero_a()}),
            "dt 10": (u, 10.0, {"model": okid.model.paper_system(10.0)})}[case]
    with pytest.raises(okid.OkidError, match="cannot compute the bound: the Fisher information is singular"):
        okid.crlb(args[0], args[1], noise=0.05, **args[2])


# --- 2. aliasing -----------------------------------------------------------------------------------

@pytest.mark.parametrize("dt", [1, 10])
def test_crlb_cli_aliased_mode_is_refused(dt):
    line = refused(run("crlb", "--noise", 0.05, "--dt", dt), code=2)
    assert line == (f"okid: --dt {dt}: the chain's mode of natural frequency 1.04769 Hz (damped 0.98931 Hz) is at or "
                    f"above the Nyquist frequency 1/(2 dt) = {0.5 / dt:g} Hz and aliases at this dt: its bound would "
                    f"be another mode's; give --dt below 0.505403 s")


def test_crlb_cli_below_nyquist_still_bounds():
    # dt 0.5: Nyquist 1 Hz, above the damped 0.989 Hz: both true modes, finite bounds
    table = crlb_table(run("crlb", "--noise", 0.05, "--dt", 0.5))
    np.testing.assert_allclose(table[:, 0], [0.503292121, 1.047686096], rtol=1e-9)
    assert np.all(np.isfinite(table[:, [1, 3]])) and np.all(table[:, [1, 3]] > 0)


def test_crlb_python_aliased_mode_is_refused():
    u = np.random.default_rng(1).standard_normal(1001)
    with pytest.raises(okid.BadParameterError, match=r"dt = 1\.0: the paper system's mode of natural frequency "
                       r"1\.04769 Hz \(damped 0\.98931 Hz\) is at or above the Nyquist frequency 1/\(2 dt\) = "
                       r"0\.5 Hz"):
        okid.crlb(u, 1.0, noise=0.05)
    assert okid.crlb(u, 0.5, noise=0.05).frequencies_hz.tolist() == pytest.approx([0.503292121, 1.047686096], rel=1e-9)


# --- 3. column names that look like counts --------------------------------------------------------

@pytest.fixture(scope="module")
def numbered(tmp_path_factory):
    """okid simulate's paper record with the header t,1,2,3 (force in '1', the outputs in '2' and '3')."""
    proc = run("simulate", "--samples", 400)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0] == "t,force,acc1,acc2"
    path = tmp_path_factory.mktemp("numbered") / "numbered.csv"
    path.write_text("\n".join(["t,1,2,3", *lines[1:]]) + "\n")
    return path


def test_outputs_count_or_name_is_refused(numbered):
    line = refused(run("identify", "--order", 2, "--outputs", 2, numbered), code=2)
    assert line == ("okid: --outputs 2: ambiguous, both a count (the next 2 column(s)) and the name of column 3 "
                    "('2'): write --outputs 2, (a trailing comma: a list of names) for that column, or name the "
                    "columns you mean (--outputs A,B)")


def outputs_of(proc):
    assert proc.returncode == 0, proc.stderr
    return [line for line in proc.stdout.splitlines() if line.startswith("inputs:")][0]


@pytest.mark.parametrize("spec,expected", [("2,", "inputs: 1; outputs: 2"), ("3,", "inputs: 1; outputs: 3"),
                                           ("2,3", "inputs: 1; outputs: 2 3")])
def test_outputs_names_with_a_comma(numbered, spec, expected):
    assert outputs_of(run("identify", "--order", 2, "--outputs", spec, numbered)) == expected


def test_count_and_name_of_the_same_column_is_not_ambiguous(numbered):
    # --inputs 1: the next column is the one named '1'
    assert outputs_of(run("identify", "--order", 2, "--inputs", 1, numbered)) == "inputs: 1; outputs: 2 3"


# --- 4. --dt against the time column ----------------------------------------------------------------

@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    proc = run("simulate", "--samples", 1000)
    assert proc.returncode == 0, proc.stderr
    path = tmp_path_factory.mktemp("paper") / "paper.csv"
    path.write_text(proc.stdout)
    return path


def identify_json(*args):
    proc = run("identify", "--json", "--order", 4, *args)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_dt_disagreeing_with_the_stamps_is_refused(paper):
    line = refused(run("identify", "--order", 4, "--dt", 0.02, paper), code=2)
    assert line == ("okid: --dt 0.02 disagrees with the time column 't', whose stamps step by 0.01 s (1e-06 s "
                    "allowed): drop --dt, or give --ignore-time-column to use --dt anyway")


def test_dt_agreeing_with_the_stamps_is_the_same_run(paper):
    plain = identify_json(paper)
    assert identify_json("--dt", 0.01, paper)["modes"] == plain["modes"]
    f = [mode["frequency_hz"] for mode in plain["modes"]]
    assert f == pytest.approx([0.503292121, 1.047686096], rel=1e-6)


def test_ignore_time_column_uses_dt(paper):
    plain = identify_json(paper)
    forced = identify_json("--dt", 0.02, "--ignore-time-column", paper)
    assert forced["config"]["dt"] == 0.02
    np.testing.assert_allclose([m["frequency_hz"] for m in forced["modes"]],
                               [m["frequency_hz"] / 2 for m in plain["modes"]], rtol=1e-12)


def test_dt_within_jittery_stamps_is_accepted(tmp_path, paper):
    lines = paper.read_text().splitlines()
    rows = [line.split(",", 1) for line in lines[1:]]
    # stamps printed to 3 digits with a 1 ms jitter on every 10th: not uniform, --dt 0.01 within their steps
    jittery = [f"{float(t) + (0.001 if k % 10 == 5 else 0):.3f},{rest}" for k, (t, rest) in enumerate(rows)]
    path = tmp_path / "jittery.csv"
    path.write_text("\n".join([lines[0], *jittery]) + "\n")
    assert "is not uniform" in refused(run("identify", "--order", 4, path))
    assert identify_json("--dt", 0.01, path)["config"]["dt"] == 0.01
    assert "disagrees with the time column 't', whose stamps step by 0.009 to 0.011 s" in \
        refused(run("identify", "--order", 4, "--dt", 0.02, path), code=2)


# --- 5. Python: numbers must be numbers ----------------------------------------------------------------

@pytest.fixture(scope="module")
def record():
    u = np.random.default_rng(3).standard_normal(2000)
    a, b, c, d = okid.model.paper_system(0.01)
    y, _ = okid.model.simulate(a, b, c, d, u.reshape(-1, 1))
    return u, y


@pytest.mark.parametrize("dt", [True, np.bool_(True), 0.01 + 0j, "0.01"])
def test_dt_must_be_a_real_number(record, dt):
    u, y = record
    with pytest.raises(TypeError, match=r"^dt = .*: a real number \(int or float\), not "):
        okid.identify(u, y, dt, order=4)
    with pytest.raises(TypeError, match=r"^dt = "):
        okid.Identifier(1, 2, dt)
    with pytest.raises(TypeError, match=r"^dt = "):
        okid.crlb(u, dt, noise=0.05)


@pytest.mark.parametrize("name", ["u", "y"])
@pytest.mark.parametrize("kind", ["bool", "complex"])
def test_arrays_must_be_real(record, name, kind):
    u, y = record
    bad = {"bool": lambda a: a > 0, "complex": lambda a: a + 1e-3j}[kind]
    args = {"u": (bad(u), y), "y": (u, bad(y))}[name]
    with pytest.raises(TypeError, match=rf"^{name} has dtype (bool|complex128): an array of real numbers"):
        okid.identify(*args, 0.01, order=4)
    identifier = okid.Identifier(1, 2, 0.01, order=4)
    with pytest.raises(TypeError, match=rf"^{name} has dtype"):
        identifier.push(*args)
    assert identifier.progress.samples == 0
    result = okid.identify(u, y, 0.01, order=4)
    with pytest.raises(TypeError, match=rf"^{name} has dtype"):
        result.refine(*args)


def test_crlb_arrays_and_noise_must_be_real(record):
    u, _ = record
    with pytest.raises(TypeError, match=r"^u has dtype bool"):
        okid.crlb(u > 0, 0.01, noise=0.05)
    with pytest.raises(TypeError, match=r"^A has dtype complex128"):
        a, b, c, d = okid.model.paper_system(0.01)
        okid.crlb(u, 0.01, model=(a + 0j, b, c, d), noise=0.05)
    with pytest.raises(TypeError, match=r"^noise = True: a real number"):
        okid.crlb(u, 0.01, noise=True)
    with pytest.raises(TypeError, match=r"^noise_std has dtype complex128"):
        okid.crlb(u, 0.01, noise_std=[0.1 + 0j, 0.1])


@pytest.mark.parametrize("refine", ["no", "", 1, 0, None])
def test_refine_must_be_a_bool(record, refine):
    u, y = record
    with pytest.raises(TypeError, match=rf"^refine = {refine!r}: True or False, not "):
        okid.identify(u, y, 0.01, order=4, refine=refine)


def test_real_numbers_still_work(record):
    u, y = record
    plain = okid.identify(u, y, 0.01, order=4)
    assert okid.identify(u.tolist(), y, np.float32(0.01).item(), order=4).frequencies_hz.tolist() == \
        pytest.approx(plain.frequencies_hz.tolist(), rel=1e-6)
    assert len(okid.identify((u * 1000).astype(np.int64), y, 0.01, order=4).modes) == 2
    assert plain.frequencies_hz.tolist() == pytest.approx([0.503292121, 1.047686096], rel=1e-6)
    refined = okid.identify(u, y, 0.01, order=4, refine=np.bool_(True), observer_order=20, hankel_rows=20,
                            hankel_cols=20)
    assert refined.refinement is not None and refined.refinement.converged


@pytest.mark.parametrize("how", [copy.copy, copy.deepcopy])
def test_identifier_cannot_be_copied(record, how):
    u, y = record
    identifier = okid.Identifier(1, 2, 0.01, order=4)
    identifier.push(u[:1000], y[:1000])
    with pytest.raises(TypeError, match=r"^an okid.Identifier cannot be copied: the copy would share its C core"):
        how(identifier)
    assert identifier.progress.samples == 1000


# --- 6. the host reader's limits (host_tools/common/csv_reader.c) ---------------------------------

def test_long_header_line_is_refused_before_it_is_read_whole():
    """A 64 MB header line: refused once its first ~1 MB (4096 names of 256 characters) is read.
    Fed through a pipe, the bytes the reader took are what was written before the pipe broke (the
    pipe itself holds 64 KiB); before, the whole line was read and then refused by the name limit."""
    proc = subprocess.Popen([OKID, "identify", "--dt", "0.01", "-"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    chunk, written = b"x" * (1 << 16), 0
    try:
        while written < 64 << 20:
            proc.stdin.write(chunk)
            written += len(chunk)
        proc.stdin.close()
    except BrokenPipeError:
        pass
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 1 and out == b""
    line = err.decode().strip()
    assert line.startswith("okid: standard input: line 1 is longer than 1081344 bytes") and "\n" not in line
    assert written <= 4 << 20, written  # the 2 MiB buffer, the pipe and a chunk of slack


def test_long_numeric_cell_is_a_number(tmp_path):
    """A 300-digit number is a number (it was "not a number" past 256 characters); past 4096
    characters a cell is refused as too long, naming the limit."""
    digits = "1" + "0" * 299                              # 1e299, written out
    rows = "".join(f"{k * 0.01!r},{np.sin(k) if k != 5 else digits},{np.cos(k)}\n" for k in range(50))
    path = tmp_path / "long.csv"
    path.write_text("t,f,a\n" + rows)
    rec = okid.read_record(path)
    assert rec.u[5, 0] == 1e299 and rec.u.shape == (50, 1)
    path.write_text("t,f,a\n" + rows.replace(digits, "0." + "1" * 5000))
    with pytest.raises(okid.RecordError, match="line 7, column 'f': a cell of more than 4096 characters"):
        okid.read_record(path)


@pytest.mark.parametrize("name, value", [("order", 2**31), ("observer_order", 2**40), ("hankel_rows", -2**31 - 1),
                                         ("decimation", 10**30)])
def test_integers_beyond_a_c_int_are_an_okid_error(name, value):
    """order=2**31 raised RuntimeError: std::bad_cast from the binding's int conversion."""
    with pytest.raises(okid.ConfigurationError, match=rf"^{name} = {value} is outside the range of a C int"):
        okid.Identifier(1, 2, 0.01, **{name: value})


def test_config_message_is_the_clis(paper):
    """The explanation of a refused configuration is written once (config_explain.c): Python prints
    the CLI's line with the settings spelled as keywords."""
    cli = refused(run("identify", "--order", 5, "--observer-order", 2, "--hankel-rows", 20, "--hankel-cols", 20,
                      "--decimation", 1, paper), code=2)
    with pytest.raises(okid.BadOrderError) as info:
        okid.Identifier(1, 2, 0.01, order=5, observer_order=2)
    assert str(info.value) == cli[len("okid: "):].replace("--order ", "order=")
    assert "order = 5 is outside 0..4" in str(info.value)


def test_sufficiency_before_the_workspace():
    """50 samples, 10 inputs, 40 outputs, p = 300: okid.identify allocated the 1766 MB workspace
    (1.8 GB peak resident) before NotEnoughDataError; now the CLI's check (config_explain.c) comes
    first, with the CLI's message. Measured in a child: its peak resident memory must stay far below
    the workspace (a quarter of it: the interpreter, numpy and okid take some 45 MB)."""
    import sys
    bytes_needed = okid._core.workspace_size(okid._config.build(10, 40, 0.01, {"observer_order": 300}))[1]
    assert bytes_needed > 1.7e9
    child = ("import resource, numpy as np, okid\n"
             "rng = np.random.default_rng(1)\n"
             "try:\n"
             "    okid.identify(rng.standard_normal((50, 10)), rng.standard_normal((50, 40)), 0.01, observer_order=300)\n"
             "except okid.NotEnoughDataError as e:\n"
             "    print(e)\n"
             "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n")
    proc = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=120)
    message, peak_kib = proc.stdout.splitlines()
    assert message == ("not enough data: 50 samples give at most 0 regressor rows, 15010 needed "
                       "(q = r + (r+m)p with p = 300)")
    assert int(peak_kib) * 1024 < bytes_needed / 4, peak_kib


# --- 7. okid-fleet: every network call has a timeout, every refusal is one line -----------------

def _fleet(*args, timeout=120):
    import sys
    cmd = [sys.executable, "-c", "import sys; from okid.fleet.cli import main; sys.exit(main())", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


# A port that accepts and never speaks Dask: test_fleet.py's test_a_port_that_is_not_dask_times_out.


@pytest.mark.parametrize("args, says", [
    (["--scheduler", "notaproto://x:1"], "no Dask scheduler answered at notaproto://x:1 within 20 s (unknown address scheme"),
    (["--scheduler", "tls://127.0.0.1:1"], "no Dask scheduler answered at tls://127.0.0.1:1 within 20 s (TLS expects"),
])
def test_fleet_refusals_are_one_line(paper, tmp_path, args, says):
    # --quiet: without it a "connecting to ..." progress line comes first
    proc = _fleet("identify", "--quiet", "--out", tmp_path / "out.parquet", *args, paper)
    assert proc.returncode == 1 and proc.stderr.splitlines() == [proc.stderr.strip()], proc.stderr
    assert proc.stderr.startswith("okid-fleet: " + says)


def test_fleet_out_that_is_a_file_is_one_line(paper, tmp_path):
    """--out naming a file (or a folder under one) was a FileExistsError / NotADirectoryError traceback."""
    blocker = tmp_path / "a_file"
    blocker.write_text("mine\n")
    for out in (blocker, blocker / "modes.parquet"):
        proc = _fleet("identify", "--workers", 1, "--out", out, paper)
        assert proc.returncode == 1 and len(proc.stderr.splitlines()) == 1, proc.stderr
        assert proc.stderr.startswith(f"okid-fleet: --out {out}") and "folder" in proc.stderr, proc.stderr
    assert blocker.read_text() == "mine\n"


# --- 8. okid crlb names the cause --------------------------------------------------------------

@pytest.mark.parametrize("args", [("--dt", "1e-300"), ("--dt", "1e-6"), ("--samples", 1)])
def test_crlb_short_record_is_named(args):
    """--dt 1e-300 blamed the force ("rank deficient ... not persistently exciting") and --samples 1
    "a real parameter": the cause is a record shorter than one period of the fastest mode (0.954 s,
    1.04769 Hz: the paper chain's, numpy's eig of its K and M in test_refine_cli.py)."""
    proc = run("crlb", "--noise", 0.02, *args)
    line = refused(proc, code=proc.returncode if proc.returncode in (1, 2) else 2)
    assert "less than one period of the chain's fastest mode (0.954484 s at 1.04769 Hz)" in line
    assert "excit" not in line and "real parameter" not in line


# --- okid.crlb names the cause okid crlb names ---------------------------------------------------

def _cli_force(samples, dt):
    """okid simulate's force record for --samples and --dt (okid crlb bounds that experiment)."""
    proc = run("simulate", "--samples", samples, "--dt", dt)
    assert proc.returncode == 0, proc.stderr
    return np.array([float(line.split(",")[1]) for line in proc.stdout.splitlines()[1:]])


@pytest.mark.parametrize("samples, dt, code", [(1, 0.01, 2), (12, 0.01, 1), (1001, 1e-300, 2), (1001, 1e-6, 2)])
def test_crlb_python_names_the_clis_cause(samples, dt, code):
    # a record shorter than one period of the fastest mode (1.04769 Hz): the CLI names the record's
    # span, not the force ("excitation") nor the noise std (was: "noise std [0.0017, 0.0]")
    line = refused(run("crlb", "--noise", 0.05, "--samples", samples, "--dt", dt), code=code)
    assert "less than one period of the chain's fastest mode (0.954484 s at 1.04769 Hz)" in line
    with pytest.raises(okid.OkidError) as caught:
        okid.crlb(_cli_force(samples, dt), dt, noise=0.05)
    expected = line[len("okid: "):].replace("the chain's", "the paper system's")
    expected = expected.replace("--dt", "dt").replace("--samples", "samples")
    # the same words; Python's exception then adds the library's description of its status
    assert str(caught.value) == expected or str(caught.value).startswith(expected + ": ")


def test_crlb_python_refusals_name_the_argument():
    u = np.random.default_rng(1).standard_normal(1001)
    with pytest.raises(okid.NonFiniteSampleError, match=r"^u holds NaN or Inf at sample 7 \(1 of 1001 samples\)"):
        okid.crlb(np.where(np.arange(1001) == 7, np.nan, u), 0.01, noise=0.05)
    with pytest.raises(okid.BadSizeError, match=r"^noise_std has 3 values: one per output \(2\) or one for all$"):
        okid.crlb(u, 0.01, noise_std=[1.0, 2.0, 3.0])  # was numpy's broadcast ValueError
    with pytest.raises(okid.BadParameterError, match=r"^output 1 is zero over the record's 1001 sample\(s\)"):
        okid.crlb(np.zeros(1001), 0.01, noise=0.05)  # was "noise std [0.0, 0.0]"
    a, b, c, d = okid.model.paper_system(0.01)
    with pytest.raises(okid.BadSizeError, match=r"^B has shape \(3, 1\): expected \(4, r\)"):
        okid.crlb(u, 0.01, noise=0.05, model=(a, np.ones((3, 1)), c, d))  # was numpy's reshape ValueError


# --- audit of issue 27: classes fixed without a test of their own ---------------------------------

def test_automatic_order_beyond_the_limit_says_give_order(paper):
    """The CLI ends this refusal with "give --order"; Python says "give order=<n>" in the same line."""
    cli = refused(run("identify", "--observer-order", 300, "--hankel-rows", 300, "--hankel-cols", 600,
                      "--decimation", 1, paper), code=2)
    assert cli.endswith("more than 512: give --order")
    with pytest.raises(okid.BadOrderError) as info:
        okid.Identifier(1, 2, 0.01, observer_order=300, hankel_rows=300, hankel_cols=600, decimation=1)
    assert str(info.value) == cli[len("okid: "):].replace("give --order", "give order=<n>")


def test_crlb_python_100_state_model_is_refused_naming_why():
    """A 100-state model (50 lightly damped modes, 4 outputs) over 3001 samples: the bound is not
    determined, and okid.crlb says why (it was -1 as a std with success). Measured: with 5001
    samples the same model gives 50 positive finite stds (2.3 s, too slow for this file)."""
    rng = np.random.default_rng(1)
    a = np.zeros((100, 100))
    for i in range(50):
        w, z = 2 * np.pi * (0.2 + 0.04 * i), 0.02
        r, th = np.exp(-z * w * 0.01), w * np.sqrt(1 - z * z) * 0.01
        a[2 * i:2 * i + 2, 2 * i:2 * i + 2] = r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    b, c, d = rng.standard_normal((100, 1)), rng.standard_normal((4, 100)), np.zeros((4, 1))
    with pytest.raises(okid.OkidError, match="^cannot compute the bound: the Fisher information is singular"):
        okid.crlb(rng.standard_normal(3001), 0.01, model=(a, b, c, d), noise=0.05)


# --- issue 27, the last items: crlb of a 16-mass chain ---------------------------------------------

def _chain_options(masses, damper, dt, samples):
    """okid simulate / okid crlb options of a chain of unit masses and springs with equal dampers."""
    return ["--masses", ",".join(["1"] * masses), "--dampers", ",".join([str(damper)] * (masses + 1)),
            "--springs", ",".join(["1"] * (masses + 1)), "--dt", dt, "--samples", samples]


def _unit_chain(masses, damper, dt):
    """The same chain's discrete model (A, B, C, D) at dt: force on mass 1, every acceleration."""
    mrk = okid.model.chain_model(np.ones(masses), np.full(masses + 1, float(damper)), np.ones(masses + 1))
    b2 = np.zeros((masses, 1))
    b2[0] = 1
    ac, bc, c, d = okid.model.state_space(*mrk, b2, acceleration=np.eye(masses))
    return (*okid.model.discretize_zoh(ac, bc, dt), c, d)


def numpy_crlb(a, b, c, d, u, dt, sigma):
    """The Cramer-Rao bound of the modes by numpy alone, without okid's refinement: the model in
    real modal form normalised on C's first row (okid normalises on B: another parametrisation of
    the same model class, order n with feedthrough and unknown x(0), so an eigenvalue's bound is the
    same), each output's derivative by the complex step (exact to round-off for the linear
    recursion), the Fisher information J' W J, its inverse, and the delta method from each pair's
    (alpha, beta), lambda = alpha + i beta, to frequency and damping. (frequency, std, damping, std)
    per mode by frequency, and the condition number of the unit-diagonal Fisher information."""
    n, m, r = a.shape[0], c.shape[0], b.shape[1]
    lam, vec = np.linalg.eig(a)
    pairs = [k for k in range(n) if lam[k].imag > 0]
    q = len(pairs)
    assert 2 * q == n
    t = np.column_stack([part for k in pairs for part in (vec[:, k].real, vec[:, k].imag)])
    am, bm, cm = np.linalg.solve(t, a @ t), np.linalg.solve(t, b), c @ t
    c_free = [(i, j) for i in range(1, m) for j in range(n)]  # C's first row fixed: the normalisation
    theta = np.concatenate([am[::2, ::2].diagonal(), am[::2, 1::2].diagonal(), bm.ravel(),
                            [cm[i, j] for i, j in c_free], d.ravel(), np.zeros(n)])
    npar, h = theta.size, 1e-30
    th = np.tile(theta.astype(complex), (npar, 1))  # every parameter's complex step at once
    th[np.arange(npar), np.arange(npar)] += 1j * h
    A = np.zeros((npar, n, n), dtype=complex)
    for j in range(q):
        A[:, 2 * j, 2 * j] = A[:, 2 * j + 1, 2 * j + 1] = th[:, j]
        A[:, 2 * j, 2 * j + 1], A[:, 2 * j + 1, 2 * j] = th[:, q + j], -th[:, q + j]
    k = 2 * q
    B = th[:, k:k + n * r].reshape(npar, n, r)
    k += n * r
    C = np.tile(cm.astype(complex), (npar, 1, 1))
    for idx, (i, j) in enumerate(c_free):
        C[:, i, j] = th[:, k + idx]
    k += len(c_free)
    D = th[:, k:k + m * r].reshape(npar, m, r)
    x = th[:, k + m * r:].copy()
    jac = np.empty((len(u), m, npar))
    for s in range(len(u)):
        jac[s] = (np.einsum("pij,pj->pi", C, x) + D @ u[s]).imag.T / h
        x = np.einsum("pij,pj->pi", A, x) + B @ u[s]
    fisher = np.einsum("kip,i,kiq->pq", jac, 1 / np.asarray(sigma) ** 2, jac)
    scale = 1 / np.sqrt(np.diag(fisher))
    unit = scale[:, None] * fisher * scale[None, :]
    cov = scale[:, None] * np.linalg.inv(unit) * scale[None, :]
    out = []
    for j in range(q):
        z = theta[j] + 1j * theta[q + j]
        s = np.log(z) / dt
        ds = np.array([1, 1j]) / (z * dt)  # d s / d (alpha, beta)
        dabs = (np.conj(s) * ds).real / abs(s)
        g_f, g_z = dabs / (2 * np.pi), -ds.real / abs(s) + s.real * dabs / abs(s) ** 2
        sub = cov[np.ix_([j, q + j], [j, q + j])]
        out.append((abs(s) / (2 * np.pi), np.sqrt(g_f @ sub @ g_f), -s.real / abs(s), np.sqrt(g_z @ sub @ g_z)))
    return np.array(sorted(out)), np.linalg.cond(unit)


def test_crlb_cli_16_mass_chain_names_why():
    """16 unit masses, dampers and springs, the CLI's largest chain: "stopped: max_passes reached
    before convergence" (exit 1 after ~3 s) told neither why nor what to do. The bound is one pass
    (the inverse Fisher information at the exact model), so convergence was never the question: the
    information is singular, because the heavily damped upper modes overlap (the 0.317 Hz mode,
    damping 0.9957, has a half-power band 155 times its gap to the next; numpy's own Fisher
    information of this chain has condition 2e18 at 10, 100 and 200 s of record, measured with
    numpy_crlb above: no record length helps)."""
    line = refused(run("crlb", "--noise", 0.02, *_chain_options(16, 1, 0.01, 1001)))
    assert "max_passes" not in line
    assert line.startswith("okid: cannot compute the bound: the Fisher information is singular at working precision: "
                           "the chain's modes overlap (the 0.316952 Hz mode, damping ratio 0.9957, has a half-power "
                           "band 2 zeta f 155 times the gap to its nearest mode)"), line
    assert line.endswith("give lighter --dampers or fewer --masses")


def test_crlb_cli_light_mode_beyond_the_refinements_modulus_is_named():
    """The paper chain with dampers 0.02, 0.04, 0.03 at dt 0.01: the 0.503 Hz mode (damping
    0.00158) has |lambda| = exp(-zeta 2 pi f dt) = 0.999950 > 0.9999, which the refinement's start
    pulls inside, so its one pass is not the exact model's ("max_passes reached" before; 16 unit
    masses with dampers 0.1 are the same case at 0.0294 Hz)."""
    line = refused(run("crlb", "--noise", 0.02, "--dampers", "0.02,0.04,0.03"))
    assert "the 0.503292 Hz mode (damping ratio 0.001581) has a discrete eigenvalue of modulus 0.999950 at dt " \
           "0.01 s, beyond the refinement's 0.9999" in line, line
    assert line.endswith("give a larger --dt or heavier --dampers")


def test_crlb_cli_heavily_damped_chain_is_numpys_fisher_bound():
    """4 unit masses, dampers and springs (damping up to 0.951: the factor 12.7 that stays
    computable) at dt 0.1: okid crlb's table is numpy's own Fisher bound of the same record. The
    table prints 6 digits (5e-6 relative); numpy's inverse of an information of condition 1.5e10
    adds 1.5e10 x 2.2e-16 = 3e-6: 2e-5 holds both with margin."""
    options = _chain_options(4, 1, 0.1, 1001)
    sim = run("simulate", *options)
    assert sim.returncode == 0, sim.stderr
    u = np.array([[float(line.split(",")[1])] for line in sim.stdout.splitlines()[1:]])
    table = crlb_table(run("crlb", "--noise", 0.02, *options))
    a, b, c, d = _unit_chain(4, 1, 0.1)
    y, _ = okid.model.simulate(a, b, c, d, u)
    reference, cond = numpy_crlb(a, b, c, d, u, 0.1, 0.02 * np.sqrt(np.mean(y * y, axis=0)))
    assert cond < 1e11, cond
    np.testing.assert_allclose(table, reference, rtol=2e-5)


def test_crlb_python_is_numpys_fisher_bound_and_names_the_overlap():
    """okid.crlb with the 4-mass chain's model: numpy's bound to the round-off of inverting an
    information of condition 1.5e10 (x 2.2e-16 = 3e-6, times 10 for the two sides' sums); the
    8-mass chain (factor 43): the overlap named, not "max_passes"."""
    u = np.random.default_rng(27).standard_normal((1001, 1))
    model = _unit_chain(4, 1, 0.1)
    y, _ = okid.model.simulate(*model, u)
    sigma = 0.02 * np.sqrt(np.mean(y * y, axis=0))
    bound = okid.crlb(u, 0.1, model=model, noise_std=sigma)
    reference, cond = numpy_crlb(*model, u, 0.1, sigma)
    got = np.column_stack([bound.frequencies_hz, bound.frequency_std, bound.damping_ratios, bound.damping_std])
    np.testing.assert_allclose(got, reference, rtol=10 * cond * np.finfo(float).eps)
    with pytest.raises(okid.NotPersistentlyExcitingError,
                       match=r"^cannot compute the bound: the Fisher information is singular at working precision: the "
                             r"model's modes overlap \(the 0\.313474 Hz mode, damping ratio 0\.9848, has a half-power band "
                             r"2 zeta f 43 times the gap to its nearest mode\)"):
        okid.crlb(u, 0.1, model=_unit_chain(8, 1, 0.1), noise=0.02)
