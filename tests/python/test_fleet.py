# SPDX-License-Identifier: Apache-2.0
"""okid-fleet end to end on real Dask clusters of processes on localhost.

A synthetic fleet from okid's simulator (some assets losing stiffness) is identified on a cluster
that the test starts itself (a `dask scheduler` and two `dask worker` processes, started in a
folder of their own, the job given relative paths) and on the local default; the tables must equal
a serial loop over okid.identify, a corrupt and a non-exciting record must be status rows, a
worker killed mid-job and a Ctrl-C mid-job must cost nothing, a record that kills its worker must
fail alone, the user's files must survive every --out and --overwrite, and the tracks must find the
simulated stiffness loss (exact modes from numpy, not from okid), whatever one outlier or a record
with its columns swapped does.
"""
import os

# The serial loop of this process must run as the workers do (one BLAS thread each, job.py): a
# threaded OpenBLAS kernel rounds otherwise, and the tables are compared bit for bit.
os.environ["OPENBLAS_NUM_THREADS"] = "1"

import contextlib
import json
import logging
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pandas as pd
import pytest

import okid
from okid import fleet
import okid.fleet.cli  # for okid_fleet_here: fleet/__init__ does not import it

OPTIONS = {"order": 4, "zero_initial_state": 1}
CLI_OPTIONS = ["--order", "4", "--zero-initial-state"]
DASK = os.path.join(os.path.dirname(sys.executable), "dask")
POISON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fleet_poison.py")
POISON_DT = 0.0421  # fleet_poison.py kills the worker that identifies a record sampled so
HANG_DT = 0.0433    # and hangs the one identifying a record sampled so
MEMORY_DT = 0.0437  # and takes memory until its worker's nanny kills it, for a record sampled so
BUCKET = "okid-fleet"
AMBIENT_RECORDS, AMBIENT_SAMPLES = 8, 4000
# the tracked change of an output-only fleet against the exact one: worst error 0.014 over seeds 9-11
# (20 s records of a chain damped 1.6 and 3.4 %, identified at L = 40, n = 4), with a margin
AMBIENT_CHANGE_TOLERANCE = 0.02


def okid_fleet_here(capsys, *args):
    """okid-fleet's main in this process (no interpreter to start, no imports to repeat): (status, stdout, stderr)."""
    capsys.readouterr()
    status = fleet.cli.main([str(a) for a in args])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def okid_fleet(*args, check=True, timeout=300, cwd=None):
    proc = subprocess.run([sys.executable, "-m", "okid.fleet.cli", *map(str, args)], capture_output=True,
                          text=True, timeout=timeout, cwd=cwd)
    if check and proc.returncode != 0:
        raise AssertionError(f"okid-fleet {' '.join(map(str, args))}: {proc.returncode}\n{proc.stderr}")
    return proc


