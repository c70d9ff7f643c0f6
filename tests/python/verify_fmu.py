# SPDX-License-Identifier: Apache-2.0
"""Verifies the okid FMUs (FMI 2 and 3) against the paper's 2-DOF reference computed with numpy/scipy.

    .venv/bin/python tests/python/verify_fmu.py --fmu-dir build/fmu [--plots docs/img] [--cli build/host_tools/cli/okid]

(a) validation (fmpy.validation.validate_fmu and fmutool -check must report nothing), (b) the plant
alone with simulate_fmu against the exact discrete model, (c) the identifier fed from arrays
(FMI 2: simulate_fmu with an input table; FMI 3, whose inputs are arrays of structural size:
fmpy's low-level calls) and coupled to the plant in a master loop, (d) identified
against exact in a table, (e) the paper's plots. Exit status 0 when every check passes.
"""
import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np
from fmpy.validation import validate_fmu

from fmu_runs import NOISY_SETTINGS, PAPER_SETTINGS, cosimulate, identify_from_arrays, modes_from, simulate_plant
from reference import mac, paper_reference

PAPER_PRINTED = [0.9945 + 0.0311j, 0.9767 + 0.0608j]  # eq. 94, sorted by frequency as okid reports
NOISE_FREE_TOL = 1e-6
NOISY_FREQ_TOL, NOISY_DAMP_TOL = 0.005, 0.05


class Checks:
    def __init__(self):
        self.failures = []

    def expect(self, ok, what):
        print(f"  [{'ok' if ok else 'FAIL'}] {what}")
        if not ok:
            self.failures.append(what)


def fmutool_problems(path):
    """fmutool -check: the lines that are not the 'compliant / no error' report."""
    exe = Path(sys.executable).with_name("fmutool")
    proc = subprocess.run([str(exe), "-input", str(path), "-check"], capture_output=True, text=True)
    text = proc.stdout + proc.stderr
    bad = [line for line in text.splitlines() if ("ERROR" in line or "WARNING" in line) and "INFO" not in line[:8]]
    if proc.returncode != 0 or "seems to be compliant" not in text or "No semantic error" not in text:
        bad.append(f"fmutool exit {proc.returncode}")
    return bad


def compare(ref, modes, label, checks, freq_tol, damp_tol, eig_tol=None, table=None):
    rows = []
    for k, (got, want) in enumerate(zip(modes, ref.modes), start=1):
        f_err = abs(got["frequency_hz"] - want.frequency_hz) / want.frequency_hz
        z_err = abs(got["damping_ratio"] - want.damping_ratio) / want.damping_ratio
        l_err = abs(got["eigenvalue"] - want.eigenvalue) / abs(want.eigenvalue)
        shape_mac = mac(got["shape"], want.shape)
        rows.append((label, k, want.frequency_hz, got["frequency_hz"], f_err, want.damping_ratio, got["damping_ratio"],
                     z_err, got["eigenvalue"], l_err, shape_mac))
        checks.expect(f_err <= freq_tol, f"{label} mode {k}: frequency error {f_err:.2e} <= {freq_tol:g}")
        checks.expect(z_err <= damp_tol, f"{label} mode {k}: damping error {z_err:.2e} <= {damp_tol:g}")
        if eig_tol is not None:
            checks.expect(l_err <= eig_tol, f"{label} mode {k}: eigenvalue error {l_err:.2e} <= {eig_tol:g}")
    if table is not None:
        table.extend(rows)
    return rows


