# SPDX-License-Identifier: Apache-2.0
"""Mode and the flags of a result: the leaf of the package (it imports only the binding), which
_result and _refine both build on."""
from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from . import _core
from ._document import ComplexArray, Travelling


class WarningFlag(enum.IntFlag):
    """okid_result.warnings (lib/include/okid/status.h): the result is usable but deserves a look."""
    REGRESSOR_RANK_DEFICIENT = 1 << 0
    UNSTABLE_POLE = 1 << 1
    NONPHYSICAL_POLE = 1 << 2
    ORDER_AT_LIMIT = 1 << 3
    RANK_BELOW_MODEL = 1 << 4
    WEAK_EXCITATION = 1 << 5
    OBSERVER_ORDER_ABOVE_MINIMUM = 1 << 6
    HANKEL_SPAN_SHORT = 1 << 7
    REALIZATION_ILL_CONDITIONED = 1 << 8
    RESIDUAL_NOT_WHITE = 1 << 9
    OUTPUT_NOT_EXPLAINED = 1 << 10
    CORRELATION_FALLBACK = 1 << 11  #: set by okid.identify() and the CLI only (estimator="correlation")
    NO_OUTPUT_EXPLAINED = 1 << 12  #: set by okid.identify() and the CLI only: every output's fit_percent below 50
    RESIDUAL_INPUT_CORRELATED = 1 << 13  #: a refined output's residual is correlated with an input
    NO_PHYSICAL_MODE = 1 << 14  #: identify / identify_ambient without an order, okid identify, the identifier FMU (all_poles false, order 0): no physical mode found
    MODE_SPLIT = 1 << 15  #: two refined pairs are one mode split in two (Refinement.split_modes): the order is too high there

    def describe(self) -> Tuple[str, ...]:
        """The library's sentence for each bit set."""
        return tuple(_core.warning_str(int(bit)) for bit in WarningFlag if bit & self)


class StabilityFlag(enum.IntFlag):
    """A mode's stability against the previous order of a stabilization diagram."""
    FREQUENCY = 1 << 0
    DAMPING = 1 << 1
    SHAPE = 1 << 2
    ALL = 7


@dataclass(frozen=True)
class Mode(Travelling):
    """One mode of the identified model; a complex-conjugate pair is reported once (Im(eigenvalue) > 0).

    eigenvalue: discrete-time eigenvalue of A (complex); pole: continuous-time pole ln(eigenvalue)/dt
    [1/s]; frequency_hz: undamped natural frequency |pole|/2 pi [Hz]; damping_ratio: -Re(pole)/|pole|
    [-]; is_pair: a complex pair (two states); sensor_shape: C psi at the m sensors, (m,) complex,
    unit norm, largest component real positive; shape: eq. 64 with continuous poles, (2 m,) complex,
    displacements then velocities; emac, emac_output, emac_input: extended modal amplitude
    coherence [0, 1]; mpc: modal phase collinearity [0, 1]; msv: mode singular value (units of the
    Hankel singular values); cmi: consistent mode indicator EMAC x MPC [0, 1]. A refined mode
    (Result.refinement.modes, okid.crlb) also has one standard deviation of each: frequency_std
    [Hz], damping_std [-], eigenvalue_std and pole_std [1/s] (std of the real part as the real
    part, std of the imaginary part as the imaginary part), sensor_shape_std ((m,) complex, alike).
    """
    eigenvalue: complex       #: discrete-time eigenvalue of A
    pole: complex             #: continuous-time pole ln(eigenvalue) / dt [1/s]
    frequency_hz: float       #: undamped natural frequency |pole| / 2 pi [Hz]
    damping_ratio: float      #: -Re(pole) / |pole| [-]
    is_pair: bool             #: True for a complex pair (two states), False for a real eigenvalue
    sensor_shape: ComplexArray  #: C psi, (m,) complex, unit norm
    shape: ComplexArray       #: eq. 64 with continuous poles: (2 m,) complex, displacements then velocities
    emac: float               #: extended modal amplitude coherence, [0, 1]
    emac_output: float        #: output (C-side) EMAC, [0, 1]
    emac_input: float         #: input (B-side) EMAC, [0, 1]
    mpc: float                #: modal phase collinearity of sensor_shape, [0, 1]
    msv: float                #: mode singular value (units of the Hankel singular values)
    cmi: float                #: consistent mode indicator EMAC * MPC, [0, 1]
    # Set on the modes of a refinement (Result.refinement.modes, okid.crlb), None on OKID/ERA's;
    # one standard deviation each, from the inverse Fisher information (-1 when it diverged).
    frequency_std: Optional[float] = None          #: std of frequency_hz [Hz]
    damping_std: Optional[float] = None            #: std of damping_ratio [-]
    eigenvalue_std: Optional[complex] = None       #: std of Re (real part) and of Im (imaginary part) of eigenvalue
    pole_std: Optional[complex] = None             #: std of Re and of Im of pole, as a complex number [1/s]
    sensor_shape_std: Optional[ComplexArray] = None  #: (m,) complex: std of Re and of Im of each sensor_shape entry


@dataclass(frozen=True)
class SelectedMode(Mode):
    """A physical mode chosen automatically (okid/mode_selection.h, docs/quality.md section 8): the
    representative pole of a cluster of poles stable across model orders, with the cluster's spread.

    order: model order of the representative; num_orders of of_orders: orders of its window's
    stabilization table the cluster has a pole in (lowest_order..highest_order); frequency_mean,
    frequency_std (population), frequency_min, frequency_max [Hz] and damping_mean, damping_std,
    damping_min, damping_max [-] over the cluster; cmi_min: its smallest CMI; windows of
    of_windows: the Hankel windows whose selection holds the mode (without the EMAC criterion in a
    window the mode outlasts, docs/quality.md section 8); input-output only, observers of
    of_observers: the observer orders whose windows hold it, observer_order: the representative's
    (0 on the output-only path).
    """
    order: int = 0
    num_orders: int = 0
    of_orders: int = 0
    lowest_order: int = 0
    highest_order: int = 0
    frequency_mean: float = 0.0
    frequency_std: float = 0.0
    frequency_min: float = 0.0
    frequency_max: float = 0.0
    damping_mean: float = 0.0
    damping_std: float = 0.0
    damping_min: float = 0.0
    damping_max: float = 0.0
    cmi_min: float = 0.0
    windows: int = 0
    of_windows: int = 0
    observers: int = 0
    of_observers: int = 0
    observer_order: int = 0


@dataclass(frozen=True)
class Pole(Mode):
    """A pole (mode) of the reported model with the selection's verdict: "physical" when it is one of
    Result.modes, else "rejected" with the reason (a real pole, unstable, damping above 1/sqrt(2), outside
    the band, MPC or EMAC below 0.5, or not stable across orders, windows and observer orders)."""
    verdict: str = "physical"
    reason: Optional[str] = None


def modes_from_dicts(dicts) -> Tuple[Mode, ...]:
    """The binding's mode dicts (mode_dict() in python/src) as Modes."""
    return tuple(Mode(**d) for d in dicts)


class ModeArrays:
    """Each mode's frequency and damping ratio as arrays, for every object with modes (Result,
    Refinement, CramerRaoBound)."""
    modes: Tuple[Mode, ...]

    def _column(self, field: str) -> np.ndarray:
        return np.array([getattr(md, field) for md in self.modes])

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Natural frequency of every mode [Hz]."""
        return self._column("frequency_hz")

    @property
    def damping_ratios(self) -> np.ndarray:
        """Damping ratio of every mode [-]."""
        return self._column("damping_ratio")
