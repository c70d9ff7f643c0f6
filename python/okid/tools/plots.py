# SPDX-License-Identifier: Apache-2.0
"""The paper's figures (exact and identified Markov parameters, force, accelerations, Hankel singular
values) and the convergence of the identifier FMU's frequencies and damping ratios, as PNG files."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any, Optional  # noqa: E402

import okid  # noqa: E402


def _identified(t, force, y):
    """Markov parameters and Hankel singular values identified by okid (in-process) from the same
    data, with the CLI's paper settings (the FMU publishes modes, not Markov parameters)."""
    dt = float(t[1] - t[0])
    res = okid.identify(np.reshape(force, (-1, 1)), y, dt, observer_order=20, order=4, zero_initial_state=1)
    return res.markov.T, res.singular_values


def paper_plots(folder: Path, ref: Any, cs: Any, noisy: Any, noisy_ref: Any, cli: Optional[Any] = None) -> None:
    """The paper's figures in folder; with cli (tests/python/verify_fmu.py --cli) also okid's identified Markov
    parameters, which now come from the okid package in-process."""
    folder.mkdir(parents=True, exist_ok=True)
    markov = np.array([Y[:, 0] for Y in ref.markov(60)])  # D, CB, CAB, ...: m = 2 per block
    fig, ax = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    for i in range(2):
        ax[i].stem(np.arange(len(markov)), markov[:, i], basefmt=" ")
        ax[i].set_ylabel(f"Y_k (acc{i + 1} / force)")
    ax[0].set_title("Exact system Markov parameters (paper fig. 1)")
    ax[1].set_xlabel("k")
    fig.tight_layout()
    fig.savefig(folder / "markov_exact.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(3, 1, figsize=(7, 6), sharex=True)
    ax[0].plot(cs.t, cs.force)
    ax[0].set_ylabel("force [N]")
    ax[0].set_title("White-noise force and accelerations from the plant FMU (paper figs. 2-3)")
    for i in range(2):
        ax[i + 1].plot(cs.t, cs.y[:, i])
        ax[i + 1].set_ylabel(f"acc{i + 1} [m/s2]")
    ax[2].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(folder / "signals.png", dpi=110)
    plt.close(fig)

    sv = [cs.final[f"singular_value{i}"] for i in range(1, 9)]
    if cli:
        identified, sv = _identified(cs.t, cs.force, cs.y)
        count = min(len(identified), len(markov))
        fig, ax = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
        for i in range(2):
            ax[i].plot(np.arange(count), markov[:count, i], "o", mfc="none", label="exact")
            ax[i].plot(np.arange(count), identified[:count, i], "x", label="identified (eq. 51)")
            ax[i].set_ylabel(f"Y_k (acc{i + 1} / force)")
        ax[0].set_title("Identified against exact system Markov parameters (paper fig. 4)")
        ax[0].legend()
        ax[1].set_xlabel("k")
        fig.tight_layout()
        fig.savefig(folder / "markov_identified.png", dpi=110)
        plt.close(fig)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.semilogy(np.arange(1, len(sv) + 1), sv, "o-")
    ax.set_title("Hankel singular values (paper fig. 5): a gap after n = 4")
    ax.set_xlabel("index")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "singular_values.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    h = noisy.history
    ok = h["status"] == 1
    for k, want in enumerate(noisy_ref.modes, start=1):
        ax[0].plot(noisy.t[ok], h[f"mode{k}_frequency_hz"][ok], label=f"mode {k}")
        ax[0].axhline(want.frequency_hz, color="k", lw=0.6, ls="--")
        ax[1].plot(noisy.t[ok], h[f"mode{k}_damping_ratio"][ok], label=f"mode {k}")
        ax[1].axhline(want.damping_ratio, color="k", lw=0.6, ls="--")
    ax[0].set_ylabel("frequency [Hz]")
    ax[1].set_ylabel("damping ratio")
    ax[1].set_xlabel("t [s]")
    ax[0].set_title("Identifier FMU in co-simulation, 2 % output noise, dt = 0.05 s (dashed: exact)", fontsize=10)
    ax[0].legend()
    fig.tight_layout()
    fig.savefig(folder / "convergence.png", dpi=110)
    plt.close(fig)
