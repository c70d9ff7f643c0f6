# SPDX-License-Identifier: Apache-2.0
"""The fleet job on Dask: records in batches, one task per batch, each task writing its own part
of the Parquet output.

No scheduler given: a LocalCluster of single-threaded worker processes, one per core (the nanny
sets OMP/OPENBLAS/MKL_NUM_THREADS=1 in each, so BLAS does not oversubscribe). A scheduler address
(or its scheduler file): the same code on an existing cluster; the records and the output folder
go to the workers as absolute paths, so they must be reachable under the same paths from every
worker (a shared file system), or as fsspec URLs (s3://..., storage.py) that every worker reads
with its own credentials; every worker needs okid.

Every part is written to a temporary name and renamed when complete (in an object store: one
upload, seen whole or not at all), so an interrupted job leaves only whole parts; a part holds every record of its batch (a failed record is a status row), so
``resume`` finds the records already done from the output alone. The output folder's manifest
(output.py) keeps the job's settings and the runs that wrote it: nothing else is ever removed.

A task that fails or kills its worker (Dask's KilledWorker) is retried record by record, so one
poison record costs its batch a retry and ends as its own status row (worker_died, or
out_of_memory when the worker's nanny restarted it past its memory limit); the others are kept. A
record past its Limits (time, size) is a status row too, and a worker left busy by a record that
timed out is restarted.
"""
from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import math
import os
import signal
import sys
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Mapping, Optional, Sequence, Set, TextIO, Tuple

from . import storage
from .storage import StorageError
from .output import Output, OutputError, part_name, settings, write_part
from .records import ChannelSpec, RecordRef, RowGroupCache, discover, expand
from .rows import (STATUS_OK, STATUS_OUT_OF_MEMORY, STATUS_TASK_FAILED, STATUS_TIMED_OUT, STATUS_TOO_LARGE,
                   STATUS_WORKER_DIED, check_options, failure_row, identify_record)

if TYPE_CHECKING:  # for the annotations only: pandas and pyarrow are the fleet extra's
    import pandas as pd
    import pyarrow as pa

LOST_WORKER_TIMEOUT: str = "600s"  # a local nanny's worker may take this long to come back (see identify_fleet)
MAX_BATCH: int = 50  # records per task at most: the scheduler's ~1 ms per task stays small against them


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
    failures: Tuple[Tuple[str, int, str], ...] = ()  #: (status, records, first message), most frequent first

    def too_many_failed(self, max_failed_fraction: float) -> bool:
        """Every record of the run failed, or more than MAX_FAILED_FRACTION of them."""
        return self.records > 0 and (self.failed == self.records or self.failed > max_failed_fraction * self.records)


@dataclass(frozen=True)
class Limits:
    """What one record may cost; past a limit it is a status row and the job goes on."""
    record_timeout: Optional[float] = None  #: seconds to read and identify one record (None: no limit)
    max_record_mb: Optional[float] = None   #: MB (1e6 bytes) of a record, refused unread past it (None: no limit)

    def check(self) -> None:
        for name, value in (("record_timeout", self.record_timeout), ("max_record_mb", self.max_record_mb)):
            if value is not None and not (value > 0 and math.isfinite(value)):
                raise FleetError(f"--{name.replace('_', '-')} {value}: a number of "
                                 f"{'seconds' if name == 'record_timeout' else 'MB'} > 0")