class Cluster:
    """A dask scheduler and N single-threaded worker processes, each in its own process group, all
    started in the folder TMP (not the tests' working directory: relative paths do not reach
    them). PRELOAD: a module each worker imports first; ALLOWED_FAILURES: the scheduler's worker
    deaths per task before it gives the task up (KilledWorker)."""

    def __init__(self, tmp, workers=2, preload=None, allowed_failures=None):
        self.file = os.path.join(tmp, "scheduler.json")
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")  # with the S3 endpoint's, if any
        if allowed_failures is not None:
            env["DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES"] = str(allowed_failures)
        self.scheduler = subprocess.Popen([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0",
                                           "--no-dashboard", "--scheduler-file", self.file],
                                          env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL, cwd=tmp)
        deadline = time.monotonic() + 60
        while not os.path.exists(self.file) and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(0.2)
        with open(self.file) as f:
            self.address = json.load(f)["address"]
        extra = ["--preload", preload] if preload else []
        self.workers = [subprocess.Popen([DASK, "worker", "--scheduler-file", self.file, "--nthreads", "1",
                                          "--no-dashboard", "--host", "127.0.0.1", "--name", f"w{i}", *extra],
                                         env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                                         stderr=subprocess.DEVNULL, cwd=tmp)
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
    tiny = fleet.synthesize(str(root / "tiny"), fleet.FleetSpec(assets=1, records=3, samples=600, seed=6, fmt="csv"))
    return {"records": info["records_dir"], "truth": info["truth"], "damaged": info["damaged"],
            "extra": str(root / "extra"), "big": big["records_dir"], "tiny": tiny["records_dir"], "root": root}


@contextlib.contextmanager
def _environment(env):
    """ENV in os.environ (for this process and the processes started meanwhile), restored after."""
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def s3():
    """A real S3 API on localhost (moto's server) with an empty bucket, its endpoint and made-up
    credentials in the environment variables that s3fs reads, here and in the cluster's workers
    (started after this); None without moto or s3fs."""
    try:
        import s3fs
        from moto.server import ThreadedMotoServer
    except ImportError:
        yield None
        return
    port = _free_port()
    logging.getLogger("werkzeug").setLevel(logging.WARNING)  # not a line per request
    server = ThreadedMotoServer(ip_address="127.0.0.1", port=port, verbose=False)
    server.start()
    env = {"AWS_ENDPOINT_URL": f"http://127.0.0.1:{port}", "AWS_ACCESS_KEY_ID": "okid-test",
           "AWS_SECRET_ACCESS_KEY": "okid-test", "AWS_DEFAULT_REGION": "us-east-1"}
    with _environment(env):
        fs = s3fs.S3FileSystem()
        fs.mkdir(BUCKET)
        yield fs
    server.stop()


@pytest.fixture(scope="module")
def gcs():
    """A Google Cloud Storage JSON API on localhost (gcp-storage-emulator, in memory) with an empty
    bucket; None without it or gcsfs. gcsfs finds it through STORAGE_EMULATOR_HOST and asks no
    credentials with token "anon" (fsspec's FSSPEC_GS_TOKEN, here and in the cluster's workers).
    gcsfs's experimental zonal/HNS bucket support (on by default since 2025) asks each bucket's
    layout over gRPC with TLS, which the emulator does not serve (the call retries for minutes):
    GCSFS_EXPERIMENTAL_ZB_HNS_SUPPORT=false keeps gcsfs on the JSON API, which a real bucket
    serves too."""
    env = {"GCSFS_EXPERIMENTAL_ZB_HNS_SUPPORT": "false", "FSSPEC_GS_TOKEN": "anon"}
    with _environment(env):
        try:
            import gcsfs
            from gcp_storage_emulator.server import create_server
        except ImportError:
            yield None
            return
        port = _free_port()
        logging.getLogger("gcp_storage_emulator").setLevel(logging.WARNING)
        server = create_server("127.0.0.1", port, in_memory=True, default_bucket=BUCKET)
        server.start()
        import fsspec.config

        saved = fsspec.config.conf.get("gs")
        fsspec.config.conf["gs"] = dict(saved or {}, token="anon")
        with _environment({"STORAGE_EMULATOR_HOST": f"http://127.0.0.1:{port}"}):
            yield gcsfs.GCSFileSystem()
        if saved is None:
            fsspec.config.conf.pop("gs", None)
        else:
            fsspec.config.conf["gs"] = saved
        server.stop()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory, s3, gcs):
    """The shared cluster: its workers run in a folder of their own, import fleet_poison.py, reach
    the S3 endpoint and the GCS emulator, and a task is given up after its second worker death
    (Dask's default is the fourth)."""
    c = Cluster(str(tmp_path_factory.mktemp("dask")), preload=POISON, allowed_failures=1)
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
    """The job given paths relative to its own working directory, which the workers do not share."""
    out = str(tmp_path_factory.mktemp("out") / "modes.parquet")
    root = data["root"]
    okid_fleet("identify", os.path.relpath(data["records"], root), os.path.relpath(data["extra"], root),
               "--out", out, "--scheduler", cluster.address, *CLI_OPTIONS, "--quiet", cwd=root)
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
    proc = okid_fleet("identify", data["records"], data["extra"], "--out", out, *CLI_OPTIONS, "--workers", "2",
                      "--memory-limit", "1GiB")
    assert "42 records identified (2 failed, 0 already done)" in proc.stdout
    assert "starting a local cluster of 2 worker process(es), at most 1GiB of memory each" in proc.stderr
    assert "okid-fleet: dashboard http://" in proc.stderr and "42/42 records, 2 failed" in proc.stderr
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


def test_a_record_without_a_physical_mode_gets_a_row_that_says_so():
    """The default options (no order: okid identify's automatic selection) on a real record where
    nothing is physical (Hayward's weak event, tests/data/other_events): one row, status no_modes,
    whose message and warnings say no physical mode was found (not that the model has no mode)."""
    from okid.fleet.records import ChannelSpec, discover
    from okid.fleet.rows import identify_record

    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "other_events",
                        "hayward_58658_005_20210803.csv")
    rows = identify_record(discover([path])[0], ChannelSpec(inputs="4"), {})
    assert [row["status"] for row in rows] == ["no_modes"]
    assert rows[0]["message"].startswith("no physical mode found") and "no_physical_mode" in rows[0]["warnings"]


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


