# SPDX-License-Identifier: Apache-2.0
"""Running the okid FMUs with fmpy: one adapter over FMI 2 and FMI 3 slaves, the plant alone,
the identifier fed from arrays (simulate_fmu), and a master loop coupling both step by step."""
import re
from dataclasses import dataclass, field

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

# Identifier settings of the verification cases (names of the FMU's parameters = okid_config's fields).
PAPER_SETTINGS = dict(dt=0.01, observer_order=20, order=4, hankel_rows=20, hankel_cols=20, identify_every=100,
                      zero_initial_state=1)
NOISY_SETTINGS = dict(dt=0.05, observer_order=20, order=4, hankel_rows=40, hankel_cols=40, identify_every=200,
                      zero_initial_state=1)

# FMI 3 arrays and the FMI 2 names of their elements ("{}" the 1-based indices; shapes index mode, then entry).
FLAT_NAMES = {"u": "u{}", "y": "y{}", "y_hat": "y_hat{}", "y_error": "y_error{}", "singular_values": "singular_value{}",
              "mode_frequency_hz": "mode{}_frequency_hz", "mode_damping_ratio": "mode{}_damping_ratio",
              "mode_emac": "mode{}_emac", "mode_mpc": "mode{}_mpc", "mode_cmi": "mode{}_cmi",
              "mode_eigenvalue_re": "mode{}_eigenvalue_re", "mode_eigenvalue_im": "mode{}_eigenvalue_im",
              "mode_shape_re": "mode{}_shape{}_re", "mode_shape_im": "mode{}_shape{}_im"}


