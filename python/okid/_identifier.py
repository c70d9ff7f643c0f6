# SPDX-License-Identifier: Apache-2.0
"""okid.identify() and okid.Identifier: the C identifier in-process. Time runs along axis 0; the
caller's arrays are read, never written; a C-contiguous float64 block goes to okid_push_block()
without a copy."""
from __future__ import annotations

import json
import warnings
from dataclasses import dataclass, fields, replace
from types import MappingProxyType
from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _config, _core
from ._config import DEFAULTS, Estimator, Realization, Scaling, Sensing
from ._errors import (E_BAD_PARAMETER, E_BAD_SIZE, E_NONFINITE_SAMPLE, E_NOT_AVAILABLE, E_NOT_ENOUGH_DATA, OK,
                      BadParameterError, BadSizeError, DecompositionError, NonFiniteSampleWarning,
                      NoOutputExplainedWarning, NotEnoughDataError, OkidError, check, error_for)
from ._mode import Mode, Pole, SelectedMode, WarningFlag
from ._progress import CALLER, ProgressArg, phase, reported, run_unchunked
from ._refine import REFINE_DEFAULTS, REFINE_MODELS, check_refine_model, check_settings
from ._result import Result
from ._stays_here import StaysHere
from .model import lift as _lift


@dataclass(frozen=True)
class Progress:
    """Counters of an Identifier."""
    samples: int      #: samples accepted since creation or reset
    rejected: int     #: samples rejected as non-finite
    rows: int         #: regressor rows folded into the least squares
    rows_needed: int  #: rows needed before identify() can succeed (the unknowns q)


def _block(values: Any, channels: int, name: str) -> np.ndarray:
    """values as a C-contiguous float64 (count, channels) array: no copy when it is one already."""
    a = _config.real_array(values, name)
    if a.ndim == 1 and channels == 1:
        a = a.reshape(-1, 1)
    if a.ndim != 2 or a.shape[1] != channels:
        hint = f" (pass {name}.T)" if a.ndim == 2 and a.shape[0] == channels else ""
        raise BadSizeError(f"{name} has shape {np.shape(values)}: expected (samples, {channels}) with time along "
                           f"axis 0{' or (samples,)' if channels == 1 else ''}{hint}", E_BAD_SIZE)
    return np.ascontiguousarray(a)


def _sample(values: Any, channels: int, name: str) -> np.ndarray:
    a = np.ascontiguousarray(_config.real_array(values, name).reshape(-1))
    if a.shape[0] != channels:
        raise BadSizeError(f"{name} has {a.shape[0]} values: one sample has {channels}", E_BAD_SIZE)
    return a


