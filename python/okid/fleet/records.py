# SPDX-License-Identifier: Apache-2.0
"""Where records come from and how one is read: CSV files in the CLI's layout and Parquet datasets.

A record is listed on the client without reading its samples (a RecordRef: a path and, for
Parquet, the row groups that hold it); the samples are read inside the task that identifies it.

CSV (the layout of ``okid simulate`` and ``okid identify``): a header line of column names, then
one sample per line; a time column (t, time, timestamp, seconds, ... with an optional unit such as
time_ms or "t [s]", in any position: the CLI's rule) gives dt and is never a data channel;
the asset is the name of the file's folder, the record its path, the start time the file name
when it reads as an ISO 8601 time (``2026-01-05T10-20-00Z.csv``), else unknown.

Parquet: one row per sample with the columns ``asset``, ``record``, ``start`` (timestamp),
``dt`` [s] and the channels (any other numeric column, in the file's order; a ``time`` column is
skipped); ``asset`` and ``record`` may instead be Hive partition folders (``asset=a1/``). Records
are found from the row groups' statistics (one record per row group is the fast case) or, without
them, from the ``record`` column of each row group; a task reads each row group once.

A folder is searched recursively for both kinds; a Parquet file that cannot be opened is a failed
record (status ``unreadable``), never a traceback. Paths may be fsspec URLs (``s3://bucket/records``,
storage.py): a RecordRef's path is then the object's URL, and each task reads it from there.
"""
from __future__ import annotations

import glob
import math
import os
import re
import tempfile
from contextlib import nullcontext
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Optional, Sequence, Tuple
from urllib.parse import unquote

import numpy as np

from . import storage

if TYPE_CHECKING:  # for the annotations only: pyarrow is the fleet extra's
    import pyarrow as pa

META_COLUMNS: Tuple[str, ...] = ("asset", "record", "start", "dt")
class RecordError(Exception):
    """A record that cannot be read or does not have the channels asked for."""


@dataclass(frozen=True)
class RecordRef:
    """One record: enough to find it again inside a task (picklable, no samples)."""
    source: str                      #: "csv", "parquet" or "broken" (a file that cannot be opened)
    path: str                        #: the file
    record: str                      #: unique name of the record in the job
    asset: str                       #: the machine it belongs to
    start: Optional[float] = None    #: start time, seconds since 1970-01-01 UTC (None: unknown yet)
    row_groups: Optional[Tuple[int, ...]] = None  #: Parquet row groups holding it
    partition: Tuple[Tuple[str, str], ...] = ()   #: Hive partition keys of its folders
    error: Optional[str] = None      #: source "broken": why the file could not be opened
    size: Optional[int] = None       #: bytes: the CSV file, or the Parquet row groups uncompressed


@dataclass(frozen=True)
class ChannelSpec:
    """Which columns are inputs and outputs, as ``okid identify --inputs/--outputs`` take them: a
    count (taken in order after the time column) or comma-separated names; outputs None = the rest.
    Inputs "0": output-only records, every channel an output (okid.identify_ambient)."""
    inputs: str = "1"
    outputs: Optional[str] = None
    dt: Optional[float] = None       #: sample interval when a CSV has no time column
    covariates: Tuple[str, ...] = () #: columns that are no channel: their mean over the record is kept (temperature, load)

    @property
    def output_only(self) -> bool:
        """``--inputs 0``: no input column, the records identified by okid.identify_ambient."""
        return self.inputs.strip() == "0"

    def select(self, names: Sequence[str]) -> Tuple[List[int], List[int]]:
        used: set = set()
        ins = [] if self.output_only else self._pick(self.inputs, names, used, "inputs", 0)
        start = (max(ins) + 1) if ins and self.inputs.strip().isdigit() else 0
        if self.outputs is None:
            outs = [i for i in range(len(names)) if i not in used]
        else:
            outs = self._pick(self.outputs, names, used, "outputs", start)
        if not outs:
            raise RecordError(f"no output column left (columns: {', '.join(names)})")
        return ins, outs

    @staticmethod
    def _pick(spec: str, names: Sequence[str], used: set, what: str, start: int) -> List[int]:
        spec = spec.strip()
        if spec.isdigit():
            count = int(spec)
            free = [i for i in range(start, len(names)) if i not in used]
            if count < 1 or count > len(free):
                raise RecordError(f"--{what} {count}: the record has {len(free)} free channel column(s)")
            picked = free[:count]
        else:
            picked = []
            for name in (s.strip() for s in spec.split(",")):
                if name not in names:
                    raise RecordError(f"--{what}: no channel named '{name}' (channels: {', '.join(names)})")
                i = list(names).index(name)
                if i in used or i in picked:
                    raise RecordError(f"--{what}: channel '{name}' is already an input or an output")
                picked.append(i)
        used.update(picked)
        return picked


