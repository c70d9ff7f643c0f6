# SPDX-License-Identifier: Apache-2.0
"""One host library, one verdict (issue 27): `okid identify`, okid.read_record and okid-fleet's
CSV records read a file through the same C reader (host_tools/common), so on a grid of hostile
files they accept the same ones with the same samples and dt, and refuse the same ones with the
same line. Before the host library the fleet kept its own rule (1e-6 median step) and reader
(pyarrow): it refused jittered stamps and semicolons, and took NaN cells and duplicated names.

The accepted files are checked against an independent reading (numpy on the text the test wrote):
dt is the mean step of the stamps, the samples are the numbers written.
"""
import json
import os
import subprocess

import numpy as np
import pytest

import okid
from okid.fleet import records

OKID = os.environ.get("OKID_CLI", "okid")
DT = 0.01
N = 600


def _plant(seed=3):
    """A lightly damped 1-DOF response to white force: enough for OKID/ERA to succeed on."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal(N)
    y = np.zeros((N, 2))
    x = np.zeros(2)
    a = np.array([[0.99, 0.05], [-0.4, 0.98]])
    for k in range(N):
        y[k] = x
        x = a @ x + np.array([0.0, DT]) * u[k]
    return u, y + 1e-6 * rng.standard_normal((N, 2))


def _write(path, header, rows, sep=",", bom=False):
    # repr of a float round-trips: the file holds the numbers bit for bit
    text = sep.join(header) + "\n" + "".join(sep.join(repr(float(v)) for v in row) + "\n" for row in rows)
    path.write_bytes((b"\xef\xbb\xbf" if bom else b"") + text.encode())
    return path


def _grid(tmp_path):
    """(name, file, inputs, outputs, expected samples u, y and dt or None)."""
    u, y = _plant()
    t = np.arange(N) * DT
    rng = np.random.default_rng(7)
    files = []

    def add(name, header, columns, expect, sep=",", bom=False, inputs=None, outputs=None):
        rows = [list(r) for r in zip(*columns)]
        files.append((name, _write(tmp_path / f"{name}.csv", header, rows, sep, bom), inputs, outputs, expect))

    plain = (u[:, None], y)
    # stamps jittered by +-1e-5 dt: within the rule's 1e-4 dt (the old fleet's 1e-6 refused them)
    jitter = t + DT * 1e-5 * rng.uniform(-1, 1, N)
    add("jittered", ["t", "f", "a1", "a2"], [jitter, u, y[:, 0], y[:, 1]], plain + ((jitter[-1] - jitter[0]) / (N - 1),))
    # jittered by 1e-2 dt: a resampling or a gap, refused
    coarse = t + DT * 1e-2 * rng.uniform(-1, 1, N)
    add("jitter_coarse", ["t", "f", "a1", "a2"], [coarse, u, y[:, 0], y[:, 1]], None)
    # Unix epoch seconds: their ulps (2.4e-7 s) are the resolution, within 8 eps max|t|
    epoch = 1.7e9 + t
    add("epoch", ["timestamp", "f", "a1", "a2"], [epoch, u, y[:, 0], y[:, 1]], plain + ((epoch[-1] - epoch[0]) / (N - 1),))
    add("duplicated", ["t", "f", "a1", "a1"], [t, u, y[:, 0], y[:, 1]], None)
    add("bom", ["t", "f", "a1", "a2"], [t, u, y[:, 0], y[:, 1]], plain + ((t[-1] - t[0]) / (N - 1),), bom=True)
    add("semicolons", ["t", "f", "a1", "a2"], [t, u, y[:, 0], y[:, 1]], plain + ((t[-1] - t[0]) / (N - 1),), sep=";")
    nan_y = y[:, 0].copy()
    nan_y[N // 2] = np.nan
    add("nan_cell", ["t", "f", "a1", "a2"], [t, u, nan_y, y[:, 1]], None)
    # numbers as names: --outputs 2 is both the count 2 and the column "2" (refused as ambiguous)
    add("numbers_as_names", ["t", "1", "2", "3"], [t, u, y[:, 0], y[:, 1]], None, outputs="2")
    # ... while --outputs 2, (a list of names) takes the column "2" alone
    add("number_name_list", ["t", "1", "2", "3"], [t, u, y[:, 0], y[:, 1]],
        (u[:, None], y[:, :1], (t[-1] - t[0]) / (N - 1)), outputs="2,")
    add("ms_unit", ["time_ms", "f", "a1", "a2"], [t * 1e3, u, y[:, 0], y[:, 1]],
        plain + ((t[-1] - t[0]) * 1e3 / (N - 1) * 1e-3,))
    add("two_time_columns", ["t", "time", "f", "a1"], [t, t, u, y[:, 0]], None)
    return files


def _cli(path, inputs, outputs):
    # every setting given: the JSON's dt is then the record's (a decimation chosen from the data would multiply it)
    args = [OKID, "identify", "--json", "--order", "2", "--observer-order", "10", "--decimation", "1",
            "--hankel-rows", "20", "--hankel-cols", "20", str(path)]
    if inputs is not None:
        args += ["--inputs", inputs]
    if outputs is not None:
        args += ["--outputs", outputs]
    proc = subprocess.run(args, capture_output=True, text=True, timeout=120)
    if proc.returncode != 0:
        lines = proc.stderr.splitlines()
        assert proc.stdout == "" and len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
        return ("refused", lines[0][len("okid: "):])
    doc = json.loads(proc.stdout)
    return ("accepted", doc)


def _fleet(path, inputs, outputs):
    ref = records.discover([str(path)])[0]
    spec = records.ChannelSpec(inputs=inputs or "1", outputs=outputs)
    try:
        return ("accepted", records.read(ref, spec))
    except records.RecordError as exc:
        return ("refused", str(exc))


def _python(path, inputs, outputs):
    try:
        return ("accepted", okid.read_record(path, inputs, outputs))
    except okid.RecordError as exc:
        return ("refused", str(exc))


def test_one_verdict_on_the_grid(tmp_path):
    verdicts = {}
    for name, path, inputs, outputs, expect in _grid(tmp_path):
        cli, py, fleet = _cli(path, inputs, outputs), _python(path, inputs, outputs), _fleet(path, inputs, outputs)
        verdicts[name] = (cli[0], py[0], fleet[0])
        assert cli[0] == py[0] == fleet[0] == ("refused" if expect is None else "accepted"), (name, cli, py, fleet)
        if expect is None:
            # the same line: Python and the fleet name the file first, the CLI too where the file is the cause
            reason = py[1].split(": ", 1)[1]
            assert reason in cli[1], (name, cli[1], py[1])
            assert fleet[1] == py[1], (name, fleet[1], py[1])
            continue
        u, y, dt = expect
        rec, doc, data = py[1], cli[1], fleet[1]
        # dt: the mean step of the stamps written (a few ulps of the largest stamp apart)
        assert rec.dt == pytest.approx(dt, rel=1e-12, abs=16 * np.finfo(float).eps * 1.7e9 / N)
        assert doc["dt"] == rec.dt and data.dt == rec.dt
        assert doc["samples"] == rec.u.shape[0] == N
        np.testing.assert_array_equal(rec.u, u)  # repr() round-trips: the numbers written, bit for bit
        np.testing.assert_array_equal(rec.y, y)
        np.testing.assert_array_equal(data.u, rec.u)
        np.testing.assert_array_equal(data.y, rec.y)
        assert tuple(doc["inputs"]) == rec.input_names == data.input_names
        assert tuple(doc["outputs"]) == rec.output_names == data.output_names
    assert sorted(k for k, v in verdicts.items() if v[0] == "accepted") == [
        "bom", "epoch", "jittered", "ms_unit", "number_name_list", "semicolons"]


def test_dt_against_the_stamps_is_one_rule(tmp_path):
    """--dt / dt= / the fleet's --dt against stamps 0.01 s apart: 0.02 refused by all three."""
    u, y = _plant()
    t = np.arange(N) * DT
    path = _write(tmp_path / "r.csv", ["t", "f", "a1", "a2"], [list(r) for r in zip(t, u, y[:, 0], y[:, 1])])
    proc = subprocess.run([OKID, "identify", "--dt", "0.02", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2 and "--dt 0.02 disagrees" in proc.stderr
    with pytest.raises(okid.RecordError, match="--dt 0.02 disagrees") as info:
        okid.read_record(path, dt=0.02)
    assert info.value.status == 2
    ref = records.discover([str(path)])[0]
    with pytest.raises(records.RecordError, match="--dt 0.02 disagrees"):
        records.read(ref, records.ChannelSpec(dt=0.02))
    assert okid.read_record(path, dt=0.02, ignore_time_column=True).dt == 0.02


@pytest.mark.parametrize("name", ["t", "Time [ms]", "time_us", "elapsed_time(min)", "zeit", "seconds", "seconds_ms",
                                  "ts", "timer", "t_x", "T / h", "timestamp{ns}"])
def test_fleet_time_names_are_the_cli_rule(name):
    """The fleet's Parquet columns skip a time column by the C rule itself (no copy to drift)."""
    unit = {"t": 1.0, "Time [ms]": 1e-3, "time_us": 1e-6, "elapsed_time(min)": 60.0, "zeit": 1.0, "seconds": 1.0,
            "T / h": 3600.0, "timestamp{ns}": 1e-9}.get(name, 0.0)
    assert records.time_unit(name) == unit
