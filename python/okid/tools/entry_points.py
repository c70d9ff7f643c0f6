# SPDX-License-Identifier: Apache-2.0
"""The console scripts of pyproject.toml: each runs its tool's main(), and when a package of the
tool's extra is missing (the scripts are installed with okid, the extras are not) ends with one
line naming the extra to install instead of a traceback."""
from __future__ import annotations

import importlib
import sys
from typing import Any, Callable, Dict

#: the third-party packages each extra of pyproject.toml brings
_EXTRAS: Dict[str, tuple] = {
    "tools": ("matplotlib", "scipy", "fmpy", "fmu_manipulation_toolbox", "mdof", "control"),
    "fleet": ("dask", "distributed", "pyarrow", "pandas", "matplotlib"),
}


def _run(program: str, module: str, extra: str) -> Any:
    try:
        main: Callable[[], Any] = importlib.import_module(module).main
        return main()
    except ModuleNotFoundError as e:
        missing = (e.name or "").split(".")[0]
        if missing not in _EXTRAS[extra]:
            raise
        print(f'{program}: needs {missing}, which okid installs with its extra: pip install "okid[{extra}]"',
              file=sys.stderr)
        return 1


def stabilization() -> Any:
    return _run("okid-stabilization", "okid.tools.stabilization", "tools")


def fleet() -> Any:
    return _run("okid-fleet", "okid.fleet.cli", "fleet")
