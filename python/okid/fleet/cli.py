# SPDX-License-Identifier: Apache-2.0
"""okid-fleet: identify many records on Dask, track their modes over time, make a synthetic fleet.

    okid-fleet synth --assets 8 --records 24 --out fleet/
    okid-fleet identify fleet/records --out modes.parquet --order 4 --zero-initial-state
    okid-fleet track modes.parquet --out tracks.parquet --plot tracks.png
"""
from __future__ import annotations

import argparse
import sys
from typing import List, Optional

EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _add_okid_options(p: argparse.ArgumentParser) -> None:
    """okid identify's settings, named as okid_config's fields (docs/cli.md), defaults from the library."""
    import okid

    g = p.add_argument_group("identification (okid_config; defaults from okid_config_default)")
    for name in okid.OPTION_NAMES:
        default = okid.DEFAULTS[name]
        if name == "zero_initial_state":
            g.add_argument(_flag(name), dest=name, action="store_const", const=1, default=None,
                           help="the records start at rest")
            continue
        kind = type(default)
        g.add_argument(_flag(name), dest=name, type=kind, default=None, metavar=kind.__name__.upper(),
                       help=f"default {default}")
    c = p.add_argument_group("channels (as okid identify)")
    c.add_argument("--inputs", default="1", help="input columns: a count or comma-separated names (default 1)")
    c.add_argument("--outputs", default=None, help="output columns: a count or names (default: the rest)")
    c.add_argument("--dt", type=float, default=None, help="sample interval [s] of CSV files without a time column")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="okid-fleet", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)

    i = sub.add_parser("identify", help="identify every record (one row per record and mode)")
    i.add_argument("records", nargs="+", metavar="RECORDS",
                   help="CSV files, globs, folders of CSV files, Parquet files or folders")
    i.add_argument("--out", required=True, help="output folder of Parquet parts (e.g. modes.parquet)")
    i.add_argument("--scheduler", help="tcp://HOST:PORT of a running Dask scheduler (default: a local cluster)")
    i.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    i.add_argument("--batch-size", type=int, help="records per task (default: about 4 tasks per worker, <= 50)")
    i.add_argument("--resume", action="store_true", help="skip the records already in --out")
    i.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    i.add_argument("--quiet", action="store_true", help="no progress")
    _add_okid_options(i)

    t = sub.add_parser("track", help="match each asset's modes to its reference over time")
    t.add_argument("modes", help="the output of okid-fleet identify")
    t.add_argument("--out", required=True, help="the track table (Parquet file)")
    t.add_argument("--plot", help="draw frequencies and damping ratios against time (PNG)")
    t.add_argument("--asset", help="only this asset")
    t.add_argument("--summary", help="also write the drift summary (CSV)")
    t.add_argument("--frequency-tolerance", type=float, default=0.05, help="relative (default 0.05)")
    t.add_argument("--mac-min", type=float, default=0.9, help="least MAC to the reference shape (default 0.9)")
    t.add_argument("--drift-min", type=float, default=0.005, help="relative change called drift (default 0.005)")

    s = sub.add_parser("synth", help="write a synthetic fleet (okid's simulator) and its exact modes")
    s.add_argument("--out", required=True, help="folder: records/ and truth.parquet go there")
    s.add_argument("--assets", type=int, default=8)
    s.add_argument("--records", type=int, default=24, help="records per asset")
    s.add_argument("--damaged", type=int, help="assets losing stiffness (default: a third)")
    s.add_argument("--stiffness-loss", type=float, default=0.06, help="fraction lost by the last record")
    s.add_argument("--masses", type=int, default=2, help="masses per chain (2: the paper's system)")
    s.add_argument("--samples", type=int, default=2000)
    s.add_argument("--dt", type=float, default=0.05, help="sample interval [s]")
    s.add_argument("--noise", type=float, default=0.02, help="output noise relative to each channel's RMS")
    s.add_argument("--interval-minutes", type=float, default=10.0)
    s.add_argument("--seed", type=int, default=1)
    s.add_argument("--format", choices=("parquet", "csv"), default="parquet")
    return p


def _identify(a) -> int:
    import okid

    from .job import FleetError, Interrupted, identify_fleet
    from .records import ChannelSpec, RecordError

    options = {name: getattr(a, name) for name in okid.OPTION_NAMES if getattr(a, name) is not None}
    try:
        summary = identify_fleet(a.records, a.out, options=options,
                                 channels=ChannelSpec(a.inputs, a.outputs, a.dt), scheduler=a.scheduler,
                                 workers=a.workers, batch_size=a.batch_size, resume=a.resume,
                                 overwrite=a.overwrite, progress=None if a.quiet else sys.stderr)
    except Interrupted as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (FleetError, RecordError) as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_ERROR
    rate = summary.records / summary.seconds if summary.seconds > 0 else float("nan")
    print(f"okid-fleet: {summary.records} records identified ({summary.failed} failed, {summary.skipped} already "
          f"done) in {summary.seconds:.2f} s on {summary.workers} worker(s), {rate:.1f} records/s, "
          f"{summary.batches} tasks; {summary.rows} rows in {a.out}")
    return EXIT_OK


def _track(a) -> int:
    from .job import read_modes
    from .plot import plot_tracks
    from .track import TrackOptions, track

    modes = read_modes(a.modes)
    if modes.empty:
        print(f"okid-fleet: {a.modes} holds no rows", file=sys.stderr)
        return EXIT_ERROR
    try:
        tracks, summary = track(modes, TrackOptions(a.frequency_tolerance, a.mac_min, a.drift_min), a.asset)
    except ValueError as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_ERROR
    tracks.to_parquet(a.out, index=False)
    if a.summary:
        summary.to_csv(a.summary, index=False)
    if a.plot:
        plot_tracks(tracks, summary, a.plot, a.asset)
    with_drift = summary[summary["drift"]]
    print(f"okid-fleet: {len(tracks)} tracked points of {summary['asset'].nunique()} asset(s) in {a.out}; "
          f"drift in {len(with_drift)} of {len(summary)} tracked modes")
    for _, r in summary.iterrows():
        print(f"  {r['asset']} mode {r['mode']}: {r['reference_frequency_hz']:.4f} Hz, change "
              f"{100 * r['frequency_change']:+.2f} % (+- {100 * r['change_stderr']:.2f}) over {r['records']} "
              f"records{'  DRIFT' if r['drift'] else ''}")
    return EXIT_OK


def _synth(a) -> int:
    from .synth import FleetSpec, synthesize

    spec = FleetSpec(assets=a.assets, records=a.records, damaged=a.damaged, stiffness_loss=a.stiffness_loss,
                     masses=a.masses, samples=a.samples, dt=a.dt, noise=a.noise,
                     interval_minutes=a.interval_minutes, seed=a.seed, fmt=a.format)
    try:
        info = synthesize(a.out, spec)
    except ValueError as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_USAGE
    print(f"okid-fleet: {info['records']} records in {info['records_dir']}, exact modes in {info['truth']}; "
          f"losing stiffness: {', '.join(info['damaged'])}")
    return EXIT_OK


def main(argv: Optional[List[str]] = None) -> int:
    a = _parser().parse_args(argv)
    return {"identify": _identify, "track": _track, "synth": _synth}[a.command](a)


if __name__ == "__main__":
    sys.exit(main())
