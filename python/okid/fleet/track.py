# SPDX-License-Identifier: Apache-2.0
"""Modes tracked over time, asset by asset.

The reference modes of an asset are those of its first successful record (in time order). Every
later record's modes are matched to them: a candidate lies within the frequency tolerance of the
reference (relative) and its shape at the sensors has a MAC of at least ``mac_min`` with the
reference's; among candidates the nearest in frequency wins, each mode used once. The drift of a
tracked mode is the least-squares line of its frequency against time, evaluated from the first to
the last record, relative to the reference; it is reported as drift when it exceeds both
``drift_min`` and four standard errors of that change.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np


@dataclass(frozen=True)
class TrackOptions:
    frequency_tolerance: float = 0.05  #: relative distance from the reference frequency
    mac_min: float = 0.9               #: least MAC of the sensor shapes
    drift_min: float = 0.005           #: relative frequency change reported as drift (0.5 %)


def mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex shapes, in [0, 1]."""
    den = np.vdot(a, a).real * np.vdot(b, b).real
    return float(abs(np.vdot(a, b)) ** 2 / den) if den > 0 else 0.0


def _shape(row) -> np.ndarray:
    return np.asarray(row["shape_re"], dtype=float) + 1j * np.asarray(row["shape_im"], dtype=float)


def track_asset(rows, opts: TrackOptions) -> List[dict]:
    """Track rows of one asset (status ok, sorted in time): one dict per matched (record, mode)."""
    records = list(dict.fromkeys(rows["record"]))
    if not records:
        return []
    first = rows[rows["record"] == records[0]]
    refs = [(int(r["mode"]), float(r["frequency_hz"]), float(r["damping_ratio"]), _shape(r))
            for _, r in first.iterrows()]
    out: List[dict] = []
    for record in records:
        cand = rows[rows["record"] == record]
        pairs: List[Tuple[float, int, int, float]] = []
        for i, (_, f_ref, _, s_ref) in enumerate(refs):
            for j, (_, r) in enumerate(cand.iterrows()):
                df = abs(float(r["frequency_hz"]) - f_ref) / f_ref
                if df > opts.frequency_tolerance:
                    continue
                m = mac(_shape(r), s_ref)
                if m >= opts.mac_min:
                    pairs.append((df, i, j, m))
        used_ref, used_cand = set(), set()
        for df, i, j, m in sorted(pairs):
            if i in used_ref or j in used_cand:
                continue
            used_ref.add(i)
            used_cand.add(j)
            r = cand.iloc[j]
            out.append({"asset": r["asset"], "mode": refs[i][0], "record": record, "start": r["start"],
                        "frequency_hz": float(r["frequency_hz"]), "damping_ratio": float(r["damping_ratio"]),
                        "mac": m, "reference_frequency_hz": refs[i][1],
                        "frequency_change": float(r["frequency_hz"]) / refs[i][1] - 1})
    return out


def track(modes, opts: TrackOptions = TrackOptions(), asset: Optional[str] = None):
    """The track table (asset, mode, record, start, frequency_hz, damping_ratio, mac, reference_frequency_hz,
    frequency_change) and the drift summary (one row per asset and reference mode) of a mode table."""
    import pandas as pd

    ok = modes[modes["status"] == "ok"]
    if asset is not None:
        ok = ok[ok["asset"] == asset]
        if ok.empty:
            raise ValueError(f"asset '{asset}' has no successful record")
    ok = ok.sort_values(["asset", "start", "record", "mode"], na_position="last", kind="stable")
    rows: List[dict] = []
    for _, group in ok.groupby("asset", sort=True):
        rows.extend(track_asset(group, opts))
    tracks = pd.DataFrame(rows, columns=["asset", "mode", "record", "start", "frequency_hz", "damping_ratio", "mac",
                                         "reference_frequency_hz", "frequency_change"])
    return tracks, drift_summary(tracks, opts)


def drift_summary(tracks, opts: TrackOptions):
    import pandas as pd

    out = []
    for (asset, mode), g in tracks.groupby(["asset", "mode"], sort=True):
        f = g["frequency_hz"].to_numpy(float)
        if g["start"].notna().all():
            t = (g["start"] - g["start"].iloc[0]).dt.total_seconds().to_numpy(float) / 86400.0
        else:
            t = np.arange(len(g), dtype=float)
        f_ref = float(g["reference_frequency_hz"].iloc[0])
        change = stderr = 0.0
        if len(g) >= 3 and np.ptp(t) > 0:
            design = np.column_stack([np.ones_like(t), t - t.mean()])
            coef, *_ = np.linalg.lstsq(design, f, rcond=None)
            resid = f - design @ coef
            sigma = np.sqrt(resid @ resid / (len(f) - 2))
            span = np.ptp(t)
            slope_se = sigma / np.sqrt(np.sum((t - t.mean()) ** 2))
            change = coef[1] * span / f_ref
            stderr = slope_se * span / f_ref
        drift = abs(change) > max(opts.drift_min, 4 * stderr)
        out.append({"asset": asset, "mode": int(mode), "records": len(g), "reference_frequency_hz": f_ref,
                    "frequency_change": change, "change_stderr": stderr, "drift": bool(drift),
                    "damping_ratio_median": float(np.median(g["damping_ratio"]))})
    return pd.DataFrame(out, columns=["asset", "mode", "records", "reference_frequency_hz", "frequency_change",
                                      "change_stderr", "drift", "damping_ratio_median"])
