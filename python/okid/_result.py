# SPDX-License-Identifier: Apache-2.0
"""Result and the stabilization diagram: immutable views of an identification, copied out of the C
workspace (Mode and the flags are in _mode)."""
from __future__ import annotations

import copy
import json
import math
import os
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any, Dict, Mapping, Optional, Tuple, Union

import numpy as np

from . import _core
from . import _document
from ._config import integer
from ._document import Travelling
from ._errors import E_BAD_PARAMETER, E_NOT_AVAILABLE, BadParameterError, check, error_for
from ._mode import Mode, ModeArrays, Pole, SelectedMode, StabilityFlag, WarningFlag, modes_from_dicts
from ._progress import CALLER, ProgressArg, reported
from ._refine import REFINE_DEFAULTS, Refinement, check_settings, run as _run_refinement, warn_if_stopped
from ._statespace import StateSpaceModel

#: Result.save()'s file: "format" and "format_version" first, then the members of ``okid identify
#: --json`` (Result.to_dict()), then under "python" what the CLI's JSON does not carry
#: (docs/python.md, "Results that travel"). A reader refuses a version above its own.
FORMAT = "okid.Result"
FORMAT_VERSION = 1


#: Stabilization.save()'s file: "format" and "format_version", then the members of ``okid identify
#: --json --stabilization``'s "stabilization" object (Stabilization.to_dict()).
STABILIZATION_FORMAT = "okid.Stabilization"
STABILIZATION_FORMAT_VERSION = 1


@dataclass(frozen=True)
class StabilizationOrder(Travelling):
    """The modes of one model order of a stabilization diagram, with their stability flags."""
    order: int                          #: the model order n [states]
    modes: Tuple[Mode, ...]             #: its modes, sorted by frequency
    stability: Tuple[StabilityFlag, ...]  #: each mode's stability against the previous order