def _tree(folder):
    """Every file below FOLDER with its bytes: what must survive a refused or an overwriting job."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_the_users_files_survive_every_out_and_overwrite(data, cluster, tmp_path):
    """The issue's deletion: `identify fleet/records --out fleet [--overwrite]` removed the inputs.
    An --out that overlaps an input, or holds a file okid-fleet did not write, is refused with
    --overwrite too; --overwrite removes only the earlier run's parts; --resume with other settings
    is refused and names the difference."""
    fleet_dir = tmp_path / "fleet"
    shutil.copytree(os.path.dirname(data["tiny"]), fleet_dir)
    (fleet_dir / "notes.txt").write_text("the user's\n")
    before = _tree(fleet_dir)
    records = fleet_dir / "records"
    for out in (fleet_dir, records, records / "asset-000" / "modes"):
        for flags in ((), ("--overwrite",), ("--resume",)):
            proc = okid_fleet("identify", records, "--out", out, "--scheduler", cluster.address, *flags,
                              check=False)
            assert proc.returncode == 1 and "overlap" in proc.stderr and "Traceback" not in proc.stderr, proc
    assert _tree(fleet_dir) == before

    mixed = tmp_path / "mixed"
    mixed.mkdir()
    (mixed / "truth.parquet").write_bytes((fleet_dir / "truth.parquet").read_bytes())
    for flags in ((), ("--overwrite",)):
        proc = okid_fleet("identify", records, "--out", mixed, "--scheduler", cluster.address, *flags, check=False)
        assert proc.returncode == 1 and "did not write (truth.parquet)" in proc.stderr, proc
    assert sorted(os.listdir(mixed)) == ["truth.parquet"]

    out = tmp_path / "modes"
    okid_fleet("identify", records, "--out", out, "--scheduler", cluster.address, *CLI_OPTIONS, "--quiet")
    first = sorted(os.listdir(out))
    assert first[0] == "_okid_fleet.json" and all(n.startswith("part-") for n in first[1:]), first
    manifest = json.loads((out / "_okid_fleet.json").read_text())
    assert manifest["settings"]["okid"] == okid.__version__ and manifest["settings"]["options"] == OPTIONS
    table = fleet.read_modes(str(out))
    proc = okid_fleet("identify", records, "--out", out, "--resume", "--order", "2", "--zero-initial-state",
                      check=False)
    assert proc.returncode == 1 and "options.order 4 -> 2" in proc.stderr, proc.stderr
    (out / "mine.csv").write_text("a user's file put into the output\n")
    proc = okid_fleet("identify", records, "--out", out, "--overwrite", *CLI_OPTIONS, check=False)
    assert proc.returncode == 1 and "mine.csv" in proc.stderr
    (out / "mine.csv").unlink()
    okid_fleet("identify", records, "--out", out, "--overwrite", "--scheduler", cluster.address, *CLI_OPTIONS,
               "--quiet")
    second = sorted(os.listdir(out))
    assert len(second) == len(first) and set(first) & set(second) == {"_okid_fleet.json"}, (first, second)
    assert_same_table(fleet.read_modes(str(out)), table)
    assert _tree(fleet_dir) == before


def test_a_job_where_every_record_failed_exits_non_zero(data, cluster, tmp_path):
    """Both records of `extra` fail (a corrupt file, a force of zero): status 3, the reasons counted."""
    proc = okid_fleet("identify", data["extra"], "--out", tmp_path / "o", "--scheduler", cluster.address,
                      *CLI_OPTIONS, "--quiet", check=False)
    assert proc.returncode == 3, proc
    assert "2 records identified (2 failed" in proc.stdout
    assert "1 unreadable, e.g." in proc.stdout and "1 not_persistently_exciting, e.g." in proc.stdout
    assert "2 of 2 records failed" in proc.stderr and "Traceback" not in proc.stderr
    # one failure in two is the threshold (0.5), not above it; a lower one makes it fail the job
    good = os.path.join(data["tiny"], "asset-000")
    proc = okid_fleet("identify", good, os.path.join(data["extra"], "asset-bad", "corrupt.csv"), "--out",
                      tmp_path / "p", "--scheduler", cluster.address, *CLI_OPTIONS, "--quiet",
                      "--max-failed-fraction", "0.2", check=False)
    assert proc.returncode == 3 and "1 of 4 records failed" in proc.stderr, proc


def test_lifted_decimation_gives_okid_identify_s_rows(data, cluster, tmp_path):
    """--decimation 2 --decimation-method lift on the shared cluster: each record's rows are
    okid.identify(u, y, dt, decimation=2, decimation_method="lift")'s modes, bit for bit, at dt 2 dt;
    lifting without the factor and on output-only records is refused in one line."""
    options = {**OPTIONS, "decimation": 2, "decimation_method": "lift"}
    out = tmp_path / "modes.parquet"
    okid_fleet("identify", data["tiny"], "--out", out, "--scheduler", cluster.address, *CLI_OPTIONS,
               "--decimation", "2", "--decimation-method", "lift", "--quiet")
    table = fleet.read_modes(str(out))
    folder = os.path.join(data["tiny"], "asset-000")
    names = sorted(os.listdir(folder))
    assert len(names) == 3 and table["record"].nunique() == 3
    for name in names:
        rec = np.loadtxt(os.path.join(folder, name), delimiter=",", skiprows=1)
        dt = float(rec[1, 0] - rec[0, 0])
        result = okid.identify(rec[:, 1:2], rec[:, 2:4], dt, **options)
        rows = table[table["record"] == f"asset-000/{os.path.splitext(name)[0]}"]
        assert (rows["status"] == "ok").all(), rows[["status", "message"]]
        assert list(rows["frequency_hz"]) == [m.frequency_hz for m in result.modes]
        assert list(rows["damping_ratio"]) == [m.damping_ratio for m in result.modes]
        assert rows["dt"].iloc[0] == result.dt == pytest.approx(2 * dt, rel=1e-12)
        assert json.loads(rows["config"].iloc[0])["decimation_method"] == "lift"
    proc = okid_fleet("identify", data["tiny"], "--out", tmp_path / "x", "--decimation-method", "lift", check=False)
    assert proc.returncode == 2 and "--decimation-method lift needs --decimation K" in proc.stderr
    assert not (tmp_path / "x").exists()
    proc = okid_fleet("identify", data["tiny"], "--out", tmp_path / "y", "--inputs", "0", "--decimation", "2",
                      "--decimation-method", "lift", check=False)
    assert proc.returncode == 2 and "not a setting of output-only records" in proc.stderr


def _identify_frame(rows, outputs):
    return okid.identify(rows[["force"]].to_numpy(), rows[outputs].to_numpy(), float(rows["dt"].iloc[0]), **OPTIONS)


def test_every_record_of_a_mixed_folder_is_found(data, cluster, tmp_path):
    """A CSV folder with a Parquet file at its top and one in a sub-folder, a Hive-partitioned
    dataset (asset=.../, no asset column in its files), a file holding four records in one row
    group, and a corrupt Parquet file: every record is found and identified, the corrupt file is
    one status row."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    root = tmp_path / "site"
    shutil.copytree(data["tiny"], root)                                   # 3 CSV records of asset-000
    source = pd.read_parquet(os.path.join(data["records"], "asset-001.parquet"))
    names = list(dict.fromkeys(source["record"]))
    one = source[source["record"].isin(names[:2])]
    one.to_parquet(root / "top.parquet", index=False, row_group_size=2000)  # 2 records, top level
    (root / "deeper").mkdir()
    source[source["record"] == names[2]].to_parquet(root / "deeper" / "r.parquet", index=False)
    hive = pd.read_parquet(os.path.join(data["records"], "asset-002.parquet"))
    hive_records = list(dict.fromkeys(hive["record"]))[:3]
    hive = hive[hive["record"].isin(hive_records)]
    hive.to_parquet(root / "hive", partition_cols=["asset"], index=False)  # hive/asset=asset-002/*.parquet
    shared = pd.read_parquet(os.path.join(data["records"], "asset-003.parquet"))
    shared_records = list(dict.fromkeys(shared["record"]))[:4]
    shared = shared[shared["record"].isin(shared_records)]
    pq.write_table(pa.Table.from_pandas(shared, preserve_index=False), root / "shared.parquet",
                   row_group_size=len(shared))                             # 4 records, one row group
    (root / "broken.parquet").write_bytes(b"PAR1 this is not a Parquet file")
    refs = fleet.discover([str(root)])
    by_source = {}
    for ref in refs:
        by_source.setdefault(ref.source, []).append(ref.record)
    assert len(by_source["csv"]) == 3 and len(by_source["broken"]) == 1
    assert set(by_source["parquet"]) == set(names[:3] + hive_records + shared_records)
    assert {r.asset for r in refs if r.record in hive_records} == {"asset-002"}
    assert {r.row_groups for r in refs if r.record in shared_records} == {(0,)}

    out = tmp_path / "modes"
    proc = okid_fleet("identify", root, "--out", out, "--scheduler-file", cluster.file, *CLI_OPTIONS, "--quiet")
    assert f"{len(refs)} records identified (1 failed" in proc.stdout
    table = fleet.read_modes(str(out))
    broken = table[table["status"] != "ok"]
    assert list(broken["status"]) == ["unreadable"] and "broken.parquet" in broken["message"].iloc[0]
    for frame, records in ((source, names[:3]), (hive, hive_records), (shared, shared_records)):
        for record in records:
            expected = _identify_frame(frame[frame["record"] == record], ["acc1", "acc2"])
            rows = table[table["record"] == record]
            assert list(rows["frequency_hz"]) == [m.frequency_hz for m in expected.modes], record
    assert set(table[table["record"].isin(hive_records)]["asset"]) == {"asset-002"}