def time_unit(name: str) -> float:
    """Seconds per unit when NAME names a time column (the CLI's rule: host_tools/common/time_column.c), else 0."""
    from okid import _core

    return _core.time_column_unit(name)


def is_time_name(name: str) -> bool:
    return time_unit(name) > 0


_ISO_STEM = re.compile(r"^(\d{4})-(\d{2})-(\d{2})[T_ ](\d{2})[-:](\d{2})[-:](\d{2})(?:Z|\+00[-:]?00)?$")


def start_from_name(path: str) -> Optional[float]:
    """Seconds since the epoch from a file name such as 2026-01-05T10-20-00Z.csv (UTC), else None."""
    match = _ISO_STEM.match(os.path.splitext(os.path.basename(path))[0])
    if not match:
        return None
    y, mo, d, h, mi, s = (int(g) for g in match.groups())
    return datetime(y, mo, d, h, mi, s, tzinfo=timezone.utc).timestamp()


DATA_SUFFIXES = (".csv", ".parquet")


def _hidden(name: str) -> bool:
    """Files a Parquet writer keeps beside its data (_SUCCESS, _metadata, .crc, temporary parts)."""
    return name.startswith((".", "_"))


def _walk(fs, root: str) -> List[Tuple[str, Optional[int]]]:
    """Every CSV and Parquet file under ROOT (recursively, sorted) with its size [bytes], hidden
    files and folders aside: one listing, also of an object store."""
    pm = storage.paths(fs)
    found = []
    for file, info in fs.find(root, detail=True).items():
        parts = pm.relpath(file, root).split(pm.sep)
        if file.endswith(DATA_SUFFIXES) and not any(_hidden(part) for part in parts):
            found.append((file, info.get("size")))
    return sorted(found)


def expand(paths: Iterable[str]) -> List[str]:
    """The absolute paths or URLs that PATHS name (globs expanded), in order."""
    out: List[str] = []
    for given in paths:
        fs, path = storage.resolve(given)
        if glob.has_magic(path):
            matches = sorted(glob.glob(path, recursive=True)) if storage.is_local(fs) else sorted(fs.glob(path))
            if not matches:
                raise RecordError(f"{given}: no file matches")
        else:
            matches = [path]
        out.extend(storage.url(fs, m) for m in matches)
    return out


def discover(paths: Iterable[str]) -> List[RecordRef]:
    """Every record named by PATHS: CSV files, globs, folders (searched recursively for CSV and
    Parquet files alike, Hive partitions ``key=value/`` included) and Parquet files, local or fsspec
    URLs (storage.py). Every path is made absolute here, on the client, so that workers started
    elsewhere find the files. Sorted by asset, start, record; names must be unique."""
    refs: List[RecordRef] = []
    for given in expand(paths):
        fs, path = storage.resolve(given)
        if fs.isdir(path):
            files = _walk(fs, path)
            if not files:
                raise RecordError(f"{given}: no CSV or Parquet file in this folder")
            for file, size in files:
                refs.extend(_file_records(fs, file, path, size))
        elif fs.exists(path):
            refs.extend(_file_records(fs, path, storage.paths(fs).dirname(path), fs.size(path)))
        else:
            raise RecordError(f"{given}: no such file or folder")
    seen = {}
    for ref in refs:
        if ref.record in seen:
            raise RecordError(f"record '{ref.record}' is named twice ({seen[ref.record]} and {ref.path})")
        seen[ref.record] = ref.path
    return sorted(refs, key=lambda r: (r.asset, r.start if r.start is not None else math.inf, r.record))


def _file_records(fs, file: str, root: str, size: Optional[int]) -> List[RecordRef]:
    if file.endswith(".parquet"):
        return _parquet_records(fs, file, root)
    return [_csv_record(fs, file, root, size)]


def partition_keys(file: str, root: str, pm=os.path) -> Dict[str, str]:
    """The Hive partition keys of FILE below ROOT: ``root/asset=a1/day=3/x.parquet`` -> asset, day."""
    rel = pm.relpath(pm.dirname(file), root)
    keys = {}
    for part in ([] if rel == "." else rel.split(pm.sep)):
        key, sep, value = part.partition("=")
        if sep and key:
            keys[key] = unquote(value)
    return keys


def _record_name(path: str, root: str, pm=os.path) -> Tuple[str, str]:
    """(record, asset) of a file found below ROOT: the record is its path from ROOT's folder level
    (the file's folder and name for a file at ROOT's top), the asset its folder's name."""
    rel = pm.relpath(path, root)
    folder = pm.basename(pm.dirname(path))
    record = pm.splitext(pm.join(folder, rel) if pm.dirname(rel) == "" else rel)[0]
    return record.replace(pm.sep, "/"), folder