@dataclass(frozen=True, eq=False)
class Stabilization(Travelling):
    """Stabilization diagram data: the modes of orders step, 2 step, ..., max_order from one SVD.
    Immutable; pickles, copies and saves (save(), Stabilization.load()) as a detached diagram with
    the same fields and to_dict()."""
    max_order: int                          #: the highest order asked for [states]
    step: int                               #: the order step [states]
    rank_limit: int                         #: largest order the Hankel matrix supports [states]
    orders: Tuple[StabilizationOrder, ...]  #: one entry per order computed, increasing
    _core: Any = field(repr=False, default=None)
    _document: Optional[Mapping[str, Any]] = field(repr=False, default=None)  # to_dict() of a detached diagram

    @classmethod
    def _from_core(cls, core: Any, max_order: int, step: int) -> "Stabilization":
        orders = tuple(StabilizationOrder(order, modes_from_dicts(modes), tuple(StabilityFlag(f) for f in flags))
                       for order, modes, flags in core.orders())
        return cls(max_order, step, core.rank_limit, orders, _core=core)

    def to_dict(self) -> Dict[str, Any]:
        """The "stabilization" object of ``okid identify --json --stabilization`` (the CLI's writer;
        a detached diagram gives the object it was detached with)."""
        if self._core is not None:
            text = self._core.to_json()
            return json.loads(text[text.index("{"):])
        return copy.deepcopy(_document.thaw_mapping(self._document or {}))

    def _private_state(self) -> Dict[str, Any]:
        return {"_document": self.to_dict()}

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Write the diagram to path as JSON (format STABILIZATION_FORMAT, version
        STABILIZATION_FORMAT_VERSION: docs/python.md); Stabilization.load(path) gives it back
        equal. An existing file is refused (FileExistsError)."""
        _document.save(self, self.to_dict(), path, STABILIZATION_FORMAT, STABILIZATION_FORMAT_VERSION)

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Stabilization":
        """A detached diagram from Stabilization.save()'s object or the CLI's "stabilization" object."""
        document, extra = _document.open_document(
            document, STABILIZATION_FORMAT, STABILIZATION_FORMAT_VERSION,
            f"okid.Stabilization.load reads {STABILIZATION_FORMAT!r} files and the \"stabilization\" object of "
            f"okid identify --json --stabilization", default_format=STABILIZATION_FORMAT)
        values = _document.read(cls, _document.merged(document, extra), _STABILIZATION_FALLBACKS)
        return replace(values, _document=MappingProxyType(document))

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Stabilization":
        """The diagram a file holds: Stabilization.save()'s (or the CLI's "stabilization" object)."""
        return cls.from_dict(_document.load_json(path, "Stabilization.save()"))


def _stability(obj: Mapping[str, Any], outer: Mapping[str, Any]) -> Tuple[StabilityFlag, ...]:
    """A mode's flags from the JSON's stable_frequency, stable_damping, stable_shape."""
    return tuple(StabilityFlag((StabilityFlag.FREQUENCY if m["stable_frequency"] else 0) |
                               (StabilityFlag.DAMPING if m["stable_damping"] else 0) |
                               (StabilityFlag.SHAPE if m["stable_shape"] else 0)) for m in obj["modes"])


_STABILIZATION_FALLBACKS: _document.Fallbacks = {"StabilizationOrder.stability": _stability}


#: Result's fields from the binding's fields(): okid_result's scalars (OKID_RESULT_SCALARS of
#: host_tools/cli/okid_fields.h) and its arrays.
_FIELDS = tuple(_core.RESULT_SCALARS) + ("A", "B", "C", "D", "G", "singular_values", "markov", "observer_gain_markov",
                                         "input_scales", "output_scales", "fit_percent")


@dataclass(frozen=True, eq=False)
class Result(ModeArrays, StateSpaceModel, Travelling):
    """An identified model: state space, Markov parameters, modes and diagnostics. Immutable; every
    array is a read-only copy that later pushes and identifications leave as it is. A Result keeps
    the workspace of the identifier that made it (okid_workspace_size() bytes) for stabilization():
    to collect many records, keep the numbers you need rather than the Results. A pickled, copied
    or loaded Result (save(), okid.load()) is detached: the same fields and to_dict(), no
    stabilization().

    Fields (n states, r inputs, m outputs; the model is discrete at dt, in the units of the data):

    - order: n, the realized order [states]
    - A (n, n) [-], B (n, r) [state / input unit], C (m, n) [output unit / state], D (m, r)
      [output unit / input unit]: x(k+1) = A x(k) + B u(k), y(k) = C x(k) + D u(k)
    - G: (n, m) observer gain [state / output unit] with realization="combined", else None
    - singular_values: the Hankel singular values, decreasing [output unit / input unit]
    - markov: [Y_0 Y_1 ... Y_L] (m, r (L + 1)), eq. 51 [output unit / input unit]
    - observer_gain_markov: [Y°_1 ... Y°_L] (m, m L) [-] with realization="combined", else None
    - dt: the model's sample interval [s] (decimation times the data's)
    - samples: samples accepted; rows: regressor rows in the least squares [counts]
    - regressor_rank, regressor_columns (q = r + (r + m) p), input_rank (r (p + 1) when
      persistently exciting), regressor_rank_expected (min(q, r (p + 1) + n)) [counts]
    - lsq_condition, input_condition, realization_condition (sigma_1 / sigma_n of H(0)): condition
      numbers [-]
    - decimation: K [-]; instrument_lags: L of the instrumental estimator, 0 for least squares
    - input_scales (r,), output_scales (m,): channel RMS with scaling="auto" [the channel's unit], else None
    - modes: okid.Mode tuple sorted by frequency (frequency_hz [Hz], damping_ratio [-], ...)
    - warnings: okid.WarningFlag; config: the okid_config used (keyword names)
    - refinement: the prediction-error refinement (okid.Refinement) or None; start_search: the
      starts tried with refine=True and no horizon given, else None; start: after a refinement,
      the OKID/ERA Result it started from (modes and warnings are then the refined ones)
    - chosen: the settings chosen from the data, each {value, chosen, reason}, and the outputs'
      band band_hz [Hz] (docs/quality.md section 8), else None; poles: with the order chosen,
      every pole of the model as okid.Pole (verdict, reason), while modes holds the physical
      modes as okid.SelectedMode (their spread across orders [Hz, -]), else None
    - fit_percent: (m,) how much of each output the model's response from rest explains [%], as
      MATLAB's compare (okid.identify() only: the record is needed; None with decimation > 1 or a
      pole on or outside the unit circle, and fit_note says why); every one below 50 sets WarningFlag.NO_OUTPUT_EXPLAINED and
      okid.identify() warns (okid.NoOutputExplainedWarning)
    - refine_model_choice: with refine_model="auto", the model the residual test chose and why
      ({requested, chosen, reason, detail}: words, no unit; docs/refinement.md), else None
    """
    order: int                          #: n, the realized order (states)
    A: np.ndarray                       #: (n, n) discrete state matrix
    B: np.ndarray                       #: (n, r)
    C: np.ndarray                       #: (m, n)
    D: np.ndarray                       #: (m, r)
    G: Optional[np.ndarray]             #: (n, m) observer gain (realization="combined"), else None
    singular_values: np.ndarray         #: Hankel singular values, decreasing
    markov: np.ndarray                  #: [Y_0 Y_1 ... Y_L], (m, r (L + 1)), eq. 51
    observer_gain_markov: Optional[np.ndarray]  #: [Y°_1 ... Y°_L], (m, m L) (combined), else None
    dt: float                           #: the model's sample interval [s] (decimation times the data's)
    samples: int                        #: samples accepted
    rows: int                           #: regressor rows in the least squares
    regressor_rank: int                 #: numerical rank of the regressor
    regressor_columns: int              #: q = r + (r + m) p
    input_rank: int                     #: rank of the input part: r (p + 1) when persistently exciting
    regressor_rank_expected: int        #: min(q, r (p + 1) + n), the rank of noise-free data
    lsq_condition: float                #: condition number of the equilibrated regressor factor
    input_condition: float              #: the same for the input columns alone
    realization_condition: float        #: sigma_1 / sigma_n of H(0)
    decimation: int                     #: K
    instrument_lags: int                #: L of the instrumental estimator (0 for least squares)
    input_scales: Optional[np.ndarray]  #: (r,) with scaling="auto", else None
    output_scales: Optional[np.ndarray] #: (m,) with scaling="auto", else None
    modes: Tuple[Mode, ...]             #: sorted by frequency, then damping
    warnings: WarningFlag               #: what deserves a look
    config: Mapping[str, Any]           #: the okid_config used (keyword names and values)
    refinement: Optional[Refinement]    #: the prediction-error refinement (refine=True, refine()), else None
    _core: Any = field(repr=False, default=None)
    _identifier: Any = field(repr=False, default=None)
    _generation: int = field(repr=False, default=0)
    _refine_core: Any = field(repr=False, default=None)
    _document: Optional[Mapping[str, Any]] = field(repr=False, default=None)  # to_dict() of a detached Result
    #: with refine=True and no horizon given: the starts tried ({"chosen": index, "candidates":
    #: [{observer_order, hankel_rows, hankel_cols, state, cost}]}, the JSON's "start_search"), else None
    start_search: Optional[Mapping[str, Any]] = None
    #: the settings chosen from the data, each {"value", "chosen", "reason"}, with the outputs' band
    #: (the JSON's "chosen"; docs/quality.md section 8); None when every setting was given
    chosen: Optional[Mapping[str, Any]] = None
    #: with the order chosen (order=0): every pole of the model with its verdict (okid.Pole), while
    #: ``modes`` holds the physical modes (okid.SelectedMode); else None
    poles: Optional[Tuple[Pole, ...]] = None
    #: (m,) how much of each output the model explains [%], as MATLAB's compare: 100 (1 - |y - yhat|
    #: / |y - mean y|), yhat the model's response to u from rest (okid identify's "fit_percent";
    #: WarningFlag.NO_OUTPUT_EXPLAINED when every one is below 50); after a refinement the refined
    #: model's; None without a record (Identifier.identify()), with decimation > 1 or with a pole on
    #: or outside the unit circle (fit_note says why)
    fit_percent: Optional[np.ndarray] = None
    _auto_json: Optional[str] = field(repr=False, default=None)
    #: with refine=True and refine_model="auto": which model the residual test chose and why,
    #: {"requested": "auto", "chosen", "reason", "detail"} (the JSON's "refine_model_choice",
    #: docs/refinement.md), else None
    refine_model_choice: Optional[Mapping[str, str]] = None
    #: after a refinement: the OKID/ERA result it started from (modes, warnings and model as
    #: identified; this result's modes and warnings are the refined ones, JSON "start"), else None
    start: Optional["Result"] = field(repr=False, default=None)

    @classmethod
    def _from_core(cls, core, config: Mapping[str, Any], identifier, generation: int) -> "Result":
        f = core.fields()
        values = {name: f[name] for name in _FIELDS}
        return cls(**values, modes=modes_from_dicts(f["modes"]), warnings=WarningFlag(f["warnings"]),
                   config=MappingProxyType(dict(config)), refinement=None, _core=core, _identifier=identifier,
                   _generation=generation)

    @property
    def fit_note(self) -> str:
        """Why fit_percent is None ("" when it is given). The fit compares the model's response to
        the record's inputs from rest with every output sample, so it needs the record and a model
        of that record: okid.Identifier keeps no record (fixed memory: the regressor's sums only),
        and a decimated model (decimation K > 1) describes the identifier's anti-alias-filtered
        record, one sample kept in K, which the identifier keeps to itself (its filter's state is
        not exposed): compared with the record given it would measure the filter, not the model. A
        model with a pole on or outside the unit circle gets none either: its response from rest
        grows without bound."""
        if self.fit_percent is not None:
            return ""
        # the host library's sentence (output_fit.c), as okid identify's
        missing = self._core.fit_missing() if self._core is not None else None
        if missing is not None:
            return missing
        return ("no fit: no record came with this model (okid.Identifier keeps none: fixed memory, the regressor's "
                "sums only); okid.identify(u, y) computes it over the record it is given")

    def to_dict(self) -> Dict[str, Any]:
        """The object ``okid identify --json`` prints for the same data and options, written by the
        CLI's own JSON writer (without the CLI-only "inputs", "outputs" and "elapsed_seconds"), with
        the "refinement" object of ``--refine`` when this result was refined. A detached Result
        (pickled, copied, loaded) gives the object it was detached with."""
        if self._core is not None:
            if self._refine_core is not None:
                # the run's members, OKID/ERA's model as "start", then the refined result's, as okid
                # identify --refine writes them
                text = self.start._core.to_json_refined_start() + self._refine_core.to_json() + "\n}\n"
            else:
                text = self._core.to_json()
            out = json.loads(text)
            if self._auto_json is not None:  # the CLI's members after the model: "chosen", "modes", "poles"
                out.pop("modes")
                out["config"]["order"] = self.config["order"]
                out.update(json.loads("{" + self._auto_json.lstrip().lstrip(",") + "}"))
        else:
            out = copy.deepcopy(_document.thaw_mapping(self._document or {}))
        out.pop("start_search", None)
        if self.start_search is not None:
            out["start_search"] = json.loads(json.dumps(self.start_search))
        out.pop("refine_model_choice", None)
        if self.refine_model_choice is not None:  # okid identify --refine-model auto's top-level member
            out["refine_model_choice"] = dict(self.refine_model_choice)
        return out

    def _private_state(self) -> Dict[str, Any]:
        return {"_document": self.to_dict()}

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Write this result to path as JSON (the format FORMAT, version FORMAT_VERSION:
        docs/python.md, "Results that travel"); okid.load(path) gives it back equal. An existing
        file is refused (FileExistsError): the caller removes it."""
        _document.save(self, self.to_dict(), path, FORMAT, FORMAT_VERSION)

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Result":
        """okid.load(path): the Result a file holds (Result.save()'s, or ``okid identify --json``'s)."""
        return load(path)

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Result":
        """A detached Result from a JSON object: Result.save()'s, or the CLI's ``okid identify
        --json`` (with --refine too). Fields the CLI's JSON lacks (observer_gain_markov; a
        refinement's order, dt, cost) are None, derived or nan."""
        document, extra = _document.open_document(
            document, FORMAT, FORMAT_VERSION, f"okid.load reads {FORMAT!r} files and the JSON of okid identify --json",
            default_format=FORMAT)
        for name in ("inputs", "outputs", "elapsed_seconds"):  # the CLI's, not the result's
            document.pop(name, None)
        # okid identify --refine: the top-level modes and warnings are the refined ones, the model
        # fields (A..D, diagnostics, singular values) OKID/ERA's under "start", as in Result
        start_doc = document.get("start")
        fields = dict(document)
        if isinstance(start_doc, Mapping):
            fields.pop("start")
            fields.update({k: v for k, v in start_doc.items() if k not in ("modes", "warnings", "warning_bits")})
        start_extra = extra.pop("start", None)
        fields = _document.merged(fields, extra)
        values = _document.read(cls, fields, _CLI_FALLBACKS, aliases={"warnings": "warning_bits"})
        if values.poles is not None:  # the order chosen: the modes are the physical ones the selection kept
            values = replace(values, modes=tuple(_document.read(SelectedMode, m) for m in fields["modes"]))
        if isinstance(start_doc, Mapping):
            refined_only = ("start", "refinement", "std_covariance", "initial_state", "modes", "warnings",
                            "warning_bits", "A", "B", "C", "D")
            header = {k: v for k, v in document.items() if k not in refined_only}
            start = {**header, **start_doc, **({"python": start_extra} if start_extra else {})}
            values = replace(values, start=cls.from_dict(start))
        return replace(values, _document=MappingProxyType(document))

    @reported
    def refine(self, u: Any, y: Any, *, max_passes: int = REFINE_DEFAULTS["max_passes"],
               step_tolerance: float = REFINE_DEFAULTS["step_tolerance"],
               progress: ProgressArg = None,
               refine_model: str = REFINE_DEFAULTS["refine_model"]) -> "Result":
        """This result with its prediction-error refinement over the record (u, y): the same
        arrays this model describes, (N, r) and (N, m), at its sample interval dt (docs/refinement.md).

        The record is fed to okid_refine_push_block() from the caller's arrays (no copy, the GIL
        released) once per pass until the refinement finishes. max_passes: passes at most
        (2..1000); step_tolerance: converged when the Gauss–Newton decrement (about the squared
        step in standard deviations) falls below it (> 0); refine_model: the predictor fitted,
        "output_error" (the simulation from the inputs) or "innovation" (the one-step predictor
        with its gain K free: the maximum-likelihood one when forces nobody measured act, as
        ``--refine-model``). Returns a new Result whose
        ``refinement`` holds the refined model and its modes with their standard deviations; a
        refinement that stops without converging gives an okid.RefinementWarning.

        The record goes in chunks (some 10-50 ms of work each): Ctrl-C raises KeyboardInterrupt
        between two, and progress(done, total), when given, is called after each with the samples
        fed and samples x max_passes; progress=True shows a bar on stderr instead (tqdm's when
        installed, else a plain line).
        """
        if self.decimation > 1:
            raise BadParameterError(f"refine() of a result with decimation = {self.decimation}: the refinement needs "
                                    f"the record at the model's sample interval; identify without decimation",
                                    E_BAD_PARAMETER)
        return self._refine(u, y, max_passes, step_tolerance, stacklevel=CALLER, progress=progress,
                            refine_model=refine_model)

    def _refine(self, u: Any, y: Any, max_passes: Any, step_tolerance: Any, stacklevel: int,
                progress: ProgressArg = None, refine_model: str = "output_error") -> "Result":
        passes, tol = check_settings(max_passes, step_tolerance)
        core, refined = _run_refinement((self.A, self.B, self.C, self.D), self.dt, self.config["sensing"], u, y,
                                        passes, tol, progress=progress, refine_model=refine_model)
        warn_if_stopped(refined, stacklevel + 1)
        start = self.start if self.start is not None else self
        # the refined modes and their warnings are the result; OKID/ERA's stay in start
        return replace(start, modes=refined.modes, warnings=WarningFlag(refined.warnings), refinement=refined,
                       fit_percent=refined.fit_percent, start=start, _refine_core=core)

    def to_frame(self) -> Any:
        """The modes as a pandas DataFrame, one row per mode (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("Result.to_frame() needs pandas (pip install pandas)") from e
        columns = ("frequency_hz", "damping_ratio", "emac", "emac_output", "emac_input", "mpc", "msv", "cmi",
                   "eigenvalue", "pole", "is_pair")
        return pd.DataFrame({c: [getattr(md, c) for md in self.modes] for c in columns},
                            index=pd.RangeIndex(1, len(self.modes) + 1, name="mode"))

    def stabilization(self, max_order: int, step: int = 2, *, frequency_tolerance: float = 0.01,
                      damping_tolerance: float = 0.05, mac_min: float = 0.98) -> Stabilization:
        """Stabilization diagram data for orders step, 2 step, ..., max_order (at most the Hankel
        size), from this result's Markov parameters. Available until the identifier that made this
        result identifies again or is reset (NotAvailableError afterwards, and for a detached Result)."""
        if self._identifier is None:
            raise error_for(E_NOT_AVAILABLE, "stabilization() of a detached Result (pickled, copied or loaded): "
                                             "identify again for the diagram")
        max_order, step = integer("max_order", max_order), integer("step", step)
        status, core = self._identifier.stabilization(self._generation, max_order, step,
                                                      float(frequency_tolerance), float(damping_tolerance),
                                                      float(mac_min))
        check(status, f"stabilization(max_order={max_order}, step={step}) (max_order 1.."
                      f"{len(self.singular_values)}, step 1..max_order; only for the identifier's latest result)")
        return Stabilization._from_core(core, max_order, step)


#: What the CLI's JSON lacks that a Result needs: its refinement's order, dt and cost.
_CLI_FALLBACKS: _document.Fallbacks = {
    "Refinement.order": lambda obj, outer: len(obj["A"]),
    "Refinement.dt": lambda obj, outer: outer["dt"],
    "Refinement.cost": lambda obj, outer: math.nan,
    # the residual tests (docs/refinement.md) sit in the CLI's "residual_tests" object, one entry per output
    "Refinement.whiteness": lambda obj, outer: [o["whiteness"] for o in obj["residual_tests"]["outputs"]],
    "Refinement.max_autocorrelation": lambda obj, outer: [o["max_autocorrelation"]
                                                          for o in obj["residual_tests"]["outputs"]],
    "Refinement.fit_percent": lambda obj, outer: [o["fit_percent"] for o in obj["residual_tests"]["outputs"]],
    "Refinement.output_warnings": lambda obj, outer: [o["warning_bits"] for o in obj["residual_tests"]["outputs"]],
    "Refinement.autocorrelation_band": lambda obj, outer: obj["residual_tests"]["autocorrelation_band"],
    # the cross-correlation test: one list per output (one value per input); -1 in documents written before it
    # (one -1 per input: the columns of the refined B)
    **{f"Refinement.{key}": (lambda key: lambda obj, outer: [o[key] if key in o else [-1.0] * len(obj["B"][0])
                                                            for o in obj["residual_tests"]["outputs"]])(key)
       for key in ("input_correlation", "max_input_correlation", "input_correlation_band")},
    # documents written before the innovation form: output error
    "Refinement.refine_model": lambda obj, outer: "output_error",
    # "split_modes" is written only with OKID_W_MODE_SPLIT
    "Refinement.split_modes": lambda obj, outer: None,
}


def load(path: Union[str, "os.PathLike[str]"]) -> Result:
    """The Result a file holds: one Result.save() wrote, or the output of ``okid identify --json``
    (with or without --refine). Detached: the same fields and to_dict(), no stabilization()."""
    return Result.from_dict(_document.load_json(path, "okid identify --json or Result.save()"))
