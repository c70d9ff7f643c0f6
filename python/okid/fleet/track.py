# SPDX-License-Identifier: Apache-2.0
"""Modes tracked over time, asset by asset, with statistics one outlier cannot move.

Baseline: the first ``baseline_records`` successful records of an asset (in time order). The modes
of its first record seed the reference modes; each baseline record's modes are matched to them and
a reference frequency is the **median** of its matches over the baseline, its spread the scaled
median absolute deviation (1.4826 MAD, the standard deviation for Gaussian scatter). Matching (for
the baseline and every later record): a candidate lies within the frequency tolerance of the
reference (relative) and its shape has a MAC of at least ``mac_min`` with the reference's, the
shapes compared **channel by channel by output name** (a record whose columns come in another
order is re-ordered; channels one of them lacks are left out); among candidates the nearest in
frequency wins, each mode used once.

Trend: the Theil-Sen line of a tracked mode's frequency against time (the median of the slopes of
all pairs of records, breakdown point 29 %: one outlier cannot tilt it), evaluated from the first to
the last record, relative to the reference frequency. Its standard error is that of the
least-squares slope with the robust residual scatter (1.4826 MAD of the residuals) in place of the
RMS; a change is called drift when it exceeds both ``drift_min`` and four such standard errors.

Covariates (``covariates``: a temperature, a load, recorded with okid-fleet identify --covariates)
are regressed out of the frequencies over the baseline, and every tracked mode gets an EWMA control
chart of its compensated frequency with alarms past the baseline (monitor.py); the trend and drift
are those of the compensated frequency (the frequency itself without covariates).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .monitor import chart, robust_sigma

if TYPE_CHECKING:  # for the annotations only: pandas is the fleet extra's
    import pandas as pd

THEIL_SEN_MAX_POINTS: int = 3000  # beyond: an evenly spaced subset gives the slope (all pairs: n^2 / 2 slopes)


@dataclass(frozen=True)
class TrackOptions:
    frequency_tolerance: float = 0.05  #: relative distance from the reference frequency
    mac_min: float = 0.9               #: least MAC of the sensor shapes
    drift_min: float = 0.005           #: relative frequency change reported as drift (0.5 %)
    baseline_records: int = 5          #: the first records of an asset that make its reference
    covariates: Tuple[str, ...] = ()   #: covariates regressed out of the frequencies (monitor.py)
    ewma_lambda: float = 0.2           #: the EWMA chart's weight of the newest record
    ewma_limit: float = 3.5            #: its limit, in asymptotic EWMA standard deviations (ARL0 ~ 2900)


def mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex shapes, in [0, 1]."""
    den = np.vdot(a, a).real * np.vdot(b, b).real
    return float(abs(np.vdot(a, b)) ** 2 / den) if den > 0 else 0.0


def _shape(row) -> Dict[str, complex]:
    """A mode's shape as {output name: complex amplitude}."""
    names = row["outputs"]
    values = np.asarray(row["shape_re"], dtype=float) + 1j * np.asarray(row["shape_im"], dtype=float)
    if names is None or len(names) != len(values):  # a table without names: the positions are the names
        names = [str(i) for i in range(len(values))]
    return dict(zip(names, values))


def shape_mac(a: Dict[str, complex], b: Dict[str, complex]) -> float:
    """MAC of two shapes over the outputs they share, matched by name."""
    common = [name for name in a if name in b]
    if not common:
        return 0.0
    return mac(np.array([a[n] for n in common]), np.array([b[n] for n in common]))


@dataclass
class _Reference:
    mode: int
    frequency_hz: float
    shape: Dict[str, complex]
    spread: float = 0.0   # robust relative scatter of the baseline frequencies


