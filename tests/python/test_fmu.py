"""The FMUs as an importer sees them (fmpy, FMI 2 and FMI 3): verification against the 2-DOF
reference, the shared objects' hygiene, and every behaviour an importer relies on."""
import math
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from okid.tools.fmu_runs import PAPER_SETTINGS, Slave, modes_from, mode_outputs
from okid.tools.reference import paper_reference
from okid.tools.verify_fmu import main as verify_main

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
VERSIONS = [2, 3]
MODELS = ["okid_identifier", "okid_plant_2dof"]
PLATFORM = {2: "linux64", 3: "x86_64-linux"}


def fmu(version, model="okid_identifier"):
    return str(FMU_DIR / f"fmi{version}" / f"{model}.fmu")


def shared_object(version, model):
    return FMU_DIR / f"fmi{version}" / model / "binaries" / PLATFORM[version] / f"{model}.so"


class Log:
    def __init__(self):
        self.messages = []

    def __call__(self, status, category, message):
        self.messages.append((status, category, message))

    def text(self):
        return "\n".join(m for _, _, m in self.messages)


def status_of(call, *args, **kwargs):
    try:
        result = call(*args, **kwargs)  # fmpy returns the status of calls that did not fail
        return result if isinstance(result, int) else 0
    except FMICallException as e:
        return e.status


def identifier(version, log=None, name="identifier", logging_on=True):
    return Slave(fmu(version), name, logger=log).instantiate(logging_on=logging_on)


def paper_data(samples=1001, seed=5):
    ref = paper_reference(0.01)
    u = np.random.default_rng(seed).standard_normal(samples)
    y, _ = ref.simulate(u[:, None])
    return ref, u, y


def run(slave, u, y, settings=PAPER_SETTINGS, initialize=True):
    if initialize:
        slave.set(**settings)
        slave.initialize()
    for k in range(len(u)):
        slave.set(u1=u[k], y1=y[k, 0], y2=y[k, 1])
        slave.step(k * settings["dt"], settings["dt"])
    return dict(zip(["identifications", "samples", "rejected"] + mode_outputs(),
                    slave.get("identifications", "samples", "rejected", *mode_outputs())))


def test_verification_script_passes():
    """The whole verification (validation, plant, identifier from arrays and in co-simulation,
    noise-free within 1e-6, 2 % noise within 0.5 % / 5 %) as the README runs it."""
    assert verify_main(["--fmu-dir", str(FMU_DIR)]) == 0


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("model", MODELS)
def test_shared_object_is_self_contained(version, model):
    so = shared_object(version, model)
    libs = re.findall(r"^\s*(\S+)", subprocess.run(["ldd", so], capture_output=True, text=True).stdout, re.M)
    allowed = ("linux-vdso.so.1", "libc.so.6", "libm.so.6", "/lib64/ld-linux-x86-64.so.2")
    assert all(lib in allowed for lib in libs), libs
    versions = re.findall(r"GLIBC_(\d+)\.(\d+)", subprocess.run(["objdump", "-T", so], capture_output=True,
                                                                 text=True).stdout)
    assert max((int(a), int(b)) for a, b in versions) <= (2, 17)


def fmi_functions(version):
    """Every function the FMI headers declare (fmpy's copies), e.g. fmi2DoStep."""
    import fmpy
    header = Path(fmpy.__file__).parent / "c-code" / f"fmi{version}Functions.h"
    return set(re.findall(rf"#define (fmi{version}\w+)\s+fmi{version}FullName", header.read_text()))


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("model", MODELS)
def test_exports_every_fmi_function_and_nothing_else(version, model):
    out = subprocess.run(["nm", "-D", "--defined-only", shared_object(version, model)], capture_output=True,
                         text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.strip()}
    assert exported == fmi_functions(version)


@pytest.mark.parametrize("version", VERSIONS)
def test_wrong_token_is_refused(version):
    log = Log()
    slave = Slave(fmu(version), "wrong", logger=log)
    slave.fmu.guid = "{not-this-fmu}"
    with pytest.raises(Exception):
        slave.instantiate(logging_on=True)
    assert "token/GUID '{not-this-fmu}'" in log.text()


