# SPDX-License-Identifier: Apache-2.0
"""A synthetic fleet from okid's own model and simulator, so the whole path can be tried without
real data: ASSETS chains of masses (the paper's 2-DOF system by default), each with its own small
spread of stiffness, R records each of white-noise force on mass 1 and the accelerations of every
mass with output noise; DAMAGED of the assets lose stiffness of their first spring linearly over
their records (or, with ``damage_start``, all at once from that record on). With a
``temperature_swing``, every asset's springs also follow a temperature cycle (a ``temperature``
column in every record: identify with ``--covariates temperature``), moving every frequency by up
to +- the swing, as the seasons move a real structure's. With ``ambient``, the force is not
written (an unmeasured excitation, as wind or traffic: identify with ``--inputs 0``). The exact
modes of every record are written beside the records (truth.parquet).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from datetime import datetime, timedelta, timezone
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .. import model

PAPER_MASSES: Tuple[float, ...] = (2.0, 3.0)            #: [kg]
PAPER_DAMPERS: Tuple[float, ...] = (2.0, 4.0, 3.0)      #: [N s/m]
PAPER_SPRINGS: Tuple[float, ...] = (20.0, 40.0, 30.0)   #: [N/m]
START: datetime = datetime(2026, 1, 1, tzinfo=timezone.utc)


@dataclass(frozen=True)
class FleetSpec:
    assets: int = 8                 #: machines
    records: int = 24               #: records per machine
    damaged: Optional[int] = None   #: machines that lose stiffness (default: a third, at least 1)
    stiffness_loss: float = 0.06    #: fraction of the first spring's stiffness lost by the last record
    masses: int = 2                 #: masses per chain (2: the paper's system)
    samples: int = 2000             #: samples per record
    dt: float = 0.05                #: sample interval [s]
    noise: float = 0.02             #: output noise, relative to each channel's RMS
    spread: float = 0.03            #: relative spread of the springs between machines
    interval_minutes: float = 10.0  #: time between a machine's records
    seed: int = 1
    fmt: str = "parquet"            #: "parquet" (one file per machine, a row group per record) or "csv"
    damage_start: Optional[int] = None  #: the record from which the loss is whole (a step), else a ramp
    temperature_swing: float = 0.0  #: relative frequency swing by temperature (0.02: +- 2 %), 0: no temperature
    temperature_period: int = 24    #: records per temperature cycle
    ambient: bool = False           #: the force unmeasured: records of the accelerations alone
    damping_scale: float = 1.0      #: the dampers scaled (0.1: the paper's chain with damping ratios of 1.6 and 3.4 %)


def chain(n: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Masses, dampers and springs of an n-mass chain: the paper's values for n = 2, repeated
    beyond (masses 2, 3, 2, ... kg; springs 20, 40, 30, 40, 30, ... N/m; dampers a tenth of them)."""
    masses = np.array([PAPER_MASSES[i % 2] for i in range(n)])
    springs = np.array([PAPER_SPRINGS[0]] + [PAPER_SPRINGS[1 + i % 2] for i in range(n)])
    dampers = springs / 10.0
    if n == 2:
        dampers = np.array(PAPER_DAMPERS)
    return masses, dampers, springs