def _match(cand, refs: Sequence[_Reference], opts: TrackOptions) -> List[Tuple[int, int, float]]:
    """(reference index, candidate row position, MAC) of the matched modes of one record."""
    shapes = [_shape(r) for _, r in cand.iterrows()]
    freqs = cand["frequency_hz"].to_numpy(float)
    pairs = []
    for i, ref in enumerate(refs):
        for j, (f, s) in enumerate(zip(freqs, shapes)):
            df = abs(f - ref.frequency_hz) / ref.frequency_hz
            if df > opts.frequency_tolerance:
                continue
            m = shape_mac(s, ref.shape)
            if m >= opts.mac_min:
                pairs.append((df, i, j, m))
    used_ref, used_cand, out = set(), set(), []
    for df, i, j, m in sorted(pairs):
        if i in used_ref or j in used_cand:
            continue
        used_ref.add(i)
        used_cand.add(j)
        out.append((i, j, m))
    return out


def _baseline(by_record: List[Tuple[str, object]], opts: TrackOptions) -> List[_Reference]:
    """Reference modes from the baseline records: seeded by the first, frequencies the median."""
    first = by_record[0][1]
    refs = [_Reference(int(r["mode"]), float(r["frequency_hz"]), _shape(r)) for _, r in first.iterrows()]
    matched: List[List[float]] = [[] for _ in refs]
    for _, cand in by_record[:max(1, opts.baseline_records)]:
        for i, j, _ in _match(cand, refs, opts):
            matched[i].append(float(cand["frequency_hz"].iloc[j]))
    for ref, freqs in zip(refs, matched):
        f = np.asarray(freqs)
        ref.frequency_hz = float(np.median(f))
        ref.spread = robust_sigma(f) / ref.frequency_hz
    return refs


def track_asset(rows: pd.DataFrame, opts: TrackOptions) -> List[Dict[str, Any]]:
    """Track rows of one asset (status ok, sorted in time): one dict per matched (record, mode)."""
    by_record = [(record, rows[rows["record"] == record]) for record in dict.fromkeys(rows["record"])]
    if not by_record:
        return []
    refs = _baseline(by_record, opts)
    out: List[Dict[str, Any]] = []
    for k, (record, cand) in enumerate(by_record):
        for i, j, m in sorted(_match(cand, refs, opts)):
            r = cand.iloc[j]
            f = float(r["frequency_hz"])
            point = {"asset": r["asset"], "mode": refs[i].mode, "record": record, "start": r["start"],
                     "frequency_hz": f, "damping_ratio": float(r["damping_ratio"]), "mac": m,
                     "reference_frequency_hz": refs[i].frequency_hz, "baseline_spread": refs[i].spread,
                     "frequency_change": f / refs[i].frequency_hz - 1, "baseline": k < opts.baseline_records}
            point.update(_covariates(r, record, opts.covariates))
            out.append(point)
    return out


def _covariates(row, record: str, names: Sequence[str]) -> Dict[str, float]:
    names_, values = row.get("covariate_names"), row.get("covariate_values")
    have = dict(zip(names_, values)) if names_ is not None and values is not None else {}
    missing = [n for n in names if n not in have]
    if missing:
        raise ValueError(f"record '{record}' has no covariate {', '.join(missing)} (identify it with "
                         f"--covariates {','.join(names)})")
    return {n: float(have[n]) for n in names}


TRACK_COLUMNS: List[str] = ["asset", "mode", "record", "start", "frequency_hz", "damping_ratio", "mac",
                            "reference_frequency_hz", "baseline_spread", "frequency_change", "baseline"]
CHART_COLUMNS: List[str] = ["compensated_hz", "compensated_change", "ewma", "ewma_limit", "alarm"]
SUMMARY_COLUMNS: List[str] = ["asset", "mode", "records", "reference_frequency_hz", "baseline_spread",
                              "frequency_change", "change_stderr", "drift", "trend_intercept_hz",
                              "trend_slope_hz_per_day", "damping_ratio_median", "alarms", "first_alarm"]
ALARM_COLUMNS: List[str] = ["asset", "mode", "record", "start", "compensated_change", "ewma", "ewma_limit"]


