# SPDX-License-Identifier: Apache-2.0
"""Results that leave the process (pickle, deepcopy, a real process pool, save/load, the CLI's
JSON loaded), the model's conversions, simulation and frequency response against scipy and
python-control, the plots (Agg: the data drawn equals the computed arrays), Ctrl-C during long
calls (a real SIGINT to a subprocess) and the progress callback, the messages and types of
issue 30.

Needs the package installed in the interpreter (scripts/setup.sh) and OKID_CLI (ctest sets it).
"""
import copy
import dataclasses
import io
import json
import os
import pickle
import signal
import subprocess
import sys
import textwrap
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import okid

ROOT = Path(__file__).resolve().parents[2]
OKID_CLI = os.environ.get("OKID_CLI", str(ROOT / "build" / "host_tools" / "cli" / "okid"))
PAPER = dict(observer_order=20, order=4, hankel_rows=20, hankel_cols=20, decimation=1, zero_initial_state=1)  # nothing chosen


def paper_record(samples=1001, seed=2024, noise=0.0):
    a, b, c, d = okid.model.paper_system(0.01)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, 1))
    y, _ = okid.model.simulate(a, b, c, d, u)
    if noise:
        y = y + noise * y.std(axis=0) * rng.standard_normal(y.shape)
    return u, y


SETTINGS = dict(order=4, observer_order=20, hankel_rows=40, hankel_cols=40, realization="combined", scaling="auto")
DT = 0.05


@pytest.fixture(scope="module")
def record():
    """The refinement's case (docs/python.md): dt 0.05 s, 2001 samples, 5 % output noise."""
    a, b, c, d = okid.model.paper_system(DT)
    rng = np.random.default_rng(5)
    u = rng.standard_normal((2001, 1))
    y, _ = okid.model.simulate(a, b, c, d, u)
    return u, y + 0.05 * y.std(axis=0) * rng.standard_normal(y.shape)


@pytest.fixture(scope="module")
def result(record):
    res = okid.identify(*record, DT, **SETTINGS)
    assert [m.is_pair for m in res.modes] == [True, True]
    return res


@pytest.fixture(scope="module")
def refined(record):
    res = okid.identify(*record, DT, **SETTINGS, refine=True)
    assert res.refinement.converged and res.G is not None and res.input_scales is not None
    return res


