# SPDX-License-Identifier: Apache-2.0
"""The real records' output-only modes against their input-output modes (docs/ambient.md, "The real
records"): the output channels of tests/data/real alone through `okid identify --inputs 0` (L, the
physical modes and the order chosen from the data; one reference channel, the roof's, which keeps
the correlations' Hankel matrix L m x L and the run near a second), against the consensus of the
same records' input-output identification (tests/data/real_consensus.json, docs/quality.md
section 7: okid grid, H1 and mdof's SRIM).

The tolerance is the two estimates' own uncertainty: the output-only mode's standard deviation from
8 segments of the correlations (blocks of 411 samples, 2 L + 1 for the larger L of the two records:
their 8200 samples make 20 blocks) and the consensus mode's spread over its grid of input-output
runs, combined as independent, times 3. Where the output-only selection does not reach a consensus
mode today (the two buildings' higher modes: earthquake records, a short non-stationary and
coloured excitation, not the white force the method assumes) a strict xfail keeps the gap in view.
Hayward and Meloland have no agreement to assert (docs/ambient.md lists what they give).
"""
import json
import math
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CONSENSUS = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())
DATA = pathlib.Path(os.environ.get("OKID_REAL_DATA", ROOT / "tests" / "data" / "real"))
OKID = os.environ.get("OKID_CLI", str(ROOT / "build" / "host_tools" / "cli" / "okid"))
REFERENCE = {"gws_building_351": "outRC_351", "gws_building_261": "outRE_261"}  # the roof channel
SIGMAS = 3


def output_columns(stem):
    with open(DATA / (stem + ".csv")) as f:
        names = f.readline().strip().split(",")
    return names[1 + CONSENSUS["records"][stem]["inputs"]:]


_RUNS = {}


def output_only(stem):
    if stem not in _RUNS:
        path = DATA / (stem + ".csv")
        if not path.exists():
            pytest.skip(f"real record {path} absent")
        proc = subprocess.run([OKID, "identify", "--inputs", "0", "--outputs", ",".join(output_columns(stem)),
                               "--references", REFERENCE[stem], "--segments", "8", "--segment-samples", "411",
                               "--json", str(path)], capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        _RUNS[stem] = json.loads(proc.stdout)
    return _RUNS[stem]


def matched(res, mode):
    """The physical pole of the reported model nearest to a consensus mode, with its segments' std."""
    physical = [(p, s) for p, s in zip(res["poles"], res["frequency_std"]) if p["verdict"] == "physical"]
    return min(physical, key=lambda ps: abs(ps[0]["frequency_hz"] - mode["frequency_hz"]), default=(None, None))


def agrees(res, mode):
    pole, std = matched(res, mode)
    if pole is None or std is None or not math.isfinite(std):
        return False
    tolerance = SIGMAS * math.hypot(std, mode["frequency_std"])
    return abs(pole["frequency_hz"] - mode["frequency_hz"]) <= tolerance


CASES = [(stem, k) for stem in REFERENCE for k, m in enumerate(CONSENSUS["records"][stem]["modes"]) if m["consensus"]]
AGREE = {("gws_building_351", 0), ("gws_building_261", 0)}  # the first modes (1.266 and 1.042 Hz)


@pytest.mark.parametrize("stem,k", sorted(AGREE))
def test_first_modes_agree_within_their_uncertainty(stem, k):
    res = output_only(stem)
    mode = [m for m in CONSENSUS["records"][stem]["modes"] if m["consensus"]][k]
    pole, std = matched(res, mode)
    assert pole is not None and res["segments_used"] == 8
    # the std is a real spread, not a floor: between 0.1 % and 5 % of the frequency
    assert 1e-3 * pole["frequency_hz"] < std < 5e-2 * pole["frequency_hz"]
    assert agrees(res, mode), (pole["frequency_hz"], std, mode["frequency_hz"], mode["frequency_std"])
    # and the selected mode itself within the same bound of the input-output one
    rep = min(res["modes"], key=lambda m: abs(m["frequency_hz"] - mode["frequency_hz"]))
    assert abs(rep["frequency_hz"] - mode["frequency_hz"]) <= SIGMAS * math.hypot(std, mode["frequency_std"])


@pytest.mark.parametrize("stem,k", sorted(set(CASES) - AGREE))
@pytest.mark.xfail(strict=True, reason="output-only does not reach this input-output mode yet (docs/ambient.md)")
def test_higher_modes_agree_within_their_uncertainty(stem, k):
    mode = [m for m in CONSENSUS["records"][stem]["modes"] if m["consensus"]][k]
    assert agrees(output_only(stem), mode)
