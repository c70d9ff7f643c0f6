# SPDX-License-Identifier: Apache-2.0
"""Result and the stabilization diagram: immutable views of an identification, copied out of the C
workspace (Mode and the flags are in _mode)."""
from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any, Dict, Mapping, Optional, Tuple

import numpy as np

from . import _core
from ._errors import E_BAD_PARAMETER, BadParameterError, check
from ._mode import Mode, ModeArrays, StabilityFlag, WarningFlag, modes_from_dicts
from ._refine import REFINE_DEFAULTS, Refinement, check_settings, run as _run_refinement, warn_if_stopped


@dataclass(frozen=True)
class StabilizationOrder:
    """The modes of one model order of a stabilization diagram, with their stability flags."""
    order: int
    modes: Tuple[Mode, ...]
    stability: Tuple[StabilityFlag, ...]


class Stabilization:
    """Stabilization diagram data: the modes of orders step, 2 step, ..., max_order from one SVD."""

    def __init__(self, core, max_order: int, step: int):
        self._core = core
        self.max_order = max_order
        self.step = step
        self.rank_limit: int = core.rank_limit  #: largest order the Hankel matrix supports
        self.orders: Tuple[StabilizationOrder, ...] = tuple(
            StabilizationOrder(order, modes_from_dicts(modes), tuple(StabilityFlag(f) for f in flags))
            for order, modes, flags in core.orders())

    def to_dict(self) -> Dict[str, Any]:
        """The "stabilization" object of ``okid identify --json --stabilization`` (the CLI's writer)."""
        text = self._core.to_json()
        return json.loads(text[text.index("{"):])


#: Result's fields from the binding's fields(): okid_result's scalars (OKID_RESULT_SCALARS of
#: host_tools/cli/okid_fields.h) and its arrays.
_FIELDS = tuple(_core.RESULT_SCALARS) + ("A", "B", "C", "D", "G", "singular_values", "markov", "observer_gain_markov",
                                         "input_scales", "output_scales")


@dataclass(frozen=True, eq=False)
class Result(ModeArrays):
    """An identified model: state space, Markov parameters, modes and diagnostics. Immutable; every
    array is a read-only copy that later pushes and identifications leave as it is. A Result keeps
    the workspace of the identifier that made it (okid_workspace_size() bytes) for stabilization():
    to collect many records, keep the numbers you need rather than the Results."""
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
    _core: Any = field(repr=False)
    _identifier: Any = field(repr=False)
    _generation: int = field(repr=False)
    _refine_core: Any = field(repr=False, default=None)
    #: with refine=True and no horizon given: the starts tried ({"chosen": index, "candidates":
    #: [{observer_order, hankel_rows, hankel_cols, state, cost}]}, the JSON's "start_search"), else None
    start_search: Optional[Mapping[str, Any]] = None
    #: the settings chosen from the data, each {"value", "chosen", "reason"}, with the outputs' band
    #: (the JSON's "chosen"; docs/quality.md section 8); None when every setting was given
    chosen: Optional[Mapping[str, Any]] = None
    #: with the order chosen (order=0): every pole of the model with its verdict (okid.Pole), while
    #: ``modes`` holds the physical modes (okid.SelectedMode); else None
    poles: Optional[Tuple[Any, ...]] = None
    _auto_json: Optional[str] = field(repr=False, default=None)
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

    def to_dict(self) -> Dict[str, Any]:
        """The object ``okid identify --json`` prints for the same data and options, written by the
        CLI's own JSON writer (without the CLI-only "inputs", "outputs" and "elapsed_seconds"), with
        the "refinement" object of ``--refine`` when this result was refined."""
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
        if self.start_search is not None:
            out["start_search"] = json.loads(json.dumps(self.start_search))
        return out

    def refine(self, u: Any, y: Any, *, max_passes: int = REFINE_DEFAULTS["max_passes"],
               step_tolerance: float = REFINE_DEFAULTS["step_tolerance"]) -> "Result":
        """This result with its prediction-error refinement over the record (u, y): the same
        arrays this model describes, (N, r) and (N, m), at its sample interval dt (docs/refinement.md).

        The record is fed to okid_refine_push_block() from the caller's arrays (no copy, the GIL
        released) once per pass until the refinement finishes. max_passes: passes at most
        (2..1000); step_tolerance: converged when the Gauss–Newton decrement (about the squared
        step in standard deviations) falls below it (> 0). Returns a new Result whose
        ``refinement`` holds the refined model and its modes with their standard deviations; a
        refinement that stops without converging gives an okid.RefinementWarning.
        """
        if self.decimation > 1:
            raise BadParameterError(f"refine() of a result with decimation = {self.decimation}: the refinement needs "
                                    f"the record at the model's sample interval; identify without decimation",
                                    E_BAD_PARAMETER)
        return self._refine(u, y, max_passes, step_tolerance, stacklevel=2)

    def _refine(self, u: Any, y: Any, max_passes: Any, step_tolerance: Any, stacklevel: int) -> "Result":
        passes, tol = check_settings(max_passes, step_tolerance)
        core, refined = _run_refinement((self.A, self.B, self.C, self.D), self.dt, self.config["sensing"], u, y,
                                        passes, tol)
        warn_if_stopped(refined, stacklevel + 1)
        start = self.start if self.start is not None else self
        # the refined modes and their warnings are the result; OKID/ERA's stay in start
        return replace(start, modes=refined.modes, warnings=WarningFlag(refined.warnings), refinement=refined,
                       start=start, _refine_core=core)

    def to_frame(self):
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
        result identifies again or is reset (NotAvailableError afterwards)."""
        status, core = self._identifier.stabilization(self._generation, int(max_order), int(step),
                                                      float(frequency_tolerance), float(damping_tolerance),
                                                      float(mac_min))
        check(status, f"stabilization(max_order={max_order}, step={step}) (max_order 1.."
                      f"{len(self.singular_values)}, step 1..max_order; only for the identifier's latest result)")
        return Stabilization(core, int(max_order), int(step))
