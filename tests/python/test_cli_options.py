# SPDX-License-Identifier: Apache-2.0
"""The options of okid identify and okid simulate (docs/cli.md): names after the okid_config fields,
old spellings as aliases, every refusal naming the value and the valid range, and the JSON "config"
object holding the settings the run used.
"""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

OKID = os.environ.get("OKID_CLI", "okid")
DBL_EPSILON = sys.float_info.epsilon
SETTINGS = ("--order", 4, "--zero-initial-state")


def run(*args, check=True):
    proc = subprocess.run([OKID, *map(str, args)], capture_output=True, text=True, timeout=120)
    if check and proc.returncode != 0:
        raise AssertionError(f"okid {' '.join(map(str, args))} failed: {proc.stderr}")
    return proc


def refusal(*args):
    """The one 'okid: ' line of a usage error (exit 2, nothing on stdout)."""
    proc = run(*args, check=False)
    assert proc.returncode == 2 and proc.stdout == "", (proc.returncode, proc.stdout, proc.stderr)
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("okid: "), proc.stderr
    return lines[0]


@pytest.fixture(scope="module")
def paper_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "paper.csv"
    run("simulate", "--output", path)
    return path


def identify(path, *extra):
    return json.loads(run("identify", "--json", *extra, path).stdout)


def eigenvalues(result):
    return [tuple(m["eigenvalue"]) for m in result["modes"]]


# ---- names: the okid_config field's, the old spelling as an alias ----

@pytest.mark.parametrize("new,old", [
    (("--forgetting-factor", 0.999), ("--forgetting", 0.999)),
    (("--decimation", 2), ("--decimate", 2)),
    (("--scaling", "auto"), ("--scale", "auto")),
    (("--estimator", "least_squares"), ("--estimator", "least-squares")),
])
def test_new_names_and_old_spellings_agree(paper_csv, new, old):
    with_new, with_old = identify(paper_csv, *SETTINGS, *new), identify(paper_csv, *SETTINGS, *old)
    assert with_new == with_old  # the whole JSON, bit for bit
    assert with_new["config"][new[0][2:].replace("-", "_")] == new[1]


def test_equals_form_is_the_same_option(paper_csv):
    spaced = identify(paper_csv, "--order", 4, "--observer-order", 12, "--zero-initial-state")
    joined = identify(paper_csv, "--order=4", "--observer-order=12", "--zero-initial-state=1")
    assert spaced == joined
    assert joined["config"]["observer_order"] == 12 and joined["config"]["zero_initial_state"] == 1
    off = identify(paper_csv, "--order", 4, "--zero-initial-state=0")
    assert off["config"]["zero_initial_state"] == 0 and off["samples"] == 1001


def test_block_rows_sets_the_field(paper_csv):
    """block_rows changes how rows are folded, not which rows: the modes agree to round-off."""
    default, blocked = identify(paper_csv, *SETTINGS), identify(paper_csv, *SETTINGS, "--block-rows", 7)
    assert default["config"]["block_rows"] == 0 and blocked["config"]["block_rows"] == 7
    assert np.allclose(eigenvalues(default), eigenvalues(blocked), rtol=0, atol=1e-11)


LIBRARY_DEFAULTS = {"num_inputs": 1, "num_outputs": 2, "observer_order": 20, "order": 0, "hankel_rows": 20,
                    "hankel_cols": 20, "block_rows": 0, "dt": 0.01, "forgetting_factor": 1.0,
                    "rank_tolerance": 0.0, "sensing": "acceleration", "realization": "system",
                    "zero_initial_state": 0, "decimation": 1, "scaling": "none",
                    "estimator": "least_squares", "instrument_lags": 0}
CHOSEN = ("decimation", "observer_order", "hankel_rows", "hankel_cols", "order")


def test_defaults_are_okid_config_default(paper_csv):
    """No option given: the settings are okid_config_default()'s (observer order 20, not 10), except
    those chosen from the data, which "chosen" names with their reasons."""
    res = identify(paper_csv)
    config, chosen = res["config"], res["chosen"]
    assert {k: v for k, v in config.items() if k not in CHOSEN} == {
        k: v for k, v in LIBRARY_DEFAULTS.items() if k not in CHOSEN}
    for key in CHOSEN:  # "config" keeps order 0 (automatic); the model's order is the top-level "order"
        used = res["order"] if key == "order" else config[key]
        assert chosen[key]["chosen"] is True and chosen[key]["value"] == used and chosen[key]["reason"]
    fixed = identify(paper_csv, "--decimation", 1, "--observer-order", 20, "--hankel-rows", 20, "--hankel-cols", 20)
    assert fixed["config"] == LIBRARY_DEFAULTS and not fixed["chosen"]["observer_order"]["chosen"]


