# SPDX-License-Identifier: Apache-2.0
"""What a co-simulation master needs besides stepping (issue 22): the outputs' direct dependencies
on inputs in <ModelStructure> (no false algebraic loop when a controller closes the loop through
the plant's positions), and FMU states for masters that roll back a step: get, step, set, redo
gives the same outputs bit for bit (FMI 2 and 3, identifier and plant); the plant's state
serializes and restores into another instance, the identifier's refuses to (docs/fmu.md)."""
import math
import os
import struct
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException

from fmu_runs import PAPER_SETTINGS, Slave, mode_outputs
from reference import paper_reference

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
VERSIONS = [2, 3]
PLANT_OUTPUTS = ["acc1", "acc2", "x1", "x2", "v1", "v2"]


def fmu(version, model):
    return str(FMU_DIR / f"fmi{version}" / f"{model}.fmu")


def bits(values):
    """The exact bits of a list of numbers (NaN payloads included): equal bits, equal outputs."""
    return b"".join(struct.pack("<d", float(v)) for v in values)


# ---- <ModelStructure>: direct dependencies ----

@pytest.mark.parametrize("version", VERSIONS)
def test_plant_declares_feedthrough_only_for_the_accelerations(version):
    md = read_model_description(fmu(version, "okid_plant_2dof"))
    deps = {u.variable.name: ([d.name for d in u.dependencies], u.dependenciesKind) for u in md.outputs}
    assert set(deps) == set(PLANT_OUTPUTS)
    # acc = C x + D force with D = M^-1 b = (1/m1, 0), fixed by the masses: only mass 1 feels the force at once
    assert deps["acc1"] == (["force"], ["fixed"]), deps["acc1"]
    for name in ("acc2", "x1", "x2", "v1", "v2"):  # DoStep moves them, the force at this point does not
        assert deps[name][0] == [], (name, deps[name])


@pytest.mark.parametrize("version", VERSIONS)
def test_identifier_declares_no_feedthrough(version):
    md = read_model_description(fmu(version, "okid_identifier"))
    assert md.outputs and all(u.dependencies == [] for u in md.outputs)


@pytest.mark.parametrize("version", VERSIONS)
def test_declared_dependencies_are_the_behaviour(version):
    """Between steps, a new force changes acc1 at once and nothing else."""
    p = Slave(fmu(version, "okid_plant_2dof")).instantiate()
    p.initialize()
    for k, force in enumerate([1.0, -0.5, 2.0]):
        p.set(force=force)
        p.step(k * 0.01, 0.01)
    before = p.get(*PLANT_OUTPUTS)
    p.set(force=7.0)
    after = p.get(*PLANT_OUTPUTS)
    assert after[0] != before[0]
    assert bits(after[1:]) == bits(before[1:])
    p.close()


# ---- FMU states ----

def state_calls(slave):
    f = slave.fmu
    if slave.version == 2:
        return f.getFMUstate, f.setFMUstate, f.freeFMUstate
    return f.getFMUState, f.setFMUState, f.freeFMUState


def paper_inputs(samples):
    ref = paper_reference(0.01)
    u = np.random.default_rng(5).standard_normal(samples)
    y, _ = ref.simulate(u[:, None])
    return u, y


def identifier_run(s, u, y, first, last, outputs):
    rows = []
    for k in range(first, last):
        s.set_inputs(u[k], y[k])
        s.step(k * 0.01, 0.01)
        rows.append(bits(s.get(*outputs)))
    return rows


