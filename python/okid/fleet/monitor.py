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
   L sqrt(lambda / (2 - lambda)) after the baseline. With lambda = 0.25 and L = 3 (the defaults) the
   in-control average run length is about 500 records for independent Gaussian e (Montgomery,
   Introduction to Statistical Quality Control, the EWMA table for ARL0 = 500: L = 2.998 at
   lambda = 0.25); a short baseline makes sigma uncertain and false alarms more frequent.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np

MAD_TO_SIGMA = 1.4826  # 1 / Phi^-1(3/4): the MAD of Gaussian scatter times this is its standard deviation


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


def chart(tracks, covariates: Sequence[str], lam: float, limit_l: float) -> List[dict]:
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
    limit = limit_l * np.sqrt(lam / (2 - lam))
    alarm = (np.abs(z) > limit) & ~baseline
    return [{"compensated_hz": float(a), "compensated_change": float(b), "ewma": float(c), "ewma_limit": float(limit),
             "alarm": bool(d)} for a, b, c, d in zip(fc, change, z, alarm)]
