# SPDX-License-Identifier: Apache-2.0
"""One record identified: the rows of the mode table, and the table's schema.

A record gives one row per identified mode, or one status row when it fails (an unreadable file,
a force that does not excite the structure, too few samples, ...): the job goes on either way.
"""
from __future__ import annotations

import json
import re
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Tuple

import numpy as np

from .records import ChannelSpec, RecordError, RecordRef, RowGroupCache, read

if TYPE_CHECKING:  # for the annotations only: pyarrow is the fleet extra's
    import pyarrow as pa

STATUS_OK: str = "ok"
STATUS_UNREADABLE: str = "unreadable"
STATUS_WORKER_DIED: str = "worker_died"   # the record's task killed its worker process, alone, twice
STATUS_OUT_OF_MEMORY: str = "out_of_memory"  # the same, its worker restarted by its nanny past its memory limit
STATUS_TASK_FAILED: str = "task_failed"   # the record's task raised outside the identification
STATUS_TIMED_OUT: str = "timed_out"       # reading and identifying it took longer than --record-timeout
STATUS_TOO_LARGE: str = "too_large"       # the record is larger than --max-record-mb: refused unread


def _schema():
    import pyarrow as pa

    return pa.schema([
        ("asset", pa.string()), ("record", pa.string()), ("start", pa.timestamp("us", tz="UTC")),
        ("status", pa.string()), ("message", pa.string()),
        ("mode", pa.int32()), ("frequency_hz", pa.float64()), ("damping_ratio", pa.float64()),
        ("eigenvalue_re", pa.float64()), ("eigenvalue_im", pa.float64()),
        ("shape_re", pa.list_(pa.float64())), ("shape_im", pa.list_(pa.float64())),
        ("emac", pa.float64()), ("mpc", pa.float64()), ("cmi", pa.float64()),
        ("warnings", pa.list_(pa.string())), ("warning_bits", pa.int64()),
        ("order", pa.int32()), ("samples", pa.int64()), ("dt", pa.float64()),
        ("outputs", pa.list_(pa.string())), ("config", pa.string()),
        ("covariate_names", pa.list_(pa.string())), ("covariate_values", pa.list_(pa.float64())),
    ])


#: The columns of the mode table (Arrow schema), one row per (record, mode) or per failed record.
SCHEMA: Optional[pa.Schema] = None


def schema() -> pa.Schema:
    global SCHEMA
    if SCHEMA is None:
        SCHEMA = _schema()
    return SCHEMA


def status_of(exc: BaseException) -> str:
    """NotPersistentlyExcitingError -> 'not_persistently_exciting'; a bad file -> 'unreadable'."""
    if isinstance(exc, RecordError):
        return STATUS_UNREADABLE
    name = type(exc).__name__
    name = name[:-5] if name.endswith("Error") else name
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def _base(ref: RecordRef, start: Optional[float]) -> Dict[str, Any]:
    micros = None if start is None else int(round(start * 1e6))
    return {"asset": ref.asset, "record": ref.record, "start": micros}


def _failure(ref: RecordRef, start: Optional[float], exc: BaseException, config: str) -> Dict[str, Any]:
    row = _base(ref, start)
    row.update(status=status_of(exc), message=str(exc), config=config)
    return row


def failure_row(ref: RecordRef, status: str, message: str, options: Mapping[str, Any]) -> Dict[str, Any]:
    """The status row of a record whose task could not give one (its worker died, ...)."""
    row = _base(ref, ref.start)
    row.update(status=status, message=message, config=json.dumps(dict(options), sort_keys=True))
    return row


#: The settings of an output-only job (``--inputs 0``, okid.identify_ambient's keywords that are
#: okid_config's names too); the observer's settings mean nothing without an input.
AMBIENT_OPTIONS: Tuple[str, ...] = ("hankel_rows", "order", "sensing")


def check_options(options: Mapping[str, Any], channels: ChannelSpec) -> None:
    """Refuse (ValueError, one line) the settings an output-only job cannot use, and lifting
    without the factor (okid.identify would refuse it for every record)."""
    if options.get("decimation_method") == "lift" and "decimation" not in options:
        raise ValueError("--decimation-method lift needs --decimation K (the lifting factor; lifting does not "
                         "follow a decimation chosen from the data)")
    if channels.output_only:
        other = [name for name in options if name not in AMBIENT_OPTIONS]
        if other:
            flags = ", ".join("--" + name.replace("_", "-") for name in other)
            raise ValueError(f"{flags}: not a setting of output-only records (--inputs 0 takes "
                             f"{', '.join('--' + n.replace('_', '-') for n in AMBIENT_OPTIONS)})")


def identify_record(ref: RecordRef, channels: ChannelSpec, options: Mapping[str, Any],
                    cache: Optional[RowGroupCache] = None) -> List[Dict[str, Any]]:
    """Read and identify one record with okid.identify (okid.identify_ambient for output-only
    records, ``--inputs 0``); never raises for a property of the record."""
    import okid

    config = json.dumps(dict(options), sort_keys=True)
    try:
        data = read(ref, channels, cache)
    except RecordError as exc:
        return [_failure(ref, ref.start, exc, config)]
    try:
        if channels.output_only:
            result = okid.identify_ambient(data.y, data.dt, **options)
        else:
            result = okid.identify(data.u, data.y, data.dt, **options)
    except (okid.OkidError, ValueError) as exc:
        return [_failure(ref, data.start, exc, config)]
    common = _base(ref, data.start)
    common.update(status=STATUS_OK, message="", warnings=[flag.name.lower() for flag in okid.WarningFlag if flag & result.warnings],
                  warning_bits=int(result.warnings), order=int(result.order), samples=int(result.samples),
                  dt=float(result.dt), outputs=list(data.output_names), config=config,
                  covariate_names=[name for name, _ in data.covariates],
                  covariate_values=[value for _, value in data.covariates])
    if not result.modes:
        row = dict(common)
        found_none = result.warnings & okid.WarningFlag.NO_PHYSICAL_MODE  # the order chosen, nothing selected
        row.update(status="no_modes", message="no physical mode found (no pole stays put across the orders)" if found_none
                   else "the identified model has no oscillating or real mode")
        return [row]
    rows = []
    for k, mode in enumerate(result.modes, start=1):
        shape = np.asarray(mode.sensor_shape)
        row = dict(common)
        row.update(mode=k, frequency_hz=float(mode.frequency_hz), damping_ratio=float(mode.damping_ratio),
                   eigenvalue_re=float(mode.eigenvalue.real), eigenvalue_im=float(mode.eigenvalue.imag),
                   shape_re=shape.real.tolist(), shape_im=shape.imag.tolist(), emac=float(mode.emac),
                   mpc=float(mode.mpc), cmi=float(mode.cmi))
        rows.append(row)
    return rows


def to_table(rows: List[Dict[str, Any]]) -> pa.Table:
    import pyarrow as pa

    return pa.Table.from_pylist(rows, schema=schema())
