# SPDX-License-Identifier: Apache-2.0
"""The automatic mode selection (okid_select_modes, through tests/mode_selection_run) on the real
records of tests/data/real against their consensus modes (tests/data/real_consensus.json,
made by scripts/real_consensus.py from an okid grid at fixed orders, the multi-input H1 estimate
and mdof's SRIM: independent of the selection).

At the settings the consensus file records for each record (the settings-from-data step is still
to come: which settings were needed is part of that file, and docs/quality.md section 7 says why),
the selection must give every consensus mode within 2 % in frequency and nothing else in the
record's band. A record for which no setting of the grid gives exactly the consensus (Hayward) has
no such test yet: docs/quality.md section 7 says what the selection gives there.

The records: OKID_REAL_DATA, else tests/data/real (README there). The driver: OKID_MODE_SELECTION_RUN (ctest sets it).
"""
import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CONSENSUS = json.loads((ROOT / "tests" / "data" / "real_consensus.json").read_text())
DATA = pathlib.Path(os.environ.get("OKID_REAL_DATA", ROOT / "tests" / "data" / "real"))
RUNNER = os.environ.get("OKID_MODE_SELECTION_RUN", str(ROOT / "build" / "tests" / "mode_selection_run"))
FREQUENCY_TOL = 0.02  # the acceptance: 2 % in frequency


def select(stem, rec, decimation, observer_order, hankel, max_order):
    path = DATA / (stem + ".csv")
    assert path.exists(), f"real record {path} absent"
    if not os.path.exists(RUNNER):
        pytest.skip(f"driver {RUNNER} not built")
    lo, hi = rec["band_hz"]
    cmd = [RUNNER, "--inputs", str(rec["inputs"]), "--outputs", str(rec["outputs"]), "--decimation", str(decimation),
           "--observer-order", str(observer_order), "--hankel", str(hankel), "--max-order", str(max_order),
           "--frequency-min", str(lo), "--frequency-max", str(hi), str(path)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def mismatch(rec, modes):
    """What keeps the selection from the consensus: missed modes and extra ones (empty when it matches)."""
    want = [m["frequency_hz"] for m in rec["modes"]]
    got = [m["frequency_hz"] for m in modes]
    missed = [w for w in want if not any(abs(g - w) <= FREQUENCY_TOL * w for g in got)]
    extra = [g for g in got if not any(abs(g - w) <= FREQUENCY_TOL * w for w in want)]
    problems = [f"missed {w:.3f} Hz" for w in missed] + [f"extra {g:.3f} Hz" for g in extra]
    if len(got) != len(want) and not problems:
        problems.append(f"{len(got)} modes for {len(want)} consensus modes")
    return problems


RECORDS = sorted(CONSENSUS["records"])
SELECTABLE = [stem for stem in RECORDS if CONSENSUS["records"][stem]["selection_settings"] is not None]


@pytest.mark.parametrize("stem", RECORDS)
def test_consensus_is_meaningful(stem):
    """Each consensus mode was found by two independent routes at least (the file's own rule)."""
    rec = CONSENSUS["records"][stem]
    assert rec["modes"], f"{stem}: no consensus mode"
    for m in rec["modes"]:
        assert len(m["found_by"]) >= 2 and rec["band_hz"][0] <= m["frequency_hz"] <= rec["band_hz"][1]


@pytest.mark.parametrize("stem", SELECTABLE)
def test_selection_finds_the_consensus(stem):
    rec = CONSENSUS["records"][stem]
    s = rec["selection_settings"]
    res = select(stem, rec, s["decimation"], s["observer_order"], s["hankel"], s["max_order"])
    problems = mismatch(rec, res["modes"])
    assert not problems, f"{stem} at {s}: " + ", ".join(problems)
    for m in res["modes"]:
        # each selected mode is a physical mode by the rule: in at least min_orders orders
        assert m["num_orders"] >= res["min_orders"]
        assert m["frequency_min"] <= m["frequency_hz"] <= m["frequency_max"]
