# SPDX-License-Identifier: Apache-2.0
"""okid.read_record: a CSV recording read by the CLI's own reader (host_tools/common, record_load.c),
so a file gives the same samples, dt and refusals here, in ``okid identify`` and in okid-fleet."""
from __future__ import annotations

import os
from typing import Any, NamedTuple, Optional, Tuple, Union

import numpy as np

from . import _core
from ._config import real_number
from ._document import frozen
from ._errors import RecordError


class Record(NamedTuple):
    """A recording: time along axis 0."""
    u: np.ndarray                  #: (N, r) inputs, read-only
    y: np.ndarray                  #: (N, m) outputs, read-only
    dt: float                      #: sample interval [s]
    input_names: Tuple[str, ...]
    output_names: Tuple[str, ...]
    start: Optional[float]         #: the time column's first stamp [s] (None without a time column)

    def __reduce__(self) -> Tuple[Any, ...]:
        return _unpickled, tuple(self)  # the arrays read-only again (an unpickled array is writable)


def _unpickled(u: np.ndarray, y: np.ndarray, *rest: Any) -> Record:
    return Record(frozen(u), frozen(y), *rest)


def _spec(name: str, value: Union[None, int, str]) -> Optional[str]:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, str)):
        raise TypeError(f"{name} must be a count (int) or comma-separated column names (str), not {value!r}")
    return str(value)


def read_record(path: Union[str, os.PathLike[str]], inputs: Union[None, int, str] = None,
                outputs: Union[None, int, str] = None, dt: Optional[float] = None,
                ignore_time_column: bool = False) -> Record:
    """Read a CSV recording as ``okid identify`` does (docs/cli.md, docs/robustness.md).

    inputs / outputs: a count (the next columns that are not the time column) or comma-separated
    column names, as ``--inputs`` / ``--outputs``; by default one input and every other column an
    output. dt [s]: the sample interval when the file has no time column; with one, it must agree
    with the stamps unless ignore_time_column. Raises RecordError with the CLI's message.
    """
    if not isinstance(ignore_time_column, bool):
        raise TypeError(f"ignore_time_column must be a bool, not {ignore_time_column!r}")
    given = None if dt is None else real_number("dt", dt)
    name = os.fspath(path)
    if not isinstance(name, str):
        raise TypeError(f"path must be a str or os.PathLike of str, not {path!r}")
    got = _core.read_record(name, _spec("inputs", inputs), _spec("outputs", outputs), given, ignore_time_column)
    if got[0] != 0:
        raise RecordError(f"{name}: {got[1]}", got[0])
    _, _, u, y, step, input_names, output_names, start = got
    return Record(u, y, step, tuple(input_names), tuple(output_names), start)