def assert_same_value(a, b, where="result"):
    """Every public field equal: arrays bit for bit (nan equal to nan), dataclasses field by field."""
    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        for f in dataclasses.fields(a):
            if not f.name.startswith("_"):
                assert_same_value(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and a.shape == b.shape and a.dtype == b.dtype, where
        np.testing.assert_array_equal(a, b, err_msg=where)
        assert not b.flags.writeable, f"{where} is writable"
    elif isinstance(a, tuple):
        assert isinstance(b, tuple) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same_value(x, y, f"{where}[{i}]")
    elif isinstance(a, float) and np.isnan(a):
        assert isinstance(b, float) and np.isnan(b), where
    elif hasattr(a, "keys"):
        assert dict(a) == dict(b), where
    else:
        assert type(a) is type(b) and a == b, where


# ---- models that travel ----

@pytest.mark.parametrize("how", ["pickle", "deepcopy", "copy"])
def test_a_result_pickles_and_copies_equal(result, refined, how):
    clone = {"pickle": lambda r: pickle.loads(pickle.dumps(r)), "deepcopy": copy.deepcopy, "copy": copy.copy}[how]
    for res in (result, refined):
        other = clone(res)
        assert_same_value(res, other)
        assert other.to_dict() == res.to_dict()
    assert_same_value(refined.refinement, clone(refined.refinement))
    assert_same_value(result.modes[0], clone(result.modes[0]))
    with pytest.raises(okid.NotAvailableError, match="detached"):
        clone(result).stabilization(8)


def _same_error(a, b, where):
    assert type(a) is type(b) and str(a) == str(b) and getattr(a, "status", None) == getattr(b, "status", None), where


@pytest.fixture(scope="module")
def chosen(record):
    """Settings and order chosen from the data (half the record: the choice costs seconds)."""
    u, y = record
    return okid.identify(u[:1000], y[:1000], DT)


@pytest.fixture(scope="module")
def public_instances(record, result, refined, chosen, tmp_path_factory):
    """An instance of every public type of okid.__all__ (exceptions and warnings are made from their
    class below): a type added to okid.__all__ without one here fails the test that uses this."""
    u, y = record
    assert chosen.poles and isinstance(chosen.modes[0], okid.SelectedMode)
    diagram = okid.identify(u, y, DT, observer_order=20, order=4, hankel_rows=20, hankel_cols=20).stabilization(12)
    flags = [f for level in diagram.orders for f in level.stability]
    assert any(flags)  # a diagram with stable modes: the flags' round trip is seen
    csv = tmp_path_factory.mktemp("record") / "rec.csv"
    np.savetxt(csv, np.column_stack([np.arange(len(u)) * DT, u, y]), delimiter=",", header="t,force,acc1,acc2",
               comments="", fmt="%.17g")
    identifier = okid.Identifier(1, 2, DT, **SETTINGS)
    identifier.push(u, y)
    ambient = okid.AmbientIdentifier(2, DT, hankel_rows=20, order=4)
    ambient.push(y - y.mean(axis=0))
    return {
        "Result": [result, refined, chosen], "Mode": [result.modes[0], refined.refinement.modes[0]],
        "SelectedMode": [chosen.modes[0]], "Pole": [chosen.poles[0]],
        "WarningFlag": [okid.WarningFlag.UNSTABLE_POLE | okid.WarningFlag.WEAK_EXCITATION],
        "Stabilization": [diagram], "StabilizationOrder": list(diagram.orders),
        "StabilityFlag": [max(flags, key=int)], "Refinement": [refined.refinement],
        "CramerRaoBound": [okid.crlb(u, DT, noise=0.05)], "Record": [okid.read_record(csv)],
        "Progress": [identifier.progress],
        "AmbientResult": [okid.identify_ambient(y, DT, hankel_rows=20, order=4, segments=4)],
        "AmbientProgress": [ambient.progress],
    }


#: public types that do not travel, and why
NOT_PICKLABLE = {"Identifier": "its C core holds the pushed samples (TypeError, as copy.copy)",
                 "AmbientIdentifier": "its C core holds the correlation sums (TypeError, as copy.copy)"}


def _public_types():
    return {name: getattr(okid, name) for name in okid.__all__ if isinstance(getattr(okid, name), type)}


def test_every_public_type_pickles_and_copies(public_instances):
    """Every class of okid.__all__: pickle, deepcopy and copy give an equal value (arrays read-only);
    an exception keeps its message and status (a worker's error crosses a process pool as itself)."""
    types = _public_types()
    made = {name for name, cls in types.items() if issubclass(cls, BaseException)}
    assert set(types) == set(public_instances) | made | set(NOT_PICKLABLE), \
        "a public type without an instance in public_instances (or a reason in NOT_PICKLABLE)"
    clones = (lambda v: pickle.loads(pickle.dumps(v)), copy.deepcopy, copy.copy)
    for name, cls in types.items():
        if name in NOT_PICKLABLE:
            continue
        if name in made:
            value = cls("a message", -4) if issubclass(cls, okid.OkidError) else cls("a message")
            for clone in clones:
                _same_error(value, clone(value), name)
            continue
        for i, value in enumerate(public_instances[name]):
            assert type(value) is cls, name
            for clone in clones:
                other = clone(value)
                if isinstance(value, okid.Record):
                    assert type(other) is okid.Record and other[2:] == value[2:], name
                    for a, b in zip(value[:2], other[:2]):
                        np.testing.assert_array_equal(a, b)
                        assert not b.flags.writeable, f"{name}: an array came back writable"
                else:
                    assert_same_value(value, other, f"{name}[{i}]")
                if hasattr(value, "to_dict"):
                    assert other.to_dict() == value.to_dict(), name
    identifier = okid.Identifier(1, 2, DT, **SETTINGS)
    with pytest.raises(TypeError, match="cannot be pickled: its C core"):
        pickle.dumps(identifier)
    with pytest.raises(TypeError, match="cannot be pickled: its C core"):
        pickle.dumps(okid.AmbientIdentifier(2, DT))


def test_every_public_result_with_save_loads_back_equal(public_instances, tmp_path):
    """Every public type with save() (the results a user keeps) gives an equal value back from its
    file, by its class's load(), and refuses to overwrite; one type's file is refused by another's."""
    savable = {name for name, cls in _public_types().items() if hasattr(cls, "save")}
    assert savable == {"Result", "Stabilization", "CramerRaoBound"}
    for name in sorted(savable):
        cls = getattr(okid, name)
        for i, value in enumerate(public_instances[name]):
            path = tmp_path / f"{name}-{i}.json"
            value.save(path)
            back = cls.load(path)
            assert_same_value(value, back, f"{name}[{i}]")
            assert back.to_dict() == value.to_dict(), name
            with pytest.raises(FileExistsError):
                value.save(path)
    with pytest.raises(ValueError, match=r"^format = 'okid.Stabilization': okid.load reads 'okid.Result' files.*"
                                         r"okid.Stabilization.load reads that one$"):
        okid.load(tmp_path / "Stabilization-0.json")
    with pytest.raises(ValueError, match=r"^format = 'okid.Result': okid.Stabilization.load .*okid.load reads that one$"):
        okid.Stabilization.load(tmp_path / "Result-0.json")


def _identify_in_worker(seed):
    u, y = paper_record(seed=seed, noise=0.01)
    return okid.identify(u, y, 0.01, **PAPER)


def test_a_process_pool_returns_results():
    """The docs recommend process pools: each worker's Result crosses back by pickle, equal to the
    same identification in this process."""
    seeds = [1, 2, 3]
    with ProcessPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(_identify_in_worker, seeds))
    for seed, res in zip(seeds, results):
        here = _identify_in_worker(seed)
        assert_same_value(here, res)
        assert res.to_dict() == here.to_dict()