class Slave:
    """An FMU instance with the same few calls in FMI 2 and FMI 3. Names are the FMI 2 (flat) names
    in both: in FMI 3, "mode2_frequency_hz" is element 2 of the array mode_frequency_hz, read through
    the low-level calls with nValues = the array's size for the structural parameters set."""

    def __init__(self, path, name="instance", logger=None, unzipdir=None):
        self.md = read_model_description(path)
        self.version = 2 if self.md.fmiVersion.startswith("2") else 3
        self.unzipdir = unzipdir or extract(path)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.structural = {v.name: int(v.start) for v in self.md.modelVariables if v.causality == "structuralParameter"}
        cls = FMU2Slave if self.version == 2 else FMU3Slave
        self.fmu = cls(guid=self.md.guid, unzipDirectory=self.unzipdir,
                       modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.logger = logger

    def instantiate(self, logging_on=False):
        if self.version == 2:
            if self.logger is None:
                self.fmu.instantiate(loggingOn=logging_on)
            else:
                from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2CallbackAllocateMemoryTYPE, \
                    fmi2CallbackFreeMemoryTYPE, printLogMessage  # noqa: F401
                from fmpy import calloc, free
                callbacks = fmi2CallbackFunctions()
                callbacks.logger = fmi2CallbackLoggerTYPE(self._log2)
                callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
                callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
                self._callbacks = callbacks
                self.fmu.instantiate(callbacks=callbacks, loggingOn=logging_on)
        else:
            if self.logger is None:
                self.fmu.instantiate(loggingOn=logging_on)
            else:
                from fmpy.fmi3 import fmi3LogMessageCallback
                self._log_cb = fmi3LogMessageCallback(self._log3)
                self.fmu.instantiate(loggingOn=logging_on, logMessage=self._log_cb)
        return self

    def _log2(self, env, name, status, category, message):
        # okid's FMI 2 messages are formats without arguments, '%' doubled: print them as printf would.
        self.logger(status, category.decode(), message.decode().replace("%%", "%"))

    def _log3(self, env, status, category, message):
        self.logger(status, category.decode(), message.decode())

    def vr(self, name):
        return self.vars[name].valueReference

    def configure(self, **sizes):
        """FMI 3 configuration mode: set the structural parameters (num_inputs=2, ...)."""
        self.fmu.enterConfigurationMode()
        for name, value in sizes.items():
            self.fmu.setUInt64([self.vars[name].valueReference], [int(value)])
        self.fmu.exitConfigurationMode()
        self.structural.update({k: int(v) for k, v in sizes.items()})
        return self

    def _size(self, v):
        n = 1
        for d in v.dimensions:
            if d.valueReference is not None:
                n *= next(s for k, s in self.structural.items() if self.vars[k].valueReference == d.valueReference)
            else:
                n *= int(d.start)
        return n

    def _locate(self, name):
        """(variable, element index or None for the whole variable)."""
        if name in self.vars:
            return self.vars[name], None
        for array, flat in FLAT_NAMES.items():
            pattern = "^" + re.escape(flat).replace(r"\{\}", r"(\d+)") + "$"
            match = re.match(pattern, name)
            if match and array in self.vars:
                v = self.vars[array]
                idx = [int(i) - 1 for i in match.groups()]
                if len(idx) == 1:
                    return v, idx[0]
                inner = self._size(v) // max(1, self.structural["max_modes"])
                return v, idx[0] * inner + idx[1]
        raise KeyError(name)

    def _access(self, v, getter):
        kind = {"Real": "Float64", "Float64": "Float64", "Integer": "Int32", "Int32": "Int32",
                "Enumeration": "Int32" if self.version == 2 else "Int64", "Boolean": "Boolean", "UInt64": "UInt64"}[v.type]
        if self.version == 2:
            kind = {"Float64": "Real", "Int32": "Integer"}.get(kind, kind)
        return getattr(self.fmu, ("get" if getter else "set") + kind)

    def set(self, **values):
        for name, value in values.items():
            v, element = self._locate(name)
            if element is not None:
                raise ValueError(f"{name}: set whole arrays in FMI 3 (set_array)")
            python_type = float if v.type in ("Real", "Float64") else bool if v.type == "Boolean" else int
            self._access(v, False)([v.valueReference], [python_type(value)])

    def set_array(self, name, values):
        """An FMI 3 array variable (all elements), or the FMI 2 scalars name1, name2, ..."""
        if self.version == 2:
            self.set(**{FLAT_NAMES[name].format(i + 1): x for i, x in enumerate(values)})
        else:
            self.fmu.setFloat64([self.vars[name].valueReference], [float(x) for x in values])

    def set_inputs(self, u, y):
        self.set_array("u", np.atleast_1d(u))
        self.set_array("y", np.atleast_1d(y))

    def get(self, *names):
        out = []
        for name in names:
            v, element = self._locate(name)
            if self.version == 2 or not v.dimensions:
                value = self._access(v, True)([v.valueReference])[0]
            else:
                value = self._access(v, True)([v.valueReference], nValues=self._size(v))
            out.append(value if element is None else value[element])
        return out

    def initialize(self, start_time=0.0):
        if self.version == 2:
            self.fmu.setupExperiment(startTime=start_time)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=start_time)
        self.fmu.exitInitializationMode()

    def step(self, t, h):
        return self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def mode_outputs(num_modes=2, m=2):
    names = []
    for k in range(1, num_modes + 1):
        names += [f"mode{k}_frequency_hz", f"mode{k}_damping_ratio", f"mode{k}_eigenvalue_re", f"mode{k}_eigenvalue_im"]
        names += [f"mode{k}_shape{j}_{part}" for j in range(1, 2 * m + 1) for part in ("re", "im")]
    return names


def modes_from(values, num_modes=2, m=2):
    """Identifier outputs (dict name -> value) to a list of (eigenvalue, frequency, damping, shape)."""
    modes = []
    for k in range(1, num_modes + 1):
        shape = np.array([values[f"mode{k}_shape{j}_re"] + 1j * values[f"mode{k}_shape{j}_im"]
                          for j in range(1, 2 * m + 1)])
        modes.append(dict(eigenvalue=values[f"mode{k}_eigenvalue_re"] + 1j * values[f"mode{k}_eigenvalue_im"],
                          frequency_hz=values[f"mode{k}_frequency_hz"], damping_ratio=values[f"mode{k}_damping_ratio"],
                          shape=shape))
    return modes


