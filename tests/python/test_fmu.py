# SPDX-License-Identifier: Apache-2.0
"""The FMUs as an importer sees them (fmpy, FMI 2 and FMI 3): verification against the 2-DOF
reference, the shared objects' hygiene, and every behaviour an importer relies on."""
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from fmu_runs import PAPER_SETTINGS, Slave, modes_from, mode_outputs
from reference import paper_reference
from verify_fmu import main as verify_main

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
        slave.set_inputs(u[k], y[k])
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


# The oldest glibc each Linux platform's binaries must load on: x86-64 2.17 (as it always was; the
# binaries need 2.14 at most), ARM64 2.17 (the first glibc of the port: its baseline symbol versions).
GLIBC_BASELINE = {"linux64": (2, 17), "x86_64-linux": (2, 17), "aarch64-linux": (2, 17)}
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "msvcrt.dll"}


def fmu_binaries():
    """(fmu file, platform folder, member name) of every binary inside every built .fmu."""
    import zipfile
    out = []
    for path in sorted(FMU_DIR.glob("fmi[23]/*.fmu")):
        with zipfile.ZipFile(path) as z:
            out += [(path, name.split("/")[1], name) for name in z.namelist()
                    if name.startswith("binaries/") and name.endswith((".so", ".dll"))]
    return out


def test_every_binary_in_every_fmu_loads_on_its_platforms_oldest_system(tmp_path):
    """Every binary of every .fmu (FMI 2 and 3, identifier and plant, every platform): an ELF
    object requires no glibc symbol version above its platform's baseline (readelf: the symbols
    and the version needs), a Windows DLL imports only system DLLs."""
    import zipfile
    binaries = fmu_binaries()
    assert {platform for _, platform, _ in binaries} >= {"linux64", "x86_64-linux"}
    assert len({path for path, _, _ in binaries}) == 4
    objdump = shutil.which("x86_64-w64-mingw32-objdump") or "objdump"
    for path, platform, name in binaries:
        with zipfile.ZipFile(path) as z:
            binary = tmp_path / f"{path.parent.name}-{path.stem}-{platform}{Path(name).suffix}"
            binary.write_bytes(z.read(name))
        if binary.suffix == ".dll":
            dump = subprocess.run([objdump, "-p", str(binary)], capture_output=True, text=True, check=True).stdout
            dlls = {d.lower() for d in re.findall(r"DLL Name: (\S+)", dump)}
            assert dlls and dlls <= WINDOWS_SYSTEM_DLLS, (path, name, dlls)
            continue
        dump = subprocess.run(["readelf", "-W", "--dyn-syms", "--version-info", str(binary)], capture_output=True,
                              text=True, check=True).stdout
        versions = {tuple(int(x) for x in v.split(".")[:2]) for v in re.findall(r"GLIBC_(\d+\.\d+(?:\.\d+)?)", dump)}
        assert versions, (path, name)
        assert max(versions) <= GLIBC_BASELINE[platform], (path, name, sorted(versions))


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
    assert status_of(s.set, identification_time=1.0) == 3  # an output
    assert status_of(s.step, 0.0, 0.02) == 3  # step size other than dt
    assert "differs from the parameter dt" in log.text()
    assert status_of(s.step, 0.5, 0.01) == 3  # a communication point that is not the FMU's time
    assert "is not the FMU's time" in log.text()
    assert status_of(s.step, 0.0, 0.01) == 0  # and the instance still works
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("bad", [dict(observer_order=0), dict(dt=0.0), dict(dt=-0.01), dict(dt=math.nan),
                                 dict(order=41), dict(hankel_rows=0), dict(forgetting_factor=1.5),
                                 dict(sensing=7), dict(order=4, observer_order=1), dict(decimation=65),
                                 dict(scaling=2), dict(estimator=-1), dict(identify_every=0)])