def _csv_record(path, dt, seed, samples=600):
    t = np.arange(samples) * dt
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    a = np.array([[0.9, 0.3], [-0.3, 0.9]])
    x, y = np.zeros(2), np.zeros((samples, 2))
    for k in range(samples):
        y[k] = x + 0.1 * u[k, 0]
        x = a @ x + np.array([1.0, 0.0]) * u[k, 0]
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([t, u, y]), delimiter=",", header="time,force,acc1,acc2", comments="",
               fmt="%.17g")


def test_a_record_that_kills_its_worker_fails_alone(cluster, tmp_path):
    """One batch of three records, the middle one killing any worker that identifies it (SIGKILL,
    fleet_poison.py): the two others are identified as okid.identify does, the killer is one
    worker_died row, the job exits 0 (1 of 3 failed)."""
    folder = tmp_path / "records" / "asset-p"
    _csv_record(folder / "a.csv", 0.05, 1)
    _csv_record(folder / "b.csv", POISON_DT, 2)
    _csv_record(folder / "c.csv", 0.05, 3)
    out = tmp_path / "modes"
    proc = okid_fleet("identify", tmp_path / "records", "--out", out, "--scheduler", cluster.address,
                      "--batch-size", "3", "--order", "2", "--quiet", check=False)
    assert proc.returncode == 0, proc.stderr
    assert "3 records identified (1 failed" in proc.stdout and "1 worker_died" in proc.stdout
    table = fleet.read_modes(str(out)).set_index("record")
    assert table.loc["asset-p/b", "status"] == "worker_died"
    for name in ("a", "c"):
        rec = okid.read_record(folder / f"{name}.csv")  # the fleet's reader: the CLI's samples and dt rule
        expected = okid.identify(rec.u, rec.y, rec.dt, order=2)
        rows = table.loc[[f"asset-p/{name}"]]
        assert (rows["status"] == "ok").all()
        assert list(rows["frequency_hz"]) == [m.frequency_hz for m in expected.modes]