def _within(seconds: float, work) -> Optional[List[Dict[str, Any]]]:
    """WORK() in a thread of its own, its result if it ends within SECONDS, else None (the thread,
    deep in native code that cannot be interrupted, is left running: the client restarts the worker)."""
    box: Dict[str, Any] = {}

    def run() -> None:
        try:
            box["rows"] = work()
        except BaseException as exc:  # handed to the task's thread, raised there
            box["error"] = exc

    thread = threading.Thread(target=run, name="okid-fleet-record", daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        return None
    if "error" in box:
        raise box["error"]
    return box["rows"]


def identify_batch(refs: Sequence[RecordRef], channels: ChannelSpec, options: Mapping[str, Any], out_dir: str,
                   part: str, limits: Limits = Limits()) -> Dict[str, Any]:
    """A task: identify REFS, write their rows to OUT_DIR/PART.parquet (atomically). A record past
    LIMITS is a status row; "stuck" names this worker when a record outlived its time limit."""
    rows: List[Dict[str, Any]] = []
    statuses: List[Tuple[str, str]] = []
    cache = RowGroupCache()
    stuck = None
    for ref in refs:
        if limits.max_record_mb is not None and ref.size is not None and ref.size > limits.max_record_mb * 1e6:
            record_rows = [failure_row(ref, STATUS_TOO_LARGE, f"{ref.size / 1e6:.3g} MB, more than --max-record-mb "
                                       f"{limits.max_record_mb:g}", options)]
        elif limits.record_timeout is not None:
            record_rows = _within(limits.record_timeout, lambda: identify_record(ref, channels, options, cache))
            if record_rows is None:
                record_rows = [failure_row(ref, STATUS_TIMED_OUT, f"reading and identifying it took longer than "
                                           f"--record-timeout {limits.record_timeout:g} s", options)]
                cache = RowGroupCache()  # the thread left running may still use the old one
                stuck = _worker_address()
        else:
            record_rows = identify_record(ref, channels, options, cache)
        statuses.append((record_rows[0]["status"], record_rows[0]["message"]))
        rows.extend(record_rows)
    write_part(rows, out_dir, part)
    return {"part": part, "records": len(refs), "rows": len(rows), "statuses": statuses, "stuck": stuck}


def _worker_address() -> Optional[str]:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):  # not inside a Dask worker
        return None


def parts(out_dir: str) -> List[str]:
    """The whole parts of OUT_DIR (a path or URL; the parts as paths inside its file system): those
    its manifest's runs wrote; a folder without a manifest (a table written by other means) gives
    all its Parquet files."""
    out = Output(out_dir)
    if out.manifest() is not None:
        return out.parts()
    return [storage.paths(out.fs).join(out.folder, f) for f in storage.listing(out.fs, out.folder)
            if f.endswith(".parquet") and not f.startswith((".", "_"))]


def _read_parts(out_dir: str, **read_options) -> List[pa.Table]:
    import pyarrow.parquet as pq

    fs = Output(out_dir).fs
    if storage.is_local(fs):
        return [pq.read_table(p, **read_options) for p in parts(out_dir)]
    tables = []
    for p in parts(out_dir):
        with fs.open(p, "rb") as f:
            tables.append(pq.read_table(f, **read_options))
    return tables


def records_done(out_dir: str) -> Set[str]:
    """The records present in the output's whole parts."""
    done: Set[str] = set()
    for table in _read_parts(out_dir, columns=["record"]):
        done.update(table.column("record").to_pylist())
    return done


def read_modes(out_dir: str) -> pd.DataFrame:
    """The mode table of a job's output (a path or URL) as a pandas DataFrame, sorted by asset,
    start, record, mode."""
    import pandas as pd
    import pyarrow as pa

    from .rows import schema

    tables = _read_parts(out_dir, schema=schema())
    table = pa.concat_tables(tables) if tables else schema().empty_table()
    frame = table.to_pandas()
    frame = frame.sort_values(["asset", "start", "record", "mode"], na_position="last", kind="stable")
    return frame.reset_index(drop=True) if isinstance(frame, pd.DataFrame) else frame


class Progress:
    """Records done, failed, rate and time left: one line redrawn on a terminal, else a line every
    10 % of the records."""

    def __init__(self, total: int, stream: TextIO, live: Optional[bool] = None) -> None:
        self.total: int = total              #: records of the job
        self.stream: TextIO = stream
        self.live: bool = stream.isatty() if live is None else live  #: one line redrawn (a terminal)
        self.done: int = 0                   #: records done so far (failed ones included)
        self.failed: int = 0                 #: of them, records whose status is not ok
        self.t0: float = time.monotonic()    #: start [s] (time.monotonic)
        self._next_report: float = 0.1

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