def test_invalid_parameters_refused_at_initialization(version, bad):
    """okid_init's own check and status, reported with the values as numbers (no C macro names)."""
    log = Log()
    s = identifier(version, log)
    s.set(**{**PAPER_SETTINGS, **bad})
    with pytest.raises(FMICallException):
        s.initialize()
    text = log.text()
    assert "parameters refused" in text
    name, value = next(iter(bad.items())) if "identify_every" in bad else list(bad.items())[-1]
    number = format(value, ".17g") if isinstance(value, float) else str(value)  # as the FMU's %.17g prints it
    assert f"{name} {number}" in text or f"{name} = {number}" in text, text
    assert "okid_status" in text or name == "identify_every"
    assert not re.search(r"OKID_[A-Z_]+", text), text
    s.fmu.terminate()
    s.fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("bad, says", [
    # the order against the Hankel sizes: alpha m = 10 x 2, beta (r) = 10 x 1, m p = 2 x 20
    (dict(order=41, hankel_rows=10, hankel_cols=10), "order = 41 is outside 0..10; order = 41 must be at most "
                                                     "min(alpha m, beta columns, m p) = min(20, 10, 40) = 10"),
    (dict(forgetting_factor=1.5), "forgetting_factor = 1.5 is outside "),
    (dict(decimation=65), "decimation = 65 is outside 0..64"),
])
def test_refused_configuration_names_the_value_and_its_range(version, bad, says):
    """The FMU's refusal in the CLI's and Python's words (host_tools/common/config_explain.c, shipped in
    sources/): the setting, its value and its valid range, not only the status's text (issue 27)."""
    log = Log()
    s = identifier(version, log)
    settings = {**PAPER_SETTINGS, **bad}
    s.set(**settings)
    with pytest.raises(FMICallException):
        s.initialize()
    text = log.text()
    assert says in text, text
    # the host library's one sentence, as Python gets it, up to the spelling of a setting (order=41)
    from okid import _core
    cfg = _core.config_default(1, 2)
    cfg.update({k: type(cfg[k])(v) for k, v in settings.items() if k in cfg})
    status, _, python = _core.explain_config(cfg)
    assert status != 0 and re.sub(r"\b(order|instrument_lags)=", r"\1 = ", python) in text, (python, text)
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
    s.set_inputs(u[500], [math.nan, y[500, 1]])
    assert status_of(s.step, 5.0, 0.01) == 0  # a warning (fmpy raises only above warning)
    assert any(cat == "logStatusWarning" and "rejected" in text for _, cat, text in log.messages)
    assert s.get("rejected")[0] == 1 and s.get("mode1_frequency_hz")[0] == before[0]["frequency_hz"]
    for k in range(501, 1001):
        s.set_inputs(u[k], y[k])
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
@pytest.mark.parametrize("estimator", [0, 1, 2])
def test_decimation_scaling_and_instruments(version, estimator):
    """docs/quality.md: 2 % output noise at the paper's dt, decimated by 2 with p = 30, alpha = beta = 50,
    sensors in mm, scaled: both modes within 1 % (measured 0.45 % with least squares, 0.39 % with instruments;
    the correlation form solves the same least squares)."""
    ref, u, y = paper_data(1001, seed=3)
    y = 1000 * (y + 0.02 * np.sqrt(np.mean(y ** 2, axis=0)) * np.random.default_rng(33).standard_normal(y.shape))
    settings = {**PAPER_SETTINGS, "observer_order": 30, "hankel_rows": 50, "hankel_cols": 50, "identify_every": 1001,
                "decimation": 2, "scaling": 1, "estimator": estimator}
    s = identifier(version)
    out = run(s, u, y, settings)
    exact = np.sort([md.frequency_hz for md in ref.modes])
    freqs = np.sort([out[f"mode{k}_frequency_hz"] for k in (1, 2)])
    assert np.all(np.abs(freqs - exact) < 0.01 * exact), freqs
    assert out["identifications"] == 1 and out["samples"] == 1001
    assert all(math.isnan(v) for v in s.get("y_hat1", "y_hat2", "y_error1", "y_error2"))  # no prediction when K > 1
    assert s.get("prediction_valid")[0] == 0
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_reset_then_rerun_is_identical(version):
    _, u, y = paper_data(400)
    s = identifier(version)
    first = run(s, u, y)
    s.fmu.reset()
    second = run(s, u, y)
    assert first["identifications"] > 0
    assert all(first[k] == second[k] or (math.isnan(first[k]) and math.isnan(second[k])) for k in first)
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
        a.set_inputs(u1[k], y1[k])
        b.set_inputs(u2[k], y2[k])
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
    s.set(**{**PAPER_SETTINGS, "order": 41})
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
    s.set_inputs(1.0, [math.nan, 0.0])
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


# ---- issue 17 class 4: every output is current or visibly not (docs/fmu.md, "Stale outputs") ----

def outputs_are_flagged(s, t):
    """The invariants an importer can rely on after every step."""
    status, valid, when, y_hat, y_error = s.get("status", "prediction_valid", "identification_time", "y_hat1", "y_error1")
    assert bool(valid) == math.isfinite(y_hat), (t, valid, y_hat)
    if not valid:
        assert math.isnan(y_error)
    if status == 0:  # collecting: no model, nothing published
        assert math.isnan(when) and all(math.isnan(v) for v in s.get(*mode_outputs()))
    else:
        assert math.isnan(when) or when <= t + 1e-12
    return status, valid, when


