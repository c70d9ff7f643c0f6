# SPDX-License-Identifier: Apache-2.0
"""okid_config from keywords: the C field names, okid_config_default()'s defaults (asked from the
library at import, so they cannot drift), enumerations by their C suffix in lower case, and
messages that name the setting and its valid range."""
from __future__ import annotations

import math
from typing import Any, Dict, Literal

import numpy as np

from . import _core
from ._errors import (_CLASSES, E_BAD_ORDER, E_BAD_PARAMETER, E_BAD_SIZE, BadOrderError, BadParameterError, BadSizeError,
                      ConfigurationError, OK)

#: The string options' values, for type checkers (okid_sensing, okid_realization, ... by their C suffix).
Sensing = Literal["displacement", "velocity", "acceleration"]
Realization = Literal["system", "combined"]
Scaling = Literal["none", "auto"]
Estimator = Literal["least_squares", "instrumental"]

SENSING = {"displacement": 0, "velocity": 1, "acceleration": 2}
REALIZATION = {"system": 0, "combined": 1}
SCALING = {"none": 0, "auto": 1}
ESTIMATOR = {"least_squares": 0, "instrumental": 1, "correlation": 2}
ENUMS = {"sensing": SENSING, "realization": REALIZATION, "scaling": SCALING, "estimator": ESTIMATOR}

#: okid_config's fields in the struct's order with their kinds ("int", "real", "enum", "flag"): the
#: binding's copy of OKID_CONFIG_FIELDS (host_tools/common/okid_fields.h), the CLI's JSON writer's table.
CONFIG_FIELDS = tuple(_core.CONFIG_FIELDS)
#: The settings of okid_config a caller gives by keyword, in the struct's order (num_inputs,
#: num_outputs and dt are positional or come from the arrays).
OPTION_NAMES = tuple(name for name, _ in CONFIG_FIELDS if name not in ("num_inputs", "num_outputs", "dt"))
_KIND = dict(CONFIG_FIELDS)


def _defaults() -> Dict[str, Any]:
    c = _core.config_default(1, 1)
    out = {}
    for name in OPTION_NAMES:
        value = c[name]
        if name in ENUMS:
            value = next(k for k, v in ENUMS[name].items() if v == value)
        out[name] = value
    return out


#: okid_config_default()'s values of the keyword settings (enumerations by name).
DEFAULTS: Dict[str, Any] = _defaults()


#: okid_config's integers are C ints.
_INT_MIN, _INT_MAX = -2**31, 2**31 - 1


def integer(name: str, value: Any) -> int:
    """A count (an order, a size, a number of passes): an int, a numpy integer or a float with an
    integral value (4.0 reads as 4, as dt=1 reads as 1.0); bool, complex, str and None are refused
    with a TypeError, a fraction with a BadParameterError (a ValueError) naming the argument."""
    if _not_a_number(value) or not (hasattr(value, "__index__") or isinstance(value, (float, np.floating))):
        raise TypeError(f"{name} = {value!r}: an integer (int, or a float with an integral value), "
                        f"not {type(value).__name__}")
    if hasattr(value, "__index__"):
        value = int(value.__index__())
    elif not (math.isfinite(value) and float(value).is_integer()):
        raise BadParameterError(f"{name} = {value!r}: an integer is needed", E_BAD_PARAMETER)
    value = int(value)
    if not _INT_MIN <= value <= _INT_MAX:  # the binding's int conversion would fail (std::bad_cast)
        cls = BadOrderError if name == "order" else BadSizeError
        code = E_BAD_ORDER if name == "order" else E_BAD_SIZE
        raise cls(f"{name} = {value} is outside the range of a C int ({_INT_MIN}..{_INT_MAX})", code)
    return value


def _not_a_number(value: Any) -> bool:
    """bool, complex, str, bytes (scalars or 0-d arrays): float() takes them, but they are no real number."""
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "iuf"
    return isinstance(value, (bool, np.bool_, complex, np.complexfloating, str, bytes))