def test_save_and_load_give_the_result_back(result, refined, tmp_path):
    for name, res in (("plain", result), ("refined", refined)):
        path = tmp_path / f"{name}.json"
        res.save(path)
        back = okid.load(path)
        assert_same_value(res, back)
        assert back.to_dict() == res.to_dict()
        document = json.loads(path.read_text())
        assert document["format"] == okid.FORMAT and document["format_version"] == okid.FORMAT_VERSION
    with pytest.raises(FileExistsError):
        result.save(tmp_path / "plain.json")  # never overwrite a file


def test_every_field_of_a_saved_result_is_a_field_the_loader_reads(refined, tmp_path):
    """Written generically over the dataclass fields: a field added to Result (or Refinement, Mode)
    travels without a change to the writer; this fails for a type the JSON cannot carry back."""
    path = tmp_path / "r.json"
    refined.save(path)
    back = okid.load(path)
    names = [f.name for f in dataclasses.fields(okid.Result) if not f.name.startswith("_")]
    assert {"A", "modes", "refinement", "config", "warnings"} <= set(names)
    for name in names:
        assert_same_value(getattr(refined, name), getattr(back, name), name)


def test_a_newer_format_is_refused(result, tmp_path):
    path = tmp_path / "new.json"
    result.save(path)
    document = json.loads(path.read_text())
    document["format_version"] = okid.FORMAT_VERSION + 1
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match="format_version = 2: this okid reads versions 1..1"):
        okid.load(path)


@pytest.mark.skipif(not Path(OKID_CLI).exists(), reason="needs the okid CLI (OKID_CLI)")
@pytest.mark.parametrize("refine", [False, True])
def test_the_cli_json_loads(record, tmp_path, refine):
    """okid identify --json (--refine) of a CSV loads as a Result equal to the package's on the same
    samples (the CLI's JSON lacks observer_gain_markov and the refinement's order, dt, cost)."""
    u, y = record
    csv = tmp_path / "rec.csv"
    t = np.arange(len(u)) * DT
    np.savetxt(csv, np.column_stack([t, u, y]), delimiter=",", header="t,force,acc1,acc2", comments="", fmt="%.17g")
    args = ["--order", "4", "--observer-order", "20", "--hankel-rows", "40", "--hankel-cols", "40",
            "--realization", "combined", "--scaling", "auto"]
    out = subprocess.run([OKID_CLI, "identify", "--json", *args, *(["--refine"] if refine else []), str(csv)],
                         capture_output=True, text=True, check=True).stdout
    path = tmp_path / "cli.json"
    path.write_text(out)
    back = okid.load(path)
    ours = okid.identify(u, y, DT, **SETTINGS, refine=refine)
    for name in ("order", "dt", "samples", "rows", "regressor_rank", "decimation", "warnings"):
        assert getattr(back, name) == getattr(ours, name), name
    for name in ("A", "B", "C", "D", "markov", "singular_values"):
        np.testing.assert_allclose(getattr(back, name), getattr(ours, name), rtol=1e-9, atol=1e-12, err_msg=name)
    np.testing.assert_allclose(back.frequencies_hz, ours.frequencies_hz, rtol=1e-12)
    assert dict(back.config) == dict(ours.config)
    if refine:
        assert back.refinement.order == 4 and back.refinement.dt == DT and np.isnan(back.refinement.cost)
        np.testing.assert_allclose(back.refinement.frequency_std, ours.refinement.frequency_std, rtol=1e-6)
    else:
        assert back.refinement is None


# ---- conversions, simulation, frequency response ----

def test_simulate_equals_scipy_dlsim_and_the_exact_system(result):
    """Result.simulate over a whole record against scipy.signal.dlsim of the same matrices, and the
    identified model's response against the exact system's (noise-free data: 1e-9)."""
    from scipy import signal
    exact = okid.identify(*paper_record(), 0.01, **PAPER)
    u = np.random.default_rng(9).standard_normal((500, 1))
    y = exact.simulate(u)
    _, y_scipy, _ = signal.dlsim(exact.to_dlti(), u)
    np.testing.assert_allclose(y, y_scipy, rtol=0, atol=1e-12 * np.abs(y).max())
    a, b, c, d = okid.model.paper_system(0.01)
    y_true, _ = okid.model.simulate(a, b, c, d, u)
    np.testing.assert_allclose(y, y_true, rtol=0, atol=1e-9 * np.abs(y_true).max())
    x0 = np.arange(1.0, 5.0)
    _, y0, _ = signal.dlsim(exact.to_dlti(), u, x0=x0)
    np.testing.assert_allclose(exact.simulate(u, x0=x0), y0, rtol=0, atol=1e-12 * np.abs(y0).max())


