# SPDX-License-Identifier: Apache-2.0
"""The prediction-error refinement (docs/refinement.md) and the Cramér–Rao bound: the library's
okid_refine_* API over the caller's arrays, fed once per pass without a copy."""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Tuple, Union

import numpy as np

from . import _core, _document
from . import model as _model_mod
from ._config import SENSING, Sensing, integer, real_array, real_number
from ._errors import (E_BAD_PARAMETER, E_BAD_SIZE, E_DATA_RANGE, E_NONFINITE_SAMPLE, E_RANK_DEFICIENT, OK,
                      BadParameterError, BadSizeError, NonFiniteSampleError, NotPersistentlyExcitingError, OkidWarning,
                      check)
from ._document import Travelling
from ._mode import Mode, ModeArrays, WarningFlag, modes_from_dicts
from ._progress import ProgressArg, phase
from ._statespace import StateSpaceModel


_MAX_PASSES, _STEP_TOLERANCE = _core.refine_config_default()
#: okid_refine_config_default()'s values (docs/cli.md: --max-passes, --step-tolerance).
REFINE_DEFAULTS: Dict[str, Any] = {"max_passes": _MAX_PASSES, "step_tolerance": _STEP_TOLERANCE,
                                   "refine_model": "output_error"}
#: okid_refine_model's names (--refine-model, docs/refinement.md) and C values
REFINE_MODELS: Dict[str, int] = {"output_error": 0, "innovation": 1}


class RefinementWarning(OkidWarning, RuntimeWarning):
    """A refinement stopped without converging (diverged, not improving, or max_passes reached):
    its modes are the best found (diverged: OKID/ERA's, with std -1), not the maximum-likelihood ones."""


class _ModeArrays(ModeArrays):
    """ModeArrays with the standard deviations (for a refinement the estimate's, for a Cramer-Rao
    bound the bound's)."""

    @property
    def frequency_std(self) -> np.ndarray:
        """One standard deviation of every frequency [Hz]."""
        return self._column("frequency_std")

    @property
    def damping_std(self) -> np.ndarray:
        """One standard deviation of every damping ratio [-]."""
        return self._column("damping_std")


@dataclass(frozen=True, eq=False)
class Refinement(_ModeArrays, StateSpaceModel, Travelling):
    """An okid_refine_result: the refined model in real modal form, its modes with their standard
    deviations, and how the refinement ended. Every array is a read-only copy."""
    state: str                      #: "converged", "diverged", "not_improving" or "iteration_limit"
    message: str                    #: the library's sentence for the state
    passes: int                     #: passes fed over the record (the first measures the channel weights)
    iterations: int                 #: accepted Levenberg–Marquardt steps
    num_parameters: int             #: free parameters, n (r + m + 1) + m r at most (+ n m for the innovation form)
    order: int                      #: n
    samples: int                    #: samples per pass
    dt: float                       #: sample interval [s]
    cost: float                     #: final negative log-likelihood (lower is more likely; nan when diverged)
    decrement: float                #: Gauss-Newton decrement at the returned model (below step_tolerance when converged; -1: singular)
    warnings: int                   #: okid_warning bits of the refined modes (see okid.WarningFlag)
    max_passes: int                 #: the setting it ran with
    step_tolerance: float           #: the setting it ran with
    refine_model: str               #: the predictor fitted: "output_error" or "innovation" (the setting it ran with)
    A: np.ndarray                   #: (n, n) real modal form
    B: np.ndarray                   #: (n, r)
    C: np.ndarray                   #: (m, n)
    D: np.ndarray                   #: (m, r)
    K: Optional[np.ndarray]         #: (n, m) innovation gain of refine_model "innovation", None otherwise
    initial_state: np.ndarray       #: (n,) estimated x(0)
    residual_rms_start: np.ndarray  #: (m,) residual RMS of each output with the starting model [output units]
    residual_rms: np.ndarray        #: (m,) the same with the refined model
    whiteness: np.ndarray           #: (m,) Ljung-Box Q of each output's residual over 20 lags (white below 45.3)
    max_autocorrelation: np.ndarray #: (m,) largest |normalised autocorrelation| of each residual, lags 1..20
    fit_percent: np.ndarray         #: (m,) 100 (1 - |e| / |y - mean y|) of each output [%]
    #: (m, r) the input-residual cross-correlation statistic of each (output, input) pair:
    #: max |rho(l)| sqrt(N / v) over lags 0..19 (uncorrelated below 4.0556; -1: not computable)
    input_correlation: np.ndarray
    max_input_correlation: np.ndarray   #: (m, r) largest |normalised cross-correlation|, lags 0..19
    input_correlation_band: np.ndarray  #: (m, r) the band of each |rho(l)|: 4.0556 sqrt(v / N)
    #: (m,) RESIDUAL_NOT_WHITE / RESIDUAL_INPUT_CORRELATED / OUTPUT_NOT_EXPLAINED of each output
    output_warnings: Tuple[WarningFlag, ...]
    autocorrelation_band: float     #: 1.96 / sqrt(N), the 95 % band of each autocorrelation of a white residual
    std_covariance: str             #: "fisher", or "sandwich" when a residual is not white
    #: MODE_SPLIT: the indices into modes of two pairs that are one mode split in two, else None
    split_modes: Optional[Tuple[int, int]]
    modes: Tuple[Mode, ...]         #: okid.Mode with frequency_std, damping_std, ... set; sorted by frequency

    @property
    def converged(self) -> bool:
        """The refinement converged: its modes are the maximum-likelihood ones."""
        return self.state == "converged"