def test_a_record_past_the_memory_limit_fails_alone(tmp_path, capsys):
    """--memory-limit on the local cluster, whose workers import fleet_poison.py (Dask's worker
    preload, from the configuration): one record of three (a task each: the batch's isolation is
    test_a_record_that_kills_its_worker_fails_alone's) takes memory until the worker's nanny
    restarts it past 95 % of the limit, twice, then twice more alone. It ends as one out_of_memory
    row naming the worker's memory and the limit; the two others are identified as okid.identify
    does; 1 of 3 failed: exit 0."""
    import dask
    import distributed  # noqa: F401  its defaults in dask.config first: the set below restores what it found

    folder = tmp_path / "records" / "asset-m"
    _csv_record(folder / "a.csv", 0.05, 1)
    _csv_record(folder / "b.csv", MEMORY_DT, 2)
    _csv_record(folder / "c.csv", 0.05, 3)
    # a worker holds about 150 MiB after importing okid, pandas and pyarrow: 400 MiB leaves room
    # below the 80 % at which Dask pauses a worker
    with dask.config.set({"distributed.worker.preload": [POISON]}):
        status, out, err = okid_fleet_here(capsys, "identify", tmp_path / "records", "--out", tmp_path / "modes",
                                           "--workers", "2", "--memory-limit", "400MiB", "--batch-size", "1",
                                           "--order", "2")
    assert status == 0, err
    assert "3 records identified (1 failed" in out and "1 out_of_memory, e.g. its worker used" in out, (out, err)
    table = fleet.read_modes(str(tmp_path / "modes")).set_index("record")
    row = table.loc["asset-m/b"]
    assert row["status"] == "out_of_memory" and "of a 400 MiB limit" in row["message"], row["message"]
    used = float(row["message"].split("its worker used ")[1].split(" MiB")[0])
    # past the nanny's 95 %; at most what the hook takes (1.2 x the limit) on top of the worker's own
    # ~150 MiB (250 MiB allowed: the nanny looks every 100 ms, later on a loaded machine)
    assert 0.95 * 400 <= used <= 1.2 * 400 + 250, used
    for name in ("a", "c"):
        rec = okid.read_record(folder / f"{name}.csv")
        expected = okid.identify(rec.u, rec.y, rec.dt, order=2)
        rows = table.loc[[f"asset-m/{name}"]]
        assert (rows["status"] == "ok").all()
        assert list(rows["frequency_hz"]) == [m.frequency_hz for m in expected.modes]


def test_records_past_their_limits_fail_alone(cluster, tmp_path, capsys):
    """One batch of four records: one hangs inside okid.identify (fleet_poison.py), one is larger
    than --max-record-mb. The hanging one is a timed_out row after --record-timeout, the large one
    a too_large row, never read; the two others are identified as okid.identify does; 2 of 4
    failed is not more than --max-failed-fraction 0.5: exit 0. The hanging worker is restarted."""
    folder = tmp_path / "records" / "asset-l"
    _csv_record(folder / "a.csv", 0.05, 1)
    _csv_record(folder / "b.csv", HANG_DT, 2)
    _csv_record(folder / "c.csv", 0.05, 3)
    _csv_record(folder / "d.csv", 0.05, 4, samples=6000)
    sizes = {name: (folder / f"{name}.csv").stat().st_size for name in "abcd"}
    limit_mb = 2 * sizes["a"] / 1e6  # a, b, c are about 600 samples of 4 columns, d ten times that
    assert max(sizes["a"], sizes["b"], sizes["c"]) < limit_mb * 1e6 < sizes["d"]
    # a 600-sample record is identified in milliseconds: 2 s is a margin of a hundred times and more
    status, out, err = okid_fleet_here(capsys, "identify", tmp_path / "records", "--out", tmp_path / "modes",
                                       "--scheduler", cluster.address, "--batch-size", "4", "--order", "2",
                                       "--record-timeout", "2", "--max-record-mb", limit_mb, "--quiet")
    assert status == 0, err
    assert "4 records identified (2 failed" in out and "could not restart" not in err, (out, err)
    assert "1 timed_out, e.g. reading and identifying it took longer than --record-timeout 2 s" in out
    assert f"1 too_large, e.g. {sizes['d'] / 1e6:.3g} MB, more than --max-record-mb" in out
    table = fleet.read_modes(str(tmp_path / "modes")).set_index("record")
    assert table.loc["asset-l/b", "status"] == "timed_out" and table.loc["asset-l/d", "status"] == "too_large"
    for name in ("a", "c"):
        rec = okid.read_record(folder / f"{name}.csv")
        expected = okid.identify(rec.u, rec.y, rec.dt, order=2)
        rows = table.loc[[f"asset-l/{name}"]]
        assert list(rows["frequency_hz"]) == [m.frequency_hz for m in expected.modes]
    status, _, err = okid_fleet_here(capsys, "identify", tmp_path / "records", "--out", tmp_path / "o2",
                                     "--record-timeout", "0")
    assert status == 2 and "--record-timeout 0.0: a number of seconds > 0" in err, err
    status, _, err = okid_fleet_here(capsys, "identify", tmp_path / "records", "--out", tmp_path / "o2",
                                     "--memory-limit", "1GiB", "--scheduler", cluster.address)
    assert status == 2 and "--memory-limit is the local cluster's" in err, err
    status, _, err = okid_fleet_here(capsys, "identify", "nosuch://bucket/records", "--out", tmp_path / "o2")
    assert status == 1 and "nosuch://bucket/records:" in err and len(err.splitlines()) == 1, err
    status, _, err = okid_fleet_here(capsys, "identify", tmp_path / "records", "--out", tmp_path / "o2",
                                     "--workers", "0")
    assert status == 2 and err == "okid-fleet: --workers 0: a count >= 1\n", err
    status, _, err = okid_fleet_here(capsys, "track", tmp_path / "nosuch", "--out", tmp_path / "t.parquet")
    assert status == 1 and err == f"okid-fleet: {tmp_path / 'nosuch'}: no such file or folder\n", err
    status, _, err = okid_fleet_here(capsys, "track", tmp_path / "modes", "--out", tmp_path / "no" / "t.parquet")
    assert status == 1 and len(err.splitlines()) == 1 and "non-existent directory" in err, err