async def _identity(address: str, timeout: float) -> dict:
    """The scheduler's identity, asked over one connection. Dask's Client waits forever for an
    answer from a port that accepts and never speaks (not a Dask scheduler); the caller bounds this."""
    from distributed.comm import connect

    comm = await connect(address, timeout=timeout)
    try:
        await comm.write({"op": "identity"})
        answer = await comm.read()
    finally:
        await comm.close()
    if not isinstance(answer, dict) or answer.get("type") != "Scheduler":
        raise ValueError(f"{address} is not a Dask scheduler")
    return answer


def _client(scheduler: Optional[str], scheduler_file: Optional[str], workers: Optional[int],
            connect_timeout: float, progress: Optional[TextIO], memory_limit: Optional[str] = None):
    import dask
    from distributed import Client, LocalCluster

    def say(text: str) -> None:
        if progress is not None:
            progress.write(f"okid-fleet: {text}\n")
            progress.flush()

    if scheduler_file:
        try:
            with open(scheduler_file, encoding="utf-8") as f:
                scheduler = json.load(f)["address"]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise FleetError(f"--scheduler-file {scheduler_file}: no scheduler address in it ({exc})") from None
    if scheduler:
        say(f"connecting to {scheduler}")
        try:
            asyncio.run(asyncio.wait_for(_identity(scheduler, connect_timeout), connect_timeout))
            return Client(scheduler, timeout=f"{connect_timeout}s"), None
        except (OSError, ValueError, TypeError) as exc:  # a timeout is an OSError, a bad address a ValueError,
            # a tls:// address without the certificates a TypeError
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise FleetError(f"no Dask scheduler answered at {scheduler} within {connect_timeout:g} s "
                             f"({reason})") from None
    n = workers or os.cpu_count() or 1
    say(f"starting a local cluster of {n} worker process(es)"
        + (f", at most {memory_limit} of memory each" if memory_limit else ""))
    # A task whose worker dies twice is lost (KilledWorker) and its records are retried one by one:
    # poison records cost two worker restarts each instead of Dask's default four.
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        try:
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                   silence_logs=logging.ERROR, memory_limit=memory_limit or "auto")
        except ValueError as exc:  # a memory limit Dask cannot parse
            raise FleetError(f"--memory-limit {memory_limit}: {exc}") from None
    return Client(cluster), cluster


def _dashboard(client) -> str:
    """The dashboard's address, or why there is none. The scheduler names its HTTP port even
    without the dashboard (no bokeh, or --no-dashboard: the page is then a 404), so the page is
    asked for once; a page slow to come (drawn under load) is there."""
    import urllib.error
    import urllib.request

    link = client.dashboard_link
    try:
        with urllib.request.urlopen(link, timeout=2):
            pass
    except urllib.error.HTTPError as exc:
        return f"no dashboard at {link} (HTTP {exc.code}: the scheduler serves none without bokeh or with --no-dashboard)"
    except (urllib.error.URLError, OSError, ValueError) as exc:
        reason = getattr(exc, "reason", exc)
        if not isinstance(reason, TimeoutError):
            return f"no dashboard at {link} (not reachable from here: {reason})"
    return f"dashboard {link}"


def _restart(client, worker: str, progress: Optional[TextIO]) -> None:
    """Restart the worker whose record outlived --record-timeout: its thread, in native code that
    cannot be interrupted, would keep a core busy. A worker without a nanny cannot be restarted:
    said, and the job goes on."""
    try:
        client.restart_workers([worker], timeout=60)
    except Exception as exc:  # the worker already gone, or no nanny
        if progress is not None:
            progress.write(f"okid-fleet: could not restart {worker}, whose record timed out ({exc})\n")


def _memory_restart(client, worker: str, wait: float = 1.0) -> Optional[Dict[str, Any]]:
    """The nanny's event "worker-restart-memory" of WORKER (its RSS past the memory limit's
    terminate fraction, 95 % by default), or None. The nanny sends it as it kills the worker, so it
    is waited for up to WAIT seconds."""
    deadline = time.monotonic() + wait
    while True:
        try:
            events = client.get_events("worker-restart-memory")
        except Exception:  # a scheduler that keeps no events: nothing to tell
            return None
        for _, event in reversed(list(events)):
            if isinstance(event, dict) and event.get("worker") == worker:
                return event
        if time.monotonic() >= deadline:
            return None
        time.sleep(0.1)