def _refinement(core) -> Refinement:
    f = core.fields()
    f.pop("std_status")  # okid.crlb's refusal (std_reason); a refinement's missing stds are -1
    modes = modes_from_dicts(f.pop("modes"))
    f["output_warnings"] = tuple(WarningFlag(w) for w in f["output_warnings"])
    return Refinement(**f, modes=modes)


def check_settings(max_passes: Any, step_tolerance: Any) -> Tuple[int, float]:
    """The CLI's ranges: --max-passes 2..1000, --step-tolerance > 0 (finite)."""
    passes = integer("max_passes", max_passes)
    if not 2 <= passes <= 1000:
        raise BadParameterError(f"max_passes = {max_passes!r}: an integer in 2..1000 (default {_MAX_PASSES})",
                                E_BAD_PARAMETER)
    try:
        tol = real_number("step_tolerance", step_tolerance)
    except BadParameterError:
        tol = math.nan
    if not (math.isfinite(tol) and tol > 0):
        raise BadParameterError(f"step_tolerance = {step_tolerance!r}: a finite number > 0 (default {_STEP_TOLERANCE:g})",
                                E_BAD_PARAMETER)
    return passes, tol


def check_refine_model(refine_model: Any, allow_auto: bool = False) -> str:
    """refine_model's names: "output_error" (the default) or "innovation"; with allow_auto (okid.identify,
    as okid identify --refine-model) also "auto", the choice from the residual test."""
    if allow_auto and refine_model == "auto":
        return refine_model
    if not isinstance(refine_model, str) or refine_model not in REFINE_MODELS:
        auto = ", 'auto'" if allow_auto else ""
        where = "" if allow_auto else "; 'auto' in okid.identify"
        raise BadParameterError(f"refine_model = {refine_model!r}: one of {', '.join(map(repr, REFINE_MODELS))}{auto} "
                                f"(default 'output_error'{where})", E_BAD_PARAMETER)
    return refine_model


def _record(u: Any, y: Any, r: int, m: int) -> Tuple[np.ndarray, np.ndarray]:
    ua = np.ascontiguousarray(real_array(u, "u"))
    ya = np.ascontiguousarray(real_array(y, "y"))
    if ua.ndim == 1 and r == 1:
        ua = ua.reshape(-1, 1)
    if ya.ndim == 1 and m == 1:
        ya = ya.reshape(-1, 1)
    if ua.ndim != 2 or ua.shape[1] != r or ya.ndim != 2 or ya.shape[1] != m or ua.shape[0] != ya.shape[0]:
        raise BadSizeError(f"u has shape {np.shape(u)} and y {np.shape(y)}: expected ({len(ua)}, {r}) and "
                           f"({len(ua)}, {m}), time along axis 0", E_BAD_SIZE)
    return ua, ya


