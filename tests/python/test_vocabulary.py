# SPDX-License-Identifier: Apache-2.0
"""The one vocabulary (docs/cli.md): every field of okid_config has a CLI flag, a JSON "config" key
and an FMU variable of the same name, with okid_config_default()'s default.

The fields come from the C header that defines `typedef struct okid_config`; the table of
docs/cli.md is checked against them and against the built CLI and FMUs, so a field added to the
struct without its flag, key, variable or documentation fails here.
"""
import json
import os
import re
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
OKID = os.environ.get("OKID_CLI", "okid")
FMU_DIR = os.environ.get("OKID_FMU_DIR") or None

# The two fields whose flag takes column names as well as a count keep the short flag (docs/cli.md).
FLAG_EXCEPTIONS = {"num_inputs": "--inputs", "num_outputs": "--outputs"}

# A valid value other than the default for each field, what "config" must then say, and the other
# fields that move with it. A field added to okid_config needs an entry here (the test says so).
PROBES = {
    "num_inputs": (["--inputs", "force,force2"], 2, set()),
    "num_outputs": (["--outputs", "acc2"], 1, set()),
    # the record's time column steps by 0.01 s: another --dt needs the CLI-only --ignore-time-column
    "dt": (["--dt", "0.02", "--ignore-time-column"], 0.02, set()),
    "observer_order": (["--observer-order", "7"], 7, set()),
    "order": (["--order", "2"], 2, set()),
    "hankel_rows": (["--hankel-rows", "11"], 11, set()),
    "hankel_cols": (["--hankel-cols", "13"], 13, set()),
    "block_rows": (["--block-rows", "5"], 5, set()),
    "forgetting_factor": (["--forgetting-factor", "0.9999"], 0.9999, set()),
    "rank_tolerance": (["--rank-tolerance", "1e-9"], 1e-9, set()),
    "sensing": (["--sensing", "velocity"], "velocity", set()),
    "realization": (["--realization", "combined"], "combined", set()),
    "zero_initial_state": (["--zero-initial-state"], 1, set()),
    "decimation": (["--decimation", "2"], 2, set()),
    "scaling": (["--scaling", "auto"], "auto", set()),
    "estimator": (["--estimator", "instrumental"], "instrumental", set()),
    "instrument_lags": (["--estimator", "instrumental", "--instrument-lags", "70"], 70, {"estimator"}),
}


def struct_members(struct, with_types=False):
    """Member names of `typedef struct <struct>`, in order, from the header under lib/include/okid/
    that defines it (with_types: (type, name) pairs)."""
    for header in sorted((ROOT / "lib/include/okid").rglob("*.h")):
        text = header.read_text()
        match = re.search(r"typedef\s+struct\s+%s\s*\{(.*?)\}\s*%s\s*;" % (struct, struct), text, re.S)
        if match:
            body = re.sub(r"/\*.*?\*/|//[^\n]*", "", match.group(1), flags=re.S)
            fields = []
            for declaration in body.split(";"):
                declaration = declaration.strip()
                if declaration:
                    # "int a, b", "okid_real dt" or "const okid_real *a, *b": the names after the type
                    kind, names = re.match(r"((?:const\s+)?\w+)\s+(.*)", declaration, re.S).groups()
                    for name in names.split(","):
                        pointer = "*" in name
                        fields.append((kind + " *" * pointer, name.strip(" *")))
            return fields if with_types else [name for _, name in fields]
    raise AssertionError(f"no header under lib/include/okid defines typedef struct {struct}")


def config_fields():
    """Field names of okid_config, in order, from the header under lib/include/okid/ that defines it."""
    return struct_members("okid_config")


