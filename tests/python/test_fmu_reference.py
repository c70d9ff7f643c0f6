# SPDX-License-Identifier: Apache-2.0
"""The reference input and output each FMU ships (issue 22; FMI 3 in extra/, FMI 2 in
documentation/), as the Modelica Reference-FMUs ship <model>_in.csv and <model>_ref.csv: fmpy,
simulating the FMU with the shipped input, reproduces the shipped output bit for bit, and the
identifier's reference is the default configuration's honest answer on the paper's noise-free
record (no physical mode), whose poles are the paper's exact modes."""
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu

from fmu_runs import Slave
from reference import paper_reference

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
CASES = [(v, m) for v in (2, 3) for m in ("okid_plant_2dof", "okid_identifier")]


def shipped(version, model):
    folder = "extra" if version == 3 else "documentation"
    with zipfile.ZipFile(FMU_DIR / f"fmi{version}" / f"{model}.fmu") as z:
        tables = []
        for kind in ("in", "ref"):
            lines = z.read(f"{folder}/{model}_{kind}.csv").decode().splitlines()
            tables.append((lines[0].split(","), np.array([[float(x) for x in line.split(",")] for line in lines[1:]])))
    return tables


def by_hand(path, names, values, outputs, **settings):
    """FMI 3 identifier (array inputs, which simulate_fmu's tables cannot take): simulate_fmu's
    order by hand, inputs at t, step, outputs at t + dt; one row per communication point."""
    s = Slave(str(path)).instantiate()
    s.set(**settings)
    s.initialize()
    dt = values[1, 0] - values[0, 0]
    rows = [s.get(*outputs)]
    for k in range(len(values) - 1):
        s.set_inputs(values[k, 1:2], values[k, 2:4])
        s.step(k * dt, dt)
        rows.append(s.get(*outputs))
    s.close()
    return np.column_stack([values[:, 0], np.array(rows, dtype=float)])


@pytest.mark.parametrize("version,model", CASES)
def test_shipped_input_reproduces_the_shipped_output(version, model):
    (in_names, inputs), (ref_names, ref) = shipped(version, model)
    assert in_names[0] == ref_names[0] == "time" and len(inputs) == len(ref) == 1001
    path = FMU_DIR / f"fmi{version}" / f"{model}.fmu"
    if version == 3 and model == "okid_identifier":
        got = by_hand(path, in_names, inputs, ref_names[1:])
    else:
        signal = np.zeros(len(inputs), dtype=[(n, np.float64) for n in in_names])
        for i, n in enumerate(in_names):
            signal[n] = inputs[:, i]
        dt = inputs[1, 0] - inputs[0, 0]
        result = simulate_fmu(str(path), start_time=0.0, stop_time=inputs[-1, 0], step_size=dt, output_interval=dt,
                              input=signal, output=ref_names[1:], fmi_type="CoSimulation")
        got = np.column_stack([result[n] for n in ref_names])
    assert got.shape == ref.shape
    assert got.tobytes() == ref.tobytes()  # bit for bit, NaN included (the same binary, the same calls)


@pytest.mark.parametrize("version", [2, 3])
def test_identifier_reference_ends_on_no_physical_mode_and_its_poles_are_exact(version):
    """The shipped reference is right, not only reproducible. With the defaults (order 0, all_poles
    false) the mode outputs are the physical modes, and on the noise-free record the Hankel matrix
    has rank 4: the table holds the orders 2 and 4 only and no pole is in both within the selection's
    gates, so the last row has no mode (as `okid identify --decimation 1 --observer-order 20
    --hankel-rows 20 --hankel-cols 20` on the same record: "physical modes: 0"). The model's poles
    (all_poles true) are the paper's modes (noise-free; 1e-9 is the FMU tests' noise-free bound,
    the errors are round-off, about 1e-12 here)."""
    (in_names, inputs), (names, ref) = shipped(version, "okid_identifier")
    last = dict(zip(names, ref[-1]))
    assert last["status"] == 1 and last["num_modes"] == 0 and last["identifications"] > 0
    assert all(np.isnan(last[n]) for n in names if n.startswith("mode"))
    outputs = ["status", "num_modes", "mode1_frequency_hz", "mode2_frequency_hz", "mode1_damping_ratio",
               "mode2_damping_ratio"]
    got = dict(zip(["time"] + outputs, by_hand(FMU_DIR / f"fmi{version}" / "okid_identifier.fmu", in_names, inputs,
                                               outputs, all_poles=True)[-1]))
    assert got["status"] == 1 and got["num_modes"] == 2
    for k, mode in enumerate(paper_reference(0.01).modes, start=1):
        assert abs(got[f"mode{k}_frequency_hz"] - mode.frequency_hz) <= 1e-9 * mode.frequency_hz
        assert abs(got[f"mode{k}_damping_ratio"] - mode.damping_ratio) <= 1e-9 * mode.damping_ratio


def test_generated_fmu_does_not_carry_the_default_configurations_reference(tmp_path):
    """okid-fmu writes another configuration: the base FMU's reference is not its reference."""
    from okid.tools.fmu_generator import generate
    out = tmp_path / "chain.fmu"
    generate(FMU_DIR / "fmi2" / "okid_identifier.fmu", out, [("num_inputs", 2), ("num_outputs", 3)])
    with zipfile.ZipFile(out) as z:
        assert not [n for n in z.namelist() if n.endswith(("_in.csv", "_ref.csv"))]
