# SPDX-License-Identifier: Apache-2.0
"""JSON documents and pickles of okid's frozen dataclasses (Result, Refinement, Mode), written
generically over their fields, so that a field added to one of them travels without a change here.

A dataclass is read from a JSON object by its fields' type hints: an object's member of the
field's name (or, failing that, of its "config" member), converted by the hint. The CLI's JSON
(``okid identify --json``) uses the fields' names, numbers in %.17g (exact for doubles), non-finite
numbers as null, complex numbers as [re, im]; an array annotated ComplexArray is a list of
[re, im]. docs/python.md, "Results that travel", describes the file format.
"""
from __future__ import annotations

import collections.abc
import dataclasses
import enum
import json
import math
import os
import typing
from types import MappingProxyType
from typing import Any, Callable, Dict, Mapping, Optional, Tuple, Type, TypeVar, Union

import numpy as np

try:  # Python 3.9 has Annotated in typing too, keep the import in one place
    from typing import Annotated
except ImportError:  # pragma: no cover
    from typing_extensions import Annotated  # type: ignore[assignment]

#: A complex numpy array (a mode's shapes): a list of [re, im] in JSON.
ComplexArray = Annotated[np.ndarray, "complex"]

T = TypeVar("T")

#: For a required field a document may lack: a function of (the object being read, the enclosing
#: object's already-read fields) giving its value. The CLI's "refinement" has no order, dt, cost.
Fallbacks = Mapping[str, Callable[[Mapping[str, Any], Mapping[str, Any]], Any]]


def public_fields(instance: Any) -> Dict[str, Any]:
    """The dataclass's init fields that do not start with "_" (the C cores stay behind)."""
    return {f.name: getattr(instance, f.name) for f in dataclasses.fields(instance)
            if f.init and not f.name.startswith("_")}


def frozen(value: Any) -> Any:
    """value with every numpy array in it read-only (an unpickled array is writable)."""
    if isinstance(value, np.ndarray):
        value.flags.writeable = False
    elif isinstance(value, tuple):
        for v in value:
            frozen(v)
    return value


def restore(cls: Type[T], fields: Dict[str, Any], extra: Optional[Dict[str, Any]] = None) -> T:
    """The other end of Travelling.__reduce__: an instance of cls from its public fields (and its
    private extra ones), arrays read-only, mappings immutable."""
    values = {name: _freeze_mapping(v) if isinstance(v, dict) else frozen(v)
              for name, v in {**fields, **(extra or {})}.items()}
    return cls(**values)


def thaw_mapping(value: Mapping) -> Dict[str, Any]:
    """A mapping and the mappings in it as dicts (a mappingproxy does not pickle)."""
    return {k: thaw_mapping(v) if isinstance(v, Mapping) else v for k, v in value.items()}


def _freeze_mapping(value: Dict[str, Any]) -> Mapping[str, Any]:
    return MappingProxyType({k: _freeze_mapping(v) if isinstance(v, dict) else v for k, v in value.items()})


class Travelling:
    """Pickle and deepcopy of a frozen dataclass by its public fields (restore() rebuilds it), so a
    result can cross a process boundary (ProcessPoolExecutor) and stays read-only after it."""

    def _private_state(self) -> Dict[str, Any]:
        """Private fields the copy keeps (none by default: the C cores do not travel)."""
        return {}

    def __reduce__(self) -> Tuple[Any, ...]:
        fields = {name: thaw_mapping(v) if isinstance(v, Mapping) else v for name, v in public_fields(self).items()}
        return restore, (type(self), fields, self._private_state())


def _complex(value: Any) -> complex:
    re, im = value
    return complex(math.nan if re is None else re, math.nan if im is None else im)


def _strip_optional(hint: Any) -> Tuple[Any, bool]:
    if typing.get_origin(hint) is Union:
        args = [a for a in typing.get_args(hint) if a is not type(None)]
        if len(args) == 1:
            return args[0], True
    return hint, False


def convert(hint: Any, value: Any, fallbacks: Optional[Fallbacks] = None) -> Any:
    """One JSON value as the Python value of a field with this type hint (a dataclass in it read
    with fallbacks, see read())."""
    hint, optional = _strip_optional(hint)
    if value is None and optional:
        return None
    if typing.get_origin(hint) is Annotated:
        base, *meta = typing.get_args(hint)
        if base is np.ndarray and "complex" in meta:
            a = np.array([_complex(v) for v in value], dtype=np.complex128)
            return frozen(a)
        hint = base
    if hint is np.ndarray:
        return frozen(np.array(value, dtype=np.float64))  # null (a non-finite number) reads as nan
    if hint is complex:
        return _complex(value)
    if hint is float:
        return math.nan if value is None else float(value)
    if hint in (int, bool, str):
        return hint(value)
    origin = typing.get_origin(hint)
    if origin in (tuple, Tuple):
        args = typing.get_args(hint)
        return tuple(convert(args[0], v, fallbacks) for v in value)
    if origin in (dict, collections.abc.Mapping) or hint in (dict, Mapping):
        return MappingProxyType(dict(value))
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return hint(value)
    if dataclasses.is_dataclass(hint):
        return read(hint, value, fallbacks)
    return value