def test_frequency_response_against_scipy_and_control(result, refined):
    """H(f) = C (zI - A)^-1 B + D against python-control's frequency_response of to_statespace() to
    1e-12 relative (the same resolvent in another code: round-off times its conditioning, about
    1/(2 zeta) < 10 here), and against the DTFT of scipy.signal.dimpulse's impulse response of
    to_dlti() (a simulation, independent of the resolvent: 4000 terms, |lambda|^4000 < 1e-40, each
    term's round-off eps |h_k|: 1e-12 of max |H|)."""
    from scipy import signal
    import control
    f = np.linspace(0.0, 0.5 / DT, 301)
    for model in (result, refined.refinement):
        h = model.frequency_response(f)
        assert h.shape == (f.size, 2, 1)
        sys_c = model.to_statespace()
        assert isinstance(sys_c, control.StateSpace) and sys_c.dt == model.dt
        resp = control.frequency_response(sys_c, 2 * np.pi * f)
        hc = np.asarray(resp.magnitude) * np.exp(1j * np.asarray(resp.phase))
        np.testing.assert_allclose(h[:, :, 0], hc.reshape(2, -1).T, rtol=1e-12, atol=0)
        _, (impulse,) = signal.dimpulse(model.to_dlti(), n=4000)
        dtft = np.exp(-2j * np.pi * np.outer(f, np.arange(len(impulse))) * model.dt) @ impulse
        np.testing.assert_allclose(h[:, :, 0], dtft, rtol=0, atol=1e-12 * np.abs(dtft).max())


def test_missing_optional_packages_say_which(result, monkeypatch):
    import builtins
    real_import = builtins.__import__

    def no(name, *args, **kwargs):
        if name.split(".")[0] in ("control", "scipy", "matplotlib"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)
    monkeypatch.setattr(builtins, "__import__", no)
    with pytest.raises(ImportError, match=r'^to_statespace\(\) needs python-control: pip install "okid\[control\]"$'):
        result.to_statespace()
    with pytest.raises(ImportError, match=r"^to_dlti\(\) needs scipy: pip install scipy$"):
        result.to_dlti()
    with pytest.raises(ImportError, match=r'^okid.plot needs matplotlib: pip install "okid\[plot\]"$'):
        okid.plot.mac(result)


# ---- plots ----

@pytest.fixture()
def axes():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)


def _written(ax, tmp_path, name):
    path = tmp_path / f"{name}.png"
    ax.figure.savefig(path)
    assert path.stat().st_size > 5000
    return path


def test_plot_mac_draws_the_mac_matrix(result, refined, axes, tmp_path):
    assert okid.plot.mac(result, refined.refinement, ax=axes) is axes
    drawn = np.asarray(axes.images[0].get_array())
    pa = np.array([m.sensor_shape for m in result.modes])
    pb = np.array([m.sensor_shape for m in refined.refinement.modes])
    expected = np.array([[abs(np.vdot(x, z)) ** 2 / (np.vdot(x, x).real * np.vdot(z, z).real) for z in pb]
                         for x in pa])
    np.testing.assert_allclose(drawn, expected, rtol=1e-14)
    assert list(np.argmax(drawn, axis=1)) == [0, 1]  # each OKID/ERA mode is its refined one
    np.testing.assert_allclose(np.diag(okid.plot.mac_matrix(result)), 1.0, rtol=1e-14)
    _written(axes, tmp_path, "mac")


def test_plot_mode_shapes(result, axes, tmp_path):
    okid.plot.mode_shapes(result, ["mass 1", "mass 2"], ax=axes)
    for line, mode in zip(axes.get_lines(), result.modes):
        np.testing.assert_array_equal(line.get_ydata(), mode.sensor_shape.real)
    assert [t.get_text() for t in axes.get_xticklabels()] == ["mass 1", "mass 2"]
    _written(axes, tmp_path, "shapes")


def test_plot_response_and_its_fit(result, refined, record, axes, tmp_path):
    u, y = record
    okid.plot.response(result, u, y, ax=axes)
    lines = axes.get_lines()
    y_model = result.simulate(u)
    np.testing.assert_array_equal(lines[0].get_ydata(), y[:, 0])
    np.testing.assert_array_equal(lines[1].get_ydata(), y_model[:, 0])
    np.testing.assert_array_equal(lines[0].get_xdata(), np.arange(len(y)) * DT)
    fit = 100 * (1 - np.linalg.norm(y - y_model, axis=0) / np.linalg.norm(y - y.mean(axis=0), axis=0))
    labels = [t.get_text() for t in axes.get_legend().get_texts()]
    assert labels[1] == f"y1 model, fit {fit[0]:.1f} %" and labels[3] == f"y2 model, fit {fit[1]:.1f} %"
    _written(axes, tmp_path, "response")
    # the maximum-likelihood model from its x(0) leaves the noise: 5 % of each output's std, a fit of
    # 100 (1 - 0.05 / sqrt(1 + 0.05^2)) = 95.0 %, give or take the noise's sample spread (0.1 %)
    ref = refined.refinement
    fit_ml = okid.plot.fit_percent(y, ref.simulate(u, ref.initial_state))
    np.testing.assert_allclose(fit_ml, 95.0, atol=0.5)