@pytest.mark.parametrize("version", VERSIONS)
def test_outputs_before_the_first_identification_are_nan(version):
    """On main y_error was 0 and the mode outputs 0 before any model existed."""
    _, u, y = paper_data(120)
    s = identifier(version)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    for k in range(59):  # the first identification comes once 60 regressor rows are in
        s.set_inputs(u[k], y[k])
        s.step(k * 0.01, 0.01)
        status, valid, when = outputs_are_flagged(s, k * 0.01)
        assert status == 0 and not valid and math.isnan(when)
        assert math.isnan(s.get("y_error2")[0]) and math.isnan(s.get("singular_value1")[0])
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_prediction_after_a_nan_sample_is_nan_until_the_window_refills(version):
    """After a NaN sample the regressor window restarts: for p samples there is no prediction. On
    main the FMU kept publishing the last y_hat/y_error, so a 5-unit sensor fault in that window
    read as y_error1 = -5.6e-16. Now y_hat/y_error are NaN with prediction_valid false, and once
    the window is full again the fault shows in y_error1."""
    _, u, y = paper_data(600)
    s = identifier(version)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    p = PAPER_SETTINGS["observer_order"]
    for k in range(600):
        yk = y[k].copy()
        if k == 500:
            yk[0] = math.nan
        elif k > 500:
            yk[0] += 5.0  # the sensor comes back with an offset
        s.set_inputs(u[k], yk)
        s.step(k * 0.01, 0.01)
        status, valid, _ = outputs_are_flagged(s, k * 0.01)
        if 300 <= k < 500:
            assert status == 1 and valid
        elif k == 500:  # predicted from the past, but the measurement is NaN
            assert valid and math.isnan(s.get("y_error1")[0])
        elif 500 < k <= 500 + p:
            assert not valid and math.isnan(s.get("y_error1")[0]), k
        elif 500 + p + 1 < k < 600:  # before the next identification re-fits the model to the offset data
            assert valid and s.get("y_error1")[0] > 1.0, (k, s.get("y_error1"))
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_failed_identification_is_visible(version):
    """No excitation: the identification fails; status says so and nothing is published."""
    s = identifier(version)
    s.set(**PAPER_SETTINGS)
    s.initialize()
    for k in range(200):
        s.set_inputs(0.0, [0.0, 0.0])
        s.step(k * 0.01, 0.01)
        outputs_are_flagged(s, k * 0.01)
    status, last_error, when, identifications = s.get("status", "last_error", "identification_time", "identifications")
    assert status == 2 and last_error < 0 and math.isnan(when) and identifications == 0
    assert all(math.isnan(v) for v in s.get(*mode_outputs()))
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_failure_after_success_keeps_the_model_with_its_time(version):
    """Identified, then the forgetting factor forgets everything (zero data): the failure is
    reported (status failed, last_error) while the mode outputs keep the last successful
    identification and identification_time says when that was."""
    _, u, y = paper_data(400)
    s = identifier(version)
    s.set(**{**PAPER_SETTINGS, "forgetting_factor": 0.5, "observer_order": 4, "hankel_rows": 10, "hankel_cols": 10})
    s.initialize()
    last_good = None
    for k in range(4000):
        uk, yk = (u[k], y[k]) if k < 400 else (0.0, [0.0, 0.0])
        s.set_inputs(uk, yk)
        s.step(k * 0.01, 0.01)
        status, _, when = outputs_are_flagged(s, k * 0.01)
        if status == 1:
            last_good = (when, s.get(*mode_outputs()))
        elif status == 2 and last_good is not None:
            assert s.get("last_error")[0] < 0 and when == last_good[0] < k * 0.01
            assert s.get(*mode_outputs()) == last_good[1]
            break
    else:
        pytest.fail("no identification failed after a success")
    s.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_model_description_is_honest(version):
    """Variable steps are not claimed (the identifier samples once per step of dt); every ranged
    parameter has min and max; booleans are Boolean; enumerations are FMI 3 enumerations and, in
    FMI 2, integers whose description lists the values; parameter names are okid_config's."""
    from fmpy import read_model_description
    md = read_model_description(fmu(version))
    assert md.coSimulation.canHandleVariableCommunicationStepSize is False
    v = {x.name: x for x in md.modelVariables}
    for name in ("observer_order", "order", "hankel_rows", "hankel_cols", "block_rows", "decimation",
                 "instrument_lags", "forgetting_factor", "rank_tolerance"):
        assert v[name].min is not None and v[name].max is not None, name
    assert v["dt"].min is not None
    assert v["zero_initial_state"].type == "Boolean"
    enum_type = "Enumeration" if version == 3 else "Integer"
    for name, items in [("sensing", "displacement velocity acceleration"), ("realization", "system combined"),
                        ("scaling", "none auto"), ("estimator", "least_squares instrumental correlation")]:
        assert v[name].type == enum_type
        if version == 3:
            assert [i.name for i in v[name].declaredType.items] == items.split()
        else:
            assert all(item.split("_")[0] in v[name].description for item in items.split())
    # the parameters are okid_config's fields (their defaults: tests/python/test_vocabulary.py)
    assert {"dt", "observer_order", "order", "hankel_rows", "hankel_cols", "block_rows", "forgetting_factor",
            "rank_tolerance", "sensing", "realization", "zero_initial_state", "decimation", "scaling", "estimator",
            "instrument_lags"} <= {x.name for x in md.modelVariables if x.causality == "parameter"}
    assert v["order"].start in ("0", 0) and v["zero_initial_state"].start in ("false", False, 0)


# ---- issue 16: the configurable FMI 3 identifier, through fmpy's low-level calls ----

CHAIN = dict(masses=(2.0, 3.0, 2.5), dampers=(2.0, 4.0, 3.0, 2.0), springs=(20.0, 40.0, 30.0, 25.0))


def chain_case(samples=1001, seed=7):
    from reference import chain_reference
    ref = chain_reference(0.01, CHAIN["masses"], CHAIN["dampers"], CHAIN["springs"], forces_on=(0, 2))
    u = np.random.default_rng(seed).standard_normal((samples, 2))
    y, _ = ref.simulate(u)
    return ref, u, y


def assert_modes_match(s, ref, tolerance=1e-9):
    m = ref.C.shape[0]
    got = modes_from(dict(zip(mode_outputs(len(ref.modes), m), s.get(*mode_outputs(len(ref.modes), m)))),
                     len(ref.modes), m)
    from reference import mac
    for g, want in zip(got, ref.modes):
        assert abs(g["frequency_hz"] - want.frequency_hz) / want.frequency_hz < tolerance
        assert abs(g["damping_ratio"] - want.damping_ratio) / want.damping_ratio < tolerance
        assert abs(g["eigenvalue"] - want.eigenvalue) < tolerance
        assert mac(g["shape"], want.shape) > 1 - tolerance


