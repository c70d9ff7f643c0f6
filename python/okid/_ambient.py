# SPDX-License-Identifier: Apache-2.0
"""Output-only (ambient) identification: okid.identify_ambient, the streaming okid.AmbientIdentifier
and okid.AmbientResult, through the C library's okid_ambient (okid/ambient.h, docs/ambient.md), as
``okid identify --inputs 0`` runs it."""
from __future__ import annotations

import json
import warnings as _warnings
from dataclasses import dataclass, fields
from types import MappingProxyType
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _core
from ._config import SENSING
from ._document import Travelling
from ._errors import (E_BAD_SIZE, E_NONFINITE_SAMPLE, E_NOT_ENOUGH_DATA, OK, BadParameterError, BadSizeError,
                      NonFiniteSampleWarning, check, error_for)
from ._mode import Mode, ModeArrays, Pole, SelectedMode, WarningFlag, modes_from_dicts
from ._stays_here import StaysHere

__all__ = ["AmbientIdentifier", "AmbientProgress", "AmbientResult", "identify_ambient"]


@dataclass(frozen=True, eq=False)
class AmbientResult(ModeArrays, Travelling):
    """An output-only identification. Immutable; every array is a read-only copy.

    Fields (n states, m outputs, r_ref references, L = hankel_rows; discrete at dt):

    - order: n [states]; A (n, n) [-], C (m, n) [output unit / state]
    - G (n, r_ref): E[x(t+1) y_ref(t)'] [state x output unit], so that R(k) = C A^(k-1) G
    - correlations: [R(0) R(1) ... R(2L)] (m, r_ref (2L + 1)), R(k) = E[y(t+k) y_ref(t)'] of the
      mean-removed record [output unit^2]
    - singular_values: of the correlations' block Hankel matrix, decreasing [output unit^2]
    - realization_condition: sigma_1 / sigma_n [-]
    - modes: okid.Mode tuple sorted by frequency (frequency_hz [Hz], damping_ratio [-], shapes,
      indicators; emac_input judges G's side); with the order chosen (order=0), the physical modes
      as okid.SelectedMode (stable across orders and Hankel sizes, docs/ambient.md)
    - poles: with the order chosen, every pole of the model as okid.Pole (verdict, reason), else None
    - chosen: with the order chosen, each choice and its reason ({value, chosen, reason}: hankel_rows,
      order; band_hz, hankel_windows, max_order, selection_band_hz), else None
    - dt [s]; samples: samples accepted; pairs: products summed at lag 2L [counts]
    - hankel_rows: L used; band_hz: the outputs' 5 % frequency that chose it [Hz] (0 when given)
    - references: the reference outputs' indices; warnings: okid.WarningFlag
    - frequency_std [Hz], damping_std [-]: with segments, each pole's standard deviations (NaN when
      fewer than two segments hold it; in the order of modes, or of poles when the order is
      chosen), else None; segments_used: the segments realized
    """
    order: int
    A: np.ndarray
    C: np.ndarray
    G: np.ndarray
    correlations: np.ndarray
    singular_values: np.ndarray
    realization_condition: float
    modes: Tuple[Mode, ...]
    dt: float
    samples: int
    pairs: int
    hankel_rows: int
    band_hz: float
    references: Tuple[int, ...]
    warnings: WarningFlag
    frequency_std: Optional[np.ndarray]
    damping_std: Optional[np.ndarray]
    segments_used: int
    poles: Optional[Tuple[Pole, ...]] = None
    chosen: Optional[Mapping[str, Any]] = None


def identify_ambient(y: Any, dt: float, *, hankel_rows: int = 0, order: int = 0,
                     references: Optional[Sequence[int]] = None, sensing: str = "acceleration",
                     segments: int = 0, segment_samples: int = 0,
                     progress: Optional[Callable[[int, int], None]] = None) -> AmbientResult:
    """Identify modes from the outputs alone: no measured force (operational modal analysis).

    y is (N, m), time along axis 0, in any unit; dt the sample interval [s]. Each channel's mean is
    removed (y is never written), the correlations R(k) = sum y(t+k) y_ref(t)' / (N - k)
    of lags 0..2L are summed in fixed memory, and their L x L block Hankel matrix is realized by the
    same ERA as okid.identify(). Samples with a NaN or Inf are skipped (a gap: no product spans
    them) with a NonFiniteSampleWarning.

    hankel_rows: L, block rows and columns (okid_ambient_config.hankel_rows); 0 chooses L dt = one
    period at the frequency below which 5 % of the outputs' energy lies. order: n; 0 = the physical
    modes as ``modes`` (selected across the even orders 2..60 of the correlations' stabilization
    table at three Hankel sizes, as okid identify --inputs 0 without --order) and the lowest order
    that holds them (the largest singular-value gap when none is found). references: indices of
    the reference outputs (any order), None = all.
    sensing: "displacement", "velocity" or "acceleration" (the shapes of eq. 64). segments: 2..64
    keeps the sums of as many segments apart (blocks of segment_samples samples, 0 = 20 (2L + 1),
    dealt out in turn) and gives each mode's frequency_std and damping_std from their spread;
    0 or 1 = none. progress(done, total) is called between chunks of samples.
    """
    data = np.ascontiguousarray(np.asarray(y, dtype=float))
    if data.ndim != 2 or data.shape[1] < 1:
        raise BadSizeError(f"y must be (N, m) with m >= 1, not of shape {data.shape}", -2)
    refs = _references(references)
    status, field, value, lo, hi, res = _core.ambient_identify(data, float(dt), int(hankel_rows), int(order), refs,
                                                               _sensing(sensing), int(segments), int(segment_samples),
                                                               progress)
    if status != OK:
        _refuse(status, field, value, lo, hi, "output-only identification failed")
    if res["rejected_samples"]:
        _warnings.warn("samples with a NaN or Inf were skipped (a gap in the correlations)", NonFiniteSampleWarning,
                       stacklevel=2)
    return _result(res, refs, data.shape[1])


