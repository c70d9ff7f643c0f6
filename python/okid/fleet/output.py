# SPDX-License-Identifier: Apache-2.0
"""The output folder of a fleet job, and what makes it safe with the user's data.

A manifest (``_okid_fleet.json``) beside the parts names the tool, the okid version, every setting
of the job and the runs that wrote into the folder; a part is a file ``part-RUN-NNNNN[-MMMM].parquet``
of one of those runs. Only these files are the tool's: ``overwrite`` removes them and nothing else
(and refuses a folder that holds anything else), ``resume`` refuses a job whose settings differ
from the manifest's, and the output may neither lie inside an input nor hold one.
"""
from __future__ import annotations

import json
import os
import re
import time
import uuid
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence

if TYPE_CHECKING:
    from .records import ChannelSpec

MANIFEST: str = "_okid_fleet.json"
TOOL: str = "okid-fleet"
_PART = re.compile(r"^part-(?P<run>\d{8}T\d{6}-[0-9a-f]{6})-\d{5}(?:-\d{4})?\.parquet$")
_TMP = re.compile(r"^\.part-(?P<run>\d{8}T\d{6}-[0-9a-f]{6})-[0-9-]+\.[0-9a-f]{32}\.tmp$")


class OutputError(Exception):
    """An output folder the job may not use as asked (refused before anything is written)."""


def settings(options: Mapping[str, Any], channels: ChannelSpec) -> Dict[str, Any]:
    """Everything that decides a job's rows: the okid version, the identification settings and the
    channel choice. Two runs into one folder must agree on all of it."""
    import okid

    return {"okid": okid.__version__, "options": {k: options[k] for k in sorted(options)},
            "channels": {"inputs": channels.inputs, "outputs": channels.outputs, "dt": channels.dt,
                         "covariates": list(channels.covariates)}}


def _differences(old: Mapping[str, Any], new: Mapping[str, Any], prefix: str = "") -> List[str]:
    out = []
    for key in sorted(set(old) | set(new)):
        a, b = old.get(key), new.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            out += _differences(a, b, prefix + key + ".")
        elif a != b:
            out.append(f"{prefix}{key} {a!r} -> {b!r}" if key in old and key in new else
                       f"{prefix}{key} {'set to ' + repr(b) if key in new else repr(a) + ' unset'}")
    return out


def _is_inside(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


class Output:
    """The output folder OUT_DIR (made absolute: the workers write into it under this path)."""

    def __init__(self, out_dir: str) -> None:
        self.path: str = os.path.abspath(out_dir)                        #: the folder, absolute
        self.manifest_path: str = os.path.join(self.path, MANIFEST)      #: its manifest

    def manifest(self) -> Optional[Dict[str, Any]]:
        try:
            with open(self.manifest_path, encoding="utf-8") as f:
                manifest = json.load(f)
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            raise OutputError(f"{self.manifest_path}: not a readable okid-fleet manifest ({exc})") from None
        if not isinstance(manifest, dict) or manifest.get("tool") != TOOL:
            raise OutputError(f"{self.manifest_path}: not an okid-fleet manifest")
        return manifest

    def _listing(self) -> List[str]:
        return sorted(os.listdir(self.path)) if os.path.isdir(self.path) else []

    def owned(self) -> List[str]:
        """The files of the folder this tool wrote: the manifest, the parts and temporary parts of its runs."""
        manifest = self.manifest()
        if manifest is None:
            return []
        runs = set(manifest.get("runs", []))
        return [name for name in self._listing() if name == MANIFEST or any(
            m and m.group("run") in runs for m in (_PART.match(name), _TMP.match(name)))]

    def parts(self) -> List[str]:
        """The whole parts (paths) of the tool's runs."""
        return [os.path.join(self.path, n) for n in self.owned() if _PART.match(n)]

    def check_inputs(self, inputs: Sequence[str]) -> None:
        """Refuse an output inside an input folder, equal to an input, or holding one."""
        out = os.path.realpath(self.path)
        for given in inputs:
            real = os.path.realpath(given)
            if _is_inside(out, real) or _is_inside(real, out):
                raise OutputError(f"--out {self.path} and the input {given} overlap: write the output "
                                  "outside the input folders")

    def prepare(self, job_settings: Mapping[str, Any], *, resume: bool, overwrite: bool) -> str:
        """Make the folder ready for a run with JOB_SETTINGS; returns the new run's id."""
        if os.path.exists(self.path) and not os.path.isdir(self.path):
            raise OutputError(f"--out {self.path} is a file, not a folder: name a new folder")
        parent = os.path.dirname(os.path.abspath(self.path))
        while parent and not os.path.exists(parent):
            parent = os.path.dirname(parent)
        if parent and not os.path.isdir(parent):
            raise OutputError(f"--out {self.path} lies under the file {parent}, not a folder: name a new folder")
        manifest = self.manifest()
        owned = set(self.owned())
        foreign = [n for n in self._listing() if n not in owned]
        if foreign:
            shown = ", ".join(foreign[:3]) + (f" and {len(foreign) - 3} more" if len(foreign) > 3 else "")
            raise OutputError(f"--out {self.path} holds files okid-fleet did not write ({shown}): "
                              "name an empty or new folder")
        parts = [n for n in owned if _PART.match(n)]
        if manifest is not None and parts and not (resume or overwrite):
            raise OutputError(f"{self.path} already holds {len(parts)} part(s) of an earlier job: --resume to "
                              "finish it, --overwrite to start again")
        if manifest is not None and overwrite:
            for name in sorted(owned - {MANIFEST}):
                os.remove(os.path.join(self.path, name))
            manifest = None
        if manifest is not None and resume:
            diff = _differences(manifest.get("settings", {}), dict(job_settings))
            if diff:
                raise OutputError(f"--resume: {self.path} was written with other settings ({'; '.join(diff)}): "
                                  "run with the same settings, or write to another --out")
        os.makedirs(self.path, exist_ok=True)
        for name in owned:
            if _TMP.match(name):  # a part an interrupted run did not finish
                os.remove(os.path.join(self.path, name))
        run = time.strftime("%Y%m%dT%H%M%S") + "-" + uuid.uuid4().hex[:6]
        runs = (manifest or {}).get("runs", []) + [run]
        self._write_manifest({"tool": TOOL, "format": 1, "settings": dict(job_settings), "runs": runs})
        return run

    def _write_manifest(self, manifest: Mapping[str, Any]) -> None:
        tmp = self.manifest_path + f".{uuid.uuid4().hex}.tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(manifest, f, indent=1, sort_keys=True)
            f.write("\n")
        os.replace(tmp, self.manifest_path)


def part_name(run: str, batch: int, record: Optional[int] = None) -> str:
    """A part's name (no suffix): one per task; a record retried alone gets its own."""
    return f"part-{run}-{batch:05d}" + ("" if record is None else f"-{record:04d}")


def write_part(rows: List[Dict[str, Any]], out_dir: str, part: str) -> None:
    """ROWS to OUT_DIR/PART.parquet, written under a temporary name and renamed when whole."""
    import pyarrow.parquet as pq

    from .rows import to_table

    final = os.path.join(out_dir, part + ".parquet")
    tmp = os.path.join(out_dir, f".{part}.{uuid.uuid4().hex}.tmp")
    pq.write_table(to_table(rows), tmp)
    os.replace(tmp, final)