def _model(a, b, c, d) -> Tuple[np.ndarray, ...]:
    a = np.ascontiguousarray(real_array(a, "A"))
    n = a.shape[0] if a.ndim == 2 else -1
    if n < 1 or a.shape != (n, n):
        raise BadSizeError(f"A has shape {a.shape}: expected (n, n)", E_BAD_SIZE)
    b = real_array(b, "B")
    if b.size == 0 or b.size % n != 0 or b.ndim > 2 or (b.ndim == 2 and b.shape[0] != n):
        raise BadSizeError(f"B has shape {b.shape}: expected ({n}, r) for the {n} states of A", E_BAD_SIZE)
    b = np.ascontiguousarray(np.reshape(b, (n, -1)))
    c = np.ascontiguousarray(real_array(c, "C"))
    if c.ndim != 2 or c.shape[1] != n:
        raise BadSizeError(f"C has shape {c.shape}: expected (m, {n})", E_BAD_SIZE)
    d = real_array(d, "D")
    if d.size != c.shape[0] * b.shape[1] or (d.ndim == 2 and d.shape != (c.shape[0], b.shape[1])):
        raise BadSizeError(f"D has shape {d.shape}: expected ({c.shape[0]}, {b.shape[1]}) (m outputs of C, r inputs "
                           f"of B)", E_BAD_SIZE)
    d = np.ascontiguousarray(np.reshape(d, (c.shape[0], b.shape[1])))
    return a, b, c, d


def run(model, dt: float, sensing: str, u: Any, y: Any, max_passes: int, step_tolerance: float,
        noise_std: Optional[np.ndarray] = None, what: str = "refine", progress: ProgressArg = None,
        refine_model: str = "output_error"):
    """okid_refine_* over the record: (RefineCore, Refinement). Ctrl-C raises KeyboardInterrupt
    within one chunk; progress(done, total) follows the samples fed."""
    a, b, c, d = _model(*model)
    ua, ya = _record(u, y, b.shape[1], c.shape[0])
    status, core = _core.refine(a, b, c, d, float(dt), SENSING[sensing], ua, ya, max_passes, step_tolerance,
                                noise_std, phase(progress, "refinement"), REFINE_MODELS[check_refine_model(refine_model)])
    check(status, f"{what} (n = {a.shape[0]}, r = {b.shape[1]}, m = {c.shape[0]}, {ua.shape[0]} samples: more "
                  f"output samples than parameters, finite inputs)")
    return core, _refinement(core)


class ResidualWarning(OkidWarning, RuntimeWarning):
    """A refined output's residual failed a test (Refinement.output_warnings): not white (a force
    nobody measured, a drift, too low an order: the stds are then the sandwich ones) or less than
    half of the output explained."""


class ResidualInputCorrelatedWarning(ResidualWarning):
    """A refined output's residual is correlated with an input (WarningFlag.RESIDUAL_INPUT_CORRELATED,
    Refinement.input_correlation above 4.0556): the model misses some of the input's dynamics (too
    low an order, a wrong D)."""


class ModeSplitWarning(RefinementWarning):
    """Two refined pairs are one mode split in two (WarningFlag.MODE_SPLIT, Refinement.split_modes):
    the same sensor shape and frequencies their gates or standard deviations do not tell apart; the
    order is higher than the record supports there (docs/refinement.md, "One mode split in two")."""


#: OKID_REFINE_INPUT_CORRELATION_BOUND (okid/refine.h)
INPUT_CORRELATION_BOUND = 4.0556


def iteration_limit_advice(decrement: float, step_tolerance: float, iterations: int) -> str:
    """What to do about a refinement stopped at max_passes (the CLI's stderr line)."""
    if decrement < 0 and iterations == 0:
        return "no step was accepted: check the start (order, horizons)"
    if decrement < 0:
        return ("the Gauss-Newton matrix is singular at the best model: the record does not determine every parameter "
                "(fewer states, or fewer inputs than the lifted record's)")
    if decrement < 100 * step_tolerance:
        return (f"the last step's decrement {decrement:.3g} is within 100x the tolerance {step_tolerance:.3g}: raise "
                f"max_passes (the modes move by about {math.sqrt(decrement):.2g} standard deviations)")
    return (f"the last step's decrement {decrement:.3g} is {decrement / step_tolerance:.3g} times the tolerance "
            f"{step_tolerance:.3g} (steps of about {math.sqrt(decrement):.2g} standard deviations): more passes may not "
            f"help; if a residual is not white the model does not describe the record (order, drift, a force nobody "
            f"measured: refine_model='innovation')")