def _upload(fs, local_dir, url):
    for path in sorted(local_dir.rglob("*")):
        if path.is_file():
            fs.put_file(str(path), f"{url}/{path.relative_to(local_dir).as_posix()}")


def test_object_storage_gives_the_local_table(data, cluster, cluster_table, s3, tmp_path, capsys):
    """One asset's Parquet file and the two bad CSV records in a bucket of a real S3 API on
    localhost (moto's server), the output written there by the cluster's workers (which run in
    another folder and read the endpoint and the credentials from the environment): the table
    equals the local run's rows of those records bit for bit, the messages naming the objects
    instead of the files. The manifest and overwrite rules hold object by object: a foreign object
    is never removed, an overlapping --out is refused, --overwrite replaces only the parts."""
    if s3 is None:
        pytest.skip("needs s3fs and moto[server] (host_tools/requirements.txt)")
    root = data["root"]
    s3.put_file(os.path.join(data["records"], "asset-000.parquet"), f"{BUCKET}/small/records/asset-000.parquet")
    _upload(s3, root / "extra", f"{BUCKET}/extra")
    inputs = [f"s3://{BUCKET}/small/records", f"s3://{BUCKET}/extra"]
    out = f"s3://{BUCKET}/modes"
    status, stdout, stderr = okid_fleet_here(capsys, "identify", *inputs, "--out", out, "--scheduler",
                                             cluster.address, *CLI_OPTIONS)
    assert status == 0 and "10 records identified (2 failed, 0 already done)" in stdout, (stdout, stderr)
    assert f"connecting to {cluster.address}" in stderr and "10/10 records, 2 failed" in stderr
    assert "okid-fleet: no dashboard at http://" in stderr  # the test's scheduler runs with --no-dashboard
    expected = cluster_table[cluster_table["asset"].isin(["asset-000", "asset-bad"])].copy()
    expected["message"] = expected["message"].str.replace(str(root), f"s3://{BUCKET}", regex=False)
    assert f"s3://{BUCKET}/extra/asset-bad/corrupt.csv" in " ".join(expected["message"])
    assert_same_table(fleet.read_modes(out), expected)

    written = sorted(s3.ls(f"{BUCKET}/modes"))
    assert written[0].endswith("/_okid_fleet.json") and all("/part-" in p for p in written[1:]), written

    def refused(**flags):
        with pytest.raises(fleet.FleetError) as refusal:
            fleet.identify_fleet(inputs, flags.pop("out", out), options=flags.pop("options", OPTIONS),
                                 scheduler=cluster.address, progress=None, **flags)
        return str(refusal.value)

    assert "--resume to finish it" in refused()
    assert "options.order 4 -> 2" in refused(resume=True, options={"order": 2, "zero_initial_state": 1})
    assert "overlap" in refused(out=f"s3://{BUCKET}/extra/modes")
    s3.pipe_file(f"{BUCKET}/modes/notes.txt", b"the user's")
    assert "did not write (notes.txt)" in refused(overwrite=True)
    s3.invalidate_cache()
    assert sorted(s3.ls(f"{BUCKET}/modes")) == sorted(written + [f"{BUCKET}/modes/notes.txt"])
    s3.rm_file(f"{BUCKET}/modes/notes.txt")
    fleet.identify_fleet(inputs, out, options=OPTIONS, scheduler=cluster.address, progress=None, overwrite=True)
    s3.invalidate_cache()
    rewritten = sorted(s3.ls(f"{BUCKET}/modes"))
    assert len(rewritten) == len(written) and set(rewritten) & set(written) == {f"{BUCKET}/modes/_okid_fleet.json"}
    assert_same_table(fleet.read_modes(out), expected)


