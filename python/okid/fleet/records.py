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
skipped); records are found from the row groups' statistics (one record per row group is the
fast case) or, without them, from the ``record`` column alone.
"""
from __future__ import annotations

import glob
import math
import os
import re
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import Iterable, List, Optional, Sequence, Tuple

import numpy as np

META_COLUMNS = ("asset", "record", "start", "dt")
class RecordError(Exception):
    """A record that cannot be read or does not have the channels asked for."""


@dataclass(frozen=True)
class RecordRef:
    """One record: enough to find it again inside a task (picklable, no samples)."""
    source: str                      #: "csv" or "parquet"
    path: str                        #: the file
    record: str                      #: unique name of the record in the job
    asset: str                       #: the machine it belongs to
    start: Optional[float] = None    #: start time, seconds since 1970-01-01 UTC (None: unknown yet)
    row_groups: Optional[Tuple[int, ...]] = None  #: Parquet row groups holding it (None: filter by name)


@dataclass(frozen=True)
class ChannelSpec:
    """Which columns are inputs and outputs, as ``okid identify --inputs/--outputs`` take them: a
    count (taken in order after the time column) or comma-separated names; outputs None = the rest."""
    inputs: str = "1"
    outputs: Optional[str] = None
    dt: Optional[float] = None       #: sample interval when a CSV has no time column

    def select(self, names: Sequence[str]) -> Tuple[List[int], List[int]]:
        used: set = set()
        ins = self._pick(self.inputs, names, used, "inputs", 0)
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


def _is_parquet_dir(path: str) -> bool:
    return any(name.endswith(".parquet") for name in os.listdir(path))


def discover(paths: Iterable[str]) -> List[RecordRef]:
    """Every record named by PATHS: CSV files, globs, folders of CSV files (searched recursively)
    and Parquet files or folders of them. Sorted by asset, start, record; names must be unique."""
    refs: List[RecordRef] = []
    for given in paths:
        matches = sorted(glob.glob(given, recursive=True)) if glob.has_magic(given) else [given]
        if not matches:
            raise RecordError(f"{given}: no file matches")
        for path in matches:
            if os.path.isdir(path):
                if path.endswith(".parquet") or _is_parquet_dir(path):
                    refs.extend(_parquet_records(path))
                else:
                    root = os.path.normpath(path)
                    for csv in sorted(glob.glob(os.path.join(root, "**", "*.csv"), recursive=True)):
                        refs.append(_csv_record(csv, root))
            elif path.endswith(".parquet"):
                refs.extend(_parquet_records(path))
            elif os.path.exists(path):
                refs.append(_csv_record(path, os.path.dirname(os.path.normpath(path)) or "."))
            else:
                raise RecordError(f"{path}: no such file or folder")
    seen = {}
    for ref in refs:
        if ref.record in seen:
            raise RecordError(f"record '{ref.record}' is named twice ({seen[ref.record]} and {ref.path})")
        seen[ref.record] = ref.path
    return sorted(refs, key=lambda r: (r.asset, r.start if r.start is not None else math.inf, r.record))


def _csv_record(path: str, root: str) -> RecordRef:
    rel = os.path.relpath(path, root)
    folder = os.path.basename(os.path.dirname(os.path.abspath(path)))
    record = os.path.splitext(os.path.join(folder, rel) if os.path.dirname(rel) == "" else rel)[0]
    return RecordRef("csv", path, record.replace(os.sep, "/"), folder, start_from_name(path))


def _parquet_files(path: str) -> List[str]:
    if os.path.isdir(path):
        return sorted(glob.glob(os.path.join(path, "**", "*.parquet"), recursive=True))
    return [path]


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


def _parquet_records(path: str) -> List[RecordRef]:
    import pyarrow.parquet as pq

    refs: List[RecordRef] = []
    for file in _parquet_files(path):
        meta = pq.ParquetFile(file).metadata
        names = [meta.schema.column(i).name for i in range(meta.num_columns)]
        missing = [c for c in ("asset", "record", "dt") if c not in names]
        if missing:
            raise RecordError(f"{file}: a record dataset needs the column(s) {', '.join(missing)}")
        col = {name: names.index(name) for name in META_COLUMNS if name in names}
        groups = {}
        by_statistics = True
        for g in range(meta.num_row_groups):
            rg = meta.row_group(g)
            record, asset = _stat(rg, col["record"]), _stat(rg, col["asset"])
            if record is None or asset is None:
                by_statistics = False
                break
            start = _timestamp_seconds(_stat(rg, col.get("start")))
            entry = groups.setdefault(str(record), [str(asset), start, []])
            entry[2].append(g)
        if by_statistics:
            for record, (asset, start, rgs) in groups.items():
                refs.append(RecordRef("parquet", file, record, asset, start, tuple(rgs)))
            continue
        table = pq.read_table(file, columns=[c for c in ("asset", "record", "start") if c in names])
        frame = table.to_pandas()
        for record, rows in frame.groupby("record", sort=True):
            start = _timestamp_seconds(rows["start"].iloc[0]) if "start" in rows else None
            if start is not None and isinstance(rows["start"].iloc[0], np.datetime64):
                start = float(rows["start"].iloc[0].astype("datetime64[us]").astype(np.int64)) / 1e6
            refs.append(RecordRef("parquet", file, str(record), str(rows["asset"].iloc[0]), start, None))
    return refs


@dataclass(frozen=True)
class RecordData:
    u: np.ndarray          #: (N, r) inputs
    y: np.ndarray          #: (N, m) outputs
    dt: float              #: sample interval [s]
    start: Optional[float] #: seconds since the epoch, or None
    input_names: Tuple[str, ...]
    output_names: Tuple[str, ...]


def read(ref: RecordRef, channels: ChannelSpec) -> RecordData:
    """The samples of one record (inside a task). Raises RecordError for anything wrong with it."""
    try:
        return _read_csv(ref, channels) if ref.source == "csv" else _read_parquet(ref, channels)
    except RecordError:
        raise
    except Exception as exc:  # a broken file: whatever the reader says, as the record's status
        raise RecordError(f"{ref.path}: {type(exc).__name__}: {exc}") from None


def _split(values: np.ndarray, names: Sequence[str], channels: ChannelSpec):
    ins, outs = channels.select(names)
    return (np.ascontiguousarray(values[:, ins]), np.ascontiguousarray(values[:, outs]),
            tuple(names[i] for i in ins), tuple(names[i] for i in outs))


def _read_csv(ref: RecordRef, channels: ChannelSpec) -> RecordData:
    """The CLI's reader and rules (okid.read_record, host_tools/common): the same samples, dt and
    refusals as ``okid identify`` with the same --inputs/--outputs/--dt."""
    import okid

    inputs = None if channels.inputs.strip() == "1" else channels.inputs  # the CLI's default: a count, never a name
    try:
        rec = okid.read_record(ref.path, inputs, channels.outputs, channels.dt)
    except okid.RecordError as exc:
        raise RecordError(str(exc)) from None
    start = ref.start
    if start is None and rec.start is not None and rec.start > 1e8:  # absolute time stamps: epoch seconds
        start = float(rec.start)
    return RecordData(rec.u, rec.y, rec.dt, start, rec.input_names, rec.output_names)


def _read_parquet(ref: RecordRef, channels: ChannelSpec) -> RecordData:
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    if ref.row_groups is not None:
        table = pq.ParquetFile(ref.path).read_row_groups(list(ref.row_groups))
    else:
        table = pq.read_table(ref.path, filters=[("record", "=", ref.record)])
    table = table.filter(pc.equal(table.column("record"), ref.record))
    if table.num_rows == 0:
        raise RecordError(f"{ref.path}: record '{ref.record}' has no samples")
    dts = np.unique(table.column("dt").to_numpy(zero_copy_only=False))
    if dts.size != 1 or not (dts[0] > 0 and math.isfinite(dts[0])):
        raise RecordError(f"{ref.path}: record '{ref.record}': dt must be one finite value > 0 (got {dts[:4]})")
    names = [n for n in table.column_names if n not in META_COLUMNS and not is_time_name(n)]
    values = np.column_stack([table.column(n).to_numpy(zero_copy_only=False).astype(np.float64) for n in names])
    u, y, inames, onames = _split(values, names, channels)
    return RecordData(u, y, float(dts[0]), ref.start, inames, onames)
