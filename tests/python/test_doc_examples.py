# SPDX-License-Identifier: Apache-2.0
"""The Python examples of the README and docs/python.md run as written: each page's ```python
blocks in order in one namespace (as a reader pastes them), in a fresh directory, and a block
shown to print something (a ```text block after prose saying "prints") prints it: the same words,
the same numbers to 1e-9 relative (the documented accuracy; digits past the tenth move with the
compiler and the BLAS kernel).

docs/fmu.md's fmpy example drives a built FMU and is run by the FMU tests' own code instead.
"""
import contextlib
import io
import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = ["README.md", "docs/python.md"]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def examples(page):
    """[(code, expected output or None, line)] of the page's python blocks."""
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
        out.append((body, expected, text.count("\n", 0, start) + 1))
    return out


def same_output(shown, printed):
    """Words equal, numbers within 1e-9 relative (or 1e-12 absolute for zeros)."""
    words = lambda s: NUMBER.sub("#", s).split()
    if words(shown) != words(printed):
        return False
    a = [float(x) for x in NUMBER.findall(shown)]
    b = [float(x) for x in NUMBER.findall(printed)]
    return len(a) == len(b) and all(abs(x - y) <= 1e-9 * max(abs(x), abs(y)) + 1e-12 for x, y in zip(a, b))


@pytest.mark.parametrize("page", PAGES)
def test_the_examples_run_and_print_what_they_show(page, tmp_path, monkeypatch):
    found = examples(page)
    assert found, f"{page} has no python example"
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__doc_example__"}
    shown = 0
    for code, expected, line in found:
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(code, f"{page}:{line}", "exec"), namespace)
        if expected is not None:
            shown += 1
            assert same_output(expected, printed.getvalue()), \
                f"{page}:{line} prints\n{printed.getvalue()}\nthe page shows\n{expected}"
    assert shown >= 1


def test_the_comparison_can_fail():
    assert same_output("0.5032921210 0.158", "0.5032921211 0.158")
    assert not same_output("0.50329212 0.158", "0.50329213 0.158")
    assert not same_output("True True", "True False")
    assert not same_output("[1, 2]", "[1, 2, 3]")


def test_every_page_with_python_is_covered():
    """A Python example added to another page must be run here too (or say why not above)."""
    pages = {str(p.relative_to(ROOT)) for p in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
             if "```python" in p.read_text(encoding="utf-8")}
    assert pages == set(PAGES) | {"docs/fmu.md"}, pages
    assert os.path.exists(ROOT / "docs" / "fmu.md")