def read(cls: Type[T], obj: Mapping[str, Any], fallbacks: Optional[Fallbacks] = None,
         outer: Optional[Mapping[str, Any]] = None, aliases: Optional[Mapping[str, Any]] = None) -> T:
    """An instance of the dataclass cls from the JSON object obj, by its fields' type hints.

    A field is obj[name], else obj["config"][name]; an enum field whose member is not a number
    (the CLI's "warnings", a list of sentences) reads aliases[name] (its "warning_bits"). A missing
    field keeps its default, an Optional one is None, a required one is fallbacks[name](obj,
    outer) or a ValueError naming it. Nested dataclasses read with fallbacks[cls.__name__ +
    "." + name] and outer = the fields read so far.
    """
    fallbacks = fallbacks or {}
    hints = typing.get_type_hints(cls, include_extras=True)
    config = obj.get("config") if isinstance(obj.get("config"), Mapping) else {}
    values: Dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        if not f.init or f.name.startswith("_"):
            continue
        hint = hints[f.name]
        base, optional = _strip_optional(hint)
        raw = obj[f.name] if f.name in obj else config.get(f.name, _MISSING)
        alias = (aliases or {}).get(f.name)
        if alias is not None and isinstance(base, type) and issubclass(base, enum.Enum) and not isinstance(raw, int):
            raw = obj.get(alias, _MISSING)
        if raw is _MISSING:
            if f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING:
                continue
            if optional:
                values[f.name] = None
                continue
            key = f"{cls.__name__}.{f.name}"
            if key not in fallbacks:
                raise ValueError(f"the document has no {f.name!r} for {cls.__name__} (its fields: "
                                 f"{', '.join(x.name for x in dataclasses.fields(cls) if not x.name.startswith('_'))})")
            values[f.name] = fallbacks[key](obj, outer or {})
            continue
        if dataclasses.is_dataclass(base) and raw is not None:
            values[f.name] = read(base, raw, fallbacks, values, aliases)
        else:
            values[f.name] = convert(hint, raw, fallbacks)
    return cls(**values)


_MISSING = object()


def encode(value: Any) -> Any:
    """A field's value as JSON: arrays as (nested) lists, complex as [re, im], non-finite as null."""
    if isinstance(value, np.ndarray):
        if np.iscomplexobj(value):
            return [[encode(float(z.real)), encode(float(z.imag))] for z in value.reshape(-1)]
        return encode(value.tolist())
    if isinstance(value, enum.Enum):
        return int(value.value)
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, (complex, np.complexfloating)):
        return [encode(float(value.real)), encode(float(value.imag))]
    if isinstance(value, (list, tuple)):
        return [encode(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): encode(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {k: encode(v) for k, v in public_fields(value).items()}
    return value


def missing(instance: Any, obj: Mapping[str, Any]) -> Dict[str, Any]:
    """The public fields of instance that the JSON object obj does not carry, encoded, with the
    same recursion into nested dataclasses and tuples of them (a result's refinement, its modes):
    what a saved file adds to the CLI's JSON so that it reloads equal."""
    out: Dict[str, Any] = {}
    for name, value in public_fields(instance).items():
        if name not in obj:  # (read() would find some in obj["config"], the setting rather than the result's)
            if value is not None:
                out[name] = encode(value)
        elif dataclasses.is_dataclass(value) and isinstance(obj[name], Mapping):
            sub = missing(value, obj[name])
            if sub:
                out[name] = sub
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]) and isinstance(obj[name], list):
            subs = [missing(v, o) for v, o in zip(value, obj[name])]
            if any(subs):
                out[name] = subs
    return out


def merged(obj: Mapping[str, Any], extra: Mapping[str, Any]) -> Dict[str, Any]:
    """obj with extra's members added, recursively (the inverse of missing())."""
    out = dict(obj)
    for name, value in extra.items():
        if isinstance(value, Mapping) and isinstance(out.get(name), Mapping):
            out[name] = merged(out[name], value)
        elif isinstance(value, list) and isinstance(out.get(name), list) and name in obj and \
                all(isinstance(v, Mapping) for v in value):
            out[name] = [merged(o, v) for o, v in zip(out[name], value)]
        else:
            out[name] = value
    return out


def save(instance: Any, document: Mapping[str, Any], path: Union[str, "os.PathLike[str]"], fmt: str,
         version: int) -> None:
    """Write instance's JSON document to path: "format" and "format_version" first, then the
    document's members, then under "python" the public fields it does not carry (missing()). An
    existing file is refused (FileExistsError): the caller removes it."""
    extra = missing(instance, document)
    text = json.dumps({"format": fmt, "format_version": version, **document, **({"python": extra} if extra else {})},
                      indent=1, allow_nan=False)
    with open(path, "x", encoding="utf-8") as f:
        f.write(text + "\n")


def open_document(document: Mapping[str, Any], fmt: str, version: int, readers: str,
                  default_format: Optional[str] = None) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """(the members, the "python" extras) of a document of format fmt, versions 1..version; a
    document without "format" is default_format's (the CLI's JSON is a Result). readers says what
    reads fmt, for the refusal of another format."""
    document = dict(document)
    found = document.pop("format", default_format)
    got = document.pop("format_version", version)
    if found != fmt:
        raise ValueError(f"format = {found!r}: {readers}{_OTHER_READERS.get(found, '')}")
    if isinstance(got, bool) or not isinstance(got, int) or not 1 <= got <= version:
        raise ValueError(f"format_version = {got!r}: this okid reads versions 1..{version} "
                         f"(a newer okid wrote the file: upgrade okid)")
    return document, dict(document.pop("python", {}))


#: who reads each format (a refusal points to it)
_OTHER_READERS = {"okid.Result": "; okid.load reads that one",
                  "okid.Stabilization": "; okid.Stabilization.load reads that one",
                  "okid.CramerRaoBound": "; okid.CramerRaoBound.load reads that one"}


def load_json(path: Union[str, "os.PathLike[str]"], what: str) -> Dict[str, Any]:
    """The JSON object of a file, or a ValueError naming what writes one."""
    with open(path, encoding="utf-8") as f:
        document = json.load(f)
    if not isinstance(document, dict):
        raise ValueError(f"{os.fspath(path)}: not a JSON object ({what} writes one)")
    return document
