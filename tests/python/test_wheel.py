# SPDX-License-Identifier: Apache-2.0
"""The portable wheels of scripts/wheel.sh (docs/python.md, "Portable wheels"): auditwheel's tag
(manylinux_2_17, x86_64 and aarch64), what the wheel holds (the extension for its architecture,
the prebuilt FMUs, the licence metadata), and the x86_64 wheel installed into a fresh venv whose
PATH has no compiler, running the README's Python snippet and okid-fmu without --base; the FMU it
writes is validated and run in fmpy (this venv) against the exact modes.

The wheels come from OKID_WHEEL_DIR when it is set (the output of an earlier scripts/wheel.sh);
otherwise the test runs scripts/wheel.sh for this Python's version, x86_64 and aarch64, with the
FMUs of OKID_FMU_DIR (the build's, as ctest sets it).
"""
import email.parser
import os
import re
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fmu_runs import PAPER_SETTINGS, Slave, modes_from, mode_outputs
from reference import paper_reference

ROOT = Path(__file__).resolve().parents[2]
TOOLS = ROOT / "build-wheel" / "tools" / "bin"
ARCHS = ["x86_64", "aarch64"]
TAG = f"cp{sys.version_info[0]}{sys.version_info[1]}"
ELF_MACHINE = {"x86_64": 62, "aarch64": 183}


def base_python():
    """This venv's interpreter outside the venv (the fresh venv is made from it)."""
    exe = getattr(sys, "_base_executable", None)
    if exe and Path(exe).exists() and Path(exe).resolve() != Path(sys.executable).resolve():
        return exe
    candidate = Path(sys.base_prefix) / "bin" / f"python{sys.version_info[0]}.{sys.version_info[1]}"
    return str(candidate)


@pytest.fixture(scope="module")
def wheels(tmp_path_factory):
    given = os.environ.get("OKID_WHEEL_DIR")
    if given:
        out = Path(given)
    else:
        fmu_dir = os.environ.get("OKID_FMU_DIR", str(ROOT / "build" / "fmu"))
        out = tmp_path_factory.mktemp("wheels")
        cmd = ["bash", str(ROOT / "scripts" / "wheel.sh"), "--python", base_python(), "--fmu-dir", fmu_dir,
               "--out", str(out)] + [a for arch in ARCHS for a in ("--arch", arch)]
        run = subprocess.run(cmd, capture_output=True, text=True)
        assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    found = {}
    for arch in ARCHS:
        names = sorted(out.glob(f"okid-*-{TAG}-*manylinux_2_17_{arch}*.whl")) or \
            sorted(out.glob(f"okid-*-cp312-abi3-*manylinux_2_17_{arch}*.whl"))
        assert names, f"no manylinux_2_17_{arch} wheel for {TAG} in {out}: {sorted(p.name for p in out.iterdir())}"
        found[arch] = names[-1]
    return found


@pytest.mark.parametrize("arch", ARCHS)
def test_auditwheel_tag_is_manylinux_2_17(wheels, arch):
    run = subprocess.run([str(TOOLS / "auditwheel"), "show", str(wheels[arch])], capture_output=True, text=True,
                         env={**os.environ, "PATH": f"{TOOLS}:{os.environ['PATH']}"})
    assert run.returncode == 0, run.stderr
    text = " ".join(run.stdout.split())
    assert f'consistent with the following platform tag: "manylinux_2_17_{arch}"' in text, text
    for lib in ("libstdc++", "libgcc_s", "libc++", "libgfortran", "libscipy_openblas", "liblapack"):
        assert lib not in text, text  # glibc only: LAPACK comes from the scipy-openblas32 package


@pytest.mark.parametrize("arch", ARCHS)
def test_wheel_contents(wheels, arch):
    with zipfile.ZipFile(wheels[arch]) as z:
        names = z.namelist()
        so = [n for n in names if re.fullmatch(r"okid/_core\.(cpython-\d+-[a-z0-9_]+-linux-gnu|abi3)\.so", n)]
        assert len(so) == 1, names
        assert so[0].endswith(".abi3.so") or f"-{arch}-linux-gnu" in so[0]
        elf = z.read(so[0])
        assert elf[:4] == b"\x7fELF" and int.from_bytes(elf[18:20], "little") == ELF_MACHINE[arch]
        for version in (2, 3):
            for model in ("okid_identifier", "okid_plant_2dof"):
                assert f"okid/fmu/fmi{version}/{model}.fmu" in names
        meta_name = next(n for n in names if n.endswith(".dist-info/METADATA"))
        meta = email.parser.Parser().parsestr(z.read(meta_name).decode())
        assert meta["License-Expression"].startswith("Apache-2.0")
        assert "License-File" in meta and "LICENSE" in meta.get_all("License-File")
        assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
        assert meta["Author"] == "okid developers" or "okid developers" in (meta["Author-email"] or "")
        assert any(u.startswith("Source,") for u in meta.get_all("Project-URL"))
        assert "Programming Language :: Python :: 3.9" in meta.get_all("Classifier")
        assert [r for r in meta.get_all("Requires-Dist") if r.startswith("scipy-openblas32")]