class Identifier(StaysHere):
    """A streaming OKID/ERA identifier: push samples or blocks as they come, identify at any time.

    ``Identifier(num_inputs, num_outputs, dt, **options)`` takes the okid_config options by their C
    names (see :func:`okid.identify`). One Identifier serves one thread at a time: a call from a
    second thread while one runs raises :class:`okid.ConcurrentUseError`. push() and identify()
    release the GIL, so identifiers in different threads run in parallel. Usable as a context
    manager (the workspace is freed at exit).
    """

    _HOLDS = ("the pushed samples", "pickle its Results, or push the same samples into an Identifier there")

    def __init__(self, num_inputs: int, num_outputs: int, dt: float, **options: Any):
        self._config = _config.build(num_inputs, num_outputs, dt, options)
        self.num_inputs: int = self._config["num_inputs"]
        self.num_outputs: int = self._config["num_outputs"]
        self.dt: float = self._config["dt"]  #: sample interval of the pushed data [s]
        self._core: Optional[Any] = _core.IdentifierCore()
        self._last: Optional[Result] = None
        check(self._core.init(self._config), "okid_init")

    @classmethod
    def _adopt(cls, num_inputs: int, num_outputs: int, dt: float, options: Dict[str, Any], core: Any) -> "Identifier":
        """An Identifier over a core the host library already identified with these options."""
        self = cls.__new__(cls)
        self._config = _config.build(num_inputs, num_outputs, dt, options)
        self.num_inputs, self.num_outputs, self.dt = num_inputs, num_outputs, self._config["dt"]
        self._core, self._last = core, None
        return self

    @property
    def config(self) -> Dict[str, Any]:
        """The okid_config in use: keyword names, enumerations by name."""
        out = dict(self._config)
        for name, values in _config.ENUMS.items():
            out[name] = next(k for k, v in values.items() if v == out[name])
        return out

    def _live(self):
        if self._core is None:
            raise ValueError("this Identifier is closed")
        return self._core

    @reported
    def push(self, u: Any, y: Any, *, progress: ProgressArg = None) -> int:
        """Push one sample (u: r values, y: m values) or a block (u: (count, r), y: (count, m)).

        A 2-D y is a block, anything else one sample. Samples holding NaN or Inf are rejected (a
        NonFiniteSampleWarning says how many), the regressor window restarts after them and
        everything learned before is kept. Returns the number of samples accepted.

        A block is folded in chunks (some 10-50 ms of work: 16384 samples for the paper's case, fewer
        for a wider regressor): Ctrl-C raises KeyboardInterrupt between two
        (the samples of the chunks done stay pushed: ``progress.samples`` counts them, and the
        identifier stays usable), and progress(done, count), when given, is called after each
        (progress=True: a bar on stderr, tqdm's when installed, else a plain line).
        """
        core = self._live()
        if np.ndim(y) == 2:
            ub = _block(u, self.num_inputs, "u")
            yb = _block(y, self.num_outputs, "y")
            if ub.shape[0] != yb.shape[0]:
                raise BadSizeError(f"u has {ub.shape[0]} samples and y {yb.shape[0]}: push equal counts", E_BAD_SIZE)
            status, accepted = core.push_block(ub, yb, phase(progress, "push"))
            count = ub.shape[0]
        else:
            status = core.push(_sample(u, self.num_inputs, "u"), _sample(y, self.num_outputs, "y"))
            count, accepted = 1, 1 if status == OK else 0
        if status == E_NONFINITE_SAMPLE:
            warnings.warn(f"{count - accepted} of {count} samples held NaN or Inf and were rejected",
                          NonFiniteSampleWarning, stacklevel=CALLER)
        elif status != OK:
            raise error_for(status, "push")
        return int(accepted)

    def identify(self) -> Result:
        """Identify from everything pushed so far; pushing can go on afterwards."""
        core = self._live()
        status, result = core.identify()
        if status == E_NOT_ENOUGH_DATA:
            p = self.progress
            raise error_for(status, f"{p.rows} regressor rows from {p.samples} samples, {p.rows_needed} needed "
                                    f"(q = r + (r + m) observer_order)")
        check(status, "identify")
        self._last = Result._from_core(result, self.config, core, core.generation)
        return self._last

    @reported
    def refine(self, u: Any, y: Any, *, max_passes: int = REFINE_DEFAULTS["max_passes"],
               step_tolerance: float = REFINE_DEFAULTS["step_tolerance"],
               progress: ProgressArg = None,
               refine_model: str = REFINE_DEFAULTS["refine_model"]) -> Result:
        """The last identify()'s result refined over the record (u, y) the caller gives: the
        samples that model describes, (N, r) and (N, m) at dt (the identifier keeps no record).
        See :meth:`okid.Result.refine`; a refinement that stops without converging warns
        (okid.RefinementWarning)."""
        if self._last is None:
            raise error_for(E_NOT_AVAILABLE, "refine() before identify(): nothing to refine")
        return self._last._refine(u, y, max_passes, step_tolerance, stacklevel=CALLER, progress=progress,
                                  refine_model=refine_model)

    def predict(self, u: Any) -> np.ndarray:
        """One-step-ahead prediction of y(k) (m values) from u(k) and the last observer_order samples,
        with the model of the last identify(). Call it before pushing sample k."""
        status, y = self._live().predict(_sample(u, self.num_inputs, "u"))
        check(status, "predict")
        return y

    def set_scales(self, input_scales: Any, output_scales: Any) -> None:
        """Channel scales of scaling="auto" given by the caller, before the first block is folded."""
        check(self._live().set_scales(_sample(input_scales, self.num_inputs, "input_scales"),
                                      _sample(output_scales, self.num_outputs, "output_scales")), "set_scales")

    def reset(self) -> None:
        """Forget every sample (the configuration stays)."""
        check(self._live().reset(), "reset")

    @property
    def progress(self) -> Progress:
        """Samples accepted and rejected, regressor rows and the rows needed."""
        status, samples, rejected, rows, needed = self._live().progress()
        check(status, "progress")
        return Progress(samples, rejected, rows, needed)

    def close(self) -> None:
        """Let go of the workspace: it is freed once no Result of this identifier refers to it
        (results keep it for stabilization()). Any later call raises ValueError."""
        self._core = None

    def __repr__(self) -> str:
        return (f"Identifier(num_inputs={self.num_inputs}, num_outputs={self.num_outputs}, dt={self.dt!r}, "
                f"observer_order={self._config['observer_order']}, order={self._config['order']})")


