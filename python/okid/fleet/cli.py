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

EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_FAILED_RECORDS, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
MAX_FAILED_FRACTION = 0.5  # more records failed than this (or all of them): the job did not work


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
    g.add_argument("--decimation-method", dest="decimation_method", choices=("filter", "lift"), default=None,
                   help="with --decimation K: the anti-alias filter (default; biased) or lifting (exact: K r inputs "
                   "at K dt; the rows' dt is K dt), as okid identify's")
    c = p.add_argument_group("channels (as okid identify)")
    c.add_argument("--inputs", default="1", help="input columns: a count or comma-separated names (default 1); 0: "
                   "output-only records, identified by okid.identify_ambient (--hankel-rows, --order, --sensing)")
    c.add_argument("--outputs", default=None, help="output columns: a count or names (default: the rest)")
    c.add_argument("--dt", type=float, default=None, help="sample interval [s] of CSV files without a time column")
    c.add_argument("--covariates", default="", metavar="NAMES",
                   help="comma-separated columns that are no channel (temperature, load): their mean per record "
                   "goes to the table, for okid-fleet track --covariates")


def _first_line(exc: BaseException) -> str:
    """An exception's message for a one-line refusal."""
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _names(text: str) -> tuple:
    return tuple(n.strip() for n in text.split(",") if n.strip())


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="okid-fleet", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)

    i = sub.add_parser("identify", help="identify every record (one row per record and mode)")
    i.add_argument("records", nargs="+", metavar="RECORDS",
                   help="CSV files, globs, folders of CSV files, Parquet files or folders; local or fsspec URLs "
                   "(s3://bucket/records, gs://...)")
    i.add_argument("--out", required=True, help="output folder of Parquet parts (e.g. modes.parquet, "
                   "s3://bucket/modes)")
    i.add_argument("--scheduler", help="tcp://HOST:PORT of a running Dask scheduler (default: a local cluster)")
    i.add_argument("--scheduler-file", help="the JSON file a running Dask scheduler wrote (dask scheduler "
                   "--scheduler-file)")
    i.add_argument("--connect-timeout", type=float, default=20.0,
                   help="seconds a scheduler may take to answer (default 20)")
    i.add_argument("--max-failed-fraction", type=float, default=MAX_FAILED_FRACTION,
                   help=f"exit with status {EXIT_FAILED_RECORDS} when more than this fraction of the records "
                   f"failed, or all of them (default {MAX_FAILED_FRACTION})")
    i.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    i.add_argument("--batch-size", type=int, help="records per task (default: about 4 tasks per worker, <= 50)")
    i.add_argument("--resume", action="store_true",
                   help="skip the records already in --out (refused when --out was written with other settings)")
    i.add_argument("--overwrite", action="store_true",
                   help="remove the parts of an earlier job in --out first (only the files okid-fleet wrote)")
    i.add_argument("--record-timeout", type=float, metavar="SECONDS",
                   help="seconds one record may take to read and identify; past it the record is a timed_out row "
                   "and its worker is restarted (default: no limit)")
    i.add_argument("--max-record-mb", type=float, metavar="MB",
                   help="a record larger than this (its CSV file, or its Parquet row groups uncompressed; MB = 1e6 "
                   "bytes) is a too_large row, never read (default: no limit)")
    i.add_argument("--memory-limit", metavar="BYTES",
                   help="memory of each local worker, as Dask takes it (e.g. 2GiB; default: the machine's, shared); "
                   "a worker past 95 %% of it is restarted and its record ends as worker_died")
    i.add_argument("--quiet", action="store_true", help="no progress")
    _add_okid_options(i)

    t = sub.add_parser("track", help="match each asset's modes to its baseline over time, robust trends")
    t.add_argument("modes", help="the output of okid-fleet identify")
    t.add_argument("--out", required=True, help="the track table (Parquet file)")
    t.add_argument("--plot", help="draw frequencies and damping ratios against time (PNG)")
    t.add_argument("--asset", help="only this asset")
    t.add_argument("--summary", help="also write the drift summary (CSV)")
    t.add_argument("--frequency-tolerance", type=float, default=0.05, help="relative (default 0.05)")
    t.add_argument("--mac-min", type=float, default=0.9, help="least MAC to the reference shape (default 0.9)")
    t.add_argument("--drift-min", type=float, default=0.005, help="relative change called drift (default 0.005)")
    t.add_argument("--baseline-records", type=int, default=5,
                   help="the first records of each asset whose median modes are the reference (default 5; with "
                   "--covariates, enough to span their range)")
    t.add_argument("--covariates", default="", metavar="NAMES",
                   help="covariates (identified with --covariates) regressed out of the frequencies over the baseline")
    t.add_argument("--ewma-lambda", type=float, default=0.2, help="weight of the newest record in the EWMA chart "
                   "(default 0.2)")
    t.add_argument("--ewma-limit", type=float, default=3.5,
                   help="the chart's limit in EWMA standard deviations (default 3.5: about 2900 records between "
                   "false alarms)")
    t.add_argument("--alarms", help="also write the alarms table (CSV)")

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
    s.add_argument("--damage-start", type=int, help="the record from which the stiffness loss is whole (default: a "
                   "ramp over all records)")
    s.add_argument("--temperature-swing", type=float, default=0.0,
                   help="relative frequency swing by a temperature cycle, e.g. 0.02 (default 0: no temperature)")
    s.add_argument("--temperature-period", type=int, default=24, help="records per temperature cycle (default 24)")
    s.add_argument("--damping-scale", type=float, default=1.0,
                   help="scale the dampers (default 1: the paper's 16 and 34 %% damping; 0.1: 1.6 and 3.4 %%)")
    s.add_argument("--ambient", action="store_true",
                   help="leave the force out of the records (unmeasured excitation: identify with --inputs 0)")
    return p