def test_google_cloud_storage_gives_the_local_table(data, cluster, cluster_table, gcs, tmp_path, capsys):
    """The records of the S3 test in a bucket of a GCS emulator on localhost, read and written
    by the cluster's workers through gcsfs: the table equals the local run's rows of those records
    bit for bit, the messages naming the objects."""
    if gcs is None:
        pytest.skip("needs gcsfs and gcp-storage-emulator (host_tools/requirements.txt)")
    root = data["root"]
    gcs.put_file(os.path.join(data["records"], "asset-000.parquet"), f"{BUCKET}/small/records/asset-000.parquet")
    _upload(gcs, root / "extra", f"{BUCKET}/extra")
    out = f"gs://{BUCKET}/modes"
    status, stdout, stderr = okid_fleet_here(capsys, "identify", f"gs://{BUCKET}/small/records",
                                             f"gs://{BUCKET}/extra", "--out", out, "--scheduler", cluster.address,
                                             *CLI_OPTIONS, "--quiet")
    assert status == 0 and "10 records identified (2 failed, 0 already done)" in stdout, (stdout, stderr)
    expected = cluster_table[cluster_table["asset"].isin(["asset-000", "asset-bad"])].copy()
    expected["message"] = expected["message"].str.replace(str(root), f"gs://{BUCKET}", regex=False)
    assert f"gs://{BUCKET}/extra/asset-bad/corrupt.csv" in " ".join(expected["message"])
    assert_same_table(fleet.read_modes(out), expected)
    gcs.invalidate_cache()
    written = sorted(gcs.ls(f"{BUCKET}/modes"))
    assert written[0].endswith("/_okid_fleet.json") and all("/part-" in p for p in written[1:]), written


def test_output_only_records_are_identified_and_tracked(cluster, tmp_path, capsys):
    """A synthetic fleet whose force is not recorded (okid-fleet synth --ambient), identified with
    --inputs 0 on the cluster: the rows are okid.identify_ambient's on the records read with
    pandas, bit for bit, in the table's one schema; every record's modes are matched to the
    baseline, the tracked changes agree with the exact ones (numpy, synth.py), the damaged asset's
    mode 1 (-2 %) drifts and no mode of the others does. (One scenario, seed 9: of seeds 9 to 11,
    seed 10 also calls two undamaged modes drifting, by -1.4 and +0.9 %: output-only frequencies
    of short records scatter more than input-output ones.) The observer's settings are refused in one
    line."""
    spec = fleet.FleetSpec(assets=3, records=AMBIENT_RECORDS, damaged=1, stiffness_loss=0.10,
                           samples=AMBIENT_SAMPLES, seed=9, ambient=True, damping_scale=0.1)
    info = fleet.synthesize(str(tmp_path / "fleet"), spec)
    out = tmp_path / "modes"
    status, stdout, stderr = okid_fleet_here(capsys, "identify", info["records_dir"], "--out", out, "--scheduler",
                                             cluster.address, "--inputs", "0", "--hankel-rows", "40", "--order", "4",
                                             "--quiet")
    assert status == 0 and f"{3 * AMBIENT_RECORDS} records identified (0 failed" in stdout, (stdout, stderr)
    table = fleet.read_modes(str(out))
    assert list(table.columns) == fleet.rows.schema().names
    for name in sorted(os.listdir(info["records_dir"])):
        frame = pd.read_parquet(os.path.join(info["records_dir"], name))
        assert "force" not in frame.columns
        for record, rows in frame.groupby("record", sort=False):
            expected = okid.identify_ambient(rows[["acc1", "acc2"]].to_numpy(), float(rows["dt"].iloc[0]),
                                             hankel_rows=40, order=4)
            got = table[table["record"] == record]
            assert (got["status"] == "ok").all(), got[["status", "message"]]
            assert list(got["frequency_hz"]) == [m.frequency_hz for m in expected.modes], record
            assert list(got["damping_ratio"]) == [m.damping_ratio for m in expected.modes], record
            assert (got["order"] == expected.order).all() and (got["samples"] == expected.samples).all()
    tracks, summary = fleet.track(table, fleet.TrackOptions(baseline_records=3))
    truth = pd.read_parquet(info["truth"])
    for (asset, mode), rows in truth.groupby(["asset", "mode"]):
        rows = rows.sort_values("start")
        true_change = rows["frequency_hz"].iloc[-1] / rows["frequency_hz"].iloc[0] - 1
        got = summary[(summary["asset"] == asset) & (summary["mode"] == mode)].iloc[0]
        assert got["records"] == AMBIENT_RECORDS, got  # every record's mode matched to the baseline
        assert abs(got["frequency_change"] - true_change) < AMBIENT_CHANGE_TOLERANCE, (asset, mode, got, true_change)
        if asset in info["damaged"] and mode == 1:
            assert true_change < -0.015 and got["drift"], (asset, mode, got, true_change)
        elif asset not in info["damaged"]:
            assert not got["drift"], (asset, mode, got)
    status, _, err = okid_fleet_here(capsys, "identify", info["records_dir"], "--out", tmp_path / "o2",
                                     "--inputs", "0", "--observer-order", "10", "--zero-initial-state")
    assert status == 2 and len(err.splitlines()) == 1, err
    assert "--observer-order, --zero-initial-state: not a setting of output-only records" in err, err