@reported
def identify(u: Any, y: Any, dt: float, *,
             observer_order: Optional[int] = None,
             order: int = DEFAULTS["order"],
             hankel_rows: Optional[int] = None,
             hankel_cols: Optional[int] = None,
             block_rows: int = DEFAULTS["block_rows"],
             forgetting_factor: float = DEFAULTS["forgetting_factor"],
             rank_tolerance: float = DEFAULTS["rank_tolerance"],
             sensing: Sensing = DEFAULTS["sensing"],
             realization: Realization = DEFAULTS["realization"],
             zero_initial_state: int = DEFAULTS["zero_initial_state"],
             decimation: Optional[int] = None,
             scaling: Scaling = DEFAULTS["scaling"],
             estimator: Estimator = DEFAULTS["estimator"],
             instrument_lags: int = DEFAULTS["instrument_lags"],
             refine: bool = False,
             max_passes: int = REFINE_DEFAULTS["max_passes"],
             step_tolerance: float = REFINE_DEFAULTS["step_tolerance"],
             refine_model: str = REFINE_DEFAULTS["refine_model"],
             progress: ProgressArg = None,
             decimation_method: str = "filter") -> Result:
    """Identify a state-space model and its modes from one record (OKID/ERA).

    u: forces, (N, r) or (N,) for one input; y: responses, (N, m) or (N,); time along axis 0.
    dt: sample interval [s]. The keywords are okid_config's fields with okid_config_default()'s
    defaults (docs/cli.md):

    observer_order: p, observer Markov parameters (1..1000; m p >= order); None: chosen from the
    data, half the slowest period (docs/quality.md section 8; with refine=True and no Hankel size
    either, by the start search below)
    order: model order n (states); 0: chosen with the physical modes: ``modes`` then holds the
    modes stable across orders and Hankel windows (okid.SelectedMode), ``poles`` every pole of the
    model with its verdict (okid.Pole), ``chosen`` each choice and its reason, as okid identify does;
    with refine=True, 0 takes the refinement's order and start from that selection (2 x the pairs
    kept, the selection's model truncated to them; ``chosen["order"]`` says how, docs/refinement.md)
    hankel_rows, hankel_cols: alpha, beta block rows/columns of the ERA Hankel matrix (1..1000);
    None: chosen from the data, three slowest periods (checked at two and four)
    block_rows: regressor rows folded per update (0 = automatic: 256, fewer for wide regressors)
    forgetting_factor: lambda in (0, 1] (0 reads as 1): a row k samples old weighs lambda^k
    rank_tolerance: relative tolerance of the rank-revealing least squares (0 = 1e-10)
    sensing: what y measures: "acceleration", "velocity" or "displacement" (sets the mode shapes' c)
    realization: "system" (robust default) or "combined" (also the observer gain G)
    zero_initial_state: 1 when the record starts at rest (uses its first samples with zero history)
    decimation: K, anti-alias filter and every K-th sample (1..64); the model's dt is K dt; None:
    chosen from the data (the filter's -3 dB point above 95 % of the outputs' energy; 1 with refine)
    scaling: "none" or "auto" (each channel divided by its RMS over the first block)
    estimator: "least_squares", "instrumental" (removes the bias of output noise) or "correlation"
    (least squares from Phi'Phi by Cholesky: half the flops; when its guard refuses, identified
    again with least_squares, Result.config says so and Result.warnings has CORRELATION_FALLBACK)
    instrument_lags: L of the instrumental estimator (0 = automatic)

    refine: also run the prediction-error (maximum-likelihood) refinement of the OKID/ERA model
    over the same record (``okid identify --refine``, docs/refinement.md): Result.refinement then
    holds the refined modes with the standard deviation of each (frequency_std [Hz], damping_std,
    eigenvalue_std, pole_std [1/s], sensor_shape_std). Not with decimation > 1. With none of
    observer_order, hankel_rows, hankel_cols given, the start is chosen from the data as the CLI
    does: OKID/ERA and a refinement from p in (10, 20, 40, 80) x alpha = beta in (20, 50, 100),
    cheap first, until two reach the same cost; the lowest cost wins, its settings are
    Result.config's and the starts tried Result.start_search (the JSON's "start_search").
    max_passes: with refine, passes over the record at most (2..1000, default 100)
    step_tolerance: with refine, converged when the Gauss-Newton decrement (about the squared step
    in standard deviations) falls below it (> 0, default 1e-6)
    decimation_method: with decimation K > 1, "filter" (the default: okid_config::decimation's
    anti-alias biquad, biased: about 1e-2 on noise-free data) or "lift" (okid.model.lift: K samples
    become one sample of K r inputs at K dt, exact; the result is that of the lifted record, its
    config's num_inputs K r, dt K dt, decimation 1; K r <= 64; ``--decimation-method``,
    docs/refinement.md). Lifting needs decimation given, and allows refine.
    refine_model: with refine, the predictor fitted: "output_error" (default, the simulation from
    the inputs), "innovation" (the one-step predictor with its gain K free, the
    maximum-likelihood one when forces nobody measured act; ``--refine-model``, docs/refinement.md)
    or "auto" (output error, and the innovation form when output error's residual is not white,
    kept only when its residual is white and its modes agree with output error's within 3
    combined standard deviations: Result.refine_model_choice says which and why)

    progress: called as progress(done, total) after each chunk (some 10-50 ms of work: 16384
    samples for the paper's case, fewer for larger problems), first of the push
    (samples folded of N), then of the refinement (samples fed of N x max_passes). Ctrl-C raises
    KeyboardInterrupt within one chunk, during the push and the refinement alike. With settings
    chosen from the data, the choice and the model (one C call without chunks) replace the push:
    progress(0, N) before it and (N, N) after; Ctrl-C during it raises KeyboardInterrupt within 0.1 s, while the
    choice runs on to its end in a background thread and is dropped. progress=True: a bar on
    stderr for each phase instead (tqdm's when tqdm is installed, else a plain line).

    Numbers are numbers: a count (observer_order, order, ..., max_passes) is an int or a float
    with an integral value (4.0 reads as 4), a real setting (dt, ...) an int or a float; bool,
    complex and str are refused with a TypeError, a fraction for a count with a ConfigurationError.

    Returns an immutable :class:`okid.Result`. Raises a :class:`okid.ConfigurationError` (a
    ValueError) naming a setting out of range, :class:`okid.NotEnoughDataError`,
    :class:`okid.NotPersistentlyExcitingError` for a force that does not excite the system.
    Samples with NaN or Inf are rejected with a NonFiniteSampleWarning. A refinement that stops
    without converging gives an :class:`okid.RefinementWarning`.
    """
    if refine is True and refine_model == "auto":
        settings = {k: v for k, v in locals().items() if k not in ("u", "y", "dt")}
        return _identify_choosing_the_model(u, y, dt, settings)
    # the settings not given are chosen from the data (docs/quality.md section 8), as okid identify does
    given = ((_core.AUTO_GIVEN_DECIMATION if decimation is not None else 0) |
             (_core.AUTO_GIVEN_OBSERVER if observer_order is not None else 0) |
             (_core.AUTO_GIVEN_HANKEL if hankel_rows is not None or hankel_cols is not None else 0))
    if decimation_method not in ("filter", "lift"):
        raise BadParameterError(f"decimation_method = {decimation_method!r}: 'filter' or 'lift' (default 'filter')",
                                E_BAD_PARAMETER)
    if decimation_method == "lift" and decimation is None:
        raise BadParameterError("decimation_method = 'lift' needs decimation = K (lifting does not follow a decimation "
                                "chosen from the data)", E_BAD_PARAMETER)
    if decimation is None:
        decimation = DEFAULTS["decimation"]
    lift_factor = _config.integer("decimation", decimation) if decimation_method == "lift" else 1
    if _config.check_bool("refine", refine):
        max_passes, step_tolerance = check_settings(max_passes, step_tolerance)
        refine_model = check_refine_model(refine_model, allow_auto=True)
        if decimation > 1 and lift_factor == 1:
            raise BadParameterError(f"refine=True with decimation = {decimation}: the refinement needs the record "
                                    f"at the model's sample interval; identify without decimation", E_BAD_PARAMETER)
    horizons_given = not (observer_order is None and hankel_rows is None and hankel_cols is None)
    options = dict(observer_order=observer_order, order=order, hankel_rows=hankel_rows, hankel_cols=hankel_cols,
                   block_rows=block_rows, forgetting_factor=forgetting_factor, rank_tolerance=rank_tolerance,
                   sensing=sensing, realization=realization, zero_initial_state=zero_initial_state,
                   decimation=decimation, scaling=scaling, estimator=estimator, instrument_lags=instrument_lags)
    for name in ("observer_order", "hankel_rows", "hankel_cols"):
        if options[name] is None:
            options[name] = DEFAULTS[name]
    ua = _config.real_array(u, "u")
    ya = _config.real_array(y, "y")
    r = 1 if ua.ndim == 1 else (ua.shape[1] if ua.ndim == 2 else -1)
    m = 1 if ya.ndim == 1 else (ya.shape[1] if ya.ndim == 2 else -1)
    if r < 0 or m < 0:
        raise BadSizeError(f"u has shape {ua.shape} and y {ya.shape}: expected (samples, channels) or (samples,)", E_BAD_SIZE)
    for name, a in (("u", ua), ("y", ya)):
        hint = _config.channels_first_hint(a.shape, name)
        if hint:
            raise BadSizeError(hint, E_BAD_SIZE)
    ub, yb = _block(ua, r, "u"), _block(ya, m, "y")
    if ub.shape[0] != yb.shape[0]:
        raise BadSizeError(f"u has {ub.shape[0]} samples and y {yb.shape[0]}: time along axis 0 must match", E_BAD_SIZE)
    if lift_factor > 1:  # the lifted record at K dt, identified undecimated (the CLI's --decimation-method lift)
        if lift_factor * r > 64:
            raise BadParameterError(f"decimation_method = 'lift' with decimation = {lift_factor} and {r} inputs: "
                                    f"{lift_factor * r} lifted inputs, at most 64", E_BAD_PARAMETER)
        ub, yb = _lift(ub, yb, lift_factor)
        r, dt = ub.shape[1], float(dt) * lift_factor
        options["decimation"] = decimation = 1
    # the data's sufficiency before the workspace is allocated (the CLI's rule, config_explain.c);
    # the start search tries smaller observer orders itself
    # (the settings chosen from the data are checked by auto_identify, after the choice)
    config = _config.build(r, m, dt, options)
    chosen_from_data = not refine and (given != _core.AUTO_GIVEN_ALL or options["order"] == 0) and \
        bool(np.isfinite(ub).all() and np.isfinite(yb).all())
    shortfall = _core.data_shortfall(config, ub.shape[0])
    if shortfall is not None and not (refine and not horizons_given) and not chosen_from_data:
        raise NotEnoughDataError(shortfall, E_NOT_ENOUGH_DATA)
    chosen = None
    if refine and options["order"] == 0:
        # okid identify --refine without --order: the order and start from the physical-mode selection
        # (host_tools/common/refine_selection.c); none kept: NotAvailableError, as the CLI refuses
        return _refined_from_selection(config, given, ub, yb, r, m, dt, options, max_passes, step_tolerance,
                                       refine_model, progress)
    search = None
    if refine and not horizons_given:
        # okid identify --refine's own start search (host_tools/common/start_search.c), each start
        # refined with these max_passes, step_tolerance and refine_model, quietly
        chosen, search_json = _core.start_search(config, ub, yb, max_passes, step_tolerance,
                                                 REFINE_MODELS[check_refine_model(refine_model)])
        options.update(chosen)
        search = json.loads("{" + search_json.lstrip().lstrip(",") + "}")["start_search"]
    if chosen_from_data:
        # okid identify's own automatic identification (host_tools/common/auto_identify.c): the
        # settings, the physical modes and the model, identified once (the correlation form's
        # fallback to the QR fold included)
        status, settings, auto_json, selected, verdicts, model = _choose(config, given, ub, yb, progress)
        if status == E_NOT_ENOUGH_DATA and auto_json is not None:  # the host library's refusal (config_explain.c)
            raise NotEnoughDataError(auto_json, E_NOT_ENOUGH_DATA)
        check(status, "identify")
        user_order = options["order"]
        code = settings.pop("estimator")  # least_squares after the fallback
        options.update(settings, estimator=next(k for k, v in _config.ENUMS["estimator"].items() if v == code))
        identifier = Identifier._adopt(r, m, dt, options, model[0])
        model[1].measure_fit(ub, yb)  # as okid identify: the fit of each output, its warning
        result = Result._from_core(model[1], identifier.config, model[0], model[0].generation)
        return _warn_if_unexplained(_with_choices(result, user_order, auto_json, selected, verdicts), CALLER)
    identifier = Identifier(r, m, dt, **options)
    status, accepted = identifier._core.push_block(ub, yb, phase(progress, "push"))
    if status == E_NONFINITE_SAMPLE:
        warnings.warn(f"{ub.shape[0] - accepted} of {ub.shape[0]} samples held NaN or Inf and were rejected",
                      NonFiniteSampleWarning, stacklevel=CALLER)
    elif status != OK:
        raise error_for(status, "push")
    try:
        result = identifier.identify()
    except DecompositionError:
        if options["estimator"] != "correlation":
            raise
        # the correlation form's guard refused (okid_estimator in okid/identifier.h): the record is
        # at hand, so identify it again with the QR fold and say so (as the CLI does)
        options = dict(options, estimator="least_squares")
        identifier = Identifier(r, m, dt, **options)
        identifier._core.push_block(ub, yb)
        result = identifier.identify()
        result = replace(result, warnings=result.warnings | WarningFlag.CORRELATION_FALLBACK)
    if not refine:
        return _warn_if_unexplained(_measured(result, ub, yb), CALLER)
    refined = replace(result._refine(ub, yb, max_passes, step_tolerance, stacklevel=CALLER, progress=progress,
                                     refine_model=refine_model), start_search=search)
    return refined if chosen is None else replace(refined, chosen=chosen)


