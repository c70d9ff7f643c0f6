#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""`okid identify` with nothing but the channel counts on the other events of the development
records' bridges, and of the Painter Street Overpass, as mdof's repository (Chern et al., the
records' own source, https://github.com/chrystalchern/mdof) holds them in notebooks/uploads:
records no setting of okid was derived from (docs/quality.md section 8, "Other events").

Each CSMIP V2 zip of a folder is converted in memory to the layout of tests/data/real (the
transverse channel sets of mdof's channel_conf.py; zips without them, or not zips, are skipped)
and identified; one line per record gives the modes reported. With --compare OTHER_CLI a second
column gives another build's modes (for example the previous commit's).

    git clone https://github.com/chrystalchern/mdof /path/to/mdof
    .venv/bin/python scripts/other_events.py /path/to/mdof [--compare /other/build/okid]
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import zipfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
# structure: (folder in mdof, input channels, output channels), CSMIP station channel numbers
STRUCTURES = {
    "painter": ("notebooks/uploads/CE89324", [3, 17, 20], [7, 9, 4]),       # Rio Dell, Hwy 101/Painter St
    "hayward": ("notebooks/uploads/hayward", [25, 2, 7, 18], [23, 13, 15, 20]),  # Hwy 580/238 interchange
    "meloland": ("notebooks/uploads/meloland", [11, 2, 26], [5, 7, 9]),      # Hwy 8/Meloland overpass
}


def read_v2(text):
    """A CSMIP V2 channel: (acceleration [cm/s^2], dt [s]) (the layout of tests/data/real's source)."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"\s*(\d+)\s+points of accel data equally spaced at\s+([.\d]+)\s+sec", line, re.IGNORECASE)
        if m:
            n, vals, j = int(m.group(1)), [], i + 1
            while len(vals) < n:
                row = lines[j]
                vals += [float(row[k:k + 10]) for k in range(0, 80, 10) if row[k:k + 10].strip()][:n - len(vals)]
                j += 1
            return np.asarray(vals), float(m.group(2))
    raise ValueError("no acceleration block")


def record(zip_path, channels):
    """The channels of a zip as one (t, columns) array, or None when a channel is missing."""
    try:
        with zipfile.ZipFile(zip_path) as z:
            names = z.namelist()
            cols, dt = [], None
            for c in channels:
                name = next((nm for nm in names if re.fullmatch(rf"(?i)chan0*{c}\.v2", nm)), None)
                if name is None:
                    return None, None
                a, d = read_v2(z.read(name).decode("latin-1"))
                if dt is not None and abs(d - dt) > 1e-9:
                    return None, None
                cols.append(a)
                dt = d
    except (zipfile.BadZipFile, ValueError):
        return None, None
    n = min(len(a) for a in cols)
    return np.column_stack([np.arange(n) * dt] + [a[:n] for a in cols]), dt


def modes(cli, path, r, m):
    out = subprocess.run([cli, "identify", "--json", "--inputs", str(r), "--outputs", str(m), str(path)],
                         capture_output=True, text=True, timeout=600)
    if out.returncode != 0:
        return "failed: " + (out.stderr.strip().splitlines() or ["?"])[-1][:60]
    found = json.loads(out.stdout)["modes"]
    return ", ".join(f"{md['frequency_hz']:.2f}" for md in found) or "none"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mdof", help="a clone of mdof's repository")
    ap.add_argument("--okid", default=str(ROOT / "build" / "host_tools" / "cli" / "okid"))
    ap.add_argument("--compare", help="another okid CLI: its modes in a second column")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for key, (folder, ins, outs) in STRUCTURES.items():
            for zip_path in sorted(pathlib.Path(args.mdof, folder).glob("*")):
                if zip_path.suffix.lower() != ".zip":
                    continue
                data, dt = record(zip_path, ins + outs)
                if data is None:
                    continue
                csv = pathlib.Path(tmp) / f"{key}_{zip_path.stem}.csv"
                header = ",".join(["t"] + [f"in{c}" for c in ins] + [f"out{c}" for c in outs])
                np.savetxt(csv, data, delimiter=",", header=header, comments="", fmt=["%.3f"] + ["%.6g"] * (data.shape[1] - 1))
                peak = np.abs(data[:, 1 + len(ins):]).max()
                line = f"| {key} | {zip_path.stem} | {data.shape[0]} x {dt:g} s | {peak:.0f} | {modes(args.okid, csv, len(ins), len(outs))} |"
                if args.compare:
                    line += f" {modes(args.compare, csv, len(ins), len(outs))} |"
                print(line, flush=True)


if __name__ == "__main__":
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    sys.exit(main())
