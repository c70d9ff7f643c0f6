# SPDX-License-Identifier: Apache-2.0
"""The FMUs' sources/ as a user rebuilds them (issue 22): over the Eigen backend, whose headers are
in sources/Eigen, so no LAPACK is needed to build or to load. fmpy's source build (FMI 2:
<SourceFiles> of modelDescription.xml, FMI 3: sources/buildDescription.xml; fmpy compiles them with
CMake, C and C++ by extension) gives binaries that load in this process, which has no LAPACK
loaded, and identify the paper's modes against the exact values; a plain C and C++ compiler builds
them too."""
import hashlib
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from fmu_runs import PAPER_SETTINGS, cosimulate, modes_from
from reference import mac, paper_reference

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
VERSIONS = [2, 3]
MODELS = ["okid_identifier", "okid_plant_2dof"]


def fmu(version, model):
    return FMU_DIR / f"fmi{version}" / f"{model}.fmu"


def fmi_functions(version):
    import fmpy
    header = Path(fmpy.__file__).parent / "c-code" / f"fmi{version}Functions.h"
    return set(re.findall(rf"#define (fmi{version}\w+)\s+fmi{version}FullName", header.read_text()))


def exported_fmi_functions(so):
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True, check=True).stdout
    return {line.split()[-1] for line in out.splitlines() if line.split() and line.split()[-1].startswith("fmi")}


_objects = {}  # (flags, sha256 of the preprocessed source) -> object file of this session


def compile_once(flags, name, cwd, obj):
    """Compiles cwd/name to obj unless the same flags have already compiled the same preprocessed
    text in this session (the FMUs share the core's files and the Eigen backend: ccache's rule,
    so each is compiled once, not once per FMU)."""
    text = subprocess.run([*flags, "-E", name], cwd=cwd, capture_output=True, check=True).stdout
    key = (tuple(flags), hashlib.sha256(text).hexdigest())
    if key not in _objects:
        subprocess.run([*flags, name, "-o", str(obj)], cwd=cwd, check=True)
        _objects[key] = obj
    elif _objects[key] != obj:
        shutil.copyfile(_objects[key], obj)


def system_lapack_loaded():
    """liblapacke / liblapack / libblas mapped into this process (scipy's own, prefixed copy aside)."""
    return bool(re.search(r"/lib(lapacke|lapack|blas)[.-]", Path("/proc/self/maps").read_text()))


def extract_without_binaries(path, into):
    with zipfile.ZipFile(path) as z:
        z.extractall(into)
    shutil.rmtree(into / "binaries")
    return into


def rebuilt_with_fmpy(tmp_path, version, model):
    """The .fmu with only the binary fmpy built from its sources/."""
    from fmpy.build import build_platform_binary
    unzipdir = extract_without_binaries(fmu(version, model), tmp_path / f"{model}{version}")
    # fmpy's `cmake --build` runs one job unless told (the test's wall time is CI's tail)
    os.environ.setdefault("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
    build_platform_binary(str(unzipdir.resolve()))
    so = next((unzipdir / "binaries").glob(f"*/{model}.so"))
    undefined = subprocess.run(["nm", "-D", "-u", str(so)], capture_output=True, text=True, check=True).stdout
    assert not re.search(r"LAPACK|dgeev|dgesvd|dgelsy", undefined, re.I), undefined
    assert exported_fmi_functions(so) == fmi_functions(version)
    out = tmp_path / f"{model}{version}.fmu"
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted(unzipdir.rglob("*")):
            if f.is_file():
                z.write(f, f.relative_to(unzipdir).as_posix())
    return out


def test_sources_carry_the_eigen_backend_and_its_licence():
    for version in VERSIONS:
        for model in MODELS:
            with zipfile.ZipFile(fmu(version, model)) as z:
                names = set(z.namelist())
                config = z.read("sources/okid/okid_build_config.h").decode()
            assert "sources/numerics/linalg_eigen.cpp" in names and "sources/numerics/linalg_lapacke.c" not in names
            assert {"sources/Eigen/Core", "sources/Eigen/Eigenvalues", "sources/Eigen/COPYING.MPL2"} <= names
            assert "#define OKID_LINALG_EIGEN 1" in config and "#define OKID_REAL_IS_FLOAT 0" in config


@pytest.mark.parametrize("version", VERSIONS)
def test_fmpy_source_build_identifies_the_paper_modes_without_lapack(tmp_path, version):
    """Plant and identifier rebuilt by fmpy from their sources/, coupled in the master loop of the
    verification (the paper's case, noise-free): the exact modes."""
    assert not system_lapack_loaded()  # nothing here could resolve a LAPACKE symbol
    plant = rebuilt_with_fmpy(tmp_path, version, "okid_plant_2dof")
    ident = rebuilt_with_fmpy(tmp_path, version, "okid_identifier")
    run = cosimulate(str(plant), str(ident), PAPER_SETTINGS, 1001)
    assert not system_lapack_loaded()
    assert run.final["identifications"] >= 1
    # Noise-free data: the errors are round-off amplified by the realization's conditioning,
    # 1e-13 .. 3e-11 on every platform and backend (docs/fmu.md); 1e-9 is the noise-free bound the
    # FMU tests use.
    tolerance = 1e-9
    ref = paper_reference(0.01)
    for got, want in zip(modes_from(run.final), ref.modes):
        assert abs(got["frequency_hz"] - want.frequency_hz) <= tolerance * want.frequency_hz
        assert abs(got["damping_ratio"] - want.damping_ratio) <= tolerance * want.damping_ratio
        assert abs(got["eigenvalue"] - want.eigenvalue) <= tolerance
        assert mac(got["shape"], want.shape) >= 1 - tolerance
        print(version, f"f {abs(got['frequency_hz'] - want.frequency_hz) / want.frequency_hz:.1e}",
              f"zeta {abs(got['damping_ratio'] - want.damping_ratio) / want.damping_ratio:.1e}")


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("model", MODELS)
def test_sources_build_with_a_plain_compiler(tmp_path, version, model):
    """cc for the C files, c++ for the backend, no library but libm: the FMI functions, unprefixed."""
    src = extract_without_binaries(fmu(version, model), tmp_path) / "sources"
    if version == 3:
        files = re.findall(r'SourceFile name="([^"]+)"', (src / "buildDescription.xml").read_text())
    else:
        files = re.findall(r'File name="([^"]+)"', (tmp_path / "modelDescription.xml").read_text())
    objects = []
    for name in files:
        compiler = ["c++", "-std=c++17"] if name.endswith(".cpp") else ["cc", "-std=c11"]
        obj = tmp_path / "objects" / (name + ".o")  # the core's files keep lib/src's folders
        obj.parent.mkdir(parents=True, exist_ok=True)
        compile_once([*compiler, "-c", "-fPIC", "-O1", "-I."], name, src, obj)
        objects.append(str(obj))
    so = tmp_path / "rebuilt.so"
    subprocess.run(["c++", "-shared", *objects, "-o", str(so), "-Wl,--no-undefined", "-lm"], check=True)
    assert exported_fmi_functions(so) == fmi_functions(version)