def readme_snippet():
    text = (ROOT / "README.md").read_text()
    section = text.split("\n## Python\n", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


@pytest.fixture(scope="module")
def fresh_venv(wheels, tmp_path_factory):
    """A new venv with the x86_64 wheel and its dependencies, and a PATH of its bin/ only."""
    if sysconfig.get_platform() != "linux-x86_64":
        pytest.skip("the x86_64 wheel is installed on an x86_64 machine only")
    home = tmp_path_factory.mktemp("fresh")
    env_dir = home / "venv"
    subprocess.run([base_python(), "-m", "venv", str(env_dir)], check=True)
    env = {"PATH": str(env_dir / "bin"), "HOME": str(home), "PIP_DISABLE_PIP_VERSION_CHECK": "1",
           "LC_ALL": "C.UTF-8"}
    for proxy in ("http_proxy", "https_proxy", "HTTP_PROXY", "HTTPS_PROXY", "PIP_INDEX_URL", "PIP_CACHE_DIR"):
        if proxy in os.environ:
            env[proxy] = os.environ[proxy]
    run = subprocess.run([str(env_dir / "bin" / "python"), "-m", "pip", "install", "-q", "--only-binary=:all:",
                          str(wheels["x86_64"])], env=env, cwd=home, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    return env_dir, env, home


def in_venv(fresh, *args):
    env_dir, env, home = fresh
    return subprocess.run(list(args), env=env, cwd=home, capture_output=True, text=True)


def test_no_compiler_on_the_fresh_path(fresh_venv):
    run = in_venv(fresh_venv, "python", "-c",
                  "import shutil; print([t for t in ('cc', 'gcc', 'c++', 'g++', 'clang', 'cmake', 'ld') if shutil.which(t)])")
    assert run.returncode == 0 and run.stdout.strip() == "[]", run.stdout + run.stderr


def test_readme_snippet_in_the_fresh_venv(fresh_venv):
    run = in_venv(fresh_venv, "python", "-c", readme_snippet())
    assert run.returncode == 0, run.stderr
    rows = [tuple(map(float, line.split())) for line in run.stdout.splitlines()]
    ref = paper_reference(0.01)
    assert len(rows) == 2
    for (f, zeta), mode in zip(sorted(rows), sorted(ref.modes, key=lambda md: md.frequency_hz)):
        assert abs(f - mode.frequency_hz) / mode.frequency_hz < 1e-9
        assert abs(zeta - mode.damping_ratio) / mode.damping_ratio < 1e-9
    # and the extension loaded is the wheel's, with LAPACK from scipy-openblas32
    run = in_venv(fresh_venv, "python", "-c", "import okid, okid._core as c; print(c.__file__)")
    assert run.returncode == 0 and str(fresh_venv[0]) in run.stdout, run.stdout + run.stderr


def test_okid_fmu_without_base_in_the_fresh_venv(fresh_venv):
    env_dir, env, home = fresh_venv
    out = home / "paper.fmu"
    run = in_venv(fresh_venv, "okid-fmu", "--inputs", "1", "--outputs", "2", "--max-modes", "4",
                  "--zero-initial-state", "1", "-o", str(out))
    assert run.returncode == 0, run.stdout + run.stderr
    help_text = in_venv(fresh_venv, "okid-fmu", "--help").stdout
    assert "site-packages/okid/fmu/fmi2/okid_identifier.fmu" in " ".join(help_text.split()).replace(" ", ""), help_text

    from fmpy.validation import validate_fmu
    assert validate_fmu(str(out)) == []
    with zipfile.ZipFile(out) as z:
        platforms = {n.split("/")[1] for n in z.namelist() if n.startswith("binaries/") and n.count("/") > 1}
    assert "linux64" in platforms
    # run in fmpy on the paper's record: the exact modes
    ref = paper_reference(0.01)
    u = np.random.default_rng(5).standard_normal(1001)
    y, _ = ref.simulate(u[:, None])
    s = Slave(str(out), "wheel_fmu").instantiate()
    settings = dict(PAPER_SETTINGS)
    s.set(**settings)
    s.initialize()
    for k in range(len(u)):
        s.set_inputs(u[k], y[k])
        s.step(k * settings["dt"], settings["dt"])
    got = modes_from(dict(zip(mode_outputs(), s.get(*mode_outputs()))))
    s.close()
    for g, want in zip(got, ref.modes):
        assert abs(g["frequency_hz"] - want.frequency_hz) / want.frequency_hz < 1e-9
        assert abs(g["damping_ratio"] - want.damping_ratio) / want.damping_ratio < 1e-9
