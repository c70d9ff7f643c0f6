"""The FMUs' other platforms' binaries run, not just built: the C importer tests/fmu_cosim.c,
cross-built for win64 (run under Wine) and aarch64-linux (run under qemu-user), couples the plant
and identifier FMUs of build/fmu/fmi2 for the paper case. Each must pass its own check against
the exact modes (1e-9) and reproduce the linux64 run's figures (the other platforms use the Eigen
backend, linux64 LAPACK: they agree to round-off, not bit for bit). Also: the Windows DLLs import
only system DLLs, the ARM64 objects need only libc and libm, and all export only FMI functions."""
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
PLATFORMS = [p for p in os.environ.get("OKID_FMU_CROSS_PLATFORMS", "").split(",") if p]
HOST_COSIM = os.environ.get("OKID_COSIM", "build/tests/fmu_cosim")
MODELS = ["okid_identifier", "okid_plant_2dof"]
FMI3_NAME = {"win64": "x86_64-windows", "aarch64-linux": "aarch64-linux"}


def runner(platform):
    if platform == "win64":
        wine = shutil.which("wine64") or "/usr/lib/wine/wine64"
        return [wine, str(FMU_DIR / "platforms" / platform / "fmu_cosim.exe")]
    return ["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu", str(FMU_DIR / "platforms" / platform / "fmu_cosim")]


def figures(command):
    env = {**os.environ, "WINEDEBUG": "-all"}
    env.setdefault("WINEPREFIX", str((FMU_DIR / "wineprefix").resolve()))
    proc = subprocess.run(command, capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+ \d): identified (\S+)", proc.stdout, re.M)}


def fmu_dirs():
    return [str(FMU_DIR / "fmi2" / "okid_plant_2dof"), str(FMU_DIR / "fmi2" / "okid_identifier")]


@pytest.mark.parametrize("platform", PLATFORMS)
def test_paper_case_on_the_platform_reproduces_linux64(platform):
    host = figures([HOST_COSIM, *fmu_dirs()])
    other = figures(runner(platform) + [*fmu_dirs(), platform])
    assert set(other) == set(host) == {"frequency 1", "frequency 2", "damping 1", "damping 2"}
    for key, value in host.items():
        assert abs(other[key] - value) <= 1e-9 * abs(value), (key, value, other[key])
    print(platform, {k: f"{abs(other[k] - v) / abs(v):.1e}" for k, v in host.items()})


def fmi_functions(version):
    import fmpy
    header = Path(fmpy.__file__).parent / "c-code" / f"fmi{version}Functions.h"
    return set(re.findall(rf"#define (fmi{version}\w+)\s+fmi{version}FullName", header.read_text()))


@pytest.mark.parametrize("platform", PLATFORMS)
@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("model", MODELS)
def test_binaries_are_self_contained(platform, version, model):
    folder = platform if version == 2 else FMI3_NAME[platform]
    binary = next((FMU_DIR / f"fmi{version}" / model / "binaries" / folder).glob(f"{model}.*"))
    if platform == "win64":
        dump = subprocess.run(["x86_64-w64-mingw32-objdump", "-p", str(binary)], capture_output=True, text=True).stdout
        assert set(re.findall(r"DLL Name: (\S+)", dump)) == {"KERNEL32.dll", "msvcrt.dll"}
        table = dump.split("[Ordinal/Name Pointer] Table")[1].split("\n\n")[0]
        exported = set(re.findall(r"\]\s+(\w+)", table))
    else:
        dynamic = subprocess.run(["readelf", "-d", str(binary)], capture_output=True, text=True).stdout
        assert set(re.findall(r"Shared library: \[(\S+)\]", dynamic)) <= {"libc.so.6", "libm.so.6"}
        symbols = subprocess.run(["readelf", "--dyn-syms", "-W", str(binary)], capture_output=True, text=True).stdout
        exported = {line.split()[-1] for line in symbols.splitlines()
                    if " GLOBAL " in line and " UND " not in line and "FUNC" in line}
    assert exported == fmi_functions(version)
