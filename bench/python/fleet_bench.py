# SPDX-License-Identifier: Apache-2.0
"""The fleet benchmark: records per second with 1 and 2 local workers, the scheduler's cost per
task, the cost of one realistic record, and a projection to a cluster. Prints figures and writes
them to bench/results.json ("fleet") and docs/fleet.md's measured table; nothing is timed against
a limit.

    .venv/bin/python bench/python/fleet_bench.py [--records 96] [--samples 60000] [--results bench/results.json]
    .venv/bin/python bench/python/fleet_bench.py --folder-records 1000 [--samples 2000]   # a folder of CSV files
    .venv/bin/python bench/python/fleet_bench.py --lightly-damped [--light-records 16]  # one realistic record, several settings
"""
from __future__ import annotations

import os

# one BLAS thread (the workers' setting, one task a core): time.process_time would count the idle
# spinning of OpenBLAS's other threads; set before numpy loads its BLAS
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import logging  # noqa: E402
import platform  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from okid.fleet.job import identify_fleet  # noqa: E402
from okid.fleet.synth import FleetSpec, synthesize  # noqa: E402

OPTIONS = {"order": 4, "zero_initial_state": 1}


def _warm_up() -> None:
    import okid.fleet.rows  # noqa: F401  (the task's imports: numpy, pyarrow, okid)
    import pyarrow.parquet  # noqa: F401


