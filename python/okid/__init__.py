# SPDX-License-Identifier: Apache-2.0
"""okid: OKID/ERA system identification of structures from measured forces and responses.

    import okid
    res = okid.identify(u, y, dt=0.01, order=4)     # u (N, r) forces, y (N, m) responses
    for mode in res.modes:
        print(mode.frequency_hz, mode.damping_ratio)

The C core runs in-process; its LAPACK is SciPy's prefixed OpenBLAS (scipy-openblas32), loaded
here before the extension so that no system LAPACK is needed.
"""
import scipy_openblas32 as _scipy_openblas32  # noqa: F401  (loads libscipy_openblas RTLD_GLOBAL first)

from . import _core
from ._ambient import AmbientIdentifier, AmbientProgress, AmbientResult, identify_ambient
from ._config import DEFAULTS, OPTION_NAMES
from ._errors import (BadOrderError, BadParameterError, BadSizeError, ConcurrentUseError, ConfigurationError,
                      DataRangeError, DecompositionError, InternalError, NonFiniteSampleError, NonFiniteSampleWarning,
                      NoOutputExplainedWarning, NotAvailableError, NotEnoughDataError, NotPersistentlyExcitingError,
                      OkidError, OkidWarning, RecordError)
from ._identifier import Identifier, Progress, identify
from ._mode import Mode, Pole, SelectedMode, StabilityFlag, WarningFlag
from ._record import Record, read_record
from ._refine import REFINE_DEFAULTS, CramerRaoBound, ModeSplitWarning, Refinement, RefinementWarning, ResidualInputCorrelatedWarning, ResidualWarning, crlb
from ._result import FORMAT, FORMAT_VERSION, Result, Stabilization, StabilizationOrder, load
from . import model, plot
from .plot import plot_stabilization

__version__ = _core.VERSION

__all__ = [
    "identify", "identify_ambient", "AmbientIdentifier", "AmbientProgress", "AmbientResult", "Identifier", "Progress", "Result", "Mode", "SelectedMode",
    "Pole", "WarningFlag", "Stabilization",
    "StabilizationOrder", "StabilityFlag", "model", "plot", "plot_stabilization", "DEFAULTS", "OPTION_NAMES", "Refinement",
    "RefinementWarning", "ModeSplitWarning", "ResidualWarning", "ResidualInputCorrelatedWarning", "REFINE_DEFAULTS", "crlb", "CramerRaoBound", "read_record", "Record",
    "RecordError", "load", "FORMAT", "FORMAT_VERSION",
    "OkidError", "ConfigurationError", "BadSizeError", "BadOrderError", "BadParameterError", "NotEnoughDataError",
    "NotPersistentlyExcitingError", "DecompositionError", "NotAvailableError", "NonFiniteSampleError", "DataRangeError",
    "ConcurrentUseError", "InternalError", "OkidWarning", "NonFiniteSampleWarning", "NoOutputExplainedWarning",
]
