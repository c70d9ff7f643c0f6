# SPDX-License-Identifier: Apache-2.0
"""Environmental compensation and alarms on tracked frequencies (structural health monitoring).

Temperature (and load, humidity, ...) moves a structure's frequencies by percents, far more than
early damage; SHM practice is to regress the frequencies on the measured covariates over a baseline
period and to watch what is left (Peeters & De Roeck 2001; Worden et al., the "data normalisation"
step). Here, per asset and mode:

1. compensation: over the baseline records, least squares of the frequency on the covariates
   (an intercept and one slope per covariate); every record's frequency minus the fitted effect of
   its covariates' departure from their baseline mean is its compensated frequency;
2. a robust baseline of the compensated frequencies: the median, and the scaled MAD as sigma;
3. an EWMA chart (Roberts 1959) of the standardised compensated change e = (f_c / median - 1) / sigma:
   z_k = lambda e_k + (1 - lambda) z_(k-1), z_0 = 0, an alarm where |z_k| exceeds
   L sqrt(lambda / (2 - lambda) + (pi / 2) / n) after the baseline of n records (the second term:
   the uncertainty of the baseline's median, the chart's centre). The in-control average run length (records
   between false alarms for independent Gaussian e) is ``average_run_length``: about 500 at
   lambda = 0.25, L = 3 (Montgomery, Introduction to Statistical Quality Control, the EWMA table for
   ARL0 = 500: L = 2.998 at lambda = 0.25; tested), about 2900 at the defaults lambda = 0.2,
   L = 3.5, which still find a shift of 2 sigma after about 5 records. A short baseline makes sigma
   uncertain and false alarms more frequent.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, List, Sequence, Tuple

import numpy as np

if TYPE_CHECKING:  # for the annotations only: pandas is the fleet extra's
    import pandas as pd

MAD_TO_SIGMA: float = 1.4826  # 1 / Phi^-1(3/4): the MAD of Gaussian scatter times this is its standard deviation


def robust_sigma(x: np.ndarray) -> float:
    return float(MAD_TO_SIGMA * np.median(np.abs(x - np.median(x))))


def compensate(f: np.ndarray, x: np.ndarray, baseline: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Frequencies F (n,) less the effect of covariates X (n, c) fitted over the BASELINE rows
    (bool mask); returns the compensated frequencies and the slopes (c,) [Hz per unit]."""
    if x.shape[1] == 0:
        return f.copy(), np.zeros(0)
    xb = x[baseline]
    mean = xb.mean(axis=0)
    design = np.column_stack([np.ones(xb.shape[0]), xb - mean])
    if xb.shape[0] <= design.shape[1] or np.linalg.matrix_rank(design) < design.shape[1]:
        raise ValueError(f"the baseline ({xb.shape[0]} records) does not span the covariates: give more "
                         "baseline records, over the range the covariates take")
    coef, *_ = np.linalg.lstsq(design, f[baseline], rcond=None)
    slopes = coef[1:]
    return f - (x - mean) @ slopes, slopes


def ewma(e: np.ndarray, lam: float) -> np.ndarray:
    z = np.empty_like(e)
    prev = 0.0
    for k, value in enumerate(e):
        prev = lam * value + (1 - lam) * prev
        z[k] = prev
    return z


def average_run_length(lam: float, limit_l: float, shift: float = 0.0, runs: int = 4000, seed: int = 1,
                       max_records: int = 1_000_000) -> Tuple[float, float]:
    """Monte Carlo: the mean number of records until the EWMA chart's first alarm when e is N(SHIFT, 1),
    and the standard error of that mean (RUNS runs)."""
    rng = np.random.default_rng(seed)
    limit = limit_l * np.sqrt(lam / (2 - lam))
    z, length = np.zeros(runs), np.zeros(runs)
    alive = np.arange(runs)
    for _ in range(max_records):
        if alive.size == 0:
            break
        z[alive] = lam * (rng.standard_normal(alive.size) + shift) + (1 - lam) * z[alive]
        length[alive] += 1
        alive = alive[np.abs(z[alive]) <= limit]
    return float(length.mean()), float(length.std() / np.sqrt(runs))


def chart(tracks: pd.DataFrame, covariates: Sequence[str], lam: float, limit_l: float) -> List[Dict[str, Any]]:
    """Per track point (TRACKS: one asset and mode, in time order, with a bool column ``baseline``
    and one per covariate): the compensated frequency, its change from the baseline median, the
    EWMA statistic with weight LAM, its limit (LIMIT_L asymptotic standard deviations) and the alarm."""
    f = tracks["frequency_hz"].to_numpy(float)
    baseline = tracks["baseline"].to_numpy(bool)
    x = np.column_stack([tracks[c].to_numpy(float) for c in covariates]) if covariates else np.zeros((len(f), 0))
    fc, _ = compensate(f, x, baseline)
    ref = float(np.median(fc[baseline]))
    change = fc / ref - 1
    sigma = robust_sigma(change[baseline])
    z = ewma(change / sigma, lam) if sigma > 0 else np.zeros_like(change)
    # the centre is the median of the baseline, itself uncertain by (pi / 2) sigma^2 / n_baseline
    # (the median's variance): a chart that ignores it alarms far more often than its ARL says
    limit = limit_l * np.sqrt(lam / (2 - lam) + 0.5 * np.pi / max(int(baseline.sum()), 1))
    alarm = (np.abs(z) > limit) & ~baseline
    return [{"compensated_hz": float(a), "compensated_change": float(b), "ewma": float(c), "ewma_limit": float(limit),
             "alarm": bool(d)} for a, b, c, d in zip(fc, change, z, alarm)]
