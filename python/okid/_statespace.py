# SPDX-License-Identifier: Apache-2.0
"""What one does with an identified discrete state space {A, B, C, D} at dt: simulate a record,
evaluate its frequency response, hand it to python-control or scipy.signal. A mixin for every
object that holds such a model (okid.Result, okid.Refinement)."""
from __future__ import annotations

import math
from typing import Any, Optional

import numpy as np

from . import model as _model
from ._config import real_array
from ._errors import E_BAD_PARAMETER, E_BAD_SIZE, BadParameterError, BadSizeError


def _needs(package: str, what: str, pip_name: str) -> ImportError:
    return ImportError(f"{what} needs {package}: pip install {pip_name}")


class StateSpaceModel:
    """x(k+1) = A x(k) + B u(k), y(k) = C x(k) + D u(k) with sample interval dt [s]."""
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: float

    def simulate(self, u: Any, x0: Optional[Any] = None) -> np.ndarray:
        """The model's response to a whole force record: y of shape (N, m) [the outputs' units] for
        u of shape (N, r) (or (N,) when r = 1) [the inputs' units], time along axis 0, from the
        state x0 ((n,), zeros when None; a refinement's ``initial_state`` reproduces its record).
        The library's simulator (okid_simulate), the same one okid.model.simulate runs."""
        r, n = self.B.shape[1], self.A.shape[0]
        ua = real_array(u, "u")
        if ua.ndim == 1 and r == 1:
            ua = ua.reshape(-1, 1)
        if ua.ndim != 2 or ua.shape[1] != r:
            hint = " (time runs along axis 0: pass u.T)" if ua.ndim == 2 and ua.shape[0] == r else ""
            raise BadSizeError(f"u has shape {np.shape(u)}: expected (samples, {r}), time along axis 0{hint}",
                               E_BAD_SIZE)
        if not np.all(np.isfinite(ua)):
            raise BadParameterError("u holds NaN or Inf: simulate() needs finite inputs", E_BAD_PARAMETER)
        x = None
        if x0 is not None:
            x = real_array(x0, "x0").reshape(-1)
            if x.shape != (n,):
                raise BadSizeError(f"x0 has {x.size} values: the model has {n} states", E_BAD_SIZE)
        y, _ = _model.simulate(self.A, self.B, self.C, self.D, ua, x)
        return y

    def frequency_response(self, frequencies_hz: Any) -> np.ndarray:
        """H(f) = C (z I - A)^-1 B + D at z = exp(2 pi i f dt) for each frequency f [Hz]: a complex
        array (K, m, r) for K frequencies, [output units / input units] (the transfer function from
        input j to output i is H[:, i, j]). Frequencies above the Nyquist frequency 1/(2 dt) give
        the aliased response, as for any discrete model."""
        f = real_array(frequencies_hz, "frequencies_hz").reshape(-1)
        if not np.all(np.isfinite(f)):
            raise BadParameterError("frequencies_hz holds NaN or Inf: give finite frequencies [Hz]", E_BAD_PARAMETER)
        n = self.A.shape[0]
        z = np.exp(2j * math.pi * f * self.dt)
        resolvent = z[:, None, None] * np.eye(n) - self.A  # (K, n, n)
        return self.C @ np.linalg.solve(resolvent, np.broadcast_to(self.B, (f.size,) + self.B.shape)) + self.D

    def to_dlti(self) -> Any:
        """The model as a ``scipy.signal.dlti`` (a StateSpace with dt): needs scipy."""
        try:
            from scipy import signal
        except ImportError as e:
            raise _needs("scipy", "to_dlti()", "scipy") from e
        return signal.dlti(np.array(self.A), np.array(self.B), np.array(self.C), np.array(self.D), dt=self.dt)

    def to_statespace(self) -> Any:
        """The model as a ``control.StateSpace`` (discrete, dt set): needs python-control."""
        try:
            import control
        except ImportError as e:
            raise _needs("python-control", "to_statespace()", '"okid[control]"') from e
        return control.ss(np.array(self.A), np.array(self.B), np.array(self.C), np.array(self.D), self.dt)