@pytest.mark.parametrize("version", VERSIONS)
def test_illegal_calls_for_the_state(version):
    log = Log()
    s = identifier(version, log)
    assert status_of(s.step, 0.0, 0.01) == 3  # before initialization
    assert "DoStep must not be called in state Instantiated" in log.text()
    s.set(**PAPER_SETTINGS)
    s.initialize()
    assert status_of(s.set, observer_order=30) == 3  # a fixed parameter after initialization
    assert "'observer_order' (a fixed parameter) cannot be set in state StepMode" in log.text()
    assert status_of(s.set, mode1_frequency=1.0) == 3  # an output
    assert status_of(s.step, 0.0, 0.02) == 3  # step size other than dt
    assert "differs from the parameter dt" in log.text()
    assert status_of(s.step, 0.5, 0.01) == 3  # a communication point that is not the FMU's time
    assert "is not the FMU's time" in log.text()
    assert status_of(s.step, 0.0, 0.01) == 0  # and the instance still works
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("bad", [dict(observer_order=0), dict(dt=0.0), dict(dt=-0.01), dict(dt=math.nan),
                                 dict(order=3), dict(order=10), dict(hankel_rows=0), dict(forgetting_factor=1.5),
                                 dict(sensing=7), dict(order=4, observer_order=1), dict(decimation=0),
                                 dict(decimation=17), dict(scaling=2), dict(estimator=-1)])
def test_invalid_parameters_refused_at_initialization(version, bad):
    log = Log()
    s = identifier(version, log)
    s.set(**{**PAPER_SETTINGS, **bad})
    with pytest.raises(FMICallException):
        s.initialize()
    assert "parameters refused" in log.text()
    s.fmu.terminate()
    s.fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
def test_nan_sample_rejected_and_learning_kept(version):
    ref, u, y = paper_data()
    log = Log()
    s = identifier(version, log)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    out = run(s, u[:500], y[:500], initialize=False)
    before = modes_from(out)
    s.set(u1=u[500], y1=math.nan, y2=y[500, 1])
    assert status_of(s.step, 5.0, 0.01) == 0  # a warning (fmpy raises only above warning)
    assert any(cat == "logStatusWarning" and "rejected" in text for _, cat, text in log.messages)
    assert s.get("rejected")[0] == 1 and s.get("mode1_frequency")[0] == before[0]["frequency_hz"]
    for k in range(501, 1001):
        s.set(u1=u[k], y1=y[k, 0], y2=y[k, 1])
        s.step(k * 0.01, 0.01)
    after = modes_from(dict(zip(mode_outputs(), s.get(*mode_outputs()))))
    for got, want in zip(after, ref.modes):
        assert abs(got["frequency_hz"] - want.frequency_hz) / want.frequency_hz < 1e-9
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_indicator_and_warning_outputs(version):
    """Noise-free paper data: both modes fully consistent (CMI = EMAC * MPC = 1), and the warnings
    output carries the okid_warning bits: rank deficient (1) and observer order above the minimum (64)."""
    _, u, y = paper_data()
    s = identifier(version)
    run(s, u, y)
    for k in (1, 2):
        emac, mpc, cmi = s.get(f"mode{k}_emac", f"mode{k}_mpc", f"mode{k}_cmi")
        assert emac == pytest.approx(1, abs=1e-6) and mpc == pytest.approx(1, abs=1e-9)
        assert cmi == pytest.approx(emac * mpc, rel=1e-12)
    warnings = s.get("warnings")[0]
    assert warnings & 1 and warnings & 64
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("estimator", [0, 1])
def test_decimation_scaling_and_instruments(version, estimator):
    """docs/quality.md: 2 % output noise at the paper's dt, decimated by 2 with p = 30, alpha = beta = 50,
    sensors in mm, scaled: both modes within 1 % (measured 0.45 % with least squares, 0.39 % with instruments)."""
    ref, u, y = paper_data(1001, seed=3)
    y = 1000 * (y + 0.02 * np.sqrt(np.mean(y ** 2, axis=0)) * np.random.default_rng(33).standard_normal(y.shape))
    settings = {**PAPER_SETTINGS, "observer_order": 30, "hankel_rows": 50, "hankel_cols": 50, "identify_every": 1001,
                "decimation": 2, "scaling": 1, "estimator": estimator}
    s = identifier(version)
    out = run(s, u, y, settings)
    exact = np.sort([md.frequency_hz for md in ref.modes])
    freqs = np.sort([out[f"mode{k}_frequency"] for k in (1, 2)])
    assert np.all(np.abs(freqs - exact) < 0.01 * exact), freqs
    assert out["identifications"] == 1 and out["samples"] == 1001
    assert s.get("y_hat1", "y_hat2") == [0.0, 0.0]  # no one-step prediction of decimated data
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_reset_then_rerun_is_identical(version):
    _, u, y = paper_data(400)
    s = identifier(version)
    first = run(s, u, y)
    s.fmu.reset()
    second = run(s, u, y)
    assert first == second and first["identifications"] > 0
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_two_instances_are_independent(version):
    _, u1, y1 = paper_data(400, seed=1)
    _, u2, y2 = paper_data(400, seed=2)
    solo = run(identifier(version, name="solo"), u1, y1)
    a, b = identifier(version, name="a"), identifier(version, name="b")
    for s in (a, b):
        s.set(**PAPER_SETTINGS)
        s.initialize()
    for k in range(400):  # interleaved, different data
        a.set(u1=u1[k], y1=y1[k, 0], y2=y1[k, 1])
        b.set(u1=u2[k], y1=y2[k, 0], y2=y2[k, 1])
        a.step(k * 0.01, 0.01)
        b.step(k * 0.01, 0.01)
    assert dict(zip(mode_outputs(), a.get(*mode_outputs()))) == {k: solo[k] for k in mode_outputs()}


