# SPDX-License-Identifier: Apache-2.0
"""The fleet job on Dask: records in batches, one task per batch, each task writing its own part
of the Parquet output.

No scheduler given: a LocalCluster of single-threaded worker processes, one per core (the nanny
sets OMP/OPENBLAS/MKL_NUM_THREADS=1 in each, so BLAS does not oversubscribe). A scheduler address:
the same code on an existing cluster; then the records and the output folder must be reachable
from every worker under the same paths (a shared file system), and every worker needs okid.

Every part is written to a temporary name and renamed when complete, so an interrupted job leaves
only whole parts; a part holds every record of its batch (a failed record is a status row), so
``resume`` finds the records already done from the output alone.
"""
from __future__ import annotations

import contextlib
import logging
import math
import os
import shutil
import signal
import sys
import threading
import time
import uuid
from dataclasses import dataclass
from typing import Any, Iterable, List, Mapping, Optional, Sequence, TextIO

from .records import ChannelSpec, RecordRef, discover
from .rows import STATUS_OK, identify_record, to_table

MAX_BATCH = 50  # records per task at most: the scheduler's ~1 ms per task stays small against them


class FleetError(Exception):
    """A job that cannot start (no records, an output that exists, a scheduler that is not there)."""


class Interrupted(FleetError):
    """Ctrl-C: the parts written so far are whole; run again with resume to finish."""


@dataclass(frozen=True)
class Summary:
    records: int        #: records identified in this run (failed ones included)
    failed: int         #: of them, records whose status is not ok
    skipped: int        #: records already in the output (resume)
    rows: int           #: rows written in this run
    batches: int        #: tasks
    workers: int        #: worker processes (at the start)
    seconds: float      #: wall time of the identification (cluster start-up excluded)


def identify_batch(refs: Sequence[RecordRef], channels: ChannelSpec, options: Mapping[str, Any], out_dir: str,
                   part: str) -> dict:
    """A task: identify REFS, write their rows to OUT_DIR/PART.parquet (atomically)."""
    import pyarrow.parquet as pq

    rows: List[dict] = []
    failed = 0
    for ref in refs:
        record_rows = identify_record(ref, channels, options)
        failed += record_rows[0]["status"] != STATUS_OK
        rows.extend(record_rows)
    final = os.path.join(out_dir, part + ".parquet")
    tmp = os.path.join(out_dir, f".{part}.{uuid.uuid4().hex}.tmp")
    pq.write_table(to_table(rows), tmp)
    os.replace(tmp, final)
    return {"part": part, "records": len(refs), "failed": failed, "rows": len(rows)}


def parts(out_dir: str) -> List[str]:
    if not os.path.isdir(out_dir):
        return []
    return sorted(os.path.join(out_dir, f) for f in os.listdir(out_dir)
                  if f.endswith(".parquet") and not f.startswith("."))


def records_done(out_dir: str) -> set:
    """The records present in the output's whole parts."""
    import pyarrow.parquet as pq

    done: set = set()
    for path in parts(out_dir):
        done.update(pq.read_table(path, columns=["record"]).column("record").to_pylist())
    return done


def read_modes(out_dir: str):
    """The mode table of a job's output as a pandas DataFrame, sorted by asset, start, record, mode."""
    import pandas as pd
    import pyarrow as pa
    import pyarrow.parquet as pq

    from .rows import schema

    tables = [pq.read_table(p, schema=schema()) for p in parts(out_dir)]
    table = pa.concat_tables(tables) if tables else schema().empty_table()
    frame = table.to_pandas()
    frame = frame.sort_values(["asset", "start", "record", "mode"], na_position="last", kind="stable")
    return frame.reset_index(drop=True) if isinstance(frame, pd.DataFrame) else frame


class Progress:
    """Records done, failed, rate and time left: one line redrawn on a terminal, else a line every
    10 % of the records."""

    def __init__(self, total: int, stream: TextIO, live: Optional[bool] = None):
        self.total, self.stream = total, stream
        self.live = stream.isatty() if live is None else live
        self.done = self.failed = 0
        self.t0 = time.monotonic()
        self._next_report = 0.1

    def line(self) -> str:
        elapsed = time.monotonic() - self.t0
        rate = self.done / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else math.inf
        eta = "?" if math.isinf(left) else time.strftime("%H:%M:%S", time.gmtime(left))
        return (f"okid-fleet: {self.done}/{self.total} records, {self.failed} failed, {rate:.1f} records/s, "
                f"{eta} left")

    def update(self, records: int, failed: int) -> None:
        self.done += records
        self.failed += failed
        if self.live:
            self.stream.write("\r" + self.line() + "\x1b[K")
            self.stream.flush()
        elif self.total and self.done / self.total >= self._next_report:
            self.stream.write(self.line() + "\n")
            self._next_report = math.floor(self.done / self.total * 10 + 1) / 10

    def close(self) -> None:
        if self.live:
            self.stream.write("\n")
            self.stream.flush()


#: Seconds a --scheduler has to answer. Dask's own timeout covers the TCP connection only: a port
#: that accepts and never speaks Dask held Client() forever, so the connection runs in a thread
#: that is given up on after this long.
CONNECT_SECONDS = 30.0


def _quiet_abandoned_clients():
    """A Client whose connection failed tries to close itself when collected and prints "Exception
    ignored in Client.__del__" with a traceback after the refusal's one line: not news."""
    previous = sys.unraisablehook

    def hook(unraisable):
        if getattr(unraisable.object, "__qualname__", "") != "Client.__del__":
            previous(unraisable)

    sys.unraisablehook = hook