def warn_if_stopped(refined: Refinement, stacklevel: int) -> None:
    """The RefinementWarning of a refinement that did not converge and the ResidualWarning of
    each failed residual test (the CLI's stderr lines)."""
    for i, w in enumerate(refined.output_warnings):
        if w & WarningFlag.RESIDUAL_NOT_WHITE:
            warnings.warn(f"output {i + 1}: the refined residual is not white (Ljung-Box Q {refined.whiteness[i]:.4g} "
                          f"above 45.31, autocorrelation up to {refined.max_autocorrelation[i]:.3g} against the band "
                          f"{refined.autocorrelation_band:.3g}): a force nobody measured, a drift or too low an order; "
                          f"the stds are the sandwich ones", ResidualWarning, stacklevel=stacklevel + 1)
        if w & WarningFlag.RESIDUAL_INPUT_CORRELATED:
            # one warning per output however many inputs failed (a lifted record has K r): the worst in full
            stats = np.asarray(refined.input_correlation)[i]
            failed = np.flatnonzero(stats > INPUT_CORRELATION_BOUND)
            if failed.size:
                j = int(failed[np.argmax(stats[failed])])
                others = [int(k) + 1 for k in failed if k != j]
                more = (f" and with {len(others)} more input{'s' if len(others) > 1 else ''} ("
                        f"{', '.join(map(str, others[:6]))}{', ...' if len(others) > 6 else ''})") if others else ""
                warnings.warn(f"output {i + 1}: the refined residual is correlated with input {j + 1} (cross-correlation "
                              f"up to {refined.max_input_correlation[i][j]:.3g} against the band "
                              f"{refined.input_correlation_band[i][j]:.3g} over lags 0..19, statistic "
                              f"{refined.input_correlation[i][j]:.3g} above {INPUT_CORRELATION_BOUND:.4g}){more}: the "
                              f"model misses some of the input's dynamics (too low an order, a wrong D)",
                              ResidualInputCorrelatedWarning, stacklevel=stacklevel + 1)
        if w & WarningFlag.OUTPUT_NOT_EXPLAINED:
            warnings.warn(f"output {i + 1}: the refined model explains {refined.fit_percent[i]:.3g} % of it (below "
                          f"50 %): a drift, an offset, a force nobody measured or a sensor the model does not "
                          f"describe", ResidualWarning, stacklevel=stacklevel + 1)
    if refined.split_modes is not None:
        a, b = (refined.modes[i] for i in refined.split_modes)
        warnings.warn(f"the refined pairs {a.frequency_hz:.4g} Hz (damping {a.damping_ratio:.3g}) and "
                      f"{b.frequency_hz:.4g} Hz (damping {b.damping_ratio:.3g}) are one mode split in two: order "
                      f"{refined.order} is higher than the record supports there; give a lower order (2 per mode) "
                      f"or leave the order to the mode selection", ModeSplitWarning, stacklevel=stacklevel + 1)
    if refined.state == "iteration_limit":
        warnings.warn(f"the refinement did not converge ({refined.message} after {refined.passes} passes): the modes "
                      f"are the best found; {iteration_limit_advice(refined.decrement, refined.step_tolerance, refined.iterations)}",
                      RefinementWarning, stacklevel=stacklevel + 1)
    elif not refined.converged:
        tail = ": the modes are OKID/ERA's" if refined.state == "diverged" else ": the modes are the best found"
        warnings.warn(f"the refinement did not converge ({refined.message} after {refined.passes} passes){tail}",
                      RefinementWarning, stacklevel=stacklevel + 1)