def _csv_record(fs, path: str, root: str, size: Optional[int]) -> RecordRef:
    record, asset = _record_name(path, root, storage.paths(fs))
    return RecordRef("csv", storage.url(fs, path), record, asset, start_from_name(path), size=size)


def _stat(rg, index: Optional[int]):
    if index is None:
        return None
    st = rg.column(index).statistics
    if st is None or not st.has_min_max or st.min != st.max:
        return None
    return st.min


def _timestamp_seconds(value) -> Optional[float]:
    if value is None:
        return None
    if isinstance(value, datetime):
        if value.tzinfo is None:
            value = value.replace(tzinfo=timezone.utc)
        return value.timestamp()
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def _parquet_records(fs, file: str, root: str) -> List[RecordRef]:
    """The records of one Parquet file. Partition keys of its folders (``asset=.../``) stand in for
    the asset and record columns a Hive-partitioned dataset leaves out of its files. A file that
    cannot be opened is one failed record (status row), not the end of the job."""
    pm = storage.paths(fs)
    keys = partition_keys(file, root, pm)
    where = storage.url(fs, file)
    try:
        pf = parquet_file(fs, file)
        meta = pf.metadata
    except Exception as exc:
        record, asset = _record_name(file, root, pm)
        return [RecordRef("broken", where, keys.get("record", record), keys.get("asset", asset),
                          error=f"{type(exc).__name__}: {exc}")]
    names = [meta.schema.column(i).name for i in range(meta.num_columns)]
    missing = [c for c in ("asset", "record", "dt") if c not in names and c not in keys]
    if missing:
        raise RecordError(f"{where}: a record dataset needs the column(s) {', '.join(missing)}")
    col = {name: names.index(name) for name in META_COLUMNS if name in names}
    partition = tuple(sorted(keys.items()))
    groups: Dict[str, list] = {}
    by_statistics = True
    for g in range(meta.num_row_groups):
        rg = meta.row_group(g)
        record = keys.get("record", _stat(rg, col.get("record")))
        asset = keys.get("asset", _stat(rg, col.get("asset")))
        if record is None or asset is None:
            by_statistics = False
            break
        entry = groups.setdefault(str(record), [str(asset), _timestamp_seconds(_stat(rg, col.get("start"))), []])
        entry[2].append(g)
    if not by_statistics:  # several records per row group: their row groups from the columns themselves
        groups = {}
        wanted = [c for c in ("asset", "record", "start") if c in names]
        for g in range(meta.num_row_groups):
            table = pf.read_row_group(g, columns=wanted)
            records = table.column("record").to_pylist() if "record" in names else [keys["record"]] * table.num_rows
            assets = table.column("asset").to_pylist() if "asset" in names else [keys["asset"]] * table.num_rows
            starts = table.column("start").to_pylist() if "start" in names else [None] * table.num_rows
            for i in _first_of_each(records):
                entry = groups.setdefault(str(records[i]), [str(assets[i]), _timestamp_seconds(starts[i]), []])
                if g not in entry[2]:
                    entry[2].append(g)
    return [RecordRef("parquet", where, record, asset, start, tuple(rgs), partition,
                      size=sum(meta.row_group(g).total_byte_size for g in rgs))
            for record, (asset, start, rgs) in groups.items()]


def parquet_file(fs, path: str):
    """A pyarrow ParquetFile of PATH in FS (a local path read by pyarrow itself)."""
    import pyarrow.parquet as pq

    return pq.ParquetFile(path if storage.is_local(fs) else fs.open(path, "rb"))


def _first_of_each(values: list) -> List[int]:
    """The index of each distinct value's first occurrence, in order."""
    first: Dict[Any, int] = {}
    for i, v in enumerate(values):
        first.setdefault(v, i)
    return list(first.values())


@dataclass(frozen=True)
class RecordData:
    u: np.ndarray          #: (N, r) inputs
    y: np.ndarray          #: (N, m) outputs
    dt: float              #: sample interval [s]
    start: Optional[float] #: seconds since the epoch, or None
    input_names: Tuple[str, ...]
    output_names: Tuple[str, ...]
    covariates: Tuple[Tuple[str, float], ...] = ()  #: (name, mean over the record)