def test_fmi3_structural_parameters_two_inputs_three_outputs():
    """Configuration mode: num_inputs 2, num_outputs 3, max_modes 3; the 3-DOF chain with forces on
    masses 1 and 3 identified to 1e-9 against the numpy reference."""
    ref, u, y = chain_case()
    s = identifier(3)
    s.configure(num_inputs=2, num_outputs=3, max_modes=3)
    s.set(dt=0.01, observer_order=10, order=6, hankel_rows=20, hankel_cols=20, identify_every=1001,
          zero_initial_state=1)
    s.initialize()
    assert len(s.fmu.getFloat64([s.vr("u")], nValues=2)) == 2
    for k in range(len(u)):
        s.set_inputs(u[k], y[k])
        s.step(k * 0.01, 0.01)
    assert s.get("status", "num_modes", "identifications") == [1, 3, 1]
    assert_modes_match(s, ref)
    s.close()


def test_fmi3_start_values_are_the_paper_case():
    """An importer that ignores structural parameters gets the paper's FMU (r 1, m 2, 4 modes)."""
    ref, u, y = paper_data()
    s = identifier(3)
    run(s, u, y, {**PAPER_SETTINGS, "identify_every": 1001})
    assert_modes_match(s, ref)
    assert math.isnan(s.get("mode3_frequency_hz")[0])  # 2 modes identified, 4 published: the rest NaN
    s.close()


def test_fmi3_structural_parameter_rules():
    log = Log()
    s = identifier(3, log)
    assert status_of(s.fmu.setUInt64, [s.vr("num_inputs")], [2]) == 3  # outside configuration mode
    assert "ConfigurationMode only" in log.text()
    s.fmu.enterConfigurationMode()
    s.fmu.setUInt64([s.vr("num_outputs")], [65])
    assert status_of(s.fmu.exitConfigurationMode) == 3
    assert "num_outputs = 65 refused: this build allows 1..64" in log.text()
    s.fmu.setUInt64([s.vr("num_outputs")], [3])
    s.fmu.exitConfigurationMode()
    s.structural["num_outputs"] = 3
    assert len(s.get("y_hat")[0]) == 3
    assert status_of(s.fmu.getFloat64, [s.vr("y_hat")], nValues=2) == 3  # nValues must match the size
    s.fmu.freeInstance()


@pytest.mark.parametrize("value", [2**31, 2**32 - 1, 2**40, 2**64 - 1])
def test_fmi3_uint64_beyond_int_is_refused_as_given(value):
    """A UInt64 above 2^31 was stored as -1 and logged so ("num_outputs = -1 refused"); now the set
    itself is refused, naming the value as the importer gave it, and nothing is stored."""
    log = Log()
    s = identifier(3, log)
    s.fmu.enterConfigurationMode()
    assert status_of(s.fmu.setUInt64, [s.vr("num_outputs")], [value]) == 3
    assert f"num_outputs = {value} is outside the integers this FMU stores (-2147483648..2147483647)" in log.text()
    assert "-1" not in log.text()
    assert s.fmu.getUInt64([s.vr("num_outputs")]) == [2]  # the start value, untouched
    s.fmu.freeInstance()


# ---- issue 16: FMI 2 FMUs for any configuration from the one prebuilt binary (okid-fmu) ----

def generated_chain_fmu(tmp_path, **extra):
    from okid.tools.fmu_generator import generate
    out = tmp_path / "chain.fmu"
    settings = [("num_inputs", 2), ("num_outputs", 3), ("max_modes", 3), ("observer_order", 10), ("order", 6),
                ("zero_initial_state", 1), *extra.items()]
    text = generate(fmu(2), out, settings)
    return out, text


def test_generated_fmi2_description_is_the_c_generators(tmp_path):
    """okid-fmu's modelDescription.xml is byte for byte the C generator's for the same resources/ file."""
    import zipfile
    out, text = generated_chain_fmu(tmp_path, dt=0.005, identify_every=500)
    with zipfile.ZipFile(out) as z:
        (tmp_path / "chain.cfg").write_bytes(z.read("resources/okid_identifier.cfg"))
    sources = re.findall(r'<File name="([^"]+)"/>', text)
    c_text = subprocess.run([str(FMU_DIR / "okid_identifier_describe"), "2", str(tmp_path / "chain.cfg"), *sources],
                            capture_output=True, text=True, check=True).stdout
    assert text == c_text


def test_generated_fmi2_fmu_identifies_the_chain(tmp_path):
    """A 2-input, 3-output FMI 2 FMU written by okid-fmu: validated by fmpy and fmutool, then the
    3-DOF chain identified to 1e-9 through fmpy's FMI 2 calls (the defaults come from resources/)."""
    from fmpy.validation import validate_fmu
    from verify_fmu import fmutool_problems
    out, _ = generated_chain_fmu(tmp_path, identify_every=1001)
    assert validate_fmu(str(out)) == [] and fmutool_problems(out) == []
    ref, u, y = chain_case()
    s = Slave(str(out), "chain").instantiate()
    s.set(dt=0.01, hankel_rows=20, hankel_cols=20)  # observer_order, order, zero_initial_state: the FMU's defaults
    s.initialize()
    for k in range(len(u)):
        s.set_inputs(u[k], y[k])
        s.step(k * 0.01, 0.01)
    assert s.get("status", "num_modes", "identifications", "num_inputs", "num_outputs") == [1, 3, 1, 2, 3]
    assert_modes_match(s, ref)
    s.close()