def _connect(scheduler: str, seconds: float):
    from distributed import Client

    box: dict = {}

    def connect():
        try:
            box["client"] = Client(scheduler, timeout=f"{max(1.0, seconds - 5)}s")
        except BaseException as exc:  # noqa: B902 (reported below as one line)
            box["error"] = exc

    thread = threading.Thread(target=connect, name="okid-fleet-connect", daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive() or "error" in box:
        _quiet_abandoned_clients()
    if thread.is_alive():
        raise FleetError(f"no Dask scheduler answered at {scheduler} within {seconds:g} s "
                         f"(is it a Dask scheduler's address?)")
    if "error" in box:
        exc = box["error"]
        raise FleetError(f"no Dask scheduler at {scheduler}: {type(exc).__name__}: {exc}") from None
    return box["client"]


def _client(scheduler: Optional[str], workers: Optional[int], connect_seconds: float = CONNECT_SECONDS):
    from distributed import Client, LocalCluster

    if scheduler:
        return _connect(scheduler, connect_seconds), None
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def _silence_shutdown_logs() -> None:
    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


def _quiet_shutdown(client) -> None:
    """Tasks cancelled mid-flight make Dask and Tornado log tracebacks while closing, here and in the
    workers (whose heartbeats fail once the scheduler has gone): not news after Ctrl-C."""
    _silence_shutdown_logs()
    try:
        client.run(_silence_shutdown_logs, on_error="ignore")
    except Exception:  # a worker already gone: nothing of it left to silence
        pass


@contextlib.contextmanager
def _ctrl_c_as_flag():
    """SIGINT sets a flag instead of raising KeyboardInterrupt inside Dask's event-loop wait (where
    it leaves tracebacks behind); a second Ctrl-C, after the job's loop, interrupts as usual."""
    interrupted = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield interrupted
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: interrupted.set())
    try:
        yield interrupted
    finally:
        signal.signal(signal.SIGINT, previous)


def _wait_some(pending: set, seconds: float = 0.5):
    """The futures done within SECONDS (at least one unless time ran out), and the rest."""
    from distributed import wait

    try:
        result = wait(list(pending), timeout=seconds, return_when="FIRST_COMPLETED")
    except TimeoutError:
        return set(), pending
    return set(result.done), set(result.not_done)


def batch_size_for(records: int, workers: int) -> int:
    """About four tasks per worker (load balance, cheap retries), at most MAX_BATCH records a task."""
    return max(1, min(MAX_BATCH, math.ceil(records / (4 * max(workers, 1)))))


def identify_fleet(paths: Iterable[str], out_dir: str, *, options: Optional[Mapping[str, Any]] = None,
                   channels: ChannelSpec = ChannelSpec(), scheduler: Optional[str] = None,
                   workers: Optional[int] = None, batch_size: Optional[int] = None, resume: bool = False,
                   overwrite: bool = False, progress: Optional[TextIO] = sys.stderr,
                   live: Optional[bool] = None) -> Summary:
    """Identify every record of PATHS on Dask and write the mode table to the Parquet folder OUT_DIR.

    options: okid.identify's keywords (the okid_config names); channels: which columns are inputs
    and outputs; scheduler: "tcp://host:port" of a running cluster, else a local one with
    ``workers`` processes (default: one per core); resume: skip the records already in OUT_DIR;
    overwrite: start OUT_DIR afresh. Raises Interrupted on Ctrl-C (the parts written stay whole).
    """
    options = dict(options or {})
    refs = discover(paths)
    if not refs:
        raise FleetError("no records found")
    existing = parts(out_dir)
    if existing and not (resume or overwrite):
        raise FleetError(f"{out_dir} already holds {len(existing)} part(s): --resume to finish it, "
                         "--overwrite to start again")
    if existing and overwrite:
        shutil.rmtree(out_dir)
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as exc:  # --out a file, or under one: one line, never a traceback
        raise FleetError(f"--out {out_dir}: cannot be the output folder ({exc.strerror})") from None
    for stale in (f for f in os.listdir(out_dir) if f.endswith(".tmp")):
        os.remove(os.path.join(out_dir, stale))  # a part an interrupted run did not finish
    done = records_done(out_dir) if resume else set()
    todo = [r for r in refs if r.record not in done]
    client, cluster = _client(scheduler, workers)
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        size = batch_size or batch_size_for(len(todo), n_workers)
        batches = [todo[i:i + size] for i in range(0, len(todo), size)]
        run = time.strftime("%Y%m%dT%H%M%S") + "-" + uuid.uuid4().hex[:6]
        out_abs = os.path.abspath(out_dir)
        bar = Progress(len(todo), progress, live) if progress is not None else None
        t0 = time.monotonic()
        futures = [client.submit(identify_batch, batch, channels, options, out_abs, f"part-{run}-{i:05d}",
                                 key=f"okid-fleet-{run}-{i:05d}", retries=2, pure=False)
                   for i, batch in enumerate(batches)]
        records = failed = rows = 0
        with _ctrl_c_as_flag() as interrupted:
            pending = set(futures)
            while pending and not interrupted.is_set():
                done_now, pending = _wait_some(pending)
                for future in done_now:
                    result = future.result()
                    records += result["records"]
                    failed += result["failed"]
                    rows += result["rows"]
                    if bar:
                        bar.update(result["records"], result["failed"])
        if pending:  # Ctrl-C: the tasks still out are cancelled, the parts written are whole
            _quiet_shutdown(client)
            client.cancel(list(pending))
            if bar:
                bar.close()
            raise Interrupted(f"interrupted: {len(records_done(out_dir))} of {len(refs)} records are in "
                              f"{out_dir}; run again with --resume to finish")
        if bar:
            bar.close()
        return Summary(records, failed, len(done), rows, len(batches), n_workers, time.monotonic() - t0)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
