# SPDX-License-Identifier: Apache-2.0
"""Plots of identified models with matplotlib (an optional dependency: ``pip install "okid[plot]"``).

Every function takes what it draws (an okid.Result, a Stabilization) and an optional matplotlib
``Axes``; without one it makes a figure. It returns the Axes it drew on, so the caller titles,
saves or combines them:

    ax = okid.plot.frequency_response(result)
    ax.figure.savefig("frf.png")

The numbers drawn are the package's own (Result.frequency_response, Result.simulate, mac()), so
a plot shows what the API returns.
"""
from __future__ import annotations

import math
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np

from ._mode import Mode, StabilityFlag
from ._result import Result, Stabilization

__all__ = ["mac", "mac_matrix", "mode_shapes", "response", "fit_percent", "frequency_response", "stabilization",
           "measured_frequency_response", "plot_stabilization"]

#: what has modes: a Result, a Refinement, a CramerRaoBound, or the modes themselves
Modes = Union[Any, Sequence[Mode]]


def _axes(ax: Any) -> Any:
    if ax is not None:
        return ax
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError('okid.plot needs matplotlib: pip install "okid[plot]"') from e
    return plt.subplots(figsize=(7, 4.5))[1]


def _modes(source: Modes) -> Tuple[Mode, ...]:
    return tuple(getattr(source, "modes", source))


def mac_matrix(a: Modes, b: Optional[Modes] = None) -> np.ndarray:
    """The modal assurance criterion of every mode of a against every mode of b (a itself when
    None) on their sensor shapes: MAC_ij = |a_i^H b_j|^2 / (|a_i|^2 |b_j|^2), in [0, 1], shape
    (modes of a, modes of b). The shapes must be at the same sensors."""
    ma, mb = _modes(a), _modes(a if b is None else b)
    pa = np.array([md.sensor_shape for md in ma]).reshape(len(ma), -1)
    pb = np.array([md.sensor_shape for md in mb]).reshape(len(mb), -1)
    if pa.shape[1] != pb.shape[1]:
        raise ValueError(f"mode shapes at {pa.shape[1]} and {pb.shape[1]} sensors: MAC needs the same sensors")
    cross = np.abs(pa.conj() @ pb.T) ** 2
    return cross / np.outer(np.sum(np.abs(pa) ** 2, axis=1), np.sum(np.abs(pb) ** 2, axis=1))


def _mode_labels(modes: Sequence[Mode]) -> list:
    return [f"{md.frequency_hz:.3g} Hz" for md in modes]


def mac(a: Modes, b: Optional[Modes] = None, *, ax: Any = None, annotate: bool = True) -> Any:
    """The MAC matrix of a against b (mac_matrix) as an image, modes labelled by frequency [Hz],
    each cell annotated with its value when annotate."""
    ax = _axes(ax)
    values = mac_matrix(a, b)
    ma, mb = _modes(a), _modes(a if b is None else b)
    image = ax.imshow(values, vmin=0.0, vmax=1.0, cmap="viridis", origin="upper")
    ax.figure.colorbar(image, ax=ax, label="MAC")
    ax.set_yticks(range(len(ma)), _mode_labels(ma))
    ax.set_xticks(range(len(mb)), _mode_labels(mb))
    if annotate:
        for (i, j), v in np.ndenumerate(values):
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", color="k" if v > 0.5 else "w", fontsize=8)
    ax.set_title("modal assurance criterion")
    return ax


def mode_shapes(result: Modes, sensors: Optional[Sequence[str]] = None, *, ax: Any = None) -> Any:
    """Each mode's sensor shape (unit norm, largest component real positive) at the sensors:
    its real part, one line per mode, the sensors on the x axis by name (sensors, m names) or
    number. The real part is the shape of a classically damped mode; mpc tells how far a mode is
    from one."""
    ax = _axes(ax)
    modes = _modes(result)
    m = len(modes[0].sensor_shape) if modes else 0
    names = list(sensors) if sensors is not None else [str(i + 1) for i in range(m)]
    if len(names) != m:
        raise ValueError(f"{len(names)} sensor names for shapes at {m} sensors")
    x = np.arange(m)
    for md in modes:
        ax.plot(x, md.sensor_shape.real, marker="o", label=f"{md.frequency_hz:.4g} Hz, damping {md.damping_ratio:.3g}")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xticks(x, names)
    ax.set_xlabel("sensor")
    ax.set_ylabel("Re(sensor shape) [-]")
    ax.legend(fontsize=8)
    ax.set_title("mode shapes")
    return ax


