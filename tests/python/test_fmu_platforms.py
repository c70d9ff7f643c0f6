# SPDX-License-Identifier: Apache-2.0
"""The FMUs' other platforms' binaries run, not just built. Two C importers, cross-built for win64
(run under Wine) and aarch64-linux (run under qemu-user): tests/fmu_cosim.c couples the FMI 2
plant and identifier of build/fmu/fmi2 for the paper case; tests/fmu3_chain.c configures the
FMI 3 identifier of build/fmu/fmi3 for the 2-input, 3-output chain through its structural
parameters. Each platform's figures must match the exact modes (1e-9) and the x86-64 Linux run's
(the other platforms use the Eigen backend, x86-64 Linux LAPACK: they agree to round-off, not bit
for bit). Also: the Windows DLLs import only system DLLs, the ARM64 objects need only libc and
libm, and all export only FMI functions."""
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

FMU_DIR = Path(os.environ.get("OKID_FMU_DIR", "build/fmu"))
PLATFORMS = [p for p in os.environ.get("OKID_FMU_CROSS_PLATFORMS", "").split(",") if p]
HOST_COSIM = os.environ.get("OKID_COSIM", "build/tests/fmu_cosim")
HOST_FMU3 = os.environ.get("OKID_FMU3_CHAIN", "build/tests/fmu3_chain")
MODELS = ["okid_identifier", "okid_plant_2dof"]
FMI3_NAME = {"win64": "x86_64-windows", "aarch64-linux": "aarch64-linux"}


def runner(platform, program="fmu_cosim"):
    if platform == "win64":
        wine = shutil.which("wine64") or "/usr/lib/wine/wine64"
        return [wine, str(FMU_DIR / "platforms" / platform / f"{program}.exe")]
    return ["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu", str(FMU_DIR / "platforms" / platform / program)]


def run(command):
    env = {**os.environ, "WINEDEBUG": "-all"}
    env.setdefault("WINEPREFIX", str((FMU_DIR / "wineprefix").resolve()))
    proc = subprocess.run(command, capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


def figures(command):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+ \d): identified (\S+)", run(command), re.M)}


def chain_figures(command):
    text = run(command)
    return [(float(f), float(z)) for f, z in re.findall(r"frequency_hz (\S+) damping_ratio (\S+)", text)]


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


def exact_chain_modes():
    from reference import chain_reference
    ref = chain_reference(0.01, (2.0, 3.0, 2.5), (2.0, 4.0, 3.0, 2.0), (20.0, 40.0, 30.0, 25.0), forces_on=(0, 2))
    return [(m.frequency_hz, m.damping_ratio) for m in ref.modes]


@pytest.mark.parametrize("platform", ["x86_64-linux"] + [FMI3_NAME[p] for p in PLATFORMS])
def test_fmi3_structural_parameters_on_the_platform(platform):
    command = [HOST_FMU3] if platform == "x86_64-linux" else \
        runner(next(p for p in PLATFORMS if FMI3_NAME[p] == platform), "fmu3_chain")
    got = chain_figures(command + [str(FMU_DIR / "fmi3" / "okid_identifier"), platform])
    host = chain_figures([HOST_FMU3, str(FMU_DIR / "fmi3" / "okid_identifier")])
    assert len(got) == 3
    for (f, z), (f_host, z_host), (f_exact, z_exact) in zip(got, host, exact_chain_modes()):
        assert abs(f - f_exact) <= 1e-9 * f_exact and abs(z - z_exact) <= 1e-9 * z_exact
        assert abs(f - f_host) <= 1e-9 * f_host and abs(z - z_host) <= 1e-9 * z_host
    print(platform, [f"{abs(f - fe) / fe:.1e} {abs(z - ze) / ze:.1e}" for (f, z), (fe, ze) in zip(got, exact_chain_modes())])


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