def records_per_second(records_dir: str, workers: int, out_dir: str, options: dict = OPTIONS) -> float:
    """Steady state: a local cluster of WORKERS processes whose imports are done before the clock
    starts (a long job pays them once; here they would be a second of a few-second run)."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        client.run(_warm_up)
        summary = identify_fleet([records_dir], out_dir, options=options, scheduler=cluster.scheduler_address,
                                 progress=None, overwrite=True)
    assert summary.failed == 0, "the benchmark fleet must identify"
    return summary.records / summary.seconds


def folder_records_per_second(records: int, samples: int, workers: int = 2) -> dict:
    """The whole identify command's work on a folder of RECORDS CSV files (one a record, as okid
    simulate writes them) on a warmed-up local cluster of WORKERS: listing the folder, then
    identifying (records/s of the job's own clock, and of the wall time listing included)."""
    from distributed import Client, LocalCluster

    with tempfile.TemporaryDirectory() as tmp:
        assets = max(1, records // 100)
        spec = FleetSpec(assets=assets, records=records // assets, samples=samples, seed=2, fmt="csv")
        synthesize(os.path.join(tmp, "fleet"), spec)
        folder = os.path.join(tmp, "fleet", "records")
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                          silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
            client.run(_warm_up)
            t0 = time.perf_counter()
            summary = identify_fleet([folder], os.path.join(tmp, "out"), options=OPTIONS,
                                     scheduler=cluster.scheduler_address, progress=None)
            wall = time.perf_counter() - t0
    assert summary.failed == 0, "the benchmark fleet must identify"
    return {"records": summary.records, "samples": samples, "workers": workers,
            "records_per_s": summary.records / summary.seconds, "records_per_s_wall": summary.records / wall,
            "before_identifying_s": wall - summary.seconds}


def scheduler_overhead_per_task(tasks: int = 2000) -> float:
    """Seconds per empty task on a 2-worker local cluster (submit to result)."""
    from distributed import Client, LocalCluster, wait

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        client.submit(int, 0).result()  # warm up
        t0 = time.perf_counter()
        futures = [client.submit(int, i, pure=False) for i in range(tasks)]
        wait(futures)
        return (time.perf_counter() - t0) / tasks


def _chain_record(masses: np.ndarray, dampers: np.ndarray, springs: np.ndarray, samples: int, seed: int = 1):
    """A chain between two walls, one force on mass 1, every mass's acceleration with 2 % noise, at
    100 Hz: (u, y, the continuous state matrix); seed draws the force and the noise."""
    from okid import model

    n = len(masses)
    m_, r_, k_ = model.chain_model(masses, dampers, springs)
    b2 = np.zeros((n, 1))
    b2[0, 0] = 1
    ac, bc, c, d = model.state_space(m_, r_, k_, b2, acceleration=np.eye(n))
    a, b = model.discretize_zoh(ac, bc, 0.01)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    y, _ = model.simulate(a, b, c, d, u)
    return u, y + 0.02 * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape), ac


def wide_record_seconds(samples: int, repeats: int = 3) -> dict:
    """One record of the projection's shape: 24 accelerometers on a 24-mass chain, one force, 10
    minutes at 100 Hz, identified in process (the work a task does per record, file reading aside)."""
    import okid

    from okid.fleet.synth import chain

    u, y, _ = _chain_record(*chain(24), samples)
    options = dict(observer_order=4, order=48, hankel_rows=20, hankel_cols=80)
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        okid.identify(u, y, 0.01, **options)
        best = min(best, time.perf_counter() - t0)
    return {"seconds": best, "samples": samples, "outputs": 24, "options": options}


#: the settings tried on the lightly damped structure, cheapest first; the last is the cheapest found
#: that recovers every frequency within 0.7 % (docs/fleet.md), the one the worker rates use
LIGHT_SETTINGS = [dict(observer_order=4, order=48, hankel_rows=20, hankel_cols=80),
                  dict(observer_order=8, order=48, hankel_rows=10, hankel_cols=200),
                  dict(observer_order=16, order=48, hankel_rows=20, hankel_cols=300, estimator="correlation"),
                  dict(observer_order=20, order=48, hankel_rows=20, hankel_cols=300),
                  dict(observer_order=20, order=48, hankel_rows=20, hankel_cols=300, estimator="correlation")]


def _light_record(samples: int):
    springs = np.full(25, 3969.0)
    return _chain_record(np.ones(24), 4.77e-4 * springs, springs, samples)


def lightly_damped_rates(samples: int, records: int) -> dict:
    """Records/s of the identify job on RECORDS copies of the lightly damped record (CSV files, as
    okid simulate writes them: reading included) with 1 and 2 local workers at the recovering
    settings (LIGHT_SETTINGS[-1]), and the load average seen."""
    import shutil

    u, y, _ = _light_record(samples)
    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.join(tmp, "records")
        os.makedirs(folder)
        first = os.path.join(folder, "r0000.csv")
        np.savetxt(first, np.column_stack([np.arange(samples) * 0.01, u[:, 0], y]), delimiter=",", fmt="%.17g",
                   header=",".join(["time", "force"] + [f"acc{i + 1}" for i in range(24)]), comments="")
        for k in range(1, records):
            shutil.copyfile(first, os.path.join(folder, f"r{k:04d}.csv"))
        load0 = os.getloadavg()[0]
        r1 = records_per_second(folder, 1, os.path.join(tmp, "o1"), LIGHT_SETTINGS[-1])
        r2 = records_per_second(folder, 2, os.path.join(tmp, "o2"), LIGHT_SETTINGS[-1])
        load1 = os.getloadavg()[0]
    return {"records": records, "records_per_s_1": r1, "records_per_s_2": r2, "load_average": (load0, load1)}


def lightly_damped_records(samples: int) -> list:
    """Issue 26's realistic record: a 24-mass chain between two walls (1 kg, 3969 N/m: modes 1.26 to
    20.0 Hz), stiffness-proportional damping (0.19 % to 3.0 %), one force on mass 1, 24
    accelerometers with 2 % noise, 100 Hz; each setting's seconds in process and its errors against
    the exact modes (each exact mode against the nearest identified pair). Seconds are CPU time
    (the machine is shared: the robust figure)."""
    import okid
    from okid.fleet.synth import exact_modes

    u, y, ac = _light_record(samples)
    f_exact, z_exact = exact_modes(ac)
    rows = []
    for options in LIGHT_SETTINGS:
        t0 = time.process_time()
        res = okid.identify(u, y, 0.01, **options)
        seconds = time.process_time() - t0
        pairs = [md for md in res.modes if md.is_pair]
        near = [min(pairs, key=lambda md: abs(md.frequency_hz - f)) for f in f_exact]
        ef = np.array([abs(md.frequency_hz - f) / f for md, f in zip(near, f_exact)])
        ez = np.array([abs(md.damping_ratio - z) / z for md, z in zip(near, z_exact)])
        rows.append({"options": options, "seconds": seconds, "pairs": len(pairs), "frequency_error_max": float(ef.max()),
                     "frequency_error_median": float(np.median(ef)), "damping_error_max": float(ez.max()),
                     "damping_error_median": float(np.median(ez))})
    return rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="bench/python/fleet_bench.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--records", type=int, default=96, help="records of the scaling run")
    p.add_argument("--samples", type=int, default=60000, help="samples per record (10 min at 100 Hz)")
    p.add_argument("--results", default=None, help="update this results.json (key 'fleet')")
    p.add_argument("--folder-records", type=int, help="only this: records/s of the identify command on a folder "
                   "of this many CSV records, 2 local workers")
    p.add_argument("--lightly-damped", action="store_true", help="only this: one record of a 24-channel lightly "
                   "damped structure (modes 1.3-20 Hz, damping 0.2-3 %%) at several settings, in process")
    p.add_argument("--light-records", type=int, default=0, help="with --lightly-damped: also the records/s of "
                   "the identify job on this many copies of the record with 1 and 2 local workers")
    a = p.parse_args(argv)
    if a.lightly_damped:
        for row in lightly_damped_records(a.samples):
            o = row["options"]
            print(f"p {o['observer_order']}, n {o['order']}, Hankel {o['hankel_rows']} x {o['hankel_cols']}, "
                  f"{o.get('estimator', 'least_squares')}: {row['seconds']:.2f} s CPU, {row['pairs']} pairs, frequency error max {row['frequency_error_max']:.1e} "
                  f"(median {row['frequency_error_median']:.1e}), damping error max {row['damping_error_max']:.2f} "
                  f"(median {row['damping_error_median']:.2f}); 10 000 assets x 144 records/day: "
                  f"{10_000 * 144 * row['seconds'] / 86400:.0f} cores")
        if a.light_records:
            f = lightly_damped_rates(a.samples, a.light_records)
            print(f"{f['records']} CSV copies of the record, the last setting, local workers: 1 worker "
                  f"{f['records_per_s_1']:.2f} records/s, 2 workers {f['records_per_s_2']:.2f} records/s; load average "
                  f"{f['load_average'][0]:.1f} before, {f['load_average'][1]:.1f} after")
        return 0
    if a.folder_records:
        f = folder_records_per_second(a.folder_records, a.samples)
        print(f"folder of {f['records']} CSV records ({f['samples']} samples each, paper system), "
              f"{f['workers']} local workers: {f['records_per_s']:.1f} records/s identifying, "
              f"{f['records_per_s_wall']:.1f} records/s with the listing and the cluster connection "
              f"({f['before_identifying_s']:.2f} s)")
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        spec = FleetSpec(assets=4, records=a.records // 4, samples=a.samples, dt=0.01, seed=2)
        synthesize(os.path.join(tmp, "fleet"), spec)
        records = os.path.join(tmp, "fleet", "records")
        records_per_second(records, 2, os.path.join(tmp, "warm"))  # page cache, imports
        r1 = records_per_second(records, 1, os.path.join(tmp, "o1"))
        r2 = records_per_second(records, 2, os.path.join(tmp, "o2"))
    overhead = scheduler_overhead_per_task()
    wide = wide_record_seconds(a.samples)
    per_day = 10_000 * 144
    cores = per_day * wide["seconds"] / 86400
    figures = {
        "fleet_records_per_s_1": r1, "fleet_records_per_s_2": r2, "fleet_speedup_1_to_2": r2 / r1,
        "fleet_records": spec.assets * spec.records, "fleet_samples_per_record": a.samples,
        "fleet_scheduler_overhead_s_per_task": overhead,
        "fleet_wide_record_seconds": wide["seconds"], "fleet_wide_record": {k: v for k, v in wide.items()
                                                                            if k != "seconds"},
        "fleet_projection_records_per_day": per_day, "fleet_projection_cores": cores,
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, {platform.python_version()}",
    }
    print(f"records/s, paper system, {a.samples} samples/record: 1 worker {r1:.2f}, 2 workers {r2:.2f} "
          f"({r2 / r1:.2f}x)")
    print(f"scheduler overhead per task (2 local workers): {overhead * 1e3:.2f} ms")
    print(f"one 24-channel record ({a.samples} samples, p = 4, n = 48, 20 x 80 Hankel): {wide['seconds']:.3f} s")
    print(f"projection, 10 000 assets x 144 records/day: {per_day * wide['seconds'] / 3600:.0f} core-hours/day, "
          f"{cores:.1f} cores busy around the clock")
    if a.results:
        data = {}
        if os.path.exists(a.results):
            with open(a.results) as f:
                data = json.load(f)
        data["fleet"] = figures
        with open(a.results, "w") as f:
            json.dump(data, f, indent=1)
            f.write("\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