@pytest.mark.parametrize("setting, value, message", [
    ("dt", float("nan"), "dt = nan is not a finite number"),
    ("dt", float("inf"), "dt = inf is not a finite number"),
    ("dt", -1.0, "dt = -1.0 is outside 2.2250738585072014e-308.."),
    ("forgetting_factor", 1e14, "forgetting_factor = 100000000000000.0 is outside 2.2250738585072014e-308..1"),
    ("observer_order", -1, "observer_order = -1 is outside 1..1000"),
    ("identify_every", 10**14, "identify_every = 100000000000000 is outside 1..2147483647"),
    ("order", 7, "invalid settings (r = 2, m = 3, p = 2, n = 7, Hankel 20 x 20)"),  # the C check: n <= m p = 6
])
def test_okid_fmu_validates_every_value(tmp_path, setting, value, message):
    """NaN, inf, 1e14, -1 made an FMU that fmpy refused or that failed at initialization; now the
    generator refuses each, naming it, and writes nothing. The settings together are checked by the
    library's own okid_config_check (its explanation: the CLI's line)."""
    from okid.tools.fmu_generator import generate
    out = tmp_path / "bad.fmu"
    settings = [("num_inputs", 2), ("num_outputs", 3), ("max_modes", 3), ("observer_order", 2), (setting, value)]
    settings = list(dict(settings).items())
    with pytest.raises(SystemExit, match="^okid-fmu: " + re.escape(message)):
        generate(fmu(2), out, settings)
    assert not out.exists()


def test_okid_fmu_refuses_to_overwrite_its_base(tmp_path):
    """okid-fmu -o X --base X replaced the prebuilt FMU, exit 0."""
    import shutil
    base = tmp_path / "base.fmu"
    shutil.copy(fmu(2), base)
    before = base.read_bytes()
    proc = subprocess.run([sys.executable, "-m", "okid.tools.fmu_generator", "--base", str(base), "--inputs", "1",
                           "--outputs", "2", "--max-modes", "2", "-o", str(tmp_path / "." / "base.fmu")],
                          capture_output=True, text=True)
    assert proc.returncode != 0 and proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [
        f"okid-fmu: the output {tmp_path / '.' / 'base.fmu'} is the prebuilt FMU it is made from (--base): give another -o"]
    assert base.read_bytes() == before
    # an output that cannot be written (its folder is a file): one line, no traceback
    proc = subprocess.run([sys.executable, "-m", "okid.tools.fmu_generator", "--base", str(base), "--inputs", "1",
                           "--outputs", "2", "--max-modes", "2", "-o", str(base / "x.fmu")],
                          capture_output=True, text=True)
    assert proc.returncode == 1 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert proc.stderr.startswith("okid-fmu: ") and "Traceback" not in proc.stderr


def test_generated_fmi2_configuration_is_bound_and_checked(tmp_path):
    """The GUID binds the resources/ file (an edited file is refused); sizes beyond the binary's
    limits are refused by the generator and by the binary, with the numbers."""
    import zipfile
    from okid.tools.fmu_generator import generate
    with pytest.raises(SystemExit, match="num_outputs = 65 is outside this binary's range 1..64"):
        generate(fmu(2), tmp_path / "big.fmu", [("num_inputs", 1), ("num_outputs", 65), ("max_modes", 1)])
    out, _ = generated_chain_fmu(tmp_path)
    for edit, message in [(lambda c: c.replace("max_modes 3", "max_modes 2"), "is not this FMU's"),
                          (lambda c: c.replace("num_outputs 3", "num_outputs 65"), "num_outputs = 65 refused: this build allows 1..64"),
                          (lambda c: c + "observer_order ten\n", "is not '<structural parameter or parameter> <number>'")]:
        edited = tmp_path / "edited.fmu"
        with zipfile.ZipFile(out) as zin, zipfile.ZipFile(edited, "w") as zout:
            for item in zin.infolist():
                data = zin.read(item)
                if item.filename == "resources/okid_identifier.cfg":
                    data = edit(data.decode()).encode()
                zout.writestr(item, data)
        log = Log()
        with pytest.raises(Exception):
            Slave(str(edited), "edited", logger=log).instantiate(logging_on=True)
        assert message in log.text()


# ---- the mode outputs: the physical modes (all_poles false, order 0) or the model's poles ----

OKID_CLI = os.environ.get("OKID_CLI", "build/host_tools/cli/okid")
# The newcomer's record of docs/quality.md section 8 (the paper's plant, 2 % output noise) and
# explicit settings at which one Hankel window's selection holds both modes (p = 50: 0.505 and
# 1.049 Hz against the exact 0.503 and 1.048 Hz).
SELECTION_RECORD = ["--samples", "10001", "--noise", "0.02", "--seed", "1"]
SELECTION_SETTINGS = dict(dt=0.01, observer_order=50, hankel_rows=100, hankel_cols=100, identify_every=10001)
MODE_VALUES = ["frequency_hz", "damping_ratio", "eigenvalue_re", "eigenvalue_im", "emac", "mpc", "cmi"]