def exact_modes(ac: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Natural frequencies [Hz] and damping ratios of the continuous model, one per pair, ascending."""
    s = np.linalg.eigvals(ac)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    return np.abs(s) / (2 * np.pi), -s.real / np.abs(s)


def _asset_name(i: int) -> str:
    return f"asset-{i:03d}"


def synthesize(out_dir: str, spec: FleetSpec = FleetSpec()) -> Dict[str, Any]:
    """Write the records under OUT_DIR/records and the exact modes to OUT_DIR/truth.parquet."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    if spec.assets < 1 or spec.records < 1 or spec.samples < 10 or spec.masses < 1:
        raise ValueError("synth needs at least 1 asset, 1 record, 10 samples and 1 mass")
    if not 0 <= spec.temperature_swing < 0.5 or spec.temperature_period < 1:
        raise ValueError(f"temperature swing {spec.temperature_swing}: in [0, 0.5); period {spec.temperature_period}: >= 1")
    if not spec.damping_scale > 0:
        raise ValueError(f"damping scale {spec.damping_scale}: > 0")
    if spec.fmt not in ("parquet", "csv"):
        raise ValueError(f"format {spec.fmt!r}: 'parquet' or 'csv'")
    rng = np.random.default_rng(spec.seed)
    damaged_count = spec.damaged if spec.damaged is not None else max(1, spec.assets // 3)
    damaged = set(rng.choice(spec.assets, size=min(damaged_count, spec.assets), replace=False).tolist())
    masses, dampers, springs0 = chain(spec.masses)
    dampers = dampers * spec.damping_scale
    records_dir = os.path.join(out_dir, "records")
    os.makedirs(records_dir, exist_ok=True)
    truth: List[Dict[str, Any]] = []
    outputs = [f"acc{i + 1}" for i in range(spec.masses)]
    for a in range(spec.assets):
        asset = _asset_name(a)
        springs_asset = springs0 * (1 + spec.spread * rng.standard_normal(springs0.size))
        phase = 2 * np.pi * a / spec.assets
        writer = None
        for j in range(spec.records):
            if a not in damaged:
                loss = 0.0
            elif spec.damage_start is not None:
                loss = spec.stiffness_loss if j >= spec.damage_start else 0.0
            else:
                loss = spec.stiffness_loss * j / max(spec.records - 1, 1)
            springs = springs_asset.copy()
            springs[0] *= 1 - loss
            # temperature in [10, 30] degC, tau = (T - 20) / 10 in [-1, 1]: the springs scale by
            # (1 + swing tau)^2 and the dampers by 1 + swing tau, so every eigenvalue of the chain
            # scales by exactly 1 + swing tau (frequencies linear in T, damping ratios unchanged)
            temperature = 20.0 + 10.0 * np.sin(2 * np.pi * j / spec.temperature_period + phase)
            scale = 1 + spec.temperature_swing * (temperature - 20.0) / 10.0
            springs *= scale ** 2
            mass_m, damp_m, stiff_m = model.chain_model(masses, dampers * scale, springs)
            b2 = np.zeros((spec.masses, 1))
            b2[0, 0] = 1.0
            ac, bc, c, d = model.state_space(mass_m, damp_m, stiff_m, b2, acceleration=np.eye(spec.masses))
            a_d, b_d = model.discretize_zoh(ac, bc, spec.dt)
            force = rng.standard_normal((spec.samples, 1))
            y, _ = model.simulate(a_d, b_d, c, d, force)
            y = y + spec.noise * np.sqrt(np.mean(y ** 2, axis=0)) * rng.standard_normal(y.shape)
            start = START + timedelta(minutes=spec.interval_minutes * j)
            stamp = start.strftime("%Y-%m-%dT%H-%M-%SZ")
            record = f"{asset}/{stamp}"
            freqs, zetas = exact_modes(ac)
            for k, (f, z) in enumerate(zip(freqs, zetas), start=1):
                truth.append({"asset": asset, "record": record, "start": start, "damaged": a in damaged,
                              "stiffness_factor": 1 - loss, "temperature": float(temperature), "mode": k,
                              "frequency_hz": float(f), "damping_ratio": float(z)})
            time_s = np.arange(spec.samples) * spec.dt
            measured = {} if spec.ambient else {"force": force[:, 0]}
            extra = {"temperature": np.full(spec.samples, temperature)} if spec.temperature_swing else {}
            if spec.fmt == "csv":
                folder = os.path.join(records_dir, asset)
                os.makedirs(folder, exist_ok=True)
                data = np.column_stack([time_s, *measured.values(), y, *extra.values()])
                np.savetxt(os.path.join(folder, stamp + ".csv"), data, delimiter=",", fmt="%.17g",
                           header=",".join(["time", *measured] + outputs + list(extra)), comments="")
                continue
            columns = {"asset": pa.array([asset] * spec.samples), "record": pa.array([record] * spec.samples),
                       "start": pa.array([start] * spec.samples, pa.timestamp("us", tz="UTC")),
                       "dt": pa.array(np.full(spec.samples, spec.dt)), "time": pa.array(time_s)}
            columns.update({name: pa.array(v) for name, v in measured.items()})
            columns.update({name: pa.array(y[:, i]) for i, name in enumerate(outputs)})
            columns.update({name: pa.array(v) for name, v in extra.items()})
            table = pa.table(columns)
            if writer is None:
                writer = pq.ParquetWriter(os.path.join(records_dir, asset + ".parquet"), table.schema)
            writer.write_table(table, row_group_size=spec.samples)  # one record, one row group
        if writer is not None:
            writer.close()
    pq.write_table(pa.Table.from_pylist(truth), os.path.join(out_dir, "truth.parquet"))
    return {"records_dir": records_dir, "truth": os.path.join(out_dir, "truth.parquet"),
            "damaged": sorted(_asset_name(a) for a in damaged), "records": spec.assets * spec.records}