def real_number(name: str, value: Any) -> float:
    """value as a float; bool, complex and str are refused with a TypeError naming the argument."""
    if _not_a_number(value):
        raise TypeError(f"{name} = {value!r}: a real number (int or float), not {type(value).__name__}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise BadParameterError(f"{name} must be a real number, not {value!r}", E_BAD_PARAMETER) from None


def real_array(values: Any, name: str) -> np.ndarray:
    """values as a float64 array (no copy when it is one); arrays of bool, complex, str or objects are
    refused with a TypeError naming the argument (a cast would drop imaginary parts, read True as 1)."""
    a = np.asarray(values)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name} has dtype {a.dtype}: an array of real numbers (integer or floating) is needed")
    return a.astype(np.float64, copy=False)


def channels_first_hint(shape: Any, name: str) -> str:
    """The sentence for a record given channels first ((channels, samples), e.g. y.T): more
    channels than samples, or more than the library takes; empty when the shape looks right."""
    if len(shape) == 2 and (shape[1] > shape[0] or shape[1] > _core.MAX_DIMENSION):
        return (f"{name} has shape {tuple(shape)}: {shape[1]} channels of {shape[0]} samples? Time runs along "
                f"axis 0, (samples, channels): pass {name}.T")
    return ""


def check_bool(name: str, value: Any) -> bool:
    """A flag argument that must be True or False (a string like "no" would be truthy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} = {value!r}: True or False, not {type(value).__name__}")
    return bool(value)


def _real(name: str, value: Any) -> float:
    return real_number(name, value)


def build(num_inputs: int, num_outputs: int, dt: float, options: Dict[str, Any]) -> Dict[str, Any]:
    """The okid_config dict for _core (enumerations as C values), checked by okid_workspace_size()."""
    unknown = sorted(set(options) - set(OPTION_NAMES))
    if unknown:
        raise TypeError(f"unknown okid option(s) {', '.join(unknown)}; the options are {', '.join(OPTION_NAMES)}")
    cfg: Dict[str, Any] = {"num_inputs": integer("num_inputs", num_inputs),
                           "num_outputs": integer("num_outputs", num_outputs)}
    dt = _real("dt", dt)
    if not (math.isfinite(dt) and dt > 0):
        raise BadParameterError(f"dt = {dt!r} s: the sample interval must be finite and > 0", E_BAD_PARAMETER)
    cfg["dt"] = dt
    for name in OPTION_NAMES:
        value = options.get(name, DEFAULTS[name])
        if name in ENUMS:
            if not isinstance(value, str):
                raise TypeError(f"{name} = {value!r}: one of {', '.join(map(repr, ENUMS[name]))}, not "
                                f"{type(value).__name__}")
            if value not in ENUMS[name]:
                raise BadParameterError(f"{name} = {value!r}: one of {', '.join(map(repr, ENUMS[name]))}",
                                        E_BAD_PARAMETER)
            value = ENUMS[name][value]
        elif _KIND[name] == "flag":
            value = int(value) if isinstance(value, (bool, np.bool_)) else integer(name, value)
            if value not in (0, 1):
                raise BadParameterError(f"{name} = {value!r}: 0 or 1 (False or True)", E_BAD_PARAMETER)
        elif _KIND[name] == "int":
            value = integer(name, value)
        else:
            value = _real(name, value)
        cfg[name] = value
    status, _ = _core.workspace_size(cfg)
    if status != OK:
        raise _explain(cfg, status)
    return cfg


def _explain(cfg: Dict[str, Any], status: int) -> Exception:
    """The refusal of cfg as the exception of status: the host library's one line (config_explain.c,
    the CLI's text with the settings spelled as keywords), naming the field okid_config_check()
    refused, its value and its valid range."""
    _, _, message = _core.explain_config(cfg)
    cls = _CLASSES.get(status, BadParameterError)
    return cls(message, status) if issubclass(cls, ConfigurationError) else BadParameterError(message, status)