@pytest.fixture(scope="module")
def selection_record(tmp_path_factory):
    path = tmp_path_factory.mktemp("selection") / "paper_noisy.csv"
    subprocess.run([OKID_CLI, "simulate", *SELECTION_RECORD, "--output", str(path)], check=True)
    return path, np.loadtxt(path, delimiter=",", skiprows=1)


def fmu_modes(version, data, settings, max_modes=4, m=2):
    """Feed (t, force, acc1, acc2) rows to the identifier; its counters and its max_modes mode outputs."""
    s = identifier(version)
    s.set(**settings)
    s.initialize()
    for k in range(len(data)):
        s.set_inputs(data[k, 1], data[k, 2:])
        s.step(k * settings["dt"], settings["dt"])
    names = ["status", "num_modes", "warnings", "identifications", "samples", "last_error"]
    out = dict(zip(names, s.get(*names)))
    out["modes"] = []
    for k in range(1, max_modes + 1):
        md = {v: s.get(f"mode{k}_{v}")[0] for v in MODE_VALUES}
        md["shape"] = [[s.get(f"mode{k}_shape{j}_re")[0], s.get(f"mode{k}_shape{j}_im")[0]] for j in range(1, 2 * m + 1)]
        out["modes"].append(md)
    s.close()
    return out


