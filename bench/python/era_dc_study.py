# SPDX-License-Identifier: Apache-2.0
"""Output-noise bias remedies at equal observer order p on the benchmark data (okid's simulator,
paper 2-DOF system, dt 0.05 s, 100 s, 5 % and 20 % output noise): plain OKID + ERA and OKID + ERA/DC
(Juang, Cooper, Wright 1987) in numpy, and okid's least squares and instrumental variables (the okid package).
The measurement behind docs/quality.md section 6 (why okid implements instrumental variables).

    .venv/bin/python bench/python/era_dc_study.py [--cli build/host_tools/cli/okid]   (the CLI simulates the data)

Prints a markdown table of the relative error of the worse of the two frequencies, mean / worst
over seeds 11-15, alpha = beta = 20, n = 4.
"""
import argparse
import os
import sys
from pathlib import Path

import numpy as np

import okid

from bench_compare import era_A, modal, numpy_okid_markov, simulate  # noqa: E402  (this folder; it puts the oracle on the path)
from reference import paper_reference  # noqa: E402

DT, SAMPLES, HANKEL, SEEDS = 0.05, 2001, 20, range(11, 16)
BLOCKS, SHIFT = 2, 2  # ERA/DC: (BLOCKS + 1)^2 correlation blocks R((i + j) SHIFT)


def era_dc_A(Y, alpha, beta, n):
    """ERA/DC: R(k) = H(k) H(0)', the block correlation Hankel of R((i + j) tau) and its shift by one
    step, then the ERA formula on it (A = S^-1/2 U' RR(1) V S^-1/2)."""
    def hankel(k):
        return np.block([[Y[i + j + 1 + k] for j in range(beta)] for i in range(alpha)])
    h0 = hankel(0)
    R = {k: hankel(k) @ h0.T for k in {(i + j) * SHIFT + d for i in range(BLOCKS + 1) for j in range(BLOCKS + 1)
                                       for d in (0, 1)}}
    RR0 = np.block([[R[(i + j) * SHIFT] for j in range(BLOCKS + 1)] for i in range(BLOCKS + 1)])
    RR1 = np.block([[R[(i + j) * SHIFT + 1] for j in range(BLOCKS + 1)] for i in range(BLOCKS + 1)])
    U, S, Vt = np.linalg.svd(RR0)
    root = np.diag(S[:n] ** -0.5)
    return root @ U[:, :n].T @ RR1 @ Vt[:n].T @ root


def frequency_error(freqs, exact):
    freqs = np.sort(freqs)
    return float(np.max(np.abs(freqs - exact) / exact)) if len(freqs) == 2 else np.inf


def okid_frequencies(u, y, p, estimator):
    """okid's frequencies (in-process) at observer order p, or none when it fails."""
    try:
        res = okid.identify(u, y, DT, order=4, zero_initial_state=1, observer_order=p, estimator=estimator)
    except okid.OkidError:
        return np.array([])
    return np.array([md.frequency_hz for md in res.modes if md.is_pair])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", default="build/host_tools/cli/okid")
    args = parser.parse_args(argv)
    exact = np.sort([md.frequency_hz for md in paper_reference(DT).modes])
    count = 2 * HANKEL + 2 * BLOCKS * SHIFT + 2
    print("| noise | p | numpy OKID + ERA | numpy OKID + ERA/DC | okid least squares | okid instrumental |")
    print("|---|---|---|---|---|---|")
    for noise in (0.05, 0.20):
        for p in (5, 10, 20):
            errors = {key: [] for key in ("era", "dc", "ls", "iv")}
            for seed in SEEDS:
                path, u, y = simulate(args.cli, DT, SAMPLES, noise, seed)
                Y = numpy_okid_markov(u, y, p, count)
                errors["era"].append(frequency_error(modal(era_A(Y, HANKEL, HANKEL, 4), DT)[0], exact))
                errors["dc"].append(frequency_error(modal(era_dc_A(Y, HANKEL, HANKEL, 4), DT)[0], exact))
                errors["ls"].append(frequency_error(okid_frequencies(u, y, p, "least_squares"), exact))
                errors["iv"].append(frequency_error(okid_frequencies(u, y, p, "instrumental"), exact))
                os.unlink(path)
            cells = [f"{100 * np.mean(e):.2f} / {100 * np.max(e):.2f} %" if np.all(np.isfinite(e)) else "no two modes"
                     for e in errors.values()]
            print(f"| {100 * noise:.0f} % | {p} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