class RowGroupCache:
    """The row groups of the last Parquet file read, so that the records sharing a row group (many
    records per row group) are read in one pass per task instead of once per record."""

    def __init__(self) -> None:
        self.path: Optional[str] = None          #: the Parquet file whose row groups are kept
        self.groups: Dict[int, pa.Table] = {}    #: its row groups read so far, by index

    def read(self, path: str, row_groups: Sequence[int]) -> pa.Table:
        """The row groups ROW_GROUPS of the Parquet file PATH as one table."""
        import pyarrow as pa

        if path != self.path:
            self.path, self.groups = path, {}
        missing = [g for g in row_groups if g not in self.groups]
        if missing:
            pf = parquet_file(*storage.resolve(path))
            self.groups.update({g: pf.read_row_group(g) for g in missing})
        return pa.concat_tables([self.groups[g] for g in row_groups])


def read(ref: RecordRef, channels: ChannelSpec, cache: Optional[RowGroupCache] = None) -> RecordData:
    """The samples of one record (inside a task). Raises RecordError for anything wrong with it.
    CACHE: keep the row groups of the file for the next records of the same file."""
    if ref.source == "broken":
        raise RecordError(f"{ref.path}: {ref.error}")
    try:
        if ref.source == "csv":
            return _read_csv(ref, channels)
        return _read_parquet(ref, channels, cache or RowGroupCache())
    except RecordError:
        raise
    except Exception as exc:  # a broken file: whatever the reader says, as the record's status
        raise RecordError(f"{ref.path}: {type(exc).__name__}: {exc}") from None


def _split(values: np.ndarray, names: Sequence[str], channels: ChannelSpec, where: str) -> dict:
    """The covariate columns taken out (their means kept), then the inputs and outputs chosen."""
    names = list(names)
    covs = []
    for name in channels.covariates:
        if name not in names:
            raise RecordError(f"{where}: no covariate column named '{name}' (columns: {', '.join(names)})")
        covs.append(names.index(name))
    covariates = tuple((names[i], float(np.mean(values[:, i]))) for i in covs)
    keep = [i for i in range(len(names)) if i not in covs]
    values, names = values[:, keep], [names[i] for i in keep]
    ins, outs = channels.select(names)
    return dict(u=np.ascontiguousarray(values[:, ins]), y=np.ascontiguousarray(values[:, outs]),
                input_names=tuple(names[i] for i in ins), output_names=tuple(names[i] for i in outs),
                covariates=covariates)


def _read_csv(ref: RecordRef, channels: ChannelSpec) -> RecordData:
    """The CLI's reader and rules (okid.read_record, host_tools/common): the same samples, dt and
    refusals as ``okid identify`` with the same --inputs/--outputs/--dt."""
    import okid

    inputs = None if channels.inputs.strip() == "1" else channels.inputs  # the CLI's default: a count, never a name
    outputs = None if channels.covariates else channels.outputs  # covariates are taken out below
    fs, path = storage.resolve(ref.path)
    # the CLI's reader takes a file name: a record in an object store is copied to a local file first
    with tempfile.TemporaryDirectory(prefix="okid-fleet-") if not storage.is_local(fs) else nullcontext() as folder:
        local = storage.local_copy(fs, path, folder)
        try:
            rec = okid.read_record(local, inputs, outputs, channels.dt)
        except okid.RecordError as exc:
            raise RecordError(str(exc).replace(local, ref.path)) from None
    start = ref.start
    if start is None and rec.start is not None and rec.start > 1e8:  # absolute time stamps: epoch seconds
        start = float(rec.start)
    if not channels.covariates:
        return RecordData(u=rec.u, y=rec.y, dt=rec.dt, start=start, input_names=rec.input_names,
                          output_names=rec.output_names, covariates=())
    # covariate columns: read as outputs, then taken out by name (as for Parquet records)
    values = np.hstack([rec.u, rec.y])
    return RecordData(dt=rec.dt, start=start, **_split(values, rec.input_names + rec.output_names, channels, ref.path))


def _read_parquet(ref: RecordRef, channels: ChannelSpec, cache: RowGroupCache) -> RecordData:
    import pyarrow.compute as pc

    table = cache.read(ref.path, ref.row_groups or ())
    if "record" in table.column_names:
        table = table.filter(pc.equal(table.column("record"), ref.record))
    if table.num_rows == 0:
        raise RecordError(f"{ref.path}: record '{ref.record}' has no samples")
    dts = np.unique(table.column("dt").to_numpy(zero_copy_only=False))
    if dts.size != 1 or not (dts[0] > 0 and math.isfinite(dts[0])):
        raise RecordError(f"{ref.path}: record '{ref.record}': dt must be one finite value > 0 (got {dts[:4]})")
    keys = {k for k, _ in ref.partition}
    names = [n for n in table.column_names if n not in META_COLUMNS and n not in keys and not is_time_name(n)]
    values = np.column_stack([table.column(n).to_numpy(zero_copy_only=False).astype(np.float64) for n in names])
    return RecordData(dt=float(dts[0]), start=ref.start, **_split(values, names, channels, ref.path))
