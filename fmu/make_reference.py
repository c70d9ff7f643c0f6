# SPDX-License-Identifier: Apache-2.0
"""Reference input and output of a built FMU, as the Modelica Reference-FMUs ship them
(<model>_in.csv, <model>_ref.csv): simulated here, at packaging, with fmpy from the staged FMU, so
no number is written by hand. FMI 3 puts them in extra/, FMI 2 (which has no extra/) in
documentation/. Numbers are written with Python's repr, which reads back to the same bits.

  python make_reference.py STAGE VERSION MODEL OUT_DIR [PLANT_FMU]

The plant's input is the paper's white-noise force (10 s at 0.01 s, numpy seed 5); the
identifier's is that force with the plant's accelerations y(k) = C x(k) + D u(k) (the plant FMU of
the same version, read after the force is set and before the step: the pairs the identifier
needs). The output is what fmpy.simulate_fmu records with the input table (one row per
communication point; FMI 3's identifier, whose inputs u[1] and y[2] simulate_fmu cannot take,
through the same calls by hand: inputs set at t, outputs read after the step to t + dt).
"""
import sys
from pathlib import Path

import numpy as np

DT, SAMPLES, SEED = 0.01, 1001, 5
OUTPUTS = {"okid_plant_2dof": ["acc1", "acc2", "x1", "x2", "v1", "v2"],
           "okid_identifier": ["status", "identifications", "num_modes", "mode1_frequency_hz", "mode2_frequency_hz",
                               "mode1_damping_ratio", "mode2_damping_ratio"]}


def write_csv(path, names, columns):
    rows = [",".join(names)]
    rows += [",".join(repr(float(c[k])) for c in columns) for k in range(len(columns[0]))]
    Path(path).write_text("\n".join(rows) + "\n")


def read_csv(path):
    lines = Path(path).read_text().splitlines()
    names = lines[0].split(",")
    values = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return names, values


def plant_accelerations(plant_fmu, force):
    """y(k) = C x(k) + D u(k): the force set, the accelerations read, then the step."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.fmi3 import FMU3Slave
    md = read_model_description(plant_fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    v3 = md.fmiVersion.startswith("3")
    slave = (FMU3Slave if v3 else FMU2Slave)(guid=md.guid, unzipDirectory=extract(plant_fmu),
                                             modelIdentifier=md.coSimulation.modelIdentifier)
    slave.instantiate()
    if v3:
        slave.enterInitializationMode(startTime=0.0)
    else:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
    slave.exitInitializationMode()
    set_, get = (slave.setFloat64, slave.getFloat64) if v3 else (slave.setReal, slave.getReal)
    y = np.empty((len(force), 2))
    for k, f in enumerate(force):
        set_([vr["force"]], [float(f)])
        y[k] = get([vr["acc1"], vr["acc2"]])
        slave.doStep(currentCommunicationPoint=k * DT, communicationStepSize=DT)
    slave.terminate()
    slave.freeInstance()
    return y


def inputs(model, version, plant_fmu):
    t = np.arange(SAMPLES) * DT
    force = np.random.default_rng(SEED).standard_normal(SAMPLES)
    if model == "okid_plant_2dof":
        return ["time", "force"], [t, force]
    y = plant_accelerations(plant_fmu, force)
    names = ["time", "u1", "y1", "y2"] if version == 2 else ["time", "u[1]", "y[1]", "y[2]"]
    return names, [t, force, y[:, 0], y[:, 1]]


def simulate(stage, version, model, names, values):
    """The outputs at every communication point, as fmpy.simulate_fmu records them."""
    from fmpy import simulate_fmu
    outputs = OUTPUTS[model]
    if version == 2 or model == "okid_plant_2dof":
        signal = np.zeros(len(values), dtype=[(n, np.float64) for n in names])
        for i, n in enumerate(names):
            signal[n] = values[:, i]
        result = simulate_fmu(str(stage), start_time=0.0, stop_time=(len(values) - 1) * DT, step_size=DT,
                              output_interval=DT, input=signal, output=outputs, fmi_type="CoSimulation")
        return ["time"] + outputs, [result[n] for n in ["time"] + outputs]
    return identifier_fmi3(stage, values, outputs)


def identifier_fmi3(stage, values, outputs):
    from fmpy import read_model_description
    from fmpy.fmi3 import FMU3Slave
    md = read_model_description(str(stage))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU3Slave(guid=md.guid, unzipDirectory=str(stage), modelIdentifier=md.coSimulation.modelIdentifier)
    s.instantiate()
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()

    def read():
        row = []
        for name in outputs:  # mode1_frequency_hz: element 1 of the array mode_frequency_hz
            if name.startswith("mode") and name[4].isdigit():
                index, array = int(name[4]) - 1, "mode_" + name[6:]
                row.append(s.getFloat64([vr[array]], nValues=4)[index])
            elif name == "status":
                row.append(float(s.getInt64([vr[name]])[0]))
            else:
                row.append(float(s.getInt32([vr[name]])[0]))
        return row

    rows = [[0.0] + read()]
    for k in range(len(values) - 1):
        s.setFloat64([vr["u"], vr["y"]], [float(x) for x in values[k, 1:4]])
        s.doStep(currentCommunicationPoint=k * DT, communicationStepSize=DT)
        rows.append([(k + 1) * DT] + read())
    s.terminate()
    s.freeInstance()
    table = np.array(rows)
    return ["time"] + outputs, [table[:, i] for i in range(table.shape[1])]


def main(argv):
    stage, version, model, out = Path(argv[0]).resolve(), int(argv[1]), argv[2], Path(argv[3])
    names, columns = inputs(model, version, argv[4] if len(argv) > 4 else None)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / f"{model}_in.csv", names, columns)
    names, values = read_csv(out / f"{model}_in.csv")  # simulate what was written
    out_names, out_columns = simulate(stage, version, model, names, values)
    write_csv(out / f"{model}_ref.csv", out_names, out_columns)


if __name__ == "__main__":
    main(sys.argv[1:])