def print_table(rows):
    print("\n| case | mode | exact f [Hz] | identified f [Hz] | rel. error | exact zeta | identified zeta | rel. error |"
          " identified eigenvalue | rel. error | MAC |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (label, k, fe, fg, fr, ze, zg, zr, lam, lr, m) in rows:
        print(f"| {label} | {k} | {fe:.8f} | {fg:.8f} | {fr:.1e} | {ze:.8f} | {zg:.8f} | {zr:.1e} |"
              f" {lam.real:.6f}{lam.imag:+.6f}i | {lr:.1e} | {m:.9f} |")


def verify_version(fmu_dir, version, checks, table, plots_dir=None, cli=None):
    plant = Path(fmu_dir) / f"fmi{version}" / "okid_plant_2dof.fmu"
    ident = Path(fmu_dir) / f"fmi{version}" / "okid_identifier.fmu"
    print(f"\nFMI {version}.0")
    for path in (plant, ident):  # (a)
        problems = validate_fmu(str(path))
        checks.expect(not problems, f"validate_fmu({path.name}): {problems or 'nothing to report'}")
        problems = fmutool_problems(path)
        checks.expect(not problems, f"fmutool -check {path.name}: {problems or 'nothing to report'}")

    ref = paper_reference(0.01)
    force = np.random.default_rng(7).standard_normal(1001)
    y_ref, states = ref.simulate(force[:, None])
    res = simulate_plant(str(plant), force, 0.01)  # (b), rows 1.. hold the state after each step
    got = np.column_stack([res["x1"], res["x2"], res["v1"], res["v2"]])[1:]
    err = np.max(np.abs(got[:-1] - states[1:])) / np.max(np.abs(states))
    checks.expect(err < 1e-12, f"plant (simulate_fmu) states vs exact ZOH: {err:.1e} < 1e-12")
    # Row j >= 1 holds C x_j + D u_(j-1): the force of the previous step (fmpy's recording lag).
    acc = np.column_stack([res["acc1"], res["acc2"]])[1:1001]
    acc_ref = states[1:1001] @ ref.C.T + force[:1000, None] @ ref.D.T
    err = np.max(np.abs(acc - acc_ref)) / np.max(np.abs(acc_ref))
    checks.expect(err < 1e-12, f"plant accelerations (lag-aligned) vs exact: {err:.1e} < 1e-12")

    out = identify_from_arrays(str(ident), force, y_ref, PAPER_SETTINGS)  # (c) from arrays
    compare(ref, modes_from(out), f"FMI{version} arrays", checks, NOISE_FREE_TOL, NOISE_FREE_TOL, table=table)
    cs = cosimulate(str(plant), str(ident), PAPER_SETTINGS, 1001, seed=1)  # (c) master loop
    modes = modes_from(cs.final)
    compare(ref, modes, f"FMI{version} co-sim", checks, NOISE_FREE_TOL, NOISE_FREE_TOL, eig_tol=NOISE_FREE_TOL,
            table=table)
    for k, printed in enumerate(PAPER_PRINTED):
        lam = modes[k]["eigenvalue"]
        ok = abs(lam.real - printed.real) < 5e-5 and abs(lam.imag - printed.imag) < 5e-5
        checks.expect(ok, f"FMI{version} eigenvalue {lam.real:.4f} {lam.imag:+.4f}i = paper's {printed:.4f}")

    noisy_ref = paper_reference(0.05)
    clean, _ = noisy_ref.simulate(np.random.default_rng(3).standard_normal((4001, 1)))
    rms = np.sqrt(np.mean(clean ** 2, axis=0))
    ns = cosimulate(str(plant), str(ident), NOISY_SETTINGS, 4001, seed=3, noise=0.02, noise_rms=rms)
    compare(noisy_ref, modes_from(ns.final), f"FMI{version} 2% noise", checks, NOISY_FREQ_TOL, NOISY_DAMP_TOL,
            table=table)
    if plots_dir is not None:
        from okid.tools.plots import paper_plots
        paper_plots(Path(plots_dir), ref, cs, ns, noisy_ref, cli=cli)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu-dir", default="build/fmu", help="folder with fmi2/ and fmi3/ (default build/fmu)")
    parser.add_argument("--fmi", choices=["2", "3", "both"], default="both")
    parser.add_argument("--plots", help="write the paper's figures as PNG files into this folder")
    parser.add_argument("--cli", help="the okid command-line tool, for the identified Markov parameters plot")
    args = parser.parse_args(argv)
    checks, table = Checks(), []
    for version in ([2, 3] if args.fmi == "both" else [int(args.fmi)]):
        verify_version(args.fmu_dir, version, checks, table, args.plots if version == 3 or args.fmi != "both" else None,
                       args.cli)
    print_table(table)
    if checks.failures:
        print(f"\n{len(checks.failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