def fit_percent(measured: np.ndarray, predicted: np.ndarray) -> np.ndarray:
    """Per output, 100 (1 - |y - y_hat| / |y - mean(y)|) [%] (MATLAB's compare / NRMSE fit): 100 is
    a perfect fit, 0 no better than the mean."""
    y, yh = np.asarray(measured, dtype=float), np.asarray(predicted, dtype=float)
    return 100.0 * (1.0 - np.linalg.norm(y - yh, axis=0) / np.linalg.norm(y - y.mean(axis=0), axis=0))


def response(result: Result, u: Any, y: Any, *, x0: Optional[Any] = None, ax: Any = None,
             outputs: Optional[Sequence[str]] = None) -> Any:
    """The measured outputs y (N, m) against the model's simulation from u (N, r) and x0
    (Result.simulate), against time [s] at the model's dt, with the fit of each output
    (fit_percent) in the legend."""
    ax = _axes(ax)
    y = np.asarray(y, dtype=float).reshape(len(y), -1)
    y_model = result.simulate(u, x0)
    if y_model.shape != y.shape:
        raise ValueError(f"y has shape {y.shape} and the simulation {y_model.shape}: the same record, time along axis 0")
    t = np.arange(len(y)) * result.dt
    names = list(outputs) if outputs is not None else [f"y{i + 1}" for i in range(y.shape[1])]
    for i, fit in enumerate(fit_percent(y, y_model)):
        line = ax.plot(t, y[:, i], lw=1.0, label=f"{names[i]} measured")[0]
        ax.plot(t, y_model[:, i], lw=1.0, ls="--", color=line.get_color(), label=f"{names[i]} model, fit {fit:.1f} %")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("output")
    ax.legend(fontsize=8)
    ax.set_title("measured and identified response")
    return ax