def _death(client, exc: BaseException) -> Tuple[str, str]:
    """(status, message) of a record whose task failed alone: worker_died when it killed its worker
    twice, out_of_memory when the worker's nanny killed it for its memory, task_failed else."""
    if type(exc).__name__ != "KilledWorker":
        return STATUS_TASK_FAILED, f"{type(exc).__name__}: {exc}"
    worker = getattr(getattr(exc, "last_worker", None), "address", None)
    event = _memory_restart(client, worker) if worker else None
    if event is not None:
        limit = getattr(getattr(exc, "last_worker", None), "memory_limit", 0) or 0
        of_limit = f" of a {limit / 2**20:.0f} MiB limit" if limit else ""
        return STATUS_OUT_OF_MEMORY, (f"its worker used {event.get('rss', 0) / 2**20:.0f} MiB{of_limit} identifying "
                                      f"this record and was restarted by its nanny, twice (the record alone)")
    return STATUS_WORKER_DIED, (f"the task of this record killed its worker process twice (a native crash, or "
                                f"the kernel's out-of-memory killer): {exc}")


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


def _count(statuses: Iterable[Tuple[str, str]], failures: Dict[str, List]) -> int:
    """Add the failed records among STATUSES to FAILURES (status -> [count, first message]); their number."""
    failed = 0
    for status, message in statuses:
        if status != STATUS_OK:
            entry = failures.setdefault(status, [0, message])
            entry[0] += 1
            failed += 1
    return failed


