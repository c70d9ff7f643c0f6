# SPDX-License-Identifier: Apache-2.0
"""The tracks plot, one row of two panels per asset: each tracked mode's frequency as its change
from the reference record [%] (so a drift of a fraction of a percent shows), and its damping ratio
[%], against time."""
from __future__ import annotations

from typing import Optional

MAX_ASSETS = 12  # panels beyond this are unreadable: name an asset instead


def plot_tracks(tracks, summary, path: str, asset: Optional[str] = None) -> int:
    """Draw TRACKS (the track table) to PATH (PNG); returns the number of assets drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    assets = sorted(tracks["asset"].unique()) if asset is None else [asset]
    if asset is not None and asset not in set(tracks["asset"]):
        raise ValueError(f"asset '{asset}' has no track")
    shown = assets[:MAX_ASSETS]
    fig, axes = plt.subplots(len(shown), 2, figsize=(11, 2.4 * len(shown) + 0.6), squeeze=False, sharex="col")
    for row, name in enumerate(shown):
        g = tracks[tracks["asset"] == name]
        drifting = set(summary[(summary["asset"] == name) & summary["drift"]]["mode"])
        for mode, gm in g.groupby("mode"):
            label = f"mode {mode}, {gm['reference_frequency_hz'].iloc[0]:.3f} Hz" + (" (drift)" if mode in drifting else "")
            x = gm["start"] if gm["start"].notna().all() else range(len(gm))
            axes[row][0].plot(x, 100 * gm["frequency_change"], marker=".", label=label)
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
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return len(shown)