@pytest.mark.parametrize("version", VERSIONS)
def test_terminate_and_free_in_every_legal_state(version):
    s = identifier(version)  # instantiated
    s.fmu.freeInstance()
    s = identifier(version)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    s.close()  # step mode
    s = identifier(version)
    s.set(**{**PAPER_SETTINGS, "order": 3})
    with pytest.raises(FMICallException):
        s.initialize()
    s.close()  # after a refused initialization


@pytest.mark.parametrize("version", VERSIONS)
def test_logging_only_for_enabled_categories_and_percent_safe(version):
    log = Log()
    s = identifier(version, log)
    (s.fmu.setDebugLogging)(True, ["logStatusError"])
    s.set(**PAPER_SETTINGS)
    s.initialize()
    s.set(u1=1.0, y1=math.nan, y2=0.0)
    s.step(0.0, 0.01)
    assert s.get("rejected")[0] == 1
    assert not any(cat == "logStatusWarning" for _, cat, _ in log.messages)  # not enabled
    assert status_of(s.fmu.setDebugLogging, True, ["log%s%n%x"]) == 3
    assert "unknown category 'log%s%n%x'" in log.text()  # printed literally, never as a format
    s.close()
    quiet = Log()
    s = identifier(version, quiet, logging_on=False)
    assert status_of(s.step, 0.0, 0.01) == 3
    assert quiet.messages == []
    s.fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
def test_plant_parameters_and_time(version):
    log = Log()
    p = Slave(fmu(version, "okid_plant_2dof"), "plant", logger=log).instantiate(logging_on=True)
    p.set(m1=-1.0)
    with pytest.raises(FMICallException):
        p.initialize()
    assert "plant parameters refused" in log.text()
    p.fmu.terminate()
    p.fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("model", MODELS)
def test_sources_build_without_prefixes(tmp_path, version, model):
    """sources/ + its build description are enough to rebuild the binary (with a system LAPACK)."""
    import zipfile
    with zipfile.ZipFile(fmu(version, model)) as z:
        z.extractall(tmp_path)
    src = tmp_path / "sources"
    files = re.findall(r'SourceFile name="([^"]+)"', (src / "buildDescription.xml").read_text()) if version == 3 \
        else sorted(p.name for p in src.glob("*.c"))
    lapacke_cflags = subprocess.run(["pkg-config", "--cflags", "lapacke"], capture_output=True, text=True).stdout.split()
    so = tmp_path / "rebuilt.so"
    subprocess.run(["cc", "-std=c11", "-shared", "-fPIC", "-O1", "-I.", *lapacke_cflags, *files, "-o", str(so),
                    "-llapacke", "-llapack", "-lblas", "-lm"], cwd=src, check=True)
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.split()[-1].startswith("fmi")}
    assert exported == fmi_functions(version)