def docs_table():
    """docs/cli.md's vocabulary table: C field -> (default, CLI flag)."""
    rows = {}
    for line in (ROOT / "docs/cli.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and re.fullmatch(r"`\w+`", cells[0]) and cells[0] != "`okid_config`":
            flag = re.match(r"`(--[\w-]+)`", cells[2])
            rows[cells[0].strip("`")] = (cells[1], flag.group(1) if flag else None)
    return rows


FIELDS = config_fields()


# The settings the CLI otherwise chooses from the data, at okid_config_default()'s values (a later
# flag of the same name wins): the "config" object then holds the library's defaults.
LIBRARY_DEFAULTS = ("--decimation", "1", "--observer-order", "20", "--hankel-rows", "20", "--hankel-cols", "20")


def identify_config(path, *args):
    proc = subprocess.run([OKID, "identify", "--json", "--outputs", "acc1,acc2", *LIBRARY_DEFAULTS, *args, str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)["config"]


@pytest.fixture(scope="module")
def paper_csv(tmp_path_factory):
    """The paper's record with a second, independent force that the structure does not feel."""
    simulated = subprocess.run([OKID, "simulate", "--samples", "3000"], check=True, timeout=60, capture_output=True,
                               text=True).stdout.splitlines()
    force2 = subprocess.run([OKID, "simulate", "--samples", "3000", "--seed", "2"], check=True, timeout=60,
                            capture_output=True, text=True).stdout.splitlines()
    rows = [f"{a.split(',', 2)[0]},{a.split(',', 2)[1]},{b.split(',', 2)[1]},{a.split(',', 2)[2]}"
            for a, b in zip(simulated, force2)]
    assert rows[0] == "t,force,force,acc1,acc2"
    rows[0] = "t,force,force2,acc1,acc2"
    path = tmp_path_factory.mktemp("data") / "paper.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def test_header_parses_to_the_known_fields():
    assert len(FIELDS) == len(set(FIELDS)) and {"observer_order", "forgetting_factor", "dt"} <= set(FIELDS)


def test_docs_table_lists_every_field_with_its_flag():
    table = docs_table()
    assert set(table) == set(FIELDS), \
        f"docs/cli.md lacks {set(FIELDS) - set(table)}, has extra {set(table) - set(FIELDS)}"
    for field, (_, flag) in table.items():
        assert flag == FLAG_EXCEPTIONS.get(field, "--" + field.replace("_", "-")), field


@pytest.mark.parametrize("field", FIELDS)
def test_cli_flag_sets_the_json_key_of_the_same_name(paper_csv, field):
    assert field in PROBES, f"okid_config::{field} is new: give it a CLI flag, a JSON key, an FMU variable and a probe"
    args, want, also = PROBES[field]
    flag = FLAG_EXCEPTIONS.get(field, "--" + field.replace("_", "-"))
    assert flag in args
    assert re.search(rf"\n  {re.escape(flag)}[ \[\n]", subprocess.run([OKID, "identify", "--help"], capture_output=True,
                                                                     text=True).stdout), flag
    default, given = identify_config(paper_csv), identify_config(paper_csv, *args)
    assert given[field] == want and default[field] != want
    assert {k for k in given if given[k] != default[k]} == {field} | also


def test_json_config_has_exactly_the_fields_and_the_documented_defaults(paper_csv):
    config = identify_config(paper_csv)
    assert list(config) == FIELDS
    for field, (default, _) in docs_table().items():
        number = re.match(r"(-?[\d.]+)\b", default)
        name = re.match(r"`(\w+)`", default)
        if field in ("num_inputs", "num_outputs", "dt"):
            continue  # from the file
        assert number or name, (field, default)
        want = float(number.group(1)) if number else name.group(1)
        assert config[field] == want, (field, config[field], default)


@pytest.mark.skipif(FMU_DIR is None, reason="built without the FMUs (OKID_FMU_DIR not set)")
@pytest.mark.parametrize("version", [2, 3])
def test_fmu_has_a_variable_of_each_name(version):
    description = Path(FMU_DIR) / f"fmi{version}" / "okid_identifier" / "modelDescription.xml"
    root = ET.parse(description).getroot()
    names = {v.get("name") for v in root.iter() if v.get("valueReference") is not None and v.get("name")}
    missing = [f for f in FIELDS if f not in names]
    assert not missing, f"{description.relative_to(FMU_DIR)} has no variable named {missing}"


# FMI 2 gives an enumeration as its C value; FMI 3 as an enumeration item of the same value.
C_VALUES = {"displacement": 0, "velocity": 1, "acceleration": 2, "system": 0, "combined": 1, "none": 0, "auto": 1,
            "least_squares": 0, "instrumental": 1}


def fmu_starts(description):
    """name -> start value of every variable that has one (FMI 2: on the type child; FMI 3: an attribute)."""
    starts = {}
    for v in ET.parse(description).getroot().iter():
        start = v.get("start")
        if start is None:
            start = next((child.get("start") for child in v if child.get("start") is not None), None)
        # scalars only (an FMI 3 array's start lists its elements); Booleans as 0/1
        if v.get("name") and v.get("valueReference") is not None and start is not None and " " not in start:
            starts[v.get("name")] = {"true": 1.0, "false": 0.0}[start] if start in ("true", "false") else float(start)
    return starts


@pytest.mark.skipif(FMU_DIR is None, reason="built without the FMUs (OKID_FMU_DIR not set)")
@pytest.mark.parametrize("version", [2, 3])
def test_fmu_defaults_are_okid_config_default(version):
    description = Path(FMU_DIR) / f"fmi{version}" / "okid_identifier" / "modelDescription.xml"
    starts = fmu_starts(description)
    wrong = {}
    for field, (default, _) in docs_table().items():
        number, name = re.match(r"(-?[\d.]+)\b", default), re.match(r"`(\w+)`", default)
        if field in starts and (number or name):
            want = float(number.group(1)) if number else C_VALUES[name.group(1)]
            if starts[field] != want:
                wrong[field] = (starts[field], want)
    assert not wrong, f"{description.relative_to(FMU_DIR)}: start values (FMU, okid_config_default) {wrong}"


# ---- the field tables (host_tools/common/okid_fields.h, okid/modal.h) against the structs ----

def test_config_table_is_the_struct():
    """OKID_CONFIG_FIELDS, which the JSON writer, the binding and okid.OPTION_NAMES read, lists
    okid_config's fields in the struct's order, and okid's keywords are exactly its settings."""
    okid = pytest.importorskip("okid")
    assert [name for name, _ in okid._config.CONFIG_FIELDS] == FIELDS
    assert okid.OPTION_NAMES == tuple(f for f in FIELDS if f not in ("num_inputs", "num_outputs", "dt"))


# okid_result's members that are not scalars of the table: counts of the arrays, the bits (Result.warnings)
RESULT_NOT_SCALARS = {"num_modes", "num_singular_values", "warnings"}


def test_result_scalars_are_the_structs_scalars(paper_csv):
    """Every scalar member of okid_result is a row of OKID_RESULT_SCALARS, a key of the JSON
    object and a field of okid.Result; a scalar added to the struct without its row fails here."""
    okid = pytest.importorskip("okid")
    import dataclasses
    scalars = [name for kind, name in struct_members("okid_result", with_types=True)
               if kind in ("int", "okid_real", "uint64_t") and name not in RESULT_NOT_SCALARS]
    assert list(okid._core.RESULT_SCALARS) == [n for n in okid._core.RESULT_SCALARS if n in scalars]
    assert sorted(okid._core.RESULT_SCALARS) == sorted(scalars)
    proc = subprocess.run([OKID, "identify", "--json", "--outputs", "acc1,acc2", "--estimator", "instrumental",
                           str(paper_csv)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    keys = json.loads(proc.stdout)
    assert set(scalars) <= set(keys), set(scalars) - set(keys)
    assert set(scalars) <= {f.name for f in dataclasses.fields(okid.Result)}


def test_mode_table_is_the_struct(paper_csv):
    """OKID_MODE_FIELDS lists every member of okid_mode (in the JSON's order); the JSON writer writes
    exactly those keys in that order, and okid.Mode's fields begin with them in the same order."""
    okid = pytest.importorskip("okid")
    import dataclasses
    members = list(okid._core.MODE_FIELDS)
    assert sorted(members) == sorted(struct_members("okid_mode"))
    proc = subprocess.run([OKID, "identify", "--json", "--outputs", "acc1,acc2", "--order", "4", str(paper_csv)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    modes = json.loads(proc.stdout)["modes"]
    assert modes and all(list(md) == members for md in modes)
    assert [f.name for f in dataclasses.fields(okid.Mode)][:len(members)] == members
