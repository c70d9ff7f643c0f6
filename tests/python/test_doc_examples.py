# SPDX-License-Identifier: Apache-2.0
"""The Python examples of the README and of every docs/*.md run as written: each page's ```python
blocks in order in one namespace (as a reader pastes them), in a fresh directory, and a block
shown to print something (a ```text block after prose saying "prints") prints it: the same words,
the same numbers to 1e-9 relative (the documented accuracy; digits past the tenth move with the
compiler and the BLAS kernel).

A block that is not meant to run says so on the line before its fence, with the reason:
``<!-- not run: the reason -->``. A page whose examples need a file gets it in its directory from
NEEDS (docs/fmu.md: the built FMI 3 identifier FMU, from OKID_FMU_DIR as the FMU tests take it).
"""
import contextlib
import io
import os
import re
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
NOT_RUN = re.compile(r"<!-- not run: (.*?) -->\s*$")


def pages_with_python():
    return [str(p.relative_to(ROOT)) for p in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
            if "```python" in p.read_text(encoding="utf-8")]


def _fmu(directory):
    built = Path(os.environ.get("OKID_FMU_DIR", ROOT / "build" / "fmu")) / "fmi3" / "okid_identifier.fmu"
    if not built.is_file():
        pytest.fail(f"docs/fmu.md's example needs the built FMU {built} (cmake --build --preset default; "
                    f"ctest sets OKID_FMU_DIR)")
    shutil.copy(built, directory / "okid_identifier.fmu")


#: the files a page's examples open, put into their directory before they run
NEEDS = {"docs/fmu.md": _fmu}


def examples(page):
    """[(code, expected output or None, line, reason it is not run or None)] of the page's python blocks."""
    text = (ROOT / page).read_text(encoding="utf-8")
    blocks = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    out = []
    for i, (lang, body, start, end) in enumerate(blocks):
        if lang != "python":
            continue
        expected = None
        if i + 1 < len(blocks) and blocks[i + 1][0] == "text":
            between = text[end:blocks[i + 1][2]]
            if "prints" in between and len(between) < 400:
                expected = blocks[i + 1][1]
        before = text[:start].rstrip("\n").rsplit("\n", 1)[-1]
        skipped = NOT_RUN.search(before)
        out.append((body, expected, text.count("\n", 0, start) + 1, skipped.group(1) if skipped else None))
    return out


def same_output(shown, printed):
    """Words equal, numbers within 1e-9 relative (or 1e-12 absolute for zeros)."""
    words = lambda s: NUMBER.sub("#", s).split()
    if words(shown) != words(printed):
        return False
    a = [float(x) for x in NUMBER.findall(shown)]
    b = [float(x) for x in NUMBER.findall(printed)]
    return len(a) == len(b) and all(abs(x - y) <= 1e-9 * max(abs(x), abs(y)) + 1e-12 for x, y in zip(a, b))


@pytest.mark.parametrize("page", pages_with_python())
def test_the_examples_run_and_print_what_they_show(page, tmp_path, monkeypatch):
    found = examples(page)
    assert found, f"{page} has no python example"
    if page in NEEDS:
        NEEDS[page](tmp_path)
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__doc_example__"}
    ran = 0
    for code, expected, line, not_run in found:
        if not_run is not None:
            assert not_run.strip(), f"{page}:{line}: a block not run says why"
            continue
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(code, f"{page}:{line}", "exec"), namespace)
        ran += 1
        if expected is not None:
            assert same_output(expected, printed.getvalue()), \
                f"{page}:{line} prints\n{printed.getvalue()}\nthe page shows\n{expected}"
    assert ran >= 1, f"{page}: every example is marked not run"


def test_the_comparison_can_fail():
    assert same_output("0.5032921210 0.158", "0.5032921211 0.158")
    assert not same_output("0.50329212 0.158", "0.50329213 0.158")
    assert not same_output("True True", "True False")
    assert not same_output("[1, 2]", "[1, 2, 3]")


def test_the_pages_are_found_and_a_block_not_run_is_recognised(tmp_path, monkeypatch):
    """The pages with examples today are found (an empty list would run nothing), each runs
    something that shows what it prints, and the marker skips a block only with a reason."""
    assert {"README.md", "docs/python.md", "docs/fmu.md"} <= set(pages_with_python())
    for page in pages_with_python():
        assert any(expected is not None and not_run is None for _, expected, _, not_run in examples(page)), page
    page = tmp_path / "page.md"
    page.write_text("Text.\n\n<!-- not run: it needs a cluster -->\n```python\nraise SystemExit\n```\n\n"
                    "```python\nprint(1)\n```\n\nprints\n\n```text\n1\n```\n", encoding="utf-8")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    got = examples("page.md")
    assert [(not_run, expected) for _, expected, _, not_run in got] == [("it needs a cluster", None), (None, "1\n")]