def test_plot_frequency_response_marks_the_modes(result, axes, tmp_path):
    f = np.linspace(0, 5, 400)
    okid.plot.frequency_response(result, f, ax=axes)
    lines = axes.get_lines()
    h = result.frequency_response(f)
    np.testing.assert_array_equal(lines[0].get_ydata(), np.abs(h[:, 0, 0]))
    np.testing.assert_array_equal(lines[1].get_ydata(), np.abs(h[:, 1, 0]))
    marks = [ln.get_xdata()[0] for ln in lines[2:]]
    np.testing.assert_array_equal(marks, result.frequencies_hz)
    _written(axes, tmp_path, "frf")


def test_plot_stabilization(record, axes, tmp_path):
    u, y = record
    res = okid.identify(u, y, DT, observer_order=20, order=4, hankel_rows=20, hankel_cols=20)
    diagram = res.stabilization(12)
    okid.plot.stabilization(diagram, ax=axes)
    drawn = sorted((float(f), float(o)) for c in axes.collections for f, o in c.get_offsets())
    expected = sorted((m.frequency_hz, float(level.order)) for level in diagram.orders for m in level.modes
                      if m.is_pair)
    np.testing.assert_array_equal(drawn, expected)
    _written(axes, tmp_path, "stabilization")


def test_measured_frequency_response_is_the_exact_one():
    """okid.plot's H1 estimate (Welch, Hann) of a noise-free record of the paper's system (numpy's
    simulation and exact model, tests/python/reference.py) against C (zI - A)^-1 B + D on the unit
    circle. Its error is the window's leakage of the impulse response's decay tau = 1/(2 pi zeta f)
    (2.0 s for mode 1) over a segment of n dt = 125 s: 1.6 %; the bound is 3x that."""
    from reference import paper_reference
    ref = paper_reference(DT)
    u = np.random.default_rng(3).standard_normal((20000, 1))
    y, _ = ref.simulate(u)
    f, h = okid.plot.measured_frequency_response(u, y, DT)
    band = (f > 0.1) & (f < 3.0)
    z = np.exp(2j * np.pi * f[band] * DT)
    exact = np.array([ref.C @ np.linalg.solve(zk * np.eye(4) - ref.A, ref.B) + ref.D for zk in z])
    assert h.shape == (len(f), 2, 1)
    np.testing.assert_allclose(np.abs(h[band] - exact) / np.abs(exact).max(axis=0), 0, atol=0.05)
    with pytest.raises(ValueError, match="same number of samples, at least 64"):
        okid.plot.measured_frequency_response(u[:50], y[:50], DT)


def test_plot_stabilization_marks_the_physical_modes(record, axes, tmp_path):
    """okid.plot_stabilization on okid.identify's defaults: the diagram's poles, a line and the spread
    band at each physical mode, and the measured frequency response's singular values behind."""
    u, y = record
    res = okid.identify(u, y, DT)
    assert okid.plot_stabilization(res, u, y, ax=axes) is axes
    lines = [ln.get_xdata()[0] for ln in axes.get_lines()]
    # the paper's 1.05 Hz mode (damped 33 %) decays below the noise within each of this short record's
    # Hankel windows (4.3-8.6 s): EMAC 0 in all three, none confirms it (docs/quality.md section 8)
    assert [round(m.frequency_hz, 2) for m in res.modes] == [0.50]
    np.testing.assert_array_equal(lines, [m.frequency_hz for m in res.modes])
    behind = [a for a in axes.figure.axes if a is not axes][0]
    f, h = okid.plot.measured_frequency_response(u, y, DT)
    keep = f <= 0.5 / res.dt
    np.testing.assert_array_equal(np.array([ln.get_ydata() for ln in behind.get_lines()]).T,
                                  np.linalg.svd(h[keep], compute_uv=False))
    _written(axes, tmp_path, "stabilization_selected")


