# SPDX-License-Identifier: Apache-2.0
"""The classic stabilization diagram (model order against frequency) as a PNG, from the JSON of
``okid identify --json --stabilization NMAX``.

Each oscillating pole (complex pair) of each order is drawn at (frequency, order). Its marker says
how it compares with the nearest-frequency pole of the previous order, by the library's criteria
(okid/stabilization.h, carried in the JSON as stable_frequency/stable_damping/stable_shape):

- filled circle "stable": frequency within 1 %, damping ratio within 5 %, MAC of the sensor shapes >= 0.98;
- cross "frequency": frequency within 1 % only (damping or shape still moving);
- small dot "new": no pole of the previous order within 1 %.

Poles whose consistent mode indicator (CMI = EMAC x MPC) is below ``min_cmi`` are drawn in grey:
computational modes. Dashed vertical lines mark the modes of the identified model.

    okid identify --json --stabilization 20 --observer-order 60 --hankel-rows 100 --hankel-cols 100 rec.csv > rec.json
    okid-stabilization rec.json --output stabilization.png

Given a CSV record instead, it identifies it with okid.identify's defaults (the settings and the
physical modes chosen from the data, docs/quality.md section 8) and draws okid.plot_stabilization:
the physical modes with their spread across orders, the measured frequency response's singular
values behind.

    okid-stabilization rec.csv --inputs 2 --outputs 5 --output stabilization.png
"""
import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

KINDS = {  # kind: (marker, size, label)
    "stable": ("o", 36, "stable (f 1 %, damping 5 %, MAC 0.98)"),
    "frequency": ("x", 30, "stable in frequency only"),
    "new": (".", 20, "new or unstable"),
}


def load(source: Union[Dict[str, Any], str, Path]) -> Dict[str, Any]:
    """The result dict of ``okid identify --json``: from a dict, a path, or '-' (standard input)."""
    if isinstance(source, dict):
        return source
    if str(source) == "-":
        return json.load(sys.stdin)
    return json.loads(Path(source).read_text())


def classify(pole: Dict[str, Any]) -> str:
    """'stable', 'frequency' or 'new' from the library's flags of one pole of the diagram."""
    if pole["stable_frequency"] and pole["stable_damping"] and pole["stable_shape"]:
        return "stable"
    return "frequency" if pole["stable_frequency"] else "new"


def poles(result: Dict[str, Any], max_frequency: Optional[float] = None) -> List[Tuple[int, float, float, str, float]]:
    """(order, frequency_hz, damping_ratio, kind, cmi) of every oscillating pole of the diagram."""
    if "stabilization" not in result:
        raise ValueError("no 'stabilization' in the result: run okid identify with --stabilization NMAX")
    rows = []
    for entry in result["stabilization"]["orders"]:
        for pole in entry["modes"]:
            if not pole["is_pair"] or (max_frequency is not None and pole["frequency_hz"] > max_frequency):
                continue
            rows.append((entry["order"], pole["frequency_hz"], pole["damping_ratio"], classify(pole), pole["cmi"]))
    return rows


def plot_stabilization(source: Union[Dict[str, Any], str, Path], png: Union[str, Path],
                       max_frequency: Optional[float] = None, min_cmi: float = 0.5, title: Optional[str] = None) -> Path:
    """Draw the diagram of ``source`` (see load) into ``png``; returns the path written."""
    result = load(source)
    rows = poles(result, max_frequency)
    fig, ax = plt.subplots(figsize=(8, 5))
    for kind, (marker, size, label) in KINDS.items():
        for consistent in (True, False):
            pick = [r for r in rows if r[3] == kind and (r[4] >= min_cmi) == consistent]
            if not pick:
                continue
            ax.scatter([r[1] for r in pick], [r[0] for r in pick], marker=marker, s=size,
                       color=("C3" if kind == "stable" else "C0") if consistent else "0.7",
                       label=label if consistent else f"{label}, CMI < {min_cmi:g}")
    for mode in result.get("modes", []):
        if mode["is_pair"] and (max_frequency is None or mode["frequency_hz"] <= max_frequency):
            ax.axvline(mode["frequency_hz"], color="0.4", linestyle="--", linewidth=0.8)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order n")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title(title or f"Stabilization diagram (orders up to {result['stabilization']['max_order']}; "
                          f"dashed: identified n = {result.get('order', '?')})")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    png = Path(png)
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def plot_record(csv: Union[str, Path], png: Union[str, Path], inputs: Optional[str] = None, outputs: Optional[str] = None,
                max_frequency: Optional[float] = None) -> Path:
    """Identify a CSV record with okid.identify's defaults and draw okid.plot_stabilization into png."""
    import okid
    from okid.plot import plot_stabilization as draw
    rec = okid.read_record(csv, inputs=inputs, outputs=outputs)
    result = okid.identify(rec.u, rec.y, rec.dt)
    ax = draw(result, rec.u, rec.y, max_frequency=max_frequency)
    ax.set_title(f"{Path(csv).name}: " + ", ".join(f"{m.frequency_hz:.3f} Hz" for m in result.modes)
                 if result.modes else f"{Path(csv).name}: no physical mode found")
    png = Path(png)
    ax.figure.tight_layout()
    ax.figure.savefig(png, dpi=110)
    plt.close(ax.figure)
    return png


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(description="Stabilization diagram PNG from okid identify --json --stabilization, "
                                                 "or from a CSV record identified with the defaults.")
    parser.add_argument("source", metavar="FILE", help="the JSON file ('-' reads standard input) or a CSV record (.csv)")
    parser.add_argument("--output", "-o", default="stabilization.png", help="PNG to write (default stabilization.png)")
    parser.add_argument("--inputs", default=None, help="CSV: input columns, a count or names (as okid identify --inputs)")
    parser.add_argument("--outputs", default=None, help="CSV: output columns, a count or names (as okid identify --outputs)")
    parser.add_argument("--max-frequency", type=float, default=None, help="leave out poles above this [Hz]")
    parser.add_argument("--min-cmi", type=float, default=0.5, help="JSON: grey out poles with a lower CMI (default 0.5)")
    args = parser.parse_args(argv)
    try:
        if str(args.source).lower().endswith(".csv"):
            spec = [None if v is None else int(v) if v.isdigit() else v for v in (args.inputs, args.outputs)]
            path = plot_record(args.source, args.output, spec[0], spec[1], args.max_frequency)
        else:
            path = plot_stabilization(args.source, args.output, args.max_frequency, args.min_cmi)
    except Exception as err:  # noqa: BLE001 -- every refusal is one line (okid's errors name the value)
        print(f"okid-stabilization: {err}", file=sys.stderr)
        return 1
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