def simulate_plant(plant_path, force, dt):
    """The plant FMU with fmpy.simulate_fmu and an input array. fmpy applies the input at t, steps
    to t + dt and records at t + dt: row k + 1 holds x(k + 1), v(k + 1) and acc = C x(k+1) + D u(k)
    (the one-step recording lag of the force's feedthrough)."""
    n = len(force)
    t = np.arange(n + 1) * dt
    signal = np.zeros(n + 1, dtype=[("time", np.float64), ("force", np.float64)])
    signal["time"], signal["force"][:n], signal["force"][n] = t, force, force[-1]
    return simulate_fmu(plant_path, start_time=0.0, stop_time=n * dt, step_size=dt, output_interval=dt,
                        input=signal, output=["x1", "x2", "v1", "v2", "acc1", "acc2"], fmi_type="CoSimulation")


def identify_from_arrays(identifier_path, u, y, settings):
    """The identifier FMU fed sample k (u[k], y[k]) at t = k dt: FMI 2 through simulate_fmu with an
    input table; FMI 3 (array inputs of structural size, which simulate_fmu's input tables do not
    take) through the low-level calls."""
    dt = settings["dt"]
    n = len(u)
    names = ["status", "samples", "identifications"] + mode_outputs()
    if read_model_description(identifier_path).fmiVersion.startswith("3"):
        slave = Slave(identifier_path, "identifier").instantiate()
        slave.set(**settings)
        slave.initialize()
        for k in range(n):
            slave.set_inputs(u[k], y[k])
            slave.step(k * dt, dt)
        out = dict(zip(names, slave.get(*names)))
        slave.close()
        return out
    signal = np.zeros(n + 1, dtype=[("time", np.float64), ("u1", np.float64), ("y1", np.float64), ("y2", np.float64)])
    signal["time"] = np.arange(n + 1) * dt
    signal["u1"][:n], signal["y1"][:n], signal["y2"][:n] = u, y[:, 0], y[:, 1]
    signal[n] = signal[n - 1]
    signal["time"][n] = n * dt
    res = simulate_fmu(identifier_path, start_time=0.0, stop_time=n * dt, step_size=dt, output_interval=dt,
                       input=signal, output=names, start_values=settings, fmi_type="CoSimulation")
    return {name: res[name][-1] for name in names}


@dataclass
class CoSimulation:
    t: np.ndarray
    force: np.ndarray
    y: np.ndarray
    history: dict = field(default_factory=dict)   # identifier outputs after every step
    final: dict = field(default_factory=dict)


def cosimulate(plant_path, identifier_path, settings, samples, seed=1, noise=0.0, noise_rms=None):
    """Master loop: plant and identifier stepped together. At t_k the force u_k goes to the plant,
    its accelerations y_k = C x_k + D u_k (plus output noise) go to the identifier, then both step."""
    dt = settings["dt"]
    rng = np.random.default_rng(seed)
    force = rng.standard_normal(samples)
    noise_rng = np.random.default_rng(seed + 1000)
    plant = Slave(plant_path, "plant").instantiate()
    ident = Slave(identifier_path, "identifier").instantiate()
    plant.initialize()
    ident.set(**settings)
    ident.initialize()
    watch = ["status", "samples", "mode1_frequency_hz", "mode2_frequency_hz", "mode1_damping_ratio",
             "mode2_damping_ratio"]
    history = {name: np.empty(samples) for name in watch}
    y = np.empty((samples, 2))
    for k in range(samples):
        t = k * dt
        plant.set(force=force[k])
        y[k] = plant.get("acc1", "acc2")
        if noise > 0:
            y[k] += noise * np.asarray(noise_rms) * noise_rng.standard_normal(2)
        ident.set_inputs(force[k], y[k])
        plant.step(t, dt)
        ident.step(t, dt)
        for name, value in zip(watch, ident.get(*watch)):
            history[name][k] = value
    names = ["status", "samples", "identifications", "regressor_rank"] + mode_outputs() + \
        [f"singular_value{i}" for i in range(1, 9)]
    final = dict(zip(names, ident.get(*names)))
    plant.close()
    ident.close()
    return CoSimulation(np.arange(samples) * dt, force, y, history, final)
