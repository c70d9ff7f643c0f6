#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes reference_data.h: reference values for the C tests, computed with numpy/scipy.

Independent of the code under test: the matrices come from the paper's equations (6)-(9) written
again here, the discretisation from scipy.linalg.expm, eigenvectors from numpy.linalg.eig, and the
random generator is re-implemented from its published description (xoshiro256**, splitmix64).

    python3 tests/reference/make_reference.py > tests/reference/reference_data.h
"""
import numpy as np
from scipy.linalg import expm

MASK = (1 << 64) - 1


def chain(masses, dampers, springs):
    """M, R, K of masses in a chain between two walls (link i joins mass i-1 and mass i)."""
    n = len(masses)
    M = np.diag(masses).astype(float)

    def links(values):
        A = np.zeros((n, n))
        for i, v in enumerate(values):
            if i - 1 >= 0:
                A[i - 1, i - 1] += v
            if i < n:
                A[i, i] += v
            if 0 <= i - 1 and i < n:
                A[i - 1, i] -= v
                A[i, i - 1] -= v
        return A

    return M, links(dampers), links(springs)


def state_space(M, R, K, B2, Ca=None, Cv=None, Cd=None):
    n2, m = M.shape[0], None
    for C in (Ca, Cv, Cd):
        if C is not None:
            m = C.shape[0]
    Z = lambda: np.zeros((m, n2))
    Ca, Cv, Cd = (Z() if C is None else C for C in (Ca, Cv, Cd))
    Mi = np.linalg.inv(M)
    Ac = np.block([[np.zeros((n2, n2)), np.eye(n2)], [-Mi @ K, -Mi @ R]])
    Bc = np.vstack([np.zeros((n2, B2.shape[1])), Mi @ B2])
    C = np.hstack([Cd - Ca @ Mi @ K, Cv - Ca @ Mi @ R])
    D = Ca @ Mi @ B2
    return Ac, Bc, C, D


def zoh(Ac, Bc, dt):
    n, r = Bc.shape
    aug = np.zeros((n + r, n + r))
    aug[:n, :n], aug[:n, n:] = Ac, Bc
    E = expm(aug * dt)
    return E[:n, :n], E[:n, n:]


def modes(Ac, dt):
    """Continuous eigenpairs of Ac, one per conjugate pair (Im > 0), sorted by frequency.
    Shapes are eigenvectors of Ac = [phi; s phi], unit norm, largest component real positive:
    what eq. 64 gives when the sensors are the identity on every degree of freedom."""
    s, V = np.linalg.eig(Ac)
    out = []
    for i in np.argsort(np.abs(s)):
        if s[i].imag < 0:
            continue
        v = V[:, i] / np.linalg.norm(V[:, i])
        big = np.argmax(np.abs(v))
        v = v * (abs(v[big]) / v[big])
        out.append((np.exp(s[i] * dt), s[i], abs(s[i]) / (2 * np.pi), -s[i].real / abs(s[i]), v))
    return out


def markov(A, B, C, D, count):
    Y = [D]
    P = B
    for _ in range(count):
        Y.append(C @ P)
        P = A @ P
    return np.hstack(Y)


def hankel_singular_values(Y, r, m, alpha, beta):
    H = np.zeros((alpha * m, beta * r))
    for i in range(alpha):
        for j in range(beta):
            k = i + j + 1
            H[i * m:(i + 1) * m, j * r:(j + 1) * r] = Y[:, k * r:(k + 1) * r]
    return np.linalg.svd(H, compute_uv=False)


class Xoshiro256ss:
    def __init__(self, seed):
        x = seed & MASK
        self.s = []
        for _ in range(4):
            x = (x + 0x9E3779B97F4A7C15) & MASK
            z = x
            z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
            z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
            self.s.append(z ^ (z >> 31))

    @staticmethod
    def rotl(x, k):
        return ((x << k) | (x >> (64 - k))) & MASK

    def next(self):
        s = self.s
        result = (self.rotl((s[1] * 5) & MASK, 7) * 9) & MASK
        t = (s[1] << 17) & MASK
        s[2] ^= s[0]
        s[3] ^= s[1]
        s[1] ^= s[2]
        s[0] ^= s[3]
        s[2] ^= t
        s[3] = self.rotl(s[3], 45)
        return result

    def uniform(self):
        return (self.next() >> 11) * 2.0 ** -53

    def normals(self, count):
        out = []
        while len(out) < count:
            u1 = 1.0 - self.uniform()
            u2 = self.uniform()
            radius = np.sqrt(-2.0 * np.log(u1))
            out += [radius * np.cos(2 * np.pi * u2), radius * np.sin(2 * np.pi * u2)]
        return out[:count]


def c_array(name, values):
    flat = np.asarray(values, dtype=float).ravel(order="F")
    body = ",\n    ".join(", ".join(repr(float(v)) for v in flat[i:i + 4]) for i in range(0, len(flat), 4))
    return f"static const okid_real {name}[{len(flat)}] = {{\n    {body}\n}};\n"


def emit_case(prefix, M, R, K, B2, dt, Ca=None, Cv=None, Cd=None, markov_count=40, alpha=20, beta=20):
    Ac, Bc, C, D = state_space(M, R, K, B2, Ca, Cv, Cd)
    A, B = zoh(Ac, Bc, dt)
    m, r = D.shape
    md = modes(Ac, dt)
    Y = markov(A, B, C, D, markov_count)
    sv = hankel_singular_values(Y, r, m, alpha, beta)
    out = [f"/* {prefix}: {M.shape[0]} DOF, r = {r}, m = {m}, dt = {dt} */\n",
           f"#define {prefix}_DOFS {M.shape[0]}\n#define {prefix}_R {r}\n#define {prefix}_M {m}\n",
           f"#define {prefix}_DT {dt!r}\n#define {prefix}_MODES {len(md)}\n",
           f"#define {prefix}_MARKOV_COUNT {markov_count}\n",
           c_array(f"{prefix}_MASS", M), c_array(f"{prefix}_DAMPING", R), c_array(f"{prefix}_STIFFNESS", K),
           c_array(f"{prefix}_B2", B2)]
    for tag, Cx in (("CA", Ca), ("CV", Cv), ("CD", Cd)):
        if Cx is not None:
            out.append(c_array(f"{prefix}_{tag}", Cx))
    out += [c_array(f"{prefix}_AC", Ac), c_array(f"{prefix}_BC", Bc), c_array(f"{prefix}_C", C),
            c_array(f"{prefix}_D", D), c_array(f"{prefix}_A", A), c_array(f"{prefix}_B", B),
            c_array(f"{prefix}_EIG_RE", [x[0].real for x in md]), c_array(f"{prefix}_EIG_IM", [x[0].imag for x in md]),
            c_array(f"{prefix}_POLE_RE", [x[1].real for x in md]), c_array(f"{prefix}_POLE_IM", [x[1].imag for x in md]),
            c_array(f"{prefix}_FREQ_HZ", [x[2] for x in md]), c_array(f"{prefix}_DAMPING_RATIO", [x[3] for x in md]),
            c_array(f"{prefix}_SHAPE_RE", np.array([x[4].real for x in md]).T),
            c_array(f"{prefix}_SHAPE_IM", np.array([x[4].imag for x in md]).T),
            c_array(f"{prefix}_MARKOV", Y), c_array(f"{prefix}_HANKEL_SV", sv[:2 * M.shape[0] + 2])]
    return "".join(out)


def main():
    print("/* Generated by tests/reference/make_reference.py (numpy %s): do not edit. */" % np.__version__)
    print("#ifndef OKID_TEST_REFERENCE_DATA_H\n#define OKID_TEST_REFERENCE_DATA_H\n")
    print("#include \"okid/types.h\" /* okid_real: the values round to float in a float build */\n")
    # The paper's section III: force on mass 1, accelerations of both masses.
    M, R, K = chain([2, 3], [2, 4, 3], [20, 40, 30])
    print(emit_case("PAPER", M, R, K, np.array([[1.0], [0.0]]), 0.01, Ca=np.eye(2)))
    # The same structure after k2 = 40 -> 60 N/m (forgetting-factor tracking).
    M, R, K = chain([2, 3], [2, 4, 3], [20, 60, 30])
    print(emit_case("STIFFER", M, R, K, np.array([[1.0], [0.0]]), 0.01, Ca=np.eye(2)))
    # MIMO: a force on each mass, displacements of both masses.
    M, R, K = chain([2, 3], [2, 4, 3], [20, 40, 30])
    print(emit_case("MIMO", M, R, K, np.eye(2), 0.01, Cd=np.eye(2)))
    # A 3-DOF chain with velocity sensing and a force on mass 1.
    M, R, K = chain([1, 1.5, 2], [0.4, 0.3, 0.2, 0.1], [40, 30, 20, 10])
    print(emit_case("CHAIN3", M, R, K, np.array([[1.0], [0.0], [0.0]]), 0.02, Cv=np.eye(3)))
    # Exponential of a non-normal matrix of large norm (scaling and squaring is exercised).
    rng = np.random.default_rng(7)
    Ac = rng.standard_normal((5, 5)) * 4.0
    Bc = rng.standard_normal((5, 2))
    A, B = zoh(Ac, Bc, 0.5)
    print("/* ZOH of a 5 x 5 non-normal matrix with 2 inputs, dt = 0.5 */")
    print(c_array("ZOH5_AC", Ac) + c_array("ZOH5_BC", Bc) + c_array("ZOH5_A", A) + c_array("ZOH5_B", B))
    # Random generator: the first values for seed 2024.
    g = Xoshiro256ss(2024)
    print(c_array("RNG_SEED2024_UNIFORM", [g.uniform() for _ in range(8)]))
    g = Xoshiro256ss(2024)
    print(c_array("RNG_SEED2024_NORMAL", g.normals(9)))
    print("#endif")


if __name__ == "__main__":
    main()