def test_a_port_that_is_not_dask_times_out(data, tmp_path):
    """A TCP server that accepts and never speaks: refused in about --connect-timeout, one line."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        t0 = time.monotonic()
        proc = okid_fleet("identify", data["tiny"], "--out", tmp_path / "o", "--scheduler",
                          f"tcp://127.0.0.1:{server.getsockname()[1]}", "--connect-timeout", "2", check=False,
                          timeout=120)
        assert proc.returncode == 1 and "no Dask scheduler answered" in proc.stderr, proc
        # the records found, the scheduler asked, the refusal
        assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) <= 3, proc.stderr
        assert time.monotonic() - t0 < 60
    finally:
        stop.set()
        thread.join()
        for conn in held:
            conn.close()
        server.close()


def test_track_matches_outputs_by_name_and_shrugs_off_an_outlier(data, cluster_table):
    """A record whose output columns come swapped keeps both its modes; a first record 4 % off
    (the old reference) moves neither the reference nor the trend of an undamaged asset."""
    table = cluster_table.copy()
    undamaged = sorted(set(table["asset"]) - set(data["damaged"]) - {"asset-bad"})[0]
    records = list(dict.fromkeys(table[table["asset"] == undamaged]["record"]))
    swapped = table["record"] == records[3]
    for column in ("shape_re", "shape_im", "outputs"):
        table.loc[swapped, column] = table.loc[swapped, column].map(lambda v: list(v)[::-1])
    outlier = (table["record"] == records[0]) & (table["mode"] == 1)
    table.loc[outlier, "frequency_hz"] *= 1.04
    tracks, summary = fleet.track(table)
    mine = tracks[tracks["asset"] == undamaged]
    assert sorted(mine[mine["record"] == records[3]]["mode"]) == [1, 2]
    clean = mine[mine["record"] != records[0]]
    # undamaged: its identified frequencies scatter by the noise, 0.1-0.3 % here; 1 % is far from 4 %
    assert (clean["frequency_change"].abs() < 0.01).all(), clean
    got = summary[summary["asset"] == undamaged]
    assert (got["frequency_change"].abs() < 0.005).all() and not got["drift"].any(), got


def test_the_ewma_chart_keeps_its_stated_false_alarm_rate():
    """The Monte Carlo run length of the chart against Montgomery's EWMA table (ARL0 = 500 at
    lambda = 0.25, L = 2.998): 4000 runs give a standard error of about 1.6 %, so 10 % is 6 of them."""
    arl, stderr = fleet.monitor.average_run_length(0.25, 2.998, runs=4000, seed=3)
    assert abs(arl - 500) < 0.1 * 500 and stderr < 0.03 * arl, (arl, stderr)
    shifted, _ = fleet.monitor.average_run_length(0.2, 3.5, shift=2.0, runs=2000, seed=4)
    assert 3 < shifted < 7, shifted  # the defaults find a 2-sigma shift within a handful of records


def test_temperature_compensated_alarm_fires_on_the_damaged_asset_only(cluster, tmp_path):
    """4 assets, 72 records each, a temperature cycle of 24 records moving every frequency by +- 2 %,
    one asset losing 1 % of a spring's stiffness from record 54 (mode 1: -0.2 %, twice the
    identification's scatter). With the temperature regressed out over a 48-record baseline the
    EWMA chart alarms on the damaged asset's mode 1 within 8 records of the damage and nowhere
    else; without it the swing hides the damage. (One scenario, seed 12: of seeds 12 to 15, 13
    and 14 also alarm once on an undamaged asset, docs/fleet.md.)"""
    spec = fleet.FleetSpec(assets=4, records=72, damaged=1, damage_start=54, stiffness_loss=0.01, samples=2000,
                           seed=12, temperature_swing=0.02, temperature_period=24)
    info = fleet.synthesize(str(tmp_path / "fleet"), spec)
    truth = pd.read_parquet(info["truth"])
    assert np.ptp(truth["temperature"]) > 19  # the cycle spans 10..30 degC
    out = tmp_path / "modes"
    okid_fleet("identify", info["records_dir"], "--out", out, "--scheduler", cluster.address, *CLI_OPTIONS,
               "--covariates", "temperature", "--quiet")
    modes = fleet.read_modes(str(out))
    assert (modes["status"] == "ok").all()
    tracks, summary = fleet.track(modes, fleet.TrackOptions(baseline_records=48, covariates=("temperature",)))
    alarms = fleet.track_alarms(tracks)
    damaged = info["damaged"][0]
    assert set(alarms["asset"]) == {damaged}, alarms
    records = list(dict.fromkeys(tracks[tracks["asset"] == damaged]["record"]))
    first = records.index(alarms[alarms["mode"] == 1]["record"].iloc[0])
    assert 54 <= first <= 54 + 8, first
    raw, _ = fleet.track(modes, fleet.TrackOptions(baseline_records=48))
    assert not raw[raw["asset"] == damaged]["alarm"].any()
