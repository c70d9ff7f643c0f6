#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The SPDX licence line of okid's sources (docs/building.md, "Licence"): every tracked source file
(*.c *.h *.cpp *.py *.cmake CMakeLists.txt *.sh) starts with

    SPDX-License-Identifier: Apache-2.0

in the file's comment syntax (/* ... */ in C and headers, // in C++, # elsewhere), as its first
line, or right after a shebang line and a Python encoding declaration (PEP 263), which must stay
first.

    python3 scripts/spdx_headers.py            adds the line where it is missing, says which files it changed
    python3 scripts/spdx_headers.py --check    changes nothing; lists the files without it, exit status 1 if any

Idempotent: a file that has an SPDX-License-Identifier line in its first lines is left as it is
(with another identifier, --check reports it and the adder does not touch it). Bytes, line endings
(LF or CRLF) and the file mode are kept; only files that git tracks are looked at.
"""
import argparse
import fnmatch
import os
import re
import subprocess
import sys
from pathlib import Path

LICENSE = "Apache-2.0"
PATTERNS = ["*.c", "*.h", "*.cpp", "*.py", "*.cmake", "CMakeLists.txt", "*.sh"]
TAG = b"SPDX-License-Identifier:"
HEAD_LINES = 3  # the tag is looked for in the first lines (after a shebang and an encoding line)
CODING = re.compile(rb"^[ \t\f]*#.*?coding[:=][ \t]*[-\w.]+")


def comment(path):
    name = Path(path).name
    if name.endswith((".c", ".h")):
        return b"/* SPDX-License-Identifier: " + LICENSE.encode() + b" */"
    if name.endswith(".cpp"):
        return b"// SPDX-License-Identifier: " + LICENSE.encode()
    return b"# SPDX-License-Identifier: " + LICENSE.encode()


def is_source(path):
    name = Path(path).name
    return any(fnmatch.fnmatchcase(name, p) for p in PATTERNS)


def tracked_sources(root):
    out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], check=True, capture_output=True).stdout
    return [root / p for p in out.decode().split("\0") if p and is_source(p)]


def preamble_length(lines, path):
    """How many leading lines must stay before the SPDX line: a shebang, then (Python) an encoding line."""
    n = 0
    if lines and lines[0].startswith(b"#!"):
        n = 1
    if path.suffix == ".py":
        for i in range(n, min(2, len(lines))):  # PEP 263: line 1, or line 2 below a comment-only line
            if i == 1 and lines[0].strip() and not lines[0].lstrip().startswith(b"#"):
                break
            if CODING.match(lines[i]):
                n = i + 1
    return n


def status(data, path):
    """'ok', 'missing' or 'other' (an SPDX line with another identifier)."""
    lines = data.splitlines()
    start = preamble_length(lines, path)
    for line in lines[:start + HEAD_LINES]:
        if TAG in line:
            ident = line.split(TAG, 1)[1].strip().rstrip(b"*/").strip()
            return "ok" if ident == LICENSE.encode() else "other"
    return "missing"


def with_header(data, path):
    """The file's bytes with the SPDX line inserted (unchanged if it has one)."""
    if status(data, path) != "missing":
        return data
    newline = b"\r\n" if b"\r\n" in data.split(b"\n", 1)[0] + b"\n" else b"\n"
    lines = data.splitlines(keepends=True)
    start = preamble_length([l.rstrip(b"\r\n") for l in lines], path)
    head = b"".join(lines[:start])
    if head and not head.endswith(b"\n"):  # a file that is only a shebang without a newline
        head += newline
    return head + comment(path) + newline + b"".join(lines[start:])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if a file lacks the line")
    parser.add_argument("files", nargs="*", type=Path, help="files to treat (default: every tracked source file)")
    args = parser.parse_args(argv)
    root = Path(__file__).resolve().parent.parent
    files = args.files or tracked_sources(root)
    missing, other, changed = [], [], []
    for path in files:
        data = path.read_bytes()
        state = status(data, path)
        if state == "other":
            other.append(path)
        elif state == "missing":
            missing.append(path)
            if not args.check:
                mode = path.stat().st_mode
                path.write_bytes(with_header(data, path))
                os.chmod(path, mode)
                changed.append(path)
    def show(p):
        try:
            return str(p.resolve().relative_to(root))
        except ValueError:
            return str(p)
    for p in other:
        print(f"spdx_headers: {show(p)}: an SPDX-License-Identifier other than {LICENSE} (left as it is)")
    if args.check:
        for p in missing:
            print(f"spdx_headers: {show(p)}: no 'SPDX-License-Identifier: {LICENSE}' line")
        print(f"spdx_headers: {len(files) - len(missing) - len(other)} of {len(files)} files carry the line")
        return 1 if missing or other else 0
    for p in changed:
        print(f"spdx_headers: added to {show(p)}")
    print(f"spdx_headers: added to {len(changed)} of {len(files)} files")
    return 1 if other else 0


if __name__ == "__main__":
    sys.exit(main())