def _references(references: Optional[Sequence[int]]) -> List[int]:
    return [] if references is None else sorted({int(i) for i in references})


def _sensing(sensing: str) -> int:
    if sensing not in SENSING:
        raise BadParameterError(f"sensing = {sensing!r}: one of {', '.join(map(repr, SENSING))}", -4)
    return SENSING[sensing]


def _refuse(status: int, field: str, value: float, lo: float, hi: float, what: str) -> None:
    """Raise the exception of a refused configuration (field: the setting) or of a failure."""
    if field:
        raise error_for(status, f"{field} = {value:g}: valid {lo:g}..{hi:g} for output-only identification")
    check(status, what)


def _result(res: Dict[str, Any], refs: List[int], m: int) -> AmbientResult:
    """The AmbientResult of the binding's result dict: with the order chosen (its "auto_json"), the
    physical modes as modes, every pole of the model with its verdict and the choices."""
    modes = modes_from_dicts(res["modes"])
    poles = chosen = None
    if res["auto_json"] is not None:
        doc = json.loads("{" + res["auto_json"].lstrip().lstrip(",") + "}")
        chosen = MappingProxyType({k: MappingProxyType(v) if isinstance(v, dict) else v
                                   for k, v in doc["chosen"].items()})
        poles = tuple(Pole(**{f.name: getattr(md, f.name) for f in fields(Mode)},
                           verdict="rejected" if why else "physical", reason=why)
                      for md, why in zip(modes, res["verdicts"]))
        modes = tuple(SelectedMode(**d) for d in res["selected"])
    return AmbientResult(
        order=res["order"], A=res["A"], C=res["C"], G=res["G"], correlations=res["correlations"],
        singular_values=res["singular_values"], realization_condition=res["realization_condition"],
        modes=modes, dt=res["dt"], samples=res["samples"], pairs=res["pairs"],
        hankel_rows=res["hankel_rows"], band_hz=res["band_hz"],
        references=tuple(refs) if refs else tuple(range(m)), warnings=WarningFlag(res["warnings"]),
        frequency_std=res["frequency_std"], damping_std=res["damping_std"], segments_used=res["segments_used"],
        poles=poles, chosen=chosen)


@dataclass(frozen=True)
class AmbientProgress:
    """Counters of an AmbientIdentifier."""
    samples: int          #: samples accepted since creation or reset
    rejected: int         #: samples rejected as non-finite (each starts a gap)
    samples_needed: int   #: consecutive samples identify() needs at least: 2 hankel_rows + 1


