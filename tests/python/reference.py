# SPDX-License-Identifier: Apache-2.0
"""The paper's 2-DOF system computed independently of the C code (numpy/scipy).

Eq. 6-9 for the continuous model, scipy.linalg.expm for the exact zero-order hold (eq. 13-14),
numpy.linalg.eig for the modes; shapes in the displacement/velocity basis of eq. 64, which for
sensors on every degree of freedom are the eigenvectors [phi; s phi] of Ac, normalised like okid's
(unit norm, largest component real and positive).
"""
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

PAPER = dict(masses=(2.0, 3.0), dampers=(2.0, 4.0, 3.0), springs=(20.0, 40.0, 30.0))


def chain_matrices(masses, dampers, springs):
    n = len(masses)

    def links(values):
        A = np.zeros((n, n))
        for i, v in enumerate(values):
            for a in (i - 1, i):
                if 0 <= a < n:
                    A[a, a] += v
            if 0 <= i - 1 and i < n:
                A[i - 1, i] -= v
                A[i, i - 1] -= v
        return A

    return np.diag(masses), links(dampers), links(springs)


@dataclass
class Mode:
    eigenvalue: complex
    pole: complex
    frequency_hz: float
    damping_ratio: float
    shape: np.ndarray


@dataclass
class Reference:
    dt: float
    Ac: np.ndarray
    Bc: np.ndarray
    C: np.ndarray
    D: np.ndarray
    A: np.ndarray
    B: np.ndarray
    modes: list

    def markov(self, count):
        """D, CB, CAB, ... (count + 1 blocks), m x r each."""
        out, P = [self.D], self.B
        for _ in range(count):
            out.append(self.C @ P)
            P = self.A @ P
        return out

    def simulate(self, u):
        """y(k) = C x(k) + D u(k), x(k+1) = A x(k) + B u(k), from rest; u is (N, r)."""
        x = np.zeros(self.A.shape[0])
        y = np.empty((len(u), self.C.shape[0]))
        states = np.empty((len(u), self.A.shape[0]))
        for k, uk in enumerate(u):
            states[k] = x
            y[k] = self.C @ x + self.D @ uk
            x = self.A @ x + self.B @ uk
        return y, states


def paper_reference(dt=0.01, masses=PAPER["masses"], dampers=PAPER["dampers"], springs=PAPER["springs"]):
    """Force on mass 1, accelerations of every mass measured (the paper's section III)."""
    return chain_reference(dt, masses, dampers, springs, forces_on=(0,))


def chain_reference(dt, masses, dampers, springs, forces_on):
    """A chain of masses between two walls, forces on the masses `forces_on` (0-based), the
    accelerations of every mass measured."""
    M, R, K = chain_matrices(masses, dampers, springs)
    n, r = len(masses), len(forces_on)
    Mi = np.linalg.inv(M)
    B2 = np.zeros((n, r))
    for j, dof in enumerate(forces_on):
        B2[dof, j] = 1.0
    Ac = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ R]])
    Bc = np.vstack([np.zeros((n, r)), Mi @ B2])
    C = np.hstack([-Mi @ K, -Mi @ R])
    D = Mi @ B2
    aug = np.zeros((2 * n + r, 2 * n + r))
    aug[:2 * n, :2 * n], aug[:2 * n, 2 * n:] = Ac, Bc
    E = expm(aug * dt)
    s, V = np.linalg.eig(Ac)
    modes = []
    for i in np.argsort(np.abs(s)):
        if s[i].imag <= 0:
            continue
        v = V[:, i] / np.linalg.norm(V[:, i])
        big = np.argmax(np.abs(v))
        v = v * (abs(v[big]) / v[big])
        modes.append(Mode(np.exp(s[i] * dt), s[i], abs(s[i]) / (2 * np.pi), -s[i].real / abs(s[i]), v))
    return Reference(dt, Ac, Bc, C, D, E[:2 * n, :2 * n], E[:2 * n, 2 * n:], modes)


def mac(a, b):
    """Modal assurance criterion of two complex shapes."""
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)