def _chosen(member: str) -> MappingProxyType:
    """The JSON member ',\n  "chosen": {...}' of the host library as Result.chosen."""
    doc = json.loads("{" + member.lstrip().lstrip(",") + "}")["chosen"]
    return MappingProxyType({k: MappingProxyType(v) if isinstance(v, dict) else v for k, v in doc.items()})


def _refined_from_selection(config, given, ub, yb, r, m, dt, options, max_passes, step_tolerance, refine_model,
                            progress) -> Result:
    """refine=True without order (okid identify --refine without --order): the selection on this record
    (its decimation kept), its model truncated to the pairs kept (refine_selection.h), refined from there,
    with ``chosen``. No pair kept: NotAvailableError (no start; the CLI's refusal and advice)."""
    status, order, reason, member, settings, start, model = _core.refine_selection(
        config, given | _core.AUTO_GIVEN_DECIMATION, ub, yb)
    check(status, "identify (the physical-mode selection of refine=True without order)")
    chosen = _chosen(member)
    if order == 0:
        decimation = max(int(options.get("decimation") or 1), 1)
        raise error_for(E_NOT_AVAILABLE,
            f"refine=True without order: the mode selection keeps no physical mode on the record the refinement "
            f"fits (dt = {float(dt) * decimation:g} s, decimation {decimation}): {reason}, so there is no start to "
            f"refine; without refine the decimation is chosen from the data and may find them; to refine anyway give "
            f"order (2 per mode) and observer_order/hankel_rows/hankel_cols (in samples)")
    code = settings.pop("estimator")  # least_squares after the correlation form's fallback
    options = dict(options, **settings, estimator=next(k for k, v in _config.ENUMS["estimator"].items() if v == code))
    identifier = Identifier._adopt(r, m, dt, options, model[0])
    selection = Result._from_core(model[1], identifier.config, model[0], model[0].generation)
    a, b, c, d, g, poles = start
    truncated = replace(selection, order=order, A=a, B=b, C=c, D=d, G=g, modes=tuple(selection.modes[i] for i in poles),
                        config=MappingProxyType({**selection.config, "order": 0}))
    refined = truncated._refine(ub, yb, max_passes, step_tolerance, stacklevel=CALLER + 1, progress=progress,
                                refine_model=refine_model)
    return replace(refined, chosen=chosen)