def _identify(a) -> int:
    import okid

    from .job import FleetError, Interrupted, Limits, identify_fleet
    from .records import ChannelSpec, RecordError
    from .rows import check_options

    options = {name: getattr(a, name) for name in (*okid.OPTION_NAMES, "decimation_method")
               if getattr(a, name) is not None}
    if a.scheduler and a.scheduler_file:
        print("okid-fleet: --scheduler and --scheduler-file name the same thing: give one", file=sys.stderr)
        return EXIT_USAGE
    if a.memory_limit and (a.scheduler or a.scheduler_file):
        print("okid-fleet: --memory-limit is the local cluster's: a running cluster's workers have their own "
              "(dask worker --memory-limit)", file=sys.stderr)
        return EXIT_USAGE
    for flag, value in (("--workers", a.workers), ("--batch-size", a.batch_size)):
        if value is not None and value < 1:
            print(f"okid-fleet: {flag} {value}: a count >= 1", file=sys.stderr)
            return EXIT_USAGE
    if not 0 <= a.max_failed_fraction <= 1:
        print(f"okid-fleet: --max-failed-fraction {a.max_failed_fraction}: a fraction in [0, 1]", file=sys.stderr)
        return EXIT_USAGE
    limits = Limits(a.record_timeout, a.max_record_mb)
    channels = ChannelSpec(a.inputs, a.outputs, a.dt, _names(a.covariates))
    try:
        limits.check()
        check_options(options, channels)
    except (FleetError, ValueError) as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_USAGE
    try:
        summary = identify_fleet(a.records, a.out, options=options,
                                 channels=channels, scheduler=a.scheduler,
                                 scheduler_file=a.scheduler_file, workers=a.workers, batch_size=a.batch_size,
                                 resume=a.resume, overwrite=a.overwrite, connect_timeout=a.connect_timeout,
                                 progress=None if a.quiet else sys.stderr, memory_limit=a.memory_limit,
                                 limits=limits)
    except Interrupted as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (FleetError, RecordError) as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except OSError as exc:  # storage that refuses (no credentials, no bucket, no permission)
        print(f"okid-fleet: {type(exc).__name__}: {_first_line(exc)}", file=sys.stderr)
        return EXIT_ERROR
    rate = summary.records / summary.seconds if summary.seconds > 0 else float("nan")
    print(f"okid-fleet: {summary.records} records identified ({summary.failed} failed, {summary.skipped} already "
          f"done) in {summary.seconds:.2f} s on {summary.workers} worker(s), {rate:.1f} records/s, "
          f"{summary.batches} tasks; {summary.rows} rows in {a.out}")
    for status, count, message in summary.failures:
        print(f"  {count} {status}, e.g. {message}")
    if summary.too_many_failed(a.max_failed_fraction):
        print(f"okid-fleet: {summary.failed} of {summary.records} records failed (more than "
              f"{100 * a.max_failed_fraction:g} % or all): the job did not work", file=sys.stderr)
        return EXIT_FAILED_RECORDS
    return EXIT_OK