@dataclass(frozen=True, eq=False)
class CramerRaoBound(_ModeArrays, Travelling):
    """The Cramér–Rao lower bound of a planned (or performed) experiment: the standard deviation
    below which no unbiased estimate of a mode's frequency or damping ratio can go."""
    modes: Tuple[Mode, ...]    #: the model's modes (okid.Mode), their *_std fields the bound
    noise_std: np.ndarray      #: (m,) the output noise standard deviations used [output units]
    num_parameters: int        #: parameters of the model class (order n with feedthrough and x(0)) [counts]
    samples: int               #: N [samples]

    def to_dict(self) -> Dict[str, Any]:
        """The bound as a JSON object: its fields by name (arrays as lists, complex as [re, im])."""
        return _document.encode(self)

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Write the bound to path as JSON (format CRLB_FORMAT, version CRLB_FORMAT_VERSION:
        docs/python.md); CramerRaoBound.load(path) gives it back equal. An existing file is
        refused (FileExistsError)."""
        _document.save(self, self.to_dict(), path, CRLB_FORMAT, CRLB_FORMAT_VERSION)

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "CramerRaoBound":
        """The bound from CramerRaoBound.save()'s (or to_dict()'s) object."""
        document, extra = _document.open_document(document, CRLB_FORMAT, CRLB_FORMAT_VERSION,
                                                  f"okid.CramerRaoBound.load reads {CRLB_FORMAT!r} files",
                                                  default_format=CRLB_FORMAT)
        return _document.read(cls, _document.merged(document, extra))

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "CramerRaoBound":
        """The bound a file holds (CramerRaoBound.save()'s)."""
        return cls.from_dict(_document.load_json(path, "CramerRaoBound.save()"))


#: CramerRaoBound.save()'s file: "format", "format_version", then the bound's fields.
CRLB_FORMAT = "okid.CramerRaoBound"
CRLB_FORMAT_VERSION = 1


#: why okid_refine_result::std_status is not OKID_OK (the words of okid crlb's refusal)
_STD_REASONS = {
    E_RANK_DEFICIENT: "the Fisher information is singular: the record does not determine the model's parameters "
                      "(a constant or too short force, a mode the force does not excite or the outputs do not see)",
    E_DATA_RANGE: "a mode has no continuous-time pole (a real non-positive eigenvalue) or its standard deviation "
                  "is not a finite number",
}


def crlb(u: Any, dt: float, *, model: Optional[Tuple[Any, Any, Any, Any]] = None, noise: Optional[float] = None,
         noise_std: Any = None, sensing: Sensing = "acceleration") -> CramerRaoBound:
    """The Cramér–Rao lower bound of the natural frequencies and damping ratios of a model driven by
    the force record u, with white Gaussian output noise.

    u: (N, r) forces (or (N,)), time along axis 0; dt: sample interval [s]. model: (A, B, C, D),
    discrete time at dt, starting at rest (default: okid.model.paper_system(dt, sensing)). The noise,
    one of: noise = F > 0, each output's standard deviation F times the RMS of its noise-free
    response (as ``okid crlb --noise F``); noise_std = the standard deviation of each output (m
    values or one for all) [output units]. sensing: what the outputs measure ("acceleration",
    "velocity", "displacement"), for the mode shapes.

    The bound is for the model class the refinement estimates (order n, feedthrough, unknown x(0)):
    the library refines the true model over its noise-free response with the noise fixed
    (okid_refine_set_noise): one pass, whose inverse Fisher information is the bound in closed form.
    """
    if sensing not in SENSING:
        raise BadParameterError(f"sensing = {sensing!r}: 'acceleration', 'velocity' or 'displacement'", E_BAD_PARAMETER)
    if (noise is None) == (noise_std is None):
        raise BadParameterError("give exactly one of noise (relative to each output's RMS) and noise_std", E_BAD_PARAMETER)
    dt = real_number("dt", dt)
    if not (math.isfinite(dt) and dt > 0):
        raise BadParameterError(f"dt = {dt!r}: a finite sample interval > 0 [s]", E_BAD_PARAMETER)
    if model is None:
        # the paper's continuous modes: one whose damped frequency reaches Nyquist aliases at this dt
        poles = np.linalg.eigvals(_model_mod._paper_continuous(sensing)[0])
        fastest = poles[np.argmax(np.abs(poles.imag))]
        damped, natural = abs(fastest.imag) / (2 * math.pi), abs(fastest) / (2 * math.pi)
        fastest = float(np.max(np.abs(poles))) / (2 * math.pi)  # the natural frequency, as okid crlb's
        if damped >= 0.5 / dt:
            raise BadParameterError(f"dt = {dt!r}: the paper system's mode of natural frequency {natural:.6g} Hz "
                                    f"(damped {damped:.6g} Hz) is at or above the Nyquist frequency 1/(2 dt) = "
                                    f"{0.5 / dt:.6g} Hz and aliases at this dt: its bound would be another mode's; "
                                    f"give dt below {0.5 / damped:.6g} s", E_BAD_PARAMETER)
    whose = "the model's" if model is not None else "the paper system's"
    a, b, c, d = _model(*(model if model is not None else _model_mod.paper_system(dt, sensing)))
    m = c.shape[0]
    ua, _ = _record(u, np.zeros((np.shape(u)[0], m)), b.shape[1], m)
    bad = np.flatnonzero(~np.isfinite(ua).all(axis=1))
    if bad.size:
        raise NonFiniteSampleError(f"u holds NaN or Inf at sample {bad[0]} ({bad.size} of {len(ua)} samples): the "
                                   f"bound needs a finite force record", E_NONFINITE_SAMPLE)
    # okid crlb's causes (host_tools/cli/crlb_command.c): a record shorter than one period of the
    # fastest mode determines no mode, whatever else then fails
    if model is not None:
        fastest = _fastest_mode_hz(a, dt)
    short = fastest > 0 and len(ua) * dt * fastest < 1
    period = f"less than one period of {whose} fastest mode ({1 / fastest:g} s at {fastest:.6g} Hz)" if short else ""
    no_mode = (f"cannot compute the bound: the record spans {len(ua) * dt:g} s ({len(ua)} samples of dt {dt:g} s), "
               f"{period}: no mode is determined; give a larger dt or more samples")
    y, _ = _model_mod.simulate(a, b, c, d, ua)
    if noise is not None:
        noise = real_number("noise", noise)
        if not (math.isfinite(noise) and noise > 0):
            raise BadParameterError(f"noise = {noise!r}: F > 0, the noise std relative to each output's RMS",
                                    E_BAD_PARAMETER)
        sigma = float(noise) * np.sqrt(np.mean(y * y, axis=0))
        silent = np.flatnonzero(~(sigma > 0))
        if silent.size and short:
            raise BadParameterError(no_mode, E_BAD_PARAMETER)
        if silent.size:
            raise BadParameterError(f"output {silent[0] + 1} is zero over the record's {len(ua)} sample(s): the noise, "
                                    f"noise = {noise:g} times its RMS, is 0 and bounds nothing; the force u does not "
                                    f"reach it (a zero force, or C and D that do not see it)", E_BAD_PARAMETER)
    else:
        given = real_array(noise_std, "noise_std").reshape(-1)
        if given.size not in (1, m):
            raise BadSizeError(f"noise_std has {given.size} values: one per output ({m}) or one for all", E_BAD_SIZE)
        sigma = np.broadcast_to(given, (m,)).copy()
        if not np.all(np.isfinite(sigma) & (sigma > 0)):
            raise BadParameterError(f"noise_std = {sigma.tolist()}: every value finite and > 0 [output units]",
                                    E_BAD_PARAMETER)
    sigma = np.ascontiguousarray(sigma)
    try:
        core, bound = run((a, b, c, d), dt, sensing, ua, y, 2, _STEP_TOLERANCE, sigma, what="crlb")
    except NotPersistentlyExcitingError:
        if not short:
            raise
        raise BadParameterError(no_mode, E_BAD_PARAMETER) from None
    # the one Jacobian pass at the exact model is the bound whatever the state (okid crlb's rule,
    # crlb_command.c: bound_pass_is_the_models): accepted and reproducing the record to round-off
    rms_y = np.sqrt(np.mean(y * y, axis=0))
    exact = bound.converged or (bound.state == "iteration_limit"
                                and bool(np.all((bound.residual_rms > 0) & (bound.residual_rms <= 1e-6 * rms_y))))
    modes = _bound_causes(a, dt)
    if not exact:
        if short:
            raise BadParameterError(no_mode, E_BAD_PARAMETER)
        if modes["modulus"] >= _MAX_MODULUS:
            raise BadParameterError(f"cannot compute the bound: the {modes['modulus_hz']:.6g} Hz mode (damping ratio "
                                    f"{modes['modulus_damping']:.4g}) has a discrete eigenvalue of modulus "
                                    f"{modes['modulus']:.6f} at dt {dt:g} s, beyond the refinement's {_MAX_MODULUS:g} "
                                    f"(its start model pulls it inside: not {whose[:-2]}); give a larger dt or a "
                                    f"model with heavier damping", E_BAD_PARAMETER)
        raise BadParameterError(f"cannot compute the bound: the exact model does not reproduce its own noise-free "
                                f"record ({bound.message})", E_BAD_PARAMETER)
    std_status = core.fields()["std_status"]
    if std_status != OK:
        why = _STD_REASONS.get(std_status, "no covariance")
        if short and std_status == E_RANK_DEFICIENT:
            why += f"; the record spans {len(ua) * dt:g} s, {period}"
        elif std_status == E_RANK_DEFICIENT and modes["overlap"] >= _OVERLAP_CAUSE:
            why = (f"the Fisher information is singular at working precision: {whose[:-2]}'s modes overlap (the "
                   f"{modes['overlap_hz']:.6g} Hz mode, damping ratio {modes['overlap_damping']:.4g}, has a half-power "
                   f"band 2 zeta f {modes['overlap']:.3g} times the gap to its nearest mode): no record length tells "
                   f"them apart; give a model with lighter damping or fewer modes")
        check(std_status, f"cannot compute the bound: {why}")
    return CramerRaoBound(bound.modes, sigma, bound.num_parameters, bound.samples)


#: okid crlb's CRLB_OVERLAP_CAUSE and CRLB_MAX_MODULUS (host_tools/cli/crlb_command.c says why)
_OVERLAP_CAUSE = 10
_MAX_MODULUS = 0.9999


def _bound_causes(a: np.ndarray, dt: float) -> Dict[str, float]:
    """okid crlb's chain_modes of A's eigenvalues z (s = ln z / dt, f = |s| / 2 pi, zeta = -Re s / |s|):
    the complex pair whose half-power band 2 zeta f is the widest against the gap to the nearest
    other pair (overlap, overlap_hz, overlap_damping) and the largest |z| (modulus, modulus_hz,
    modulus_damping)."""
    z = np.linalg.eigvals(a) if np.all(np.isfinite(a)) else np.zeros(0)
    z = z[(z.imag >= 0) & (np.abs(z) > 0)]
    out = {"overlap": 0.0, "overlap_hz": 0.0, "overlap_damping": 0.0, "modulus": 0.0, "modulus_hz": 0.0,
           "modulus_damping": 0.0}
    if not z.size:
        return out
    s = np.log(z.astype(complex)) / dt
    f, zeta = np.abs(s) / (2 * math.pi), -s.real / np.maximum(np.abs(s), np.finfo(float).tiny)
    k = int(np.argmax(np.abs(z)))
    out.update(modulus=float(abs(z[k])), modulus_hz=float(f[k]), modulus_damping=float(zeta[k]))
    pairs = np.flatnonzero(z.imag > 0)
    for k in pairs:
        gaps = np.abs(f[pairs[pairs != k]] - f[k])
        if gaps.size and 2 * zeta[k] * f[k] > out["overlap"] * gaps.min():
            out.update(overlap=float(2 * zeta[k] * f[k] / gaps.min()) if gaps.min() > 0 else math.inf,
                       overlap_hz=float(f[k]), overlap_damping=float(zeta[k]))
    return out


def _fastest_mode_hz(a: np.ndarray, dt: float) -> float:
    """The largest natural frequency |ln z| / (2 pi dt) of A's eigenvalues z (0 when A has only
    zero eigenvalues, which have no continuous-time pole): okid crlb's fastest mode."""
    z = np.linalg.eigvals(a) if np.all(np.isfinite(a)) else np.zeros(0)
    z = z[np.abs(z) > 0]
    return float(np.max(np.abs(np.log(z.astype(complex)))) / (2 * math.pi * dt)) if z.size else 0.0