def _identify_choosing_the_model(u: Any, y: Any, dt: Any, settings: Dict[str, Any]) -> Result:
    """okid.identify(refine=True, refine_model="auto"), as okid identify --refine-model auto (the
    host library's rule, host_tools/common/refine_choice.c): output error first; the innovation form
    too when output error's residual is not white; the result is the chosen one's, with
    Result.refine_model_choice; the warnings are the chosen run's (a drift keeps output error's)."""
    def run(model: str):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = identify(u, y, dt, **{**settings, "refine_model": model})
        return result, caught
    oe, oe_warnings = run("output_error")
    chosen, chosen_warnings = oe, oe_warnings
    if _core.refine_needs_innovation(oe._refine_core):
        try:
            inn, inn_warnings = run("innovation")
        except OkidError:  # the innovation form failed: nothing to compare, output error stays
            inn = None
        model, reason, detail = _core.refine_choose(oe._refine_core, None if inn is None else inn._refine_core)
        if model == "innovation":
            chosen, chosen_warnings = inn, inn_warnings
    else:
        model, reason, detail = _core.refine_choose(oe._refine_core, None)
    for w in chosen_warnings:
        warnings.warn(w.message, stacklevel=CALLER + 1)
    choice = MappingProxyType({"requested": "auto", "chosen": model, "reason": reason, "detail": detail})
    return replace(chosen, refine_model_choice=choice)


