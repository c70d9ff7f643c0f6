# SPDX-License-Identifier: Apache-2.0
"""Hostile input, round three (issue 27): wrong answers with a success status, each now a correct
answer or a refusal that names the value and why.

1. okid crlb / okid.crlb: a bound that cannot be computed was printed as -1 with exit 0; a huge
   noise overflowed the weights 1 / sigma^2 into that -1 (the bound is linear in the noise).
"""
import copy
import os
import subprocess

import numpy as np
import pytest

import okid

OKID = os.environ.get("OKID_CLI", "okid")


def run(*args):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, timeout=300)
    proc.stdout, proc.stderr = proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8", "replace")
    return proc


def refused(proc, code=1):
    """A refusal: the exit status, nothing on stdout, one 'okid: ' line on stderr."""
    assert proc.returncode == code, (proc.returncode, proc.stdout, proc.stderr)
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
    return lines[0]


def crlb_table(proc):
    assert proc.returncode == 0, proc.stderr
    rows = [line.split(",") for line in proc.stdout.splitlines()[2:]]
    return np.array([[float(v) for v in row[1:]] for row in rows])


# --- 1. the Cramer-Rao bound ---------------------------------------------------------------------

def test_crlb_cli_huge_noise_is_linear():
    unit = crlb_table(run("crlb", "--noise", 1))
    huge = crlb_table(run("crlb", "--noise", 1e200))
    assert unit.shape == (2, 4) and np.all(unit[:, [1, 3]] > 0)
    np.testing.assert_allclose(huge[:, [0, 2]], unit[:, [0, 2]], rtol=0)       # the modes
    np.testing.assert_allclose(huge[:, [1, 3]], 1e200 * unit[:, [1, 3]], rtol=1e-5)  # 6 printed digits
    assert huge[0, 1] == pytest.approx(1.35e198, rel=0.01)


@pytest.mark.parametrize("extra", [("--dt", 10)])
def test_crlb_cli_singular_fisher_is_refused(extra):
    line = refused(run("crlb", "--noise", 0.05, *extra))
    assert "cannot compute the bound: the Fisher information is singular" in line


def test_crlb_python_huge_noise_is_linear():
    u = np.random.default_rng(1).standard_normal(1001)
    unit = okid.crlb(u, 0.01, noise=1.0)
    huge = okid.crlb(u, 0.01, noise=1e200)
    np.testing.assert_allclose(huge.frequency_std, 1e200 * unit.frequency_std, rtol=1e-12)
    np.testing.assert_allclose(huge.damping_std, 1e200 * unit.damping_std, rtol=1e-12)
    small = okid.crlb(u, 0.01, noise_std=1e-200)
    assert np.all(np.isfinite(small.frequency_std)) and np.all(small.frequency_std > 0)


def _zero_a():
    return np.zeros((4, 4)), np.ones((4, 1)), np.ones((2, 4)), np.zeros((2, 1))


@pytest.mark.parametrize("case", ["constant force", "zero A", "dt 10"])
def test_crlb_python_singular_fisher_is_refused(case):
    u = np.random.default_rng(1).standard_normal(1001)
    args = {"constant force": (np.ones(1001), 0.01, {}), "zero A": (u, 0.01, {"model": _zero_a()}),
            "dt 10": (u, 10.0, {})}[case]
    with pytest.raises(okid.OkidError, match="cannot compute the bound: the Fisher information is singular"):
        okid.crlb(args[0], args[1], noise=0.05, **args[2])