def same_bits(a, b):
    """Equal as stored doubles, NaN equal to NaN (a mode output beyond num_modes)."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_bits(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same_bits(x, y) for x, y in zip(a, b))
    return (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b)) or a == b


def assert_modes_are_the_clis(fmu_modes, cli_modes, tol):
    """The FMU's mode outputs (fmu_modes()) equal the CLI JSON's modes to tol; NaN beyond them."""
    for k, (c, f) in enumerate(zip(cli_modes, fmu_modes)):
        expected = dict(c, eigenvalue_re=c["eigenvalue"][0], eigenvalue_im=c["eigenvalue"][1])
        for v in MODE_VALUES:
            assert f[v] == pytest.approx(expected[v], rel=tol, abs=tol), (k, v)
        assert np.allclose(f["shape"], c["shape"], rtol=0, atol=tol), k
    assert all(math.isnan(md[v]) for md in fmu_modes[len(cli_modes):] for v in MODE_VALUES)


@pytest.mark.parametrize("version", VERSIONS)
def test_mode_outputs_are_the_clis_physical_modes(version, selection_record):
    """Order 0 and all_poles false (the defaults): the mode outputs are the modes okid identify lists
    for the same record and settings (one Hankel window, order left out: docs/quality.md section 8),
    to round-off."""
    import json
    path, data = selection_record
    s = SELECTION_SETTINGS
    cli = json.loads(subprocess.run(
        [OKID_CLI, "identify", "--json", "--decimation", "1", "--observer-order", str(s["observer_order"]),
         "--hankel-rows", str(s["hankel_rows"]), "--hankel-cols", str(s["hankel_cols"]), str(path)],
        check=True, capture_output=True, text=True).stdout)
    out = fmu_modes(version, data, s)
    assert out["status"] == 1 and out["identifications"] == 1 and out["samples"] == len(data)
    assert out["num_modes"] == len(cli["modes"]) == 2
    assert not out["warnings"] & 16384  # OKID_W_NO_PHYSICAL_MODE
    # Both runs solve the same least squares and SVD, rounded differently (the CLI folds blocks of rows
    # with the system's LAPACK, the FMU one row at a time with the reference LAPACK). A pole of the
    # table's order-N realization moves by about eps times its condition sigma_1 / sigma_N, and its
    # frequency and damping (log lambda / dt) by that over 1 - |lambda|: 1.5e-9 here (3.5e4 at N = 60,
    # 1 - |lambda| = 0.005); measured 5e-13.
    sv, top = cli["singular_values"], cli["chosen"]["max_order"]
    closest = max(abs(complex(*md["eigenvalue"])) for md in cli["modes"])
    tol = np.finfo(float).eps * sv[0] / sv[top - 1] / (1 - closest)
    assert tol < 1e-8
    assert_modes_are_the_clis(out["modes"], cli["modes"], tol)


@pytest.mark.parametrize("version", VERSIONS)
def test_all_poles_keeps_the_outputs_of_before(version, selection_record):
    """all_poles true: every pole of the identified model, as before the selection, bit for bit
    (tests/data/fmu_poles_before.json: the previous FMU's outputs on the same record)."""
    import hashlib
    import json
    path, data = selection_record
    before = json.loads((Path(__file__).parents[1] / "data" / "fmu_poles_before.json").read_text())
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before["record_sha256"], \
        "okid simulate writes another record than the one the stored outputs are of"
    out = fmu_modes(version, data, {**before["settings"], "all_poles": True})
    assert same_bits(out, before["outputs"])
    # the raw poles are not the selection here: the selection's representatives differ in the last bits
    selected = fmu_modes(version, data, before["settings"])
    assert selected["num_modes"] == out["num_modes"] == 2 and not same_bits(selected, out)


@pytest.mark.parametrize("version", VERSIONS)
def test_no_physical_mode_is_a_warning(version):
    """Outputs that are noise unrelated to the force: no pole stays put across the orders, so
    num_modes is 0, every mode output NaN and warnings has OKID_W_NO_PHYSICAL_MODE (16384); the same
    record with all_poles true publishes the model's poles without that bit."""
    rng = np.random.default_rng(7)
    data = np.column_stack([np.arange(2000) * 0.01, rng.standard_normal((2000, 3))])
    settings = dict(dt=0.01, observer_order=10, hankel_rows=20, hankel_cols=20, identify_every=2000)
    out = fmu_modes(version, data, settings)
    assert out["status"] == 1 and out["num_modes"] == 0 and out["warnings"] & 16384
    assert all(math.isnan(md[v]) for md in out["modes"] for v in MODE_VALUES)
    raw = fmu_modes(version, data, {**settings, "all_poles": True})
    assert raw["num_modes"] > 0 and not raw["warnings"] & 16384


# ---- output-only (num_inputs = 0): okid identify --inputs 0's modes from y alone ----

# tests/python/test_ambient.py's record (the paper's plant under unmeasured white forces on both
# masses, 5 % sensor noise, 40000 samples at 0.05 s) with its mean removed here, so that the CLI's
# own mean removal changes it by round-off only (the FMU streams and removes none: docs/fmu.md).
# L = 10: one Hankel size whose selection holds both modes (0.537 and 1.050 Hz against the exact
# 0.503 and 1.048 Hz; within test_ambient.py's statistical tolerances).
AMBIENT_SETTINGS = dict(hankel_rows=10, identify_every=40000)


@pytest.fixture(scope="module")
def ambient_case(tmp_path_factory):
    from okid.tools.fmu_generator import generate
    from test_ambient import DT, ambient_record
    y = ambient_record()
    y = y - y.mean(axis=0)
    folder = tmp_path_factory.mktemp("output_only")
    path = folder / "ambient.csv"
    np.savetxt(path, np.column_stack([DT * np.arange(len(y)), y]), delimiter=",", header="t,acc1,acc2", comments="",
               fmt="%.17g")  # %.17g: the CSV holds y's doubles exactly
    fmi2 = folder / "output_only.fmu"  # FMI 2 takes its sizes from resources/: okid-fmu --inputs 0
    generate(fmu(2), fmi2, [("num_inputs", 0), ("num_outputs", 2), ("max_modes", 4)])
    return dict(path=path, y=y, dt=DT, fmu={2: str(fmi2), 3: fmu(3)})


def output_only_identifier(version, case, log=None):
    s = Slave(case["fmu"][version], "output_only", logger=log).instantiate(logging_on=True)
    if version == 3:
        s.configure(num_inputs=0)
    return s


def output_only_modes(version, case, settings, max_modes=4, m=2):
    """Feed y to the output-only identifier; its counters, predictor outputs and max_modes mode outputs."""
    s = output_only_identifier(version, case)
    dt = case["dt"]
    s.set(dt=dt, **settings)
    s.initialize()
    for k, row in enumerate(case["y"]):
        s.set_array("y", row)
        s.step(k * dt, dt)
    names = ["status", "num_modes", "warnings", "identifications", "samples", "rejected", "last_error",
             "prediction_valid", "regressor_rank", "y_hat1", "y_error2", "singular_value1"]
    out = dict(zip(names, s.get(*names)))
    out["modes"] = [{v: s.get(f"mode{k}_{v}")[0] for v in MODE_VALUES} for k in range(1, max_modes + 1)]
    for k, md in enumerate(out["modes"], 1):
        md["shape"] = [[s.get(f"mode{k}_shape{j}_re")[0], s.get(f"mode{k}_shape{j}_im")[0]] for j in range(1, 2 * m + 1)]
    s.close()
    return out


@pytest.mark.parametrize("version", VERSIONS)
def test_output_only_modes_are_the_clis(version, ambient_case):
    """num_inputs 0, order 0, all_poles false: the mode outputs are the physical modes okid identify
    --inputs 0 lists for the same record and L (one Hankel size), to round-off."""
    import json
    cli = json.loads(subprocess.run(
        [OKID_CLI, "identify", "--inputs", "0", "--hankel-rows", str(AMBIENT_SETTINGS["hankel_rows"]), "--json",
         str(ambient_case["path"])], check=True, capture_output=True, text=True).stdout)
    out = output_only_modes(version, ambient_case, AMBIENT_SETTINGS)
    n = len(ambient_case["y"])
    assert out["status"] == 1 and out["identifications"] == 1 and out["samples"] == n and out["rejected"] == 0
    assert out["num_modes"] == len(cli["modes"]) == 2 and not out["warnings"] & 16384
    # no predictor output-only: visibly none
    assert not out["prediction_valid"] and out["regressor_rank"] == 0
    assert math.isnan(out["y_hat1"]) and math.isnan(out["y_error2"])
    assert out["singular_value1"] == pytest.approx(cli["singular_values"][0], rel=1e-12)
    # The same sums in another order: the CLI sums R(k) in batches of 256 samples by matrix products
    # (okid_ambient_push_block, the system's BLAS), the FMU one sample at a time (okid_ambient_push,
    # the reference BLAS). Each of the N-term sums then differs by about sqrt(N) eps relative to the
    # sum of the magnitudes, which bounds each entry of the scaled correlations (|R(k)| <= 1: the
    # channels' RMS divide them); the N x N Hankel of the table's top order N = L m changes by N times
    # that, a pole of its order-N realization by that times sigma_1 / sigma_N, and its frequency and
    # damping (log lambda / dt) by that over 1 - |lambda|: 3.9e-8 here (sigma_1 / sigma_20 = 730,
    # 1 - |lambda| = 0.017); measured 1.1e-14.
    sv, top = cli["singular_values"], min(cli["chosen"]["max_order"], AMBIENT_SETTINGS["hankel_rows"] * 2)
    closest = max(abs(complex(*md["eigenvalue"])) for md in cli["modes"])
    tol = np.finfo(float).eps * math.sqrt(n) * top * sv[0] / sv[top - 1] / (1 - closest)
    assert tol < 1e-7
    assert_modes_are_the_clis(out["modes"], cli["modes"], tol)


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("bad, says", [
    # okid_ambient_config_check's field, value and range: order <= L min(m, references) = 10 x 2
    (dict(hankel_rows=10, order=21), "order = 21, valid 0..20 for output-only identification (at most hankel_rows "
                                     "num_outputs, and 512)"),
    (dict(hankel_rows=0), "hankel_rows = 0, valid 1..1000 for output-only identification"),
    (dict(dt=-1.0), "dt = -1, valid "),
    # the observer's settings, as okid identify --inputs 0 refuses their flags
    (dict(observer_order=10), "observer_order does not apply to output-only identification (num_inputs = 0)"),
    (dict(estimator=1), "estimator does not apply to output-only identification"),
    (dict(hankel_rows=10, hankel_cols=30), "hankel_cols (L is both rows and columns: set hankel_rows) does not apply"),
])
def test_output_only_refusals_name_the_setting(version, ambient_case, bad, says):
    log = Log()
    s = output_only_identifier(version, ambient_case, log)
    s.set(**{"dt": ambient_case["dt"], **bad})
    with pytest.raises(FMICallException):
        s.initialize()
    assert says in log.text(), log.text()
    s.fmu.terminate()
    s.fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
def test_output_only_nan_gap_and_order_given(version, ambient_case):
    """A NaN sample is rejected with a warning and counted (a gap: no product spans it), the sums
    kept; with the order given the mode outputs are the order-4 model's poles, as Python's
    okid.identify_ambient(order=4) gives them (the same round-off argument as above, the condition
    now sigma_1 / sigma_4)."""
    gap = ambient_case["y"][:4000].copy()
    gap[100, 0] = math.nan
    y = gap - np.nanmean(gap, axis=0)  # the finite values' mean: what Python removes, so it removes ~0 below
    dt = ambient_case["dt"]
    log = Log()
    s = output_only_identifier(version, ambient_case, log)
    s.set(dt=dt, hankel_rows=10, order=4, identify_every=len(y) - 1)  # accepted samples
    s.initialize()
    for k, row in enumerate(y):
        s.set_array("y", row)
        assert status_of(s.step, k * dt, dt) == 0  # the NaN's a warning (fmpy raises only above warning)
    assert [text for _, cat, text in log.messages if cat == "logStatusWarning"] == [
        "non-finite output sample at t = 5 rejected (a gap in the correlations); the sums so far are kept"]
    assert s.get("status", "samples", "rejected", "identifications") == [1, len(y) - 1, 1, 1]
    fmu_modes_4 = [s.get(f"mode{k}_frequency_hz", f"mode{k}_damping_ratio") for k in (1, 2)]
    s.close()
    # the CLI refuses a NaN in a CSV; Python's okid.identify_ambient (the same library, its mean of the
    # finite values moving the record by round-off only) takes the gap
    import okid
    with pytest.warns(okid.NonFiniteSampleWarning):
        res = okid.identify_ambient(y, dt, order=4, hankel_rows=10)
    sv = res.singular_values
    closest = max(abs(md.eigenvalue) for md in res.modes)
    tol = np.finfo(float).eps * math.sqrt(len(y)) * 20 * sv[0] / sv[3] / (1 - closest)
    assert len(res.modes) == 2 and res.samples == len(y) - 1
    for (f, z), c in zip(fmu_modes_4, res.modes):
        assert f == pytest.approx(c.frequency_hz, rel=tol) and z == pytest.approx(c.damping_ratio, rel=tol)


@pytest.mark.parametrize("version", VERSIONS)
def test_output_only_state_restores_the_sums(version, ambient_case):
    """An FMU state taken halfway holds the correlation sums (the workspace): the second half run
    again from it gives the first run's outputs bit for bit."""
    y, dt = ambient_case["y"][:6000], ambient_case["dt"]
    s = output_only_identifier(version, ambient_case)
    s.set(dt=dt, hankel_rows=10, identify_every=1000)
    s.initialize()
    get_state, set_state = ("getFMUstate", "setFMUstate") if version == 2 else ("getFMUState", "setFMUState")

    def steps(first, last):
        for k in range(first, last):
            s.set_array("y", y[k])
            s.step(k * dt, dt)
        return s.get("identifications", "num_modes", "samples", "mode1_frequency_hz", "mode1_damping_ratio",
                     "singular_value1")

    steps(0, 3000)
    state = getattr(s.fmu, get_state)()
    first = steps(3000, 6000)
    getattr(s.fmu, set_state)(state)
    assert steps(3000, 6000) == first and first[:3] == [6, first[1], 6000] and first[1] >= 1
    s.close()