def test_stabilization_tool_draws_a_csv_record(record, tmp_path):
    """okid-stabilization FILE.csv: the record identified with the defaults, the PNG written, its path
    printed; a refusal is one line and exit 1, nothing written."""
    u, y = record
    csv = tmp_path / "rec.csv"
    rows = np.column_stack([np.arange(len(u)) * DT, u, y])
    np.savetxt(csv, rows, delimiter=",", header="t,force,acc1,acc2", comments="")
    tool = Path(sys.executable).with_name("okid-stabilization")
    png = tmp_path / "s.png"
    run = subprocess.run([str(tool), str(csv), "--inputs", "1", "-o", str(png)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == str(png) and png.stat().st_size > 5000
    bad = subprocess.run([str(tool), str(csv), "--inputs", "force9", "-o", str(tmp_path / "t.png")],
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 1 and len(bad.stderr.strip().splitlines()) == 1 and "force9" in bad.stderr
    assert not (tmp_path / "t.png").exists()


def test_plot_without_axes_makes_a_figure(result):
    import matplotlib
    matplotlib.use("Agg")
    ax = okid.plot.frequency_response(result)
    assert ax.figure is not None and len(ax.get_lines()) == 2 + len(result.modes)


# ---- long calls ----

def test_progress_is_reported_and_chunks_change_no_bit(record):
    u, y = record
    seen = []
    long_u = np.tile(u, (40, 1))
    long_y = np.tile(y, (40, 1))
    res = okid.identify(long_u, long_y, 0.01, **PAPER, progress=lambda done, total: seen.append((done, total)))
    n = len(long_u)
    assert seen[-1] == (n, n) and [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert [d for d, _ in seen][:2] == [16384, 32768]
    # one push of the whole record against sample-sized pieces' sum: the chunks move no bit
    ident = okid.Identifier(1, 2, 0.01, **PAPER)
    for k in range(0, n, 5000):
        ident.push(long_u[k:k + 5000], long_y[k:k + 5000])
    # (okid.identify also has the fit of each output, from the record an Identifier does not keep)
    assert ident.identify().to_dict() == {k: v for k, v in res.to_dict().items() if k != "fit_percent"}


def test_refine_progress_counts_the_passes(record):
    u, y = record
    seen = []
    res = okid.identify(u, y, DT, **SETTINGS, refine=True, progress=lambda done, total: seen.append((done, total)))
    passes = res.refinement.passes
    refine_calls = [s for s in seen if s[1] == len(u) * okid.REFINE_DEFAULTS["max_passes"]]
    assert [d for d, _ in refine_calls] == [len(u) * (k + 1) for k in range(passes)]


def test_an_exception_in_the_progress_callback_stops_the_push(record):
    u, y = record
    ident = okid.Identifier(1, 2, 0.01, **PAPER)

    def stop(done, total):
        raise RuntimeError(f"stop at {done}")
    long_u, long_y = np.tile(u, (40, 1)), np.tile(y, (40, 1))
    with pytest.raises(RuntimeError, match="stop at 16384"):
        ident.push(long_u, long_y, progress=stop)
    assert ident.progress.samples == 16384  # the chunk done stays pushed
    ident.push(long_u[16384:], long_y[16384:])
    whole = okid.identify(long_u, long_y, 0.01, **PAPER).to_dict()
    assert ident.identify().to_dict() == {k: v for k, v in whole.items() if k != "fit_percent"}


class _Stderr(io.StringIO):
    """A captured stderr that says it is (or is not) a terminal."""

    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


@pytest.mark.parametrize("tqdm", [True, False])
@pytest.mark.parametrize("tty", [True, False])
def test_progress_true_draws_a_bar_on_stderr(record, monkeypatch, tqdm, tty):
    """progress=True: tqdm's bar when tqdm imports, else one plain line per phase (redrawn in place
    on a terminal with "\r", written once at the end into a log); the result is the same bits."""
    u, y = record
    long_u, long_y = np.tile(u, (10, 1)), np.tile(y, (10, 1))
    n = len(long_u)
    quiet = okid.identify(long_u, long_y, 0.01, **PAPER).to_dict()
    if not tqdm:
        monkeypatch.setitem(sys.modules, "tqdm", None)  # as when it is not installed
    err = _Stderr(tty)
    monkeypatch.setattr(sys, "stderr", err)
    assert okid.identify(long_u, long_y, 0.01, **PAPER, progress=True).to_dict() == quiet
    text = err.getvalue()
    if tqdm:
        assert "okid: push: 100%" in text and f"{n / 1000:.1f}k/{n / 1000:.1f}k" in text, text
    else:
        last = f"okid: push 100 % ({n}/{n} samples, "
        lines = text.split("\n")
        assert lines[-1] == "" and len(lines) == 2, text  # one line, ended
        if tty:
            redraws = text.split("\r")[1:]
            assert redraws[-1].startswith(last) and all(r.startswith("okid: push ") for r in redraws), text
        else:
            assert "\r" not in text and lines[0].startswith(last) and lines[0].endswith(" s)"), text


def test_progress_true_in_a_log_writes_a_line_every_interval(record, monkeypatch):
    """Into a file (no terminal) without tqdm: a line each LOG_INTERVAL seconds, then the last one;
    the refinement is a phase of its own, ended where it converged."""
    from okid import _progress
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setattr(_progress, "LOG_INTERVAL", 0.0)
    err = _Stderr(False)
    monkeypatch.setattr(sys, "stderr", err)
    u, y = record
    res = okid.identify(u, y, DT, **SETTINGS, refine=True, progress=True)
    lines = err.getvalue().splitlines()
    refine = [line for line in lines if line.startswith("okid: refinement ")]
    total = len(u) * okid.REFINE_DEFAULTS["max_passes"]
    fed = [int(line.split("(")[1].split("/")[0]) for line in refine]
    # a line after every pass but the first (the first call only starts the clock), then the last again
    assert fed == [len(u) * (k + 1) for k in range(1, res.refinement.passes)] + [len(u) * res.refinement.passes]
    assert all(f"/{total} samples" in line for line in refine)
    assert lines[0].startswith(f"okid: push 100 % ({len(u)}/{len(u)} samples")


def test_progress_refuses_what_is_neither_a_callable_nor_a_bool(record):
    u, y = record
    for bad in ("yes", 1, 0.5):
        with pytest.raises(TypeError, match=r"^progress = .*: a callable progress\(done, total\), True for a "
                                            r"progress bar on stderr, or None$"):
            okid.identify(u, y, 0.01, **PAPER, progress=bad)


def test_a_warning_of_a_call_with_progress_points_at_the_caller(record):
    """The progress wrapper sits between the caller and the body: the warnings still name the caller."""
    u, y = record
    y = y.copy()
    y[10] = np.nan
    for call in (lambda: okid.identify(u, y, 0.01, **PAPER, progress=True),
                 lambda: okid.Identifier(1, 2, 0.01, **PAPER).push(u, y)):
        with pytest.warns(okid.NonFiniteSampleWarning) as caught:
            call()
        assert caught[0].filename == __file__


def test_the_choice_from_the_data_reports_its_phase(record, chosen):
    """With the settings chosen from the data the choice and the model are one C call (the host
    library's auto_identify(): the model is identified once): (0, N) and (N, N) around it; the same
    result as without progress."""
    u, y = record
    seen = []
    n = 1000
    res = okid.identify(u[:n], y[:n], DT, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(0, n), (n, n)]
    assert res.to_dict() == chosen.to_dict()


_CHILD = textwrap.dedent("""
    import sys, time
    import numpy as np, okid
    what = sys.argv[1]
    rng = np.random.default_rng(1)
    u = rng.standard_normal((1_000_000, 1))
    a, b, c, d = okid.model.paper_system(0.01)
    y, _ = okid.model.simulate(a, b, c, d, u)
    y = y + 0.05 * y.std(axis=0) * rng.standard_normal(y.shape)
    start = okid.identify(u[:5000], y[:5000], 0.01, order=4, observer_order=10, hankel_rows=20, hankel_cols=20)
    ident = okid.Identifier(1, 2, 0.01, order=4, observer_order=60, hankel_rows=20, hankel_cols=20)
    print("ready", flush=True)
    try:
        if what == "refine":
            start.refine(u, y, max_passes=1000, step_tolerance=1e-300)
        else:
            for _ in range(100):
                ident.push(u, y)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    if what == "push":  # the identifier is usable after the interrupt
        ident.push(u[:20000], y[:20000])
        print("usable", ident.progress.samples > 20000, ident.identify().order, flush=True)
""")


@pytest.mark.parametrize("what", ["refine", "push"])
def test_ctrl_c_stops_a_long_call_within_a_second(what):
    """A real SIGINT while the C core runs (GIL released): KeyboardInterrupt between two chunks.
    Without the checks it takes effect only when the call returns (43 s of refine in issue 30).
    The choice of settings from the data is one C call without chunks: Ctrl-C takes effect when it
    returns (a thread waited on in slices let the dropped call run on beside the next okid call,
    and OpenBLAS's buffers are not safe for two callers: "Bad memory unallocation!").
    The bound of 1 s is some 30 chunks of margin on a shared machine; the call itself would run
    for minutes (max_passes=1000 over 10^6 samples, or 10^8 samples pushed). One OpenBLAS thread:
    its worker threads spin on a loaded 2-core machine and stretch one library call (a chunk of the
    p = 60 fold, 9 ms alone) to seconds of wall time, which no check between calls can shorten."""
    child = subprocess.Popen([sys.executable, "-c", _CHILD, what], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    try:
        assert child.stdout.readline().strip() == "ready"
        time.sleep(1.0)  # well inside the call
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        line = child.stdout.readline().strip()
        latency = time.monotonic() - sent
        assert line == "interrupted", child.stderr.read()
        assert latency < 1.0, f"KeyboardInterrupt {latency:.3f} s after SIGINT"
        rest = child.communicate(timeout=120)[0]
        if what == "push":
            assert rest.split() == ["usable", "True", "4"], rest
        assert child.returncode == 0
    finally:
        if child.poll() is None:
            child.kill()


# ---- messages and types ----

def test_channels_first_input_says_time_runs_along_axis_0(record):
    u, y = record
    with pytest.raises(okid.BadSizeError, match=r"^y has shape \(2, 2001\): 2001 channels of 2 samples\? Time runs "
                                                r"along axis 0, \(samples, channels\): pass y.T$"):
        okid.identify(u, y.T, 0.01)
    with pytest.raises(okid.BadSizeError, match=r"pass u.T"):
        okid.identify(u.T, y, 0.01)
    res = okid.identify(u, y, 0.01, **PAPER)
    with pytest.raises(okid.BadSizeError, match=r"time along axis 0 \(time runs along axis 0: pass u.T\)"):
        res.simulate(np.zeros((1, 50)))


@pytest.mark.parametrize("name", ["order", "observer_order", "hankel_rows", "decimation", "zero_initial_state"])
def test_counts_take_integral_floats_and_refuse_strings(record, name):
    """Documented in identify()'s docstring: a count is an int or an integral float (as dt may be an
    int), never a bool, complex or str (TypeError); a fraction is a ConfigurationError."""
    u, y = record
    value = {"order": 4, "observer_order": 20, "hankel_rows": 20, "decimation": 1, "zero_initial_state": 1}[name]
    base = dict(PAPER)
    base[name] = value
    want = okid.identify(u, y, 0.01, **base).to_dict()
    base[name] = float(value)
    assert okid.identify(u, y, 0.01, **base).to_dict() == want
    base[name] = np.float64(value)
    assert okid.identify(u, y, 0.01, **base).to_dict() == want
    for bad in (str(value), complex(value)):
        base[name] = bad
        with pytest.raises(TypeError, match=rf"^{name} = .*: an integer \(int, or a float with an integral value\)"):
            okid.identify(u, y, 0.01, **base)
    base[name] = value + 0.5
    with pytest.raises(okid.ConfigurationError, match=rf"^{name} = {value + 0.5}"):
        okid.identify(u, y, 0.01, **base)


def test_dt_and_order_are_consistent(record):
    u, y = record
    for good in ({"dt": 0.01, "order": 4}, {"dt": np.float32(0.25) / 25, "order": 4.0}):
        okid.identify(u, y, good["dt"], order=good["order"])
    for bad in ({"dt": "0.01", "order": 4}, {"dt": 0.01, "order": "4"}):
        with pytest.raises(TypeError):
            okid.identify(u, y, bad["dt"], order=bad["order"])
    with pytest.raises(TypeError, match=r"^sensing = 2: one of"):
        okid.identify(u, y, 0.01, sensing=2)


def test_help_of_result_gives_units_for_every_field():
    doc = okid.Result.__doc__
    for f in dataclasses.fields(okid.Result):
        if not f.name.startswith("_"):
            assert f"- {f.name}" in doc or f" {f.name}" in doc or f"{f.name}:" in doc, f.name
    for unit in ("[s]", "[Hz]", "[-]", "[counts]", "[output unit / input unit]"):
        assert unit in doc


def test_literal_types_for_the_string_options():
    import typing
    hints = typing.get_type_hints(okid.identify)
    assert typing.get_args(hints["sensing"]) == ("displacement", "velocity", "acceleration")
    assert typing.get_args(hints["realization"]) == ("system", "combined")
    assert typing.get_args(hints["scaling"]) == ("none", "auto")
    assert typing.get_args(hints["estimator"]) == ("least_squares", "instrumental")


@pytest.mark.parametrize("script, blocked, extra, args", [
    ("stabilization", "matplotlib", "tools", ["--help"]),
    ("fleet", "pyarrow", "fleet", ["synth", "--assets", "1", "--records", "1", "--out", "out"]),  # issue 30's case
])
def test_console_scripts_without_their_extra_say_which_to_install(script, blocked, extra, args, tmp_path):
    """The console scripts are installed with okid, their extras are not: one line naming the extra
    (the package made unimportable as a missing one is: ModuleNotFoundError, at import or later)."""
    code = (f"import sys; sys.modules[{blocked!r}] = None; sys.argv = ['okid-{script}', *{args!r}]\n"
            f"from okid.tools.entry_points import {script}; sys.exit({script}())")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                         env={**os.environ, "MPLBACKEND": "Agg"})
    assert run.returncode == 1 and run.stdout == ""
    assert run.stderr == f'okid-{script}: needs {blocked}, which okid installs with its extra: pip install "okid[{extra}]"\n'
    scripts = Path(sys.executable).parent
    if (scripts / f"okid-{script}").exists():  # the installed script goes through the wrapper
        assert f"okid.tools.entry_points import {script}" in (scripts / f"okid-{script}").read_text()
