# SPDX-License-Identifier: Apache-2.0
"""The model side of okid (lib/include/okid/model.h): chains of masses, the mechanical model's
continuous state space (paper eq. 6-9), its exact zero-order-hold discretisation (eq. 13-14) and
the discrete simulator. Matrices are ordinary (rows, cols) arrays; time runs along axis 0."""
from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy as np

from . import _core
from ._errors import E_BAD_PARAMETER, E_BAD_SIZE, BadParameterError, BadSizeError, check

__all__ = ["chain_model", "state_space", "discretize_zoh", "simulate", "paper_system"]


def _f(a: Any, name: str, shape: Optional[Tuple[int, ...]] = None) -> np.ndarray:
    a = np.asfortranarray(np.atleast_2d(np.asarray(a, dtype=np.float64)))
    if shape is not None and a.shape != shape:
        raise BadSizeError(f"{name} has shape {a.shape}, expected {shape}", E_BAD_SIZE)
    return a


def chain_model(masses: Any, dampers: Any, springs: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, R, K of n masses [kg] in a chain between two walls: damper r_i [N s/m] and spring k_i
    [N/m] join mass i-1 and mass i (the walls are masses 0 and n+1; 0 leaves a link out).
    masses: n values > 0; dampers, springs: n + 1 values >= 0. The paper's system is
    chain_model([2, 3], [2, 4, 3], [20, 40, 30])."""
    masses = np.ascontiguousarray(masses, dtype=np.float64).reshape(-1)
    dampers = np.ascontiguousarray(dampers, dtype=np.float64).reshape(-1)
    springs = np.ascontiguousarray(springs, dtype=np.float64).reshape(-1)
    if dampers.size != masses.size + 1 or springs.size != masses.size + 1:
        raise BadSizeError(f"{masses.size} masses need {masses.size + 1} dampers and springs "
                           f"(got {dampers.size} and {springs.size})", E_BAD_SIZE)
    status, mrk = _core.chain_model(masses, dampers, springs)
    check(status, f"chain_model (1..{_core.MAX_ORDER // 2} masses > 0, dampers and springs >= 0, finite)")
    return mrk


def state_space(mass: Any, damping: Any, stiffness: Any, input_matrix: Any, *, acceleration: Any = None,
                velocity: Any = None, displacement: Any = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Continuous state space (Ac, Bc, C, D) of M x'' + R x' + K x = B2 u, y = Ca x'' + Cv x' + Cd x
    with state [x; x'] (eq. 6-9). input_matrix is B2 (n2, r); the output matrices are (m, n2), any
    of them None (zero), at least one given."""
    mass = _f(mass, "mass")
    n2 = mass.shape[0]
    damping, stiffness = _f(damping, "damping", (n2, n2)), _f(stiffness, "stiffness", (n2, n2))
    b2 = _f(input_matrix, "input_matrix")
    outs = [None if c is None else _f(c, name) for c, name in
            ((acceleration, "acceleration"), (velocity, "velocity"), (displacement, "displacement"))]
    given = [c for c in outs if c is not None]
    if not given:
        raise BadSizeError("state_space needs at least one of acceleration, velocity, displacement", E_BAD_SIZE)
    m = given[0].shape[0]
    for c in given:
        if c.shape != (m, n2):
            raise BadSizeError(f"output matrices must all be ({m}, {n2}), got {c.shape}", E_BAD_SIZE)
    if b2.shape[0] != n2:
        raise BadSizeError(f"input_matrix has shape {b2.shape}, expected ({n2}, r)", E_BAD_SIZE)
    status, mats = _core.state_space(mass, damping, stiffness, b2, outs[0], outs[1], outs[2], m)
    check(status, "state_space (finite entries, M invertible)")
    return mats


def discretize_zoh(ac: Any, bc: Any, dt: float) -> Tuple[np.ndarray, np.ndarray]:
    """Exact zero-order-hold discretisation: A = e^(Ac dt), B = int_0^dt e^(Ac t) dt Bc (dt in s)."""
    ac = _f(ac, "ac")
    n = ac.shape[0]
    bc = _f(np.reshape(bc, (n, -1)), "bc")
    status, ab = _core.discretize_zoh(ac, bc, float(dt))
    check(status, "discretize_zoh (dt finite and > 0, finite entries)")
    return ab


def simulate(a: Any, b: Any, c: Any, d: Any, u: Any, x0: Optional[Any] = None) -> Tuple[np.ndarray, np.ndarray]:
    """y(k) = C x(k) + D u(k), x(k+1) = A x(k) + B u(k) for u of shape (N, r): returns (y of shape
    (N, m), the final state). x0 is the initial state (zeros if None)."""
    a = _f(a, "A")
    n = a.shape[0]
    b = _f(np.reshape(b, (n, -1)), "B")
    c = _f(c, "C")
    d = _f(np.reshape(d, (c.shape[0], b.shape[1])), "D")
    u = np.ascontiguousarray(np.reshape(u, (np.shape(u)[0], b.shape[1])), dtype=np.float64)
    x = np.zeros(n) if x0 is None else np.ascontiguousarray(x0, dtype=np.float64).reshape(n)
    status, yx = _core.simulate(a, b, c, d, u, x)
    check(status, "simulate (finite inputs)")
    return yx


def lift(u: Any, y: Any, factor: int) -> Tuple[np.ndarray, np.ndarray]:
    """Exact decimation by lifting (okid_lift, docs/refinement.md): K = factor consecutive samples
    of u (N, r) and y (N, m), time along axis 0, become one sample with inputs [u(iK), ...,
    u(iK+K-1)] (K r channels) and outputs y(iK). Returns (u_lifted (N // K, K r), y_lifted
    (N // K, m)), new arrays; the last N % K samples are dropped. Identify the result with dt = K
    times the record's [s]: with a zero-order hold it is the same n-state system at K dt, so its
    modes are exact on noise-free data (the filter of decimation=K is biased). factor: 1..64;
    modes must lie below the decimated Nyquist frequency 1 / (2 K dt)."""
    if isinstance(factor, bool) or not hasattr(factor, "__index__") or not 1 <= factor.__index__() <= 64:
        raise BadParameterError(f"factor = {factor!r}: an integer in 1..64", E_BAD_PARAMETER)
    ua = np.ascontiguousarray(u, dtype=np.float64)
    ya = np.ascontiguousarray(y, dtype=np.float64)
    ua = ua.reshape(-1, 1) if ua.ndim == 1 else ua
    ya = ya.reshape(-1, 1) if ya.ndim == 1 else ya
    if ua.ndim != 2 or ya.ndim != 2 or ua.shape[0] != ya.shape[0] or not (1 <= ua.shape[1] <= 64 and 1 <= ya.shape[1] <= 64):
        raise BadSizeError(f"u has shape {np.shape(u)} and y {np.shape(y)}: expected (N, r) and (N, m), r and m "
                           f"in 1..64, time along axis 0", E_BAD_SIZE)
    status, lifted = _core.lift(ua, ya, int(factor.__index__()))
    check(status, f"lift(factor={factor})")
    return lifted


def paper_system(dt: float = 0.01, sensing: str = "acceleration") -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The paper's 2-DOF system (masses 2, 3 kg; dampers 2, 4, 3 N s/m; springs 20, 40, 30 N/m; the
    force on mass 1, both masses measured), discretised exactly: (A, B, C, D)."""
    ac, bc, c, d = _paper_continuous(sensing)
    a, b = discretize_zoh(ac, bc, dt)
    return a, b, c, d


def _paper_continuous(sensing: str = "acceleration") -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The paper's 2-DOF system in continuous time: (Ac, Bc, C, D)."""
    mass, damping, stiffness = chain_model([2, 3], [2, 4, 3], [20, 40, 30])
    outputs = {sensing: np.eye(2)}
    if sensing not in ("acceleration", "velocity", "displacement"):
        raise ValueError(f"sensing = {sensing!r}: 'acceleration', 'velocity' or 'displacement'")
    return state_space(mass, damping, stiffness, [[1.0], [0.0]], **outputs)
