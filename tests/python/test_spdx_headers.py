# SPDX-License-Identifier: Apache-2.0
"""The SPDX licence line of every tracked source file (scripts/spdx_headers.py, docs/building.md)."""
import importlib.util
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "spdx_headers.py"
spec = importlib.util.spec_from_file_location("spdx_headers", SCRIPT)
spdx = importlib.util.module_from_spec(spec)
spec.loader.exec_module(spdx)


def test_every_tracked_source_carries_the_line():
    run = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-4000:] + "\n(run: python3 scripts/spdx_headers.py)"


def add(tmp_path, name, text, mode=0o644):
    path = tmp_path / name
    path.write_bytes(text)
    path.chmod(mode)
    assert spdx.main([str(path)]) == 0
    return path.read_bytes()


def test_the_line_in_each_comment_syntax(tmp_path):
    assert add(tmp_path, "a.c", b"#include <x.h>\n") == b"/* SPDX-License-Identifier: Apache-2.0 */\n#include <x.h>\n"
    assert add(tmp_path, "a.h", b"#pragma once\n").startswith(b"/* SPDX-License-Identifier: Apache-2.0 */\n#pragma")
    assert add(tmp_path, "a.cpp", b"int x;\n") == b"// SPDX-License-Identifier: Apache-2.0\nint x;\n"
    for name in ("a.py", "a.cmake", "CMakeLists.txt", "a.sh"):
        assert add(tmp_path, name, b"x = 1\n") == b"# SPDX-License-Identifier: Apache-2.0\nx = 1\n"
    assert add(tmp_path, "empty.py", b"") == b"# SPDX-License-Identifier: Apache-2.0\n"


def test_shebang_and_encoding_lines_stay_first(tmp_path):
    out = add(tmp_path, "s.sh", b"#!/usr/bin/env bash\nset -e\n", 0o755)
    assert out == b"#!/usr/bin/env bash\n# SPDX-License-Identifier: Apache-2.0\nset -e\n"
    assert (tmp_path / "s.sh").stat().st_mode & 0o777 == 0o755
    out = add(tmp_path, "e.py", b"#!/usr/bin/env python3\n# -*- coding: latin-1 -*-\nx = '\xe9'\n")
    assert out == b"#!/usr/bin/env python3\n# -*- coding: latin-1 -*-\n# SPDX-License-Identifier: Apache-2.0\nx = '\xe9'\n"
    out = add(tmp_path, "f.py", b"# vim: set fileencoding=utf-8 :\nx = 1\n")
    assert out == b"# vim: set fileencoding=utf-8 :\n# SPDX-License-Identifier: Apache-2.0\nx = 1\n"
    # a comment that merely mentions an encoding further down is not a declaration
    out = add(tmp_path, "g.py", b'"""doc"""\n# encoding: utf-8\n')
    assert out.startswith(b"# SPDX-License-Identifier: Apache-2.0\n")


def test_idempotent_and_line_endings_kept(tmp_path):
    once = add(tmp_path, "w.c", b"int a;\r\nint b;\r\n")
    assert once == b"/* SPDX-License-Identifier: Apache-2.0 */\r\nint a;\r\nint b;\r\n"
    assert add(tmp_path, "w.c", once) == once
    assert spdx.main(["--check", str(tmp_path / "w.c")]) == 0


def test_check_reports_and_changes_nothing(tmp_path, capsys):
    path = tmp_path / "m.py"
    path.write_bytes(b"x = 1\n")
    assert spdx.main(["--check", str(path)]) == 1
    assert path.read_bytes() == b"x = 1\n"
    assert "no 'SPDX-License-Identifier: Apache-2.0' line" in capsys.readouterr().out
    other = tmp_path / "o.c"
    other.write_bytes(b"/* SPDX-License-Identifier: MIT */\nint a;\n")
    assert spdx.main([str(other)]) == 1  # another licence is reported, never replaced
    assert other.read_bytes() == b"/* SPDX-License-Identifier: MIT */\nint a;\n"
