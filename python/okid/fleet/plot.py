# SPDX-License-Identifier: Apache-2.0
"""The tracks plot, one row of two panels per asset: each tracked mode's frequency as its change
from the baseline's median [%] (so a drift of a fraction of a percent shows), with the baseline's
band (+- 3 robust standard deviations) and the Theil-Sen trend, and its damping ratio [%], against
time. Every asset shares one relative scale, so that 0.2 % of noise does not look like a drift."""
from __future__ import annotations

from typing import TYPE_CHECKING, Optional

from .track import days_since_first

if TYPE_CHECKING:  # for the annotations only: pandas is the fleet extra's
    import pandas as pd

MAX_ASSETS: int = 12  # panels beyond this are unreadable: name an asset instead


def plot_tracks(tracks: pd.DataFrame, summary: pd.DataFrame, path: str, asset: Optional[str] = None) -> int:
    """Draw TRACKS (the track table) to PATH (PNG); returns the number of assets drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    assets = sorted(tracks["asset"].unique()) if asset is None else [asset]
    if asset is not None and asset not in set(tracks["asset"]):
        raise ValueError(f"asset '{asset}' has no track")
    shown = assets[:MAX_ASSETS]
    fig, axes = plt.subplots(len(shown), 2, figsize=(11, 2.4 * len(shown) + 0.6), squeeze=False, sharex="col",
                             sharey="col")
    for row, name in enumerate(shown):
        g = tracks[tracks["asset"] == name]
        drifting = set(summary[(summary["asset"] == name) & summary["drift"]]["mode"])
        for mode, gm in g.groupby("mode"):
            label = f"mode {mode}, {gm['reference_frequency_hz'].iloc[0]:.3f} Hz" + (" (drift)" if mode in drifting else "")
            x = gm["start"] if gm["start"].notna().all() else range(len(gm))
            line, = axes[row][0].plot(x, 100 * gm["frequency_change"], marker=".", linestyle="none", label=label)
            band = 300 * float(gm["baseline_spread"].iloc[0])
            axes[row][0].fill_between(x, -band, band, color=line.get_color(), alpha=0.12, linewidth=0)
            trend = summary[(summary["asset"] == name) & (summary["mode"] == mode)]
            if not trend.empty:
                t = days_since_first(gm)
                f = trend["trend_intercept_hz"].iloc[0] + trend["trend_slope_hz_per_day"].iloc[0] * t
                axes[row][0].plot(x, 100 * (f / trend["reference_frequency_hz"].iloc[0] - 1), color=line.get_color(),
                                  linewidth=1.5)
            axes[row][1].plot(x, 100 * gm["damping_ratio"], marker=".", label=label)
        axes[row][0].set_ylabel(f"{name}\nfrequency change [%]")
        axes[row][1].set_ylabel("damping ratio [%]")
        axes[row][0].legend(fontsize="small", loc="best")
        axes[row][0].grid(True, alpha=0.3)
        axes[row][1].grid(True, alpha=0.3)
    title = "okid-fleet: identified modes against time"
    if len(assets) > len(shown):
        title += f" (first {len(shown)} of {len(assets)} assets; --asset NAME for another)"
    fig.suptitle(title)
    fig.autofmt_xdate()
    fig.tight_layout(rect=(0, 0, 1, 0.97))  # room for the title above the first row
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return len(shown)