@pytest.mark.parametrize("version", VERSIONS)
def test_identifier_rollback_redoes_the_steps_bit_for_bit(version):
    """A state after 150 samples; 100 steps through the identification at 200 samples; back to the
    state and the same 100 steps again: every output equal in every bit, step by step."""
    u, y = paper_inputs(260)
    outputs = ["status", "samples", "identifications", "y_hat1", "y_error2", "singular_value1"] + mode_outputs()
    s = Slave(fmu(version, "okid_identifier")).instantiate()
    s.set(**PAPER_SETTINGS)
    s.initialize()
    identifier_run(s, u, y, 0, 150, outputs)
    get, set_, free = state_calls(s)
    state = get()
    first = identifier_run(s, u, y, 150, 250, outputs)
    set_(state)
    assert s.get("samples") == [150]
    again = identifier_run(s, u, y, 150, 250, outputs)
    assert again == first
    assert s.get("identifications")[0] >= 1  # the redone steps identified, from the restored accumulation
    set_(state)  # a state stays valid after it was set
    assert identifier_run(s, u, y, 150, 250, outputs) == first
    free(state)
    s.close()


def plant_run(p, force, first, last):
    rows = []
    for k in range(first, last):
        p.set(force=force[k])
        p.step(k * 0.01, 0.01)
        rows.append(bits(p.get(*PLANT_OUTPUTS)))
    return rows


@pytest.mark.parametrize("version", VERSIONS)
def test_plant_rollback_and_serialized_state(version):
    """Rollback as for the identifier; and the serialized state restores, also into a second
    instance, which then steps exactly as the first."""
    force = np.random.default_rng(5).standard_normal(120)
    p = Slave(fmu(version, "okid_plant_2dof"), "plant").instantiate()
    p.initialize()
    plant_run(p, force, 0, 40)
    get, set_, free = state_calls(p)
    state = get()
    first = plant_run(p, force, 40, 120)
    set_(state)
    assert plant_run(p, force, 40, 120) == first
    serialized = p.fmu.serializeFMUstate(state) if version == 2 else p.fmu.serializeFMUState(state)
    free(state)
    other = Slave(fmu(version, "okid_plant_2dof"), "other").instantiate()
    other.initialize()
    if version == 2:
        restored = other.fmu.deSerializeFMUstate(serialized)
    else:
        from fmpy.fmi3 import fmi3FMUState
        restored = fmi3FMUState()
        other.fmu.deserializeFMUState(serialized, restored)  # fmpy 0.3.32 fills it, returns None
    state_calls(other)[1](restored)
    assert plant_run(other, force, 40, 120) == first
    if version == 2:  # deserialized again into the same state object (the FMU reuses it)
        restored = other.fmu.deSerializeFMUstate(serialized, restored)
    else:
        other.fmu.deserializeFMUState(serialized, restored)
    state_calls(other)[1](restored)
    assert plant_run(other, force, 40, 120) == first
    state_calls(other)[2](restored)
    p.close()
    other.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_identifier_state_is_not_serialized_nor_moved(version):
    """Its okid workspace holds pointers into itself: canSerializeFMUstate is false, serializing
    is refused with the reason, and a state restores only into its own instance's memory."""
    md = read_model_description(fmu(version, "okid_identifier"))
    assert md.coSimulation.canGetAndSetFMUstate and not md.coSimulation.canSerializeFMUstate
    assert read_model_description(fmu(version, "okid_plant_2dof")).coSimulation.canSerializeFMUstate
    log = []
    s = Slave(fmu(version, "okid_identifier"), "a", logger=lambda *m: log.append(m[2])).instantiate(logging_on=True)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    state = state_calls(s)[0]()
    with pytest.raises(FMICallException):
        s.fmu.serializeFMUstate(state) if version == 2 else s.fmu.serializeFMUState(state)
    assert any("not serialized" in m for m in log)
    other = Slave(fmu(version, "okid_identifier"), "b", logger=lambda *m: log.append(m[2])).instantiate(logging_on=True)
    other.set(**PAPER_SETTINGS)
    other.initialize()
    with pytest.raises(FMICallException):
        state_calls(other)[1](state)  # another instance's memory
    assert any("restores only into the same memory" in m for m in log)
    other.step(0.0, 0.01)  # and the instance goes on working (fmpy raises on an error status)
    assert other.get("samples") == [1]
    state_calls(s)[2](state)
    s.close()
    other.close()