def track(modes: pd.DataFrame, opts: TrackOptions = TrackOptions(),
          asset: Optional[str] = None) -> Tuple[pd.DataFrame, pd.DataFrame]:
    """The track table (TRACK_COLUMNS) and the drift summary (SUMMARY_COLUMNS, one row per asset
    and reference mode) of a mode table."""
    import pandas as pd

    if opts.baseline_records < 1:
        raise ValueError(f"baseline records {opts.baseline_records}: at least 1")
    if not (0 < opts.ewma_lambda <= 1) or not opts.ewma_limit > 0:
        raise ValueError(f"EWMA lambda {opts.ewma_lambda} must lie in (0, 1] and its limit {opts.ewma_limit} be > 0")
    ok = modes[modes["status"] == "ok"]
    if asset is not None:
        ok = ok[ok["asset"] == asset]
        if ok.empty:
            raise ValueError(f"asset '{asset}' has no successful record")
    ok = ok.sort_values(["asset", "start", "record", "mode"], na_position="last", kind="stable")
    rows: List[Dict[str, Any]] = []
    for _, group in ok.groupby("asset", sort=True):
        rows.extend(track_asset(group, opts))
    tracks = pd.DataFrame(rows, columns=TRACK_COLUMNS + list(opts.covariates))
    charted = []
    for _, g in tracks.groupby(["asset", "mode"], sort=False):
        charted.append(pd.DataFrame(chart(g, opts.covariates, opts.ewma_lambda, opts.ewma_limit),
                                    columns=CHART_COLUMNS, index=g.index))
    tracks = tracks.join(pd.concat(charted) if charted else pd.DataFrame(columns=CHART_COLUMNS))
    return tracks, drift_summary(tracks, opts)


def alarms(tracks: pd.DataFrame) -> pd.DataFrame:
    """The alarms table: every tracked point past the baseline whose EWMA is beyond its limit."""
    return tracks.loc[tracks["alarm"].astype(bool), ALARM_COLUMNS].reset_index(drop=True)


def theil_sen(t: np.ndarray, f: np.ndarray) -> Tuple[float, float]:
    """Slope and intercept of the Theil-Sen line: the median of the pairwise slopes, and the median
    of f - slope t. Times must not all be equal."""
    if t.size > THEIL_SEN_MAX_POINTS:
        keep = np.linspace(0, t.size - 1, THEIL_SEN_MAX_POINTS).round().astype(int)
        t, f = t[keep], f[keep]
    i, j = np.triu_indices(t.size, k=1)
    dt = t[j] - t[i]
    slopes = (f[j] - f[i])[dt != 0] / dt[dt != 0]
    slope = float(np.median(slopes))
    return slope, float(np.median(f - slope * t))


def days_since_first(g: pd.DataFrame) -> np.ndarray:
    if g["start"].notna().all():
        return (g["start"] - g["start"].iloc[0]).dt.total_seconds().to_numpy(float) / 86400.0
    return np.arange(len(g), dtype=float)


def drift_summary(tracks: pd.DataFrame, opts: TrackOptions) -> pd.DataFrame:
    import pandas as pd

    out = []
    for (asset, mode), g in tracks.groupby(["asset", "mode"], sort=True):
        f = g["compensated_hz"].to_numpy(float)  # the frequencies themselves without covariates
        t = days_since_first(g)
        f_ref = float(g["reference_frequency_hz"].iloc[0])
        change = stderr = slope = 0.0
        intercept = f_ref
        if len(g) >= 3 and np.ptp(t) > 0:
            slope, intercept = theil_sen(t, f)
            resid = f - (intercept + slope * t)
            sigma = robust_sigma(resid)
            span = np.ptp(t)
            change = slope * span / f_ref
            stderr = sigma / np.sqrt(np.sum((t - t.mean()) ** 2)) * span / f_ref
        drift = abs(change) > max(opts.drift_min, 4 * stderr)
        out.append({"asset": asset, "mode": int(mode), "records": len(g), "reference_frequency_hz": f_ref,
                    "baseline_spread": float(g["baseline_spread"].iloc[0]), "frequency_change": change,
                    "change_stderr": stderr, "drift": bool(drift), "trend_intercept_hz": intercept,
                    "trend_slope_hz_per_day": slope,
                    "damping_ratio_median": float(np.median(g["damping_ratio"])),
                    "alarms": int(g["alarm"].sum()),
                    "first_alarm": g.loc[g["alarm"].astype(bool), "record"].iloc[0] if g["alarm"].any() else None})
    return pd.DataFrame(out, columns=SUMMARY_COLUMNS)