def test_config_holds_what_was_given(paper_csv):
    res = identify(paper_csv, "--observer-order", 8, "--order", 4, "--hankel-rows", 30, "--hankel-cols", 25,
                   "--forgetting-factor", 0.9995, "--rank-tolerance", 1e-9, "--sensing", "acceleration",
                   "--realization", "combined", "--zero-initial-state", "--scaling", "auto",
                   "--estimator", "instrumental", "--instrument-lags", 60)
    config = res["config"]
    assert config["observer_order"] == 8 and config["order"] == 4
    assert config["hankel_rows"] == 30 and config["hankel_cols"] == 25
    assert config["forgetting_factor"] == 0.9995 and config["rank_tolerance"] == 1e-9
    assert config["realization"] == "combined" and config["scaling"] == "auto"
    assert config["estimator"] == "instrumental" and config["instrument_lags"] == 60
    # the result keeps okid_result's names at the top level
    assert res["order"] == 4 and res["instrument_lags"] == 60 and len(res["input_scales"]) == 1
    assert len(res["output_scales"]) == 2 and all(s > 0 for s in res["input_scales"] + res["output_scales"])


def test_old_top_level_setting_keys_stay_for_one_release(paper_csv):
    res = identify(paper_csv, *SETTINGS, "--decimation", 2, "--scaling", "auto")
    config = res["config"]
    assert res["scale"] == config["scaling"] == "auto"
    assert res["sample_dt"] == config["dt"] == 0.01 and res["dt"] == pytest.approx(0.02)
    assert res["estimator"] == "least-squares" and config["estimator"] == "least_squares"
    for key in ("observer_order", "sensing", "hankel_rows", "hankel_cols", "realization"):
        assert res[key] == config[key], key
    assert res["decimation"] == 2  # okid_result::decimation


def test_long_but_valid_numbers_are_numbers(paper_csv):
    long_factor = "0.999" + "0" * 300 + "1"
    long_order = "0" * 200 + "4"
    short = identify(paper_csv, "--forgetting-factor", 0.999, "--order", 4)
    assert identify(paper_csv, "--forgetting-factor", long_factor, "--order", long_order) == short
    long_masses = "2." + "0" * 300 + ",3"
    assert run("simulate", "--masses", long_masses).stdout == run("simulate").stdout


# ---- refusals: the flag as typed, the value, the valid range ----

def test_forgetting_factor_zero_is_refused_not_read_as_one(paper_csv):
    for flag in ("--forgetting-factor", "--forgetting"):
        message = refusal("identify", flag, 0, paper_csv)
        assert f"'0' for {flag}" in message and "(0, 1]" in message


def test_rank_tolerance_below_epsilon_names_the_bound_it_misses(paper_csv):
    message = refusal("identify", "--rank-tolerance", "1e-300", paper_csv)
    assert "'1e-300'" in message and ">= 0" not in message
    bound = float(message.split("0 or [")[1].split(",")[0])
    assert bound == DBL_EPSILON  # the hint is one 1e-300 does not satisfy
    # below the double range: not silently 0 (the automatic tolerance)
    assert "would read as 0" in refusal("identify", "--rank-tolerance", "1e-400", paper_csv)
    assert identify(paper_csv, "--rank-tolerance", repr(DBL_EPSILON), *SETTINGS)["config"]["rank_tolerance"] \
        == DBL_EPSILON


@pytest.mark.parametrize("value", ["5", "-1", "2", "yes"])
def test_switch_takes_only_zero_or_one(paper_csv, value):
    message = refusal("identify", f"--zero-initial-state={value}", paper_csv)
    assert f"'{value}'" in message and "0 or 1" in message