def frequency_response(result: Result, frequencies_hz: Optional[Any] = None, *, ax: Any = None,
                       output: Optional[int] = None, input: Optional[int] = None) -> Any:
    """The magnitude of Result.frequency_response (every output/input pair, or the one given by
    output and input, 0-based) against frequency [Hz] on a log scale, the identified modes'
    natural frequencies marked by dotted lines. frequencies_hz: default 2000 points up to the
    Nyquist frequency 1/(2 dt)."""
    ax = _axes(ax)
    f = np.linspace(0.0, 0.5 / result.dt, 2000) if frequencies_hz is None else np.asarray(frequencies_hz, float)
    h = result.frequency_response(f)
    outs = range(h.shape[1]) if output is None else [output]
    ins = range(h.shape[2]) if input is None else [input]
    for i in outs:
        for j in ins:
            ax.semilogy(f, np.abs(h[:, i, j]), label=f"|H| output {i + 1} / input {j + 1}")
    for md in _modes(result):
        if md.is_pair:
            ax.axvline(md.frequency_hz, color="0.4", ls=":", lw=1.0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H| [output unit / input unit]")
    ax.legend(fontsize=8)
    ax.set_title("frequency response, identified modes dotted")
    return ax


def stabilization(diagram: Stabilization, *, ax: Any = None, max_frequency: Optional[float] = None) -> Any:
    """The stabilization diagram: every oscillating pole of every order at (frequency [Hz], order),
    a filled circle when stable in frequency, damping and shape against the previous order, a
    cross when stable in frequency only, a dot otherwise (okid/stabilization.h's criteria)."""
    ax = _axes(ax)
    kinds = {"stable": ("o", "C3"), "frequency": ("x", "C0"), "new": (".", "0.5")}
    points = {k: ([], []) for k in kinds}
    limit = math.inf if max_frequency is None else max_frequency
    for level in diagram.orders:
        for md, flag in zip(level.modes, level.stability):
            if not md.is_pair or md.frequency_hz > limit:
                continue
            kind = ("stable" if flag & StabilityFlag.ALL == StabilityFlag.ALL
                    else "frequency" if flag & StabilityFlag.FREQUENCY else "new")
            points[kind][0].append(md.frequency_hz)
            points[kind][1].append(level.order)
    for kind, (marker, color) in kinds.items():
        if points[kind][0]:
            ax.scatter(points[kind][0], points[kind][1], marker=marker, color=color, label=kind)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.legend(fontsize=8)
    ax.set_title("stabilization diagram")
    return ax


def measured_frequency_response(u: Any, y: Any, dt: float, segment: Optional[int] = None) -> Tuple[np.ndarray, np.ndarray]:
    """The H1 estimate of the frequency response from a record: Welch averages (Hann window, half
    overlap) of the cross spectra, H(f) = S_yu(f) S_uu(f)^-1. u (N, r), y (N, m) [their units],
    dt [s]; segment: samples per average (default N/8, at most 4096, at least 64). Returns
    (frequencies [Hz], H (F, m, r) [output unit / input unit])."""
    u = np.asarray(u, float).reshape(len(u), -1)
    y = np.asarray(y, float).reshape(len(y), -1)
    if len(u) != len(y) or len(u) < 64:
        raise ValueError(f"u and y need the same number of samples, at least 64 (u {len(u)}, y {len(y)})")
    n = segment or int(min(4096, max(64, len(u) // 8)))
    window = np.hanning(n)
    starts = range(0, len(u) - n + 1, n // 2)
    suu = syu = 0
    for s in starts:
        fu = np.fft.rfft(window[:, None] * (u[s:s + n] - u[s:s + n].mean(0)), axis=0)
        fy = np.fft.rfft(window[:, None] * (y[s:s + n] - y[s:s + n].mean(0)), axis=0)
        suu = suu + np.einsum("fi,fj->fij", fu, fu.conj())
        syu = syu + np.einsum("fi,fj->fij", fy, fu.conj())
    h = np.linalg.solve(np.swapaxes(suu, 1, 2), np.swapaxes(syu, 1, 2))  # (S_yu S_uu^-1)^T = S_uu^-T S_yu^T
    return np.fft.rfftfreq(n, dt), np.swapaxes(h, 1, 2)


def plot_stabilization(result: Result, u: Optional[Any] = None, y: Optional[Any] = None, *, max_order: Optional[int] = None,
                       max_frequency: Optional[float] = None, ax: Any = None) -> Any:
    """The stabilization diagram a modal analyst expects, for a Result of okid.identify: the poles of
    every even order up to max_order (default: the automatic selection's table, min(60, Hankel
    size)) marked stable / stable in frequency / new (okid.plot.stabilization), each physical mode
    of result.modes marked at its frequency with its cluster's spread across orders as a band, and
    behind them, on a log axis, the singular values of the frequency response: measured from u (N, r)
    and y (N, m) when given (H1, measured_frequency_response), else the identified model's.
    max_frequency [Hz]: default the model's Nyquist frequency. Returns the Axes."""
    ax = _axes(ax)
    nyquist = 0.5 / result.dt
    top = nyquist if max_frequency is None else float(max_frequency)
    limit = min(60, len(result.singular_values))
    orders = limit - limit % 2 if max_order is None else int(max_order)
    stabilization(result.stabilization(orders), ax=ax, max_frequency=top)
    for k, md in enumerate(_modes(result)):
        if not md.is_pair:
            continue
        low, high = getattr(md, "frequency_min", md.frequency_hz), getattr(md, "frequency_max", md.frequency_hz)
        ax.axvspan(low, high, color="C2", alpha=0.2, lw=0)
        ax.axvline(md.frequency_hz, color="C2", lw=1.2, label="physical modes" if k == 0 else None)
    if u is not None and y is not None:
        f, h = measured_frequency_response(u, y, result.config["dt"])
        source = "measured (H1)"
    else:
        f = np.linspace(0.0, nyquist, 2000)
        h, source = result.frequency_response(f), "identified model"
    keep = f <= top
    sv = np.linalg.svd(h[keep], compute_uv=False)
    behind = ax.twinx()
    behind.set_zorder(ax.get_zorder() - 1)
    ax.patch.set_visible(False)
    behind.semilogy(f[keep], sv, color="0.75", lw=0.8)
    behind.set_ylabel(f"singular values of H, {source}")
    ax.set_xlim(0.0, top)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"stabilization diagram, order {result.order} reported")
    return ax