class AmbientIdentifier(StaysHere):
    """A streaming output-only identifier: push blocks of outputs as they come, identify at any time.

    ``AmbientIdentifier(num_outputs, dt, hankel_rows=20, order=0, references=None,
    sensing="acceleration", segments=0, segment_samples=0)``: the okid_ambient_config fields by
    their C names and with its defaults (okid_ambient_config_default()); dt is the sample interval
    [s]. The correlation sums of lags 0..2 hankel_rows live in a workspace of fixed size
    (``workspace_bytes``), the same for any number of samples pushed.

    With order 0 (the default) identify() gives the physical modes, as identify_ambient does with
    hankel_rows given: the stabilization table of the even orders 2..min(60, hankel_rows m) of the
    sums so far, the selection of docs/ambient.md, ``modes`` the physical modes (okid.SelectedMode),
    ``poles`` every pole of the model at the lowest order that holds them with its verdict, and
    ``chosen`` the order's reason; none found: the largest-gap model, no modes and
    WarningFlag.NO_PHYSICAL_MODE. What identify_ambient does that a stream cannot: it removes each
    channel's mean from the whole record first, chooses hankel_rows from the record's band when it
    is 0 (here it must be given, 1..), checks the modes at two more Hankel sizes, and starts the
    selection's band at a third of the record's 5 % frequency (here at 0 Hz, as the identifier
    FMU). Here the samples are summed as pushed, so they should have zero mean (subtract a known
    offset, or high-pass them, before pushing). With the same record minus its mean, the same
    hankel_rows and a given order, identify() gives identify_ambient's result. One identifier serves
    one thread at a time (a second raises okid.ConcurrentUseError); push() and identify() release
    the GIL. Usable as a context manager (the workspace is freed).
    """

    _HOLDS = ("the correlation sums", "pickle its AmbientResults, or push the same samples into an "
                                      "AmbientIdentifier there")

    def __init__(self, num_outputs: int, dt: float, *, hankel_rows: int = 20, order: int = 0,
                 references: Optional[Sequence[int]] = None, sensing: str = "acceleration", segments: int = 0,
                 segment_samples: int = 0):
        refs = _references(references)
        core = _core.AmbientCore()
        status, field, value, lo, hi, _ = core.init(int(num_outputs), float(dt), int(hankel_rows), int(order), refs,
                                                    _sensing(sensing), int(segments), int(segment_samples))
        if status != OK:
            _refuse(status, field, value, lo, hi, "okid_ambient_init")
        self.num_outputs: int = int(num_outputs)
        self.dt: float = float(dt)  #: sample interval of the pushed data [s]
        self.hankel_rows: int = int(hankel_rows)
        self.order: int = int(order)
        self.references: Tuple[int, ...] = tuple(refs) if refs else tuple(range(self.num_outputs))
        self._refs = refs
        self._core: Optional[Any] = core
        self._samples = 0
        self._rejected = 0

    def _live(self) -> Any:
        if self._core is None:
            raise ValueError("this AmbientIdentifier is closed")
        return self._core

    @property
    def workspace_bytes(self) -> int:
        """The identifier's fixed memory [bytes] (okid_ambient_workspace_size()): any record length."""
        return int(self._live().workspace_bytes)

    @property
    def progress(self) -> AmbientProgress:
        """Samples accepted and rejected so far, and how many identify() needs."""
        return AmbientProgress(self._samples, self._rejected, 2 * self.hankel_rows + 1)

    def push(self, y: Any, *, progress: Optional[Callable[[int, int], None]] = None) -> int:
        """Push a block y (count, m) of outputs, time along axis 0, or one sample (m,). y is read, never
        written (a C-contiguous float64 block goes to the library without a copy).

        A sample holding NaN or Inf is rejected, as the C library does: no product with it is summed,
        the lags restart after it (a gap) and everything summed before is kept; a
        NonFiniteSampleWarning says how many. progress(done, count), when given, is called between
        chunks of the block (Ctrl-C raises KeyboardInterrupt between two; the chunks done stay
        pushed). Returns the number of samples accepted.
        """
        core = self._live()
        block = np.asarray(y, dtype=float)
        if block.ndim == 1:
            block = block.reshape(1, -1)
        if block.ndim != 2 or block.shape[1] != self.num_outputs:
            hint = " (pass y.T)" if block.ndim == 2 and block.shape[0] == self.num_outputs else ""
            raise BadSizeError(f"y has shape {np.shape(y)}: expected (samples, {self.num_outputs}) with time along "
                               f"axis 0, or one sample ({self.num_outputs},){hint}", E_BAD_SIZE)
        block = np.ascontiguousarray(block)
        status, accepted = core.push_block(block, progress)
        self._samples += int(accepted)
        self._rejected += block.shape[0] - int(accepted)
        if status == E_NONFINITE_SAMPLE:
            _warnings.warn(f"{block.shape[0] - accepted} of {block.shape[0]} samples held NaN or Inf and were "
                           "rejected (a gap in the correlations)", NonFiniteSampleWarning, stacklevel=2)
        elif status != OK:
            raise error_for(status, "push")
        return int(accepted)

    def identify(self) -> AmbientResult:
        """Identify from everything pushed so far (okid_ambient_identify()); pushing can go on."""
        status, res = self._live().identify()
        if status == E_NOT_ENOUGH_DATA:
            raise error_for(status, f"{self._samples} samples pushed: no pair at lag 2 hankel_rows = "
                                    f"{2 * self.hankel_rows} yet (at least {2 * self.hankel_rows + 1} consecutive)")
        check(status, "identify")
        return _result(res, self._refs, self.num_outputs)

    def reset(self) -> None:
        """Forget every sample (okid_ambient_reset()); the settings and the workspace stay."""
        check(self._live().reset(), "reset")
        self._samples = self._rejected = 0

    def close(self) -> None:
        """Free the workspace; any later call raises ValueError. AmbientResults stay valid (they are copies)."""
        self._core = None

    def __repr__(self) -> str:
        state = "closed" if self._core is None else f"{self._samples} samples"
        return (f"okid.AmbientIdentifier(num_outputs={self.num_outputs}, dt={self.dt:g}, "
                f"hankel_rows={self.hankel_rows}, order={self.order}; {state})")