def test_subnormal_and_huge_values(paper_csv):
    message = refusal("identify", "--dt", "1e-320", paper_csv)
    assert "'1e-320'" in message and "[1e-75, 1e+75]" in message
    assert "not a finite number" in refusal("identify", "--dt", "1e400", paper_csv)
    message = refusal("identify", "--order", "99999999999999999999", paper_csv)
    assert "out of range" in message and "0..512" in message


# every option of the table with a value outside its range: (flag, value, the range it must name)
OUT_OF_RANGE = [
    ("--dt", "0", "[1e-75, 1e+75]"), ("--dt", "-0.01", "[1e-75, 1e+75]"),
    ("--observer-order", "0", "1..1000"), ("--observer-order", "1001", "1..1000"),
    ("--order", "-1", "0..512"), ("--order", "513", "0..512"),
    ("--hankel-rows", "0", "1..1000"), ("--hankel-cols", "1001", "1..1000"),
    ("--block-rows", "-1", "0..4096"), ("--block-rows", "4097", "0..4096"),
    ("--forgetting-factor", "1.0000001", "(0, 1]"), ("--forgetting-factor", "-0.5", "(0, 1]"),
    ("--rank-tolerance", "1", "0 or [2.220446049250313e-16, 1)"),
    ("--rank-tolerance", "-1e-9", "0 or [2.220446049250313e-16, 1)"),
    ("--sensing", "strain", "displacement|velocity|acceleration"),
    ("--realization", "both", "system|combined"),
    ("--decimation", "0", "1..64"), ("--decimate", "65", "1..64"),
    ("--scaling", "rms", "none|auto"), ("--scale", "si", "none|auto"),
    ("--estimator", "iv", "least_squares|instrumental"),
    ("--instrument-lags", "-1", "0..8000"), ("--instrument-lags", "8001", "0..8000"),
    ("--observer-seconds", "0", "> 0"), ("--hankel-seconds", "-1", "> 0"),
    ("--stabilization", "1", "2..512"), ("--repeat", "0", "1..100000"),
]


@pytest.mark.parametrize("flag,value,valid", OUT_OF_RANGE)
def test_every_refusal_names_the_value_and_the_range(paper_csv, flag, value, valid):
    message = refusal("identify", flag, value, paper_csv)
    assert f"bad value '{value}' for {flag}" in message and f"valid: {valid}" in message


@pytest.mark.parametrize("flag", ["--observer-order", "--forgetting-factor", "--decimation", "--dt"])
def test_not_a_number_is_told_apart_from_out_of_range(paper_csv, flag):
    message = refusal("identify", flag, "1x", paper_csv)
    assert "'1x'" in message and ("not a number" in message or "not an integer" in message)


def test_combinations_name_their_numbers(paper_csv):
    message = refusal("identify", "--observer-order", 1, "--order", 4, paper_csv)
    assert "--order 4" in message and "= 2" in message  # m p = 2 outputs x p = 1


@pytest.mark.parametrize("args,needle", [
    (["--masses", "-1,3"], "each > 0"),
    (["--dampers", "1,-2,3"], "each >= 0"),
    (["--samples", "0"], "1..2147483647"),
    (["--noise", "-0.1"], ">= 0"),
    (["--force-dof", "0"], "1..16"),
    (["--sensing", "strain"], "displacement|velocity|acceleration"),
])
def test_simulate_refusals_name_the_range(args, needle):
    message = refusal("simulate", *args)
    assert f"'{args[1]}'" in message and needle in message


# ---- the usage text comes from the same table ----

def test_usage_lists_every_option_once_with_its_default():
    text = run("identify", "--help").stdout.split("(okid_config_default()).\n", 1)[1]  # the option list
    for flag, default in [("--observer-order", "20"), ("--hankel-rows", "20"), ("--forgetting-factor", "1"),
                          ("--decimation", "1"), ("--scaling", "none"), ("--estimator", "least_squares"),
                          ("--block-rows", "0"), ("--zero-initial-state", "0")]:
        starts = re.findall(rf"\n  {flag}(?![\w-])", text)  # --decimation, not --decimation-method
        entry = re.split(rf"\n  {flag}(?![\w-])", text, maxsplit=1)[1].split("\n  --", 1)[0]
        assert f"default {default}" in entry, flag
        assert len(starts) == 1
    for old in ("--forgetting", "--decimate", "--scale"):
        assert f"old spelling {old}]" in text or f"old spelling {old}\n" in text
