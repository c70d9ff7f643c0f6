# SPDX-License-Identifier: Apache-2.0
"""Exceptions of okid, one per okid_status, and the warning for rejected samples."""
from __future__ import annotations

from typing import Any, Tuple

from . import _core

__all__ = [
    "OkidError", "ConfigurationError", "BadSizeError", "BadOrderError", "BadParameterError",
    "NotEnoughDataError", "NotPersistentlyExcitingError", "DecompositionError", "NotAvailableError",
    "NonFiniteSampleError", "DataRangeError", "ConcurrentUseError", "InternalError", "NonFiniteSampleWarning", "RecordError",
]

# okid_status values (lib/include/okid/status.h)
OK = 0
E_NULL_POINTER = -1
E_BAD_SIZE = -2
E_BAD_ORDER = -3
E_BAD_PARAMETER = -4
E_WORKSPACE_TOO_SMALL = -5
E_WORKSPACE_ALIGNMENT = -6
E_NOT_INITIALIZED = -7
E_NONFINITE_SAMPLE = -8
E_NOT_ENOUGH_DATA = -9
E_RANK_DEFICIENT = -10
E_DECOMPOSITION_FAILED = -11
E_BACKEND_ARGUMENT = -12
E_NOT_AVAILABLE = -13
E_DATA_RANGE = -14


class OkidError(Exception):
    """An okid call failed. ``status`` is the C library's okid_status (a negative int)."""

    def __init__(self, message: str, status: int):
        super().__init__(message)
        self.status = status

    def __reduce__(self) -> Tuple[Any, ...]:
        # by (message, status): an error raised in a process pool's worker crosses back as itself
        return type(self), (str(self), self.status)


class ConfigurationError(OkidError, ValueError):
    """A size, order or parameter is out of range; the message names the setting and its valid range."""


class BadSizeError(ConfigurationError):
    """A count or array shape is out of range (OKID_E_BAD_SIZE)."""


class BadOrderError(ConfigurationError):
    """The model order does not fit the observer order or the Hankel matrix, or (Eigen backend) exceeds its
    OKID_EIGEN_MAX_ORDER (OKID_E_BAD_ORDER)."""


class BadParameterError(ConfigurationError):
    """A real parameter or an option value is out of range or not finite (OKID_E_BAD_PARAMETER)."""


class NotEnoughDataError(OkidError):
    """Fewer regressor rows than unknowns: push more samples (OKID_E_NOT_ENOUGH_DATA)."""


class NotPersistentlyExcitingError(OkidError):
    """The force does not excite the system: zero, constant or too narrow-band input, or an order
    above the Hankel matrix's rank (OKID_E_RANK_DEFICIENT)."""


class DecompositionError(OkidError, ArithmeticError):
    """A QR, SVD or eigenvalue decomposition did not converge (OKID_E_DECOMPOSITION_FAILED)."""


class NotAvailableError(OkidError, LookupError):
    """The thing asked for does not exist yet (no identification, prediction with decimation...)."""


class NonFiniteSampleError(OkidError, ValueError):
    """An input given to predict() holds NaN or Inf (OKID_E_NONFINITE_SAMPLE)."""


class DataRangeError(OkidError, ValueError):
    """A channel's RMS lies outside the magnitudes the arithmetic carries (1e-75..1e75 in double),
    or the results would not be finite: rescale the data (scaling="auto" or other units)."""


class ConcurrentUseError(OkidError, RuntimeError):
    """Another thread is using this Identifier; one identifier serves one thread at a time."""


class InternalError(OkidError, RuntimeError):
    """okid broke its own contract (workspace, backend argument): please report it."""


class RecordError(OkidError, ValueError):
    """okid.read_record refused a file: the CLI's one line for it (status: the CLI's exit code, 1 a
    bad file, 2 a request the file cannot meet)."""


class OkidWarning(UserWarning):
    """The base of okid's warnings: ``warnings.simplefilter("error", okid.OkidWarning)`` makes every
    one of them an exception, ``"ignore"`` silences them all."""


class NonFiniteSampleWarning(OkidWarning):
    """push() rejected samples holding NaN or Inf; everything learned before is kept."""


class NoOutputExplainedWarning(OkidWarning):
    """okid.identify(): the model explains less than half of every output (each fit_percent below
    50; WarningFlag.NO_OUTPUT_EXPLAINED, the CLI's "warning:" line): pure noise, a force that does
    not drive the outputs, the wrong columns. Its modes describe nothing measured."""


_CLASSES = {
    E_BAD_SIZE: BadSizeError,
    E_BAD_ORDER: BadOrderError,
    E_BAD_PARAMETER: BadParameterError,
    E_NOT_ENOUGH_DATA: NotEnoughDataError,
    E_RANK_DEFICIENT: NotPersistentlyExcitingError,
    E_DECOMPOSITION_FAILED: DecompositionError,
    E_NOT_AVAILABLE: NotAvailableError,
    E_NONFINITE_SAMPLE: NonFiniteSampleError,
    E_DATA_RANGE: DataRangeError,
    _core.STATUS_BUSY: ConcurrentUseError,
}


def error_for(status: int, message: str = "") -> OkidError:
    """The exception for a status, with the library's own description after the message."""
    if status == _core.STATUS_BUSY:
        text = "this Identifier is in use by another thread (use one Identifier per thread)"
    else:
        text = _core.status_str(status)
    return _CLASSES.get(status, InternalError)(f"{message}: {text}" if message else text, status)


def check(status: int, message: str = "") -> None:
    """Raise the exception of a failed status."""
    if status != OK:
        raise error_for(status, message)