def identify_fleet(paths: Iterable[str], out_dir: str, *, options: Optional[Mapping[str, Any]] = None,
                   channels: ChannelSpec = ChannelSpec(), scheduler: Optional[str] = None,
                   scheduler_file: Optional[str] = None, workers: Optional[int] = None,
                   batch_size: Optional[int] = None, resume: bool = False, overwrite: bool = False,
                   connect_timeout: float = 20.0, progress: Optional[TextIO] = sys.stderr,
                   live: Optional[bool] = None, limits: Limits = Limits(),
                   memory_limit: Optional[str] = None) -> Summary:
    """Identify every record of PATHS on Dask and write the mode table to the Parquet folder OUT_DIR.

    options: okid.identify's keywords (the okid_config names); channels: which columns are inputs
    and outputs; scheduler: "tcp://host:port" of a running cluster (or scheduler_file: its JSON
    file), else a local one with ``workers`` processes (default: one per core); connect_timeout
    [s]: how long a scheduler may take to answer; resume: skip the records already in OUT_DIR
    (refused when OUT_DIR was written with other settings); overwrite: remove the parts of the
    earlier runs in OUT_DIR (and nothing else). PATHS and OUT_DIR may be fsspec URLs (s3://...).
    A task that kills its worker is retried record by record; the record that still kills it is a
    status row ``worker_died``. limits: the time and size one record may take (a status row
    ``timed_out`` or ``too_large`` past them; the worker of a record that timed out is restarted);
    memory_limit: each local worker's (Dask's, e.g. "2GiB"; the nanny restarts a worker past 95 %
    of it, and its record ends as ``worker_died``). Raises Interrupted on Ctrl-C (the parts written
    stay whole), FleetError when the job cannot start.
    """
    options = dict(options or {})
    limits.check()
    try:
        check_options(options, channels)
    except ValueError as exc:
        raise FleetError(str(exc)) from None
    try:
        inputs = expand(paths)
        refs = discover(inputs)
        out = Output(out_dir)
    except StorageError as exc:
        raise FleetError(str(exc)) from None
    if not refs:
        raise FleetError("no records found")
    try:
        out.check_inputs(inputs)
        run = out.prepare(settings(options, channels), resume=resume, overwrite=overwrite)
    except (OutputError, StorageError) as exc:
        raise FleetError(str(exc)) from None
    if progress is not None:  # listing an object store and reading Parquet metadata take a while
        files = len({r.path for r in refs})
        progress.write(f"okid-fleet: {len(refs)} records in {files} file(s) or object(s)\n")
        progress.flush()
    done = records_done(out.path) if resume else set()
    todo = [r for r in refs if r.record not in done]
    # A local cluster closes a nanny whose worker has not come back within this (Dask's default:
    # 15 s), even while the nanny is restarting it: a record that kills its worker twice in a row,
    # on a loaded machine, would leave the job without workers. The nanny's own restarts decide.
    import dask
    import distributed  # noqa: F401  its defaults in dask.config first: the set below restores what it found

    lost_worker = dask.config.set({"distributed.deploy.lost-worker-timeout": LOST_WORKER_TIMEOUT})
    try:
        client, cluster = _client(scheduler, scheduler_file, workers, connect_timeout, progress, memory_limit)
    except BaseException:
        lost_worker.__exit__(None, None, None)
        raise
    try:
        if progress is not None:
            progress.write(f"okid-fleet: {_dashboard(client)}\n")
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        size = batch_size or batch_size_for(len(todo), n_workers)
        batches = [todo[i:i + size] for i in range(0, len(todo), size)]
        bar = Progress(len(todo), progress, live) if progress is not None else None
        t0 = time.monotonic()

        def submit(refs_: Sequence[RecordRef], part: str, attempt: int = 0):
            return client.submit(identify_batch, list(refs_), channels, options, out.path, part, limits,
                                 key=f"okid-fleet-{part}" + (f"-again{attempt}" if attempt else ""),
                                 retries=1, pure=False)

        tasks = {}
        for i, batch in enumerate(batches):
            tasks[submit(batch, part_name(run, i))] = (i, None, batch, 0)
        records = rows = 0
        failures: Dict[str, List] = {}
        suspects: List[Tuple[int, Optional[int], Sequence[RecordRef]]] = []
        with _ctrl_c_as_flag() as interrupted:
            pending = set(tasks)
            suspect_out = False
            while (pending or suspects) and not interrupted.is_set():
                if suspects and not suspect_out:
                    # alone, once more, one at a time: a record queued on a worker that another
                    # record killed (its result lost with that worker) is not the killer; two
                    # suspects run side by side could kill each other's workers again
                    i, j, batch = suspects.pop(0)
                    again = submit(batch, part_name(run, i, j if j is not None else 0), 1)
                    tasks[again] = (i, j, batch, 1)
                    pending.add(again)
                    suspect_out = True
                done_now, pending = _wait_some(pending)
                for future in done_now:
                    i, j, batch, attempt = tasks.pop(future)
                    suspect_out = suspect_out and attempt == 0
                    if future.status == "error":
                        exc = future.exception()
                        if len(batch) > 1:  # isolate: every record of the batch alone
                            for k, ref in enumerate(batch):
                                single = submit([ref], part_name(run, i, k))
                                tasks[single] = (i, k, [ref], 0)
                                pending.add(single)
                            continue
                        if type(exc).__name__ == "KilledWorker" and attempt == 0:
                            suspects.append((i, j, batch))
                            continue
                        status, message = _death(client, exc)
                        part = part_name(run, i, j if j is not None else 0)
                        write_part([failure_row(batch[0], status, message, options)], out.path, part)
                        result = {"records": 1, "rows": 1, "statuses": [(status, message)]}
                    else:
                        result = future.result()
                        if result["stuck"]:
                            _restart(client, result["stuck"], progress)
                    records += result["records"]
                    rows += result["rows"]
                    failed = _count(result["statuses"], failures)
                    if bar:
                        bar.update(result["records"], failed)
        if pending or suspects:  # Ctrl-C: the tasks still out are cancelled, the parts written are whole
            _quiet_shutdown(client)
            client.cancel(list(pending))
            if bar:
                bar.close()
            raise Interrupted(f"interrupted: {len(records_done(out.path))} of {len(refs)} records are in "
                              f"{out_dir}; run again with --resume to finish")
        if bar:
            bar.close()
        failed = sum(count for count, _ in failures.values())
        reasons = tuple(sorted(((status, count, message) for status, (count, message) in failures.items()),
                               key=lambda r: (-r[1], r[0])))
        return Summary(records, failed, len(done), rows, len(batches), n_workers, time.monotonic() - t0, reasons)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
        lost_worker.__exit__(None, None, None)
