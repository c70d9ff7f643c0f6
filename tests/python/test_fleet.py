# SPDX-License-Identifier: Apache-2.0
"""okid-fleet end to end on real Dask clusters of processes on localhost.

A synthetic fleet from okid's simulator (some assets losing stiffness) is identified on a cluster
that the test starts itself (a `dask scheduler` and two `dask worker` processes) and on the local
default; the tables must equal a serial loop over okid.identify, a corrupt and a non-exciting
record must be status rows, a worker killed mid-job and a Ctrl-C mid-job must cost nothing, and the
tracks must find the simulated stiffness loss (exact modes from numpy, not from okid).
"""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest

import okid
from okid import fleet

OPTIONS = {"order": 4, "zero_initial_state": 1}
CLI_OPTIONS = ["--order", "4", "--zero-initial-state"]
DASK = os.path.join(os.path.dirname(sys.executable), "dask")


def okid_fleet(*args, check=True, timeout=300):
    proc = subprocess.run([sys.executable, "-m", "okid.fleet.cli", *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(f"okid-fleet {' '.join(map(str, args))}: {proc.returncode}\n{proc.stderr}")
    return proc


class Cluster:
    """A dask scheduler and N single-threaded worker processes, each in its own process group."""

    def __init__(self, tmp, workers=2):
        self.file = os.path.join(tmp, "scheduler.json")
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        self.scheduler = subprocess.Popen([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0",
                                           "--no-dashboard", "--scheduler-file", self.file],
                                          env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 60
        while not os.path.exists(self.file) and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(0.2)
        with open(self.file) as f:
            self.address = json.load(f)["address"]
        self.workers = [subprocess.Popen([DASK, "worker", "--scheduler-file", self.file, "--nthreads", "1",
                                          "--no-dashboard", "--host", "127.0.0.1", "--name", f"w{i}"],
                                         env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                                         stderr=subprocess.DEVNULL)
                        for i in range(workers)]
        from distributed import Client

        with Client(self.address, timeout="30s") as client:
            client.wait_for_workers(workers, timeout=60)

    def kill_worker(self, i):
        os.killpg(self.workers[i].pid, signal.SIGKILL)
        self.workers[i].wait(timeout=30)

    def close(self):
        for proc in self.workers + [self.scheduler]:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
        for proc in self.workers + [self.scheduler]:
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    """40 records of 5 assets (2 losing 10 % of a spring's stiffness), plus a corrupt CSV record and
    one whose force is zero; and a fleet of 16 long records for the interruption tests."""
    root = tmp_path_factory.mktemp("fleet")
    spec = fleet.FleetSpec(assets=5, records=8, damaged=2, stiffness_loss=0.10, samples=2000, seed=3)
    info = fleet.synthesize(str(root / "small"), spec)
    extra = root / "extra" / "asset-bad"
    extra.mkdir(parents=True)
    (extra / "corrupt.csv").write_text("time,force,acc1,acc2\n0,1,2,3\n0.05,x,y\n0.1,\x00\x01\n")
    t = np.arange(2000) * 0.05
    rng = np.random.default_rng(5)
    still = np.column_stack([t, np.zeros_like(t), rng.standard_normal((t.size, 2))])
    np.savetxt(extra / "still.csv", still, delimiter=",", header="time,force,acc1,acc2", comments="", fmt="%.17g")
    big = fleet.synthesize(str(root / "big"), fleet.FleetSpec(assets=2, records=8, samples=100000, seed=4))
    return {"records": info["records_dir"], "truth": info["truth"], "damaged": info["damaged"],
            "extra": str(root / "extra"), "big": big["records_dir"], "root": root}


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(str(tmp_path_factory.mktemp("dask")))
    yield c
    c.close()


def serial_loop(records_dir, extra_dir):
    """Every record read here with pandas/numpy and identified one by one with okid.identify."""
    out = {}
    for name in sorted(os.listdir(records_dir)):
        frame = pd.read_parquet(os.path.join(records_dir, name))
        for record, rows in frame.groupby("record", sort=False):
            u = rows[["force"]].to_numpy()
            y = rows[["acc1", "acc2"]].to_numpy()
            out[record] = okid.identify(u, y, float(rows["dt"].iloc[0]), **OPTIONS)
    data = np.loadtxt(os.path.join(extra_dir, "asset-bad", "still.csv"), delimiter=",", skiprows=1)
    with pytest.raises(okid.NotPersistentlyExcitingError):
        okid.identify(data[:, 1:2], data[:, 2:], 0.05, **OPTIONS)
    return out


def assert_same_table(a, b):
    pd.testing.assert_frame_equal(a.reset_index(drop=True), b.reset_index(drop=True), check_exact=True)


@pytest.fixture(scope="module")
def cluster_table(data, cluster, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("out") / "modes.parquet")
    okid_fleet("identify", data["records"], data["extra"], "--out", out, "--scheduler", cluster.address,
               *CLI_OPTIONS, "--quiet")
    return fleet.read_modes(out)


def test_cluster_equals_serial_loop(data, cluster_table):
    expected = serial_loop(data["records"], data["extra"])
    table = cluster_table
    assert table["record"].nunique() == 42
    for record, result in expected.items():
        rows = table[table["record"] == record]
        assert (rows["status"] == "ok").all(), rows[["status", "message"]]
        assert list(rows["mode"]) == list(range(1, len(result.modes) + 1))
        assert list(rows["frequency_hz"]) == [m.frequency_hz for m in result.modes]
        assert list(rows["damping_ratio"]) == [m.damping_ratio for m in result.modes]
        assert list(rows["cmi"]) == [m.cmi for m in result.modes]
        assert (rows["warning_bits"] == int(result.warnings)).all()
    bad = table[table["asset"] == "asset-bad"].set_index("record")
    assert bad.loc["asset-bad/corrupt", "status"] == "unreadable"
    assert "corrupt.csv" in bad.loc["asset-bad/corrupt", "message"]
    assert bad.loc["asset-bad/still", "status"] == "not_persistently_exciting"
    assert "excit" in bad.loc["asset-bad/still", "message"]
    assert bad["mode"].isna().all()


def test_local_default_gives_the_same_table(data, cluster_table, tmp_path):
    out = str(tmp_path / "modes.parquet")
    proc = okid_fleet("identify", data["records"], data["extra"], "--out", out, *CLI_OPTIONS, "--workers", "2")
    assert "42 records identified (2 failed, 0 already done)" in proc.stdout
    assert_same_table(fleet.read_modes(out), cluster_table)
    again = okid_fleet("identify", data["records"], "--out", out, *CLI_OPTIONS, check=False)
    assert again.returncode == 1 and "--resume" in again.stderr and "Traceback" not in again.stderr


def test_track_finds_the_stiffness_loss(data, cluster_table, tmp_path):
    out, plot, summary_csv = tmp_path / "tracks.parquet", tmp_path / "tracks.png", tmp_path / "drift.csv"
    proc = okid_fleet("track", _write(cluster_table, tmp_path), "--out", out, "--plot", plot,
                      "--summary", summary_csv)
    assert plot.stat().st_size > 10_000 and "DRIFT" in proc.stdout
    summary = pd.read_csv(summary_csv)
    truth = pd.read_parquet(data["truth"])
    for (asset, mode), rows in truth.groupby(["asset", "mode"]):
        rows = rows.sort_values("start")
        true_change = rows["frequency_hz"].iloc[-1] / rows["frequency_hz"].iloc[0] - 1
        got = summary[(summary["asset"] == asset) & (summary["mode"] == mode)].iloc[0]
        if asset in data["damaged"]:
            assert abs(got["frequency_change"] - true_change) < 0.005, (asset, mode, got, true_change)
            if abs(true_change) > 0.01:
                assert got["drift"], (asset, mode, got)
        else:
            assert true_change == 0 and not got["drift"], (asset, mode, got)
    assert summary[summary["asset"].isin(data["damaged"])]["drift"].any()
    tracks = pd.read_parquet(out)
    assert set(tracks["asset"]) == {f"asset-{i:03d}" for i in range(5)}
    assert (tracks["mac"] >= 0.9).all()


def _write(table, tmp_path):
    """The mode table as a one-part dataset, as identify writes it."""
    folder = tmp_path / "modes.parquet"
    folder.mkdir()
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.Table.from_pandas(table, schema=fleet.rows.schema(), preserve_index=False),
                   folder / "part-0.parquet")
    return folder


def _wait_for_parts(out, count, proc=None, timeout=120):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if len(fleet.job.parts(out)) >= count:
            return
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"the job ended before {count} part(s): {proc.stderr.read()}")
        time.sleep(0.01)
    raise AssertionError(f"no {count} part(s) in {out} after {timeout} s")


@pytest.fixture(scope="module")
def big_table(data, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("big") / "modes.parquet")
    fleet.identify_fleet([data["big"]], out, options=OPTIONS, workers=2, batch_size=1, progress=None)
    return fleet.read_modes(out)


def test_a_killed_worker_costs_only_a_retry(data, big_table, tmp_path):
    c = Cluster(str(tmp_path), workers=2)
    try:
        out = str(tmp_path / "modes.parquet")
        job = subprocess.Popen([sys.executable, "-m", "okid.fleet.cli", "identify", data["big"], "--out", out,
                                "--scheduler", c.address, "--batch-size", "1", *CLI_OPTIONS, "--quiet"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _wait_for_parts(out, 1, job)
        c.kill_worker(1)
        done_at_kill = len(fleet.job.parts(out))
        stdout, stderr = job.communicate(timeout=300)
        assert job.returncode == 0, stderr
        assert done_at_kill < 16, "the job ended before the worker was killed: make the records longer"
        assert_same_table(fleet.read_modes(out), big_table)
    finally:
        c.close()


def test_ctrl_c_then_resume_gives_the_same_table(data, big_table, tmp_path):
    out = str(tmp_path / "modes.parquet")
    job = subprocess.Popen([sys.executable, "-m", "okid.fleet.cli", "identify", data["big"], "--out", out,
                            "--workers", "2", "--batch-size", "1", *CLI_OPTIONS],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _wait_for_parts(out, 2, job)
    job.send_signal(signal.SIGINT)
    stdout, stderr = job.communicate(timeout=120)
    assert job.returncode == 130, stderr
    assert "--resume" in stderr and "Traceback" not in stderr
    partial = fleet.read_modes(out)  # whole parts only: readable
    assert 2 <= partial["record"].nunique() < 16
    proc = okid_fleet("identify", data["big"], "--out", out, "--resume", *CLI_OPTIONS, "--workers", "2")
    assert f"{partial['record'].nunique()} already done" in proc.stdout
    assert_same_table(fleet.read_modes(out), big_table)


def test_bad_invocations_say_what_is_wrong(tmp_path):
    proc = okid_fleet("identify", str(tmp_path / "nothing"), "--out", str(tmp_path / "o"), check=False)
    assert proc.returncode == 1 and "no such file" in proc.stderr and "Traceback" not in proc.stderr
    proc = okid_fleet("synth", "--out", str(tmp_path / "s"), "--assets", "0", check=False)
    assert proc.returncode == 2 and "at least 1 asset" in proc.stderr


def test_csv_time_column_follows_the_cli_rule(tmp_path):
    """A time column with a unit, in last place, gives dt and is no channel; two are refused; the
    CLI reads the same file to the same dt (its JSON config) and the same channels."""
    t = np.arange(400) * 50.0  # milliseconds
    rng = np.random.default_rng(9)
    data = np.column_stack([rng.standard_normal((400, 3)), t])
    path = tmp_path / "asset-x" / "r.csv"
    path.parent.mkdir()
    np.savetxt(path, data, delimiter=",", header="force,acc1,acc2,Timestamp [ms]", comments="", fmt="%.17g")
    rec = fleet.read(fleet.discover([str(path)])[0], fleet.ChannelSpec())
    assert rec.dt == pytest.approx(0.05, rel=1e-12)
    assert rec.input_names == ("force",) and rec.output_names == ("acc1", "acc2")
    cli = os.environ.get("OKID_CLI")
    if cli:
        out = json.loads(subprocess.run([cli, "identify", "--json", "--order", "2", str(path)], capture_output=True,
                                        text=True, check=True).stdout)
        assert out["config"]["dt"] == pytest.approx(rec.dt, rel=1e-12)
        assert out["inputs"] == list(rec.input_names) and out["outputs"] == list(rec.output_names)
    two = tmp_path / "asset-x" / "two.csv"
    np.savetxt(two, np.column_stack([t, data]), delimiter=",", header="t,force,acc1,acc2,time_ms", comments="",
               fmt="%.17g")
    with pytest.raises(fleet.RecordError, match="two time columns"):
        fleet.read(fleet.discover([str(two)])[0], fleet.ChannelSpec())
