# SPDX-License-Identifier: Apache-2.0
"""Output-only (ambient) identification: okid.identify_ambient and okid.AmbientResult, through the
C library's okid_ambient (okid/ambient.h, docs/ambient.md), as ``okid identify --inputs 0`` runs it."""
from __future__ import annotations

import json
import warnings as _warnings
from dataclasses import dataclass, fields
from types import MappingProxyType
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _core
from ._config import SENSING
from ._document import Travelling
from ._errors import BadParameterError, BadSizeError, NonFiniteSampleWarning, OK, check, error_for
from ._mode import Mode, ModeArrays, Pole, SelectedMode, WarningFlag, modes_from_dicts

__all__ = ["AmbientResult", "identify_ambient"]


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
    if sensing not in SENSING:
        raise BadParameterError(f"sensing = {sensing!r}: one of {', '.join(map(repr, SENSING))}", -4)
    refs = [] if references is None else sorted({int(i) for i in references})
    status, field, value, lo, hi, res = _core.ambient_identify(data, float(dt), int(hankel_rows), int(order), refs,
                                                               SENSING[sensing], int(segments), int(segment_samples),
                                                               progress)
    if status != OK:
        if field:
            raise error_for(status, f"{field} = {value:g}: valid {lo:g}..{hi:g} for output-only identification")
        check(status, "output-only identification failed")
    if res["rejected_samples"]:
        _warnings.warn("samples with a NaN or Inf were skipped (a gap in the correlations)", NonFiniteSampleWarning,
                       stacklevel=2)
    m = data.shape[1]
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