def _track(a) -> int:
    from .job import read_modes
    from .plot import plot_tracks
    from .storage import StorageError, resolve
    from .track import TrackOptions, alarms, track

    try:
        fs, path = resolve(a.modes)
        if not fs.exists(path):
            print(f"okid-fleet: {a.modes}: no such file or folder", file=sys.stderr)
            return EXIT_ERROR
        modes = read_modes(a.modes)
    except (OSError, StorageError) as exc:
        print(f"okid-fleet: {a.modes}: {_first_line(exc)}", file=sys.stderr)
        return EXIT_ERROR
    if modes.empty:
        print(f"okid-fleet: {a.modes} holds no rows", file=sys.stderr)
        return EXIT_ERROR
    try:
        tracks, summary = track(modes, TrackOptions(a.frequency_tolerance, a.mac_min, a.drift_min, a.baseline_records,
                                                    _names(a.covariates), a.ewma_lambda, a.ewma_limit), a.asset)
    except ValueError as exc:
        print(f"okid-fleet: {exc}", file=sys.stderr)
        return EXIT_ERROR
    try:
        tracks.to_parquet(a.out, index=False)
        if a.summary:
            summary.to_csv(a.summary, index=False)
        if a.alarms:
            alarms(tracks).to_csv(a.alarms, index=False)
        if a.plot:
            plot_tracks(tracks, summary, a.plot, a.asset)
    except OSError as exc:  # a folder that does not exist, no permission, a full disk
        print(f"okid-fleet: {_first_line(exc)}", file=sys.stderr)
        return EXIT_ERROR
    with_drift = summary[summary["drift"]]
    print(f"okid-fleet: {len(tracks)} tracked points of {summary['asset'].nunique()} asset(s) in {a.out}; "
          f"drift in {len(with_drift)} of {len(summary)} tracked modes")
    for _, r in summary.iterrows():
        print(f"  {r['asset']} mode {r['mode']}: {r['reference_frequency_hz']:.4f} Hz, change "
              f"{100 * r['frequency_change']:+.2f} % (+- {100 * r['change_stderr']:.2f}) over {r['records']} "
              f"records{'  DRIFT' if r['drift'] else ''}"
              + (f"  ALARM from {r['first_alarm']} ({r['alarms']} records)" if r["alarms"] else ""))
    return EXIT_OK


def _synth(a) -> int:
    from .synth import FleetSpec, synthesize

    spec = FleetSpec(assets=a.assets, records=a.records, damaged=a.damaged, stiffness_loss=a.stiffness_loss,
                     masses=a.masses, samples=a.samples, dt=a.dt, noise=a.noise,
                     interval_minutes=a.interval_minutes, seed=a.seed, fmt=a.format, damage_start=a.damage_start,
                     temperature_swing=a.temperature_swing, temperature_period=a.temperature_period,
                     ambient=a.ambient, damping_scale=a.damping_scale)
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