def _measured(result: Result, u: np.ndarray, y: np.ndarray) -> Result:
    """The result with the fit of each output over the record it came from, and its warning (the
    host library's output_fit.c, as okid identify)."""
    if not result._core.measure_fit(u, y):
        return result
    f = result._core.fields()
    return replace(result, fit_percent=f["fit_percent"], warnings=result.warnings | WarningFlag(f["warnings"]))


def _warn_if_unexplained(result: Result, stacklevel: int) -> Result:
    """The NoOutputExplainedWarning of a result with WarningFlag.NO_OUTPUT_EXPLAINED (the CLI's
    "warning:" line, with each output's fit); stacklevel: the caller's, from this function's caller."""
    if result.warnings & WarningFlag.NO_OUTPUT_EXPLAINED:
        fits = ", ".join(f"{v:.3g} %" for v in result.fit_percent)
        warnings.warn(f"the model explains less than half of every output (fit_percent {fits}, each below 50 %): "
                      f"pure noise, a force that does not drive the outputs, or the wrong columns; its modes "
                      f"describe nothing measured", NoOutputExplainedWarning, stacklevel=stacklevel + 1)
    return result


def _choose(config: Dict[str, Any], given: int, ub: np.ndarray, yb: np.ndarray, progress: Any) -> Tuple[Any, ...]:
    """_core.auto_identify (the settings, the physical modes and the model chosen from the data: one
    C call, its push without a progress callback since it runs in a thread) so that Ctrl-C stops the
    wait; progress sees (0, N) and (N, N) around it."""
    return run_unchunked(_core.auto_identify, (config, given, ub, yb, None), progress,
                             "choosing the settings from the data", ub.shape[0])


def _with_choices(result: Result, user_order: int, auto_json: str, selected, verdicts) -> Result:
    """The result with the settings chosen from the data and, with the order chosen, the physical
    modes as ``modes`` and every pole with its verdict as ``poles``."""
    doc = json.loads("{" + auto_json.lstrip().lstrip(",") + "}")
    chosen = MappingProxyType({k: MappingProxyType(v) if isinstance(v, dict) else v for k, v in doc["chosen"].items()})
    config = MappingProxyType({**result.config, "order": user_order})
    if selected is None:
        return replace(result, chosen=chosen, config=config, _auto_json=auto_json)
    modes = tuple(SelectedMode(**d) for d in selected)
    poles = tuple(Pole(**{f.name: getattr(md, f.name) for f in fields(Mode)}, verdict="rejected" if why else "physical",
                       reason=why) for md, why in zip(result.modes, verdicts))
    return replace(result, modes=modes, poles=poles, chosen=chosen, config=config, _auto_json=auto_json)
