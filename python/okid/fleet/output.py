# SPDX-License-Identifier: Apache-2.0
"""The output folder of a fleet job, and what makes it safe with the user's data.

A manifest (``_okid_fleet.json``) beside the parts names the tool, the okid version, every setting
of the job and the runs that wrote into the folder; a part is a file ``part-RUN-NNNNN[-MMMM].parquet``
of one of those runs. Only these files are the tool's: ``overwrite`` removes them and nothing else
(and refuses a folder that holds anything else), ``resume`` refuses a job whose settings differ
from the manifest's, and the output may neither lie inside an input nor hold one. The folder may be
an fsspec URL (``s3://bucket/modes``): the same rules hold there, object by object.
"""
from __future__ import annotations

import json
import os
import re
import time
import uuid
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence

from . import storage

if TYPE_CHECKING:
    from .records import ChannelSpec

MANIFEST: str = "_okid_fleet.json"
TOOL: str = "okid-fleet"
_PART = re.compile(r"^part-(?P<run>\d{8}T\d{6}-[0-9a-f]{6})-\d{5}(?:-\d{4})?\.parquet$")
_TMP = re.compile(r"^\.part-(?P<run>\d{8}T\d{6}-[0-9a-f]{6})-[0-9-]+(?:\.parquet)?\.[0-9a-f]{32}\.tmp$")
_TMP_MANIFEST = re.compile(r"^\.?" + re.escape(MANIFEST) + r"\.[0-9a-f]{32}\.tmp$")


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


def _is_inside(path: str, folder: str, sep: str) -> bool:
    return path == folder or path.startswith(folder.rstrip(sep) + sep)


def _location(given: str):
    """(scheme, path) of a local path (its real path) or a URL: what two of them overlap by."""
    fs, path = storage.resolve(given)
    if storage.is_local(fs):
        return "file", os.path.realpath(path), os.sep
    protocol = fs.protocol if isinstance(fs.protocol, str) else fs.protocol[0]
    return protocol, path, "/"


class Output:
    """The output folder OUT_DIR, a local path (made absolute: the workers write into it under this
    path) or an fsspec URL such as ``s3://bucket/modes`` (storage.py)."""

    def __init__(self, out_dir: str) -> None:
        self.fs, folder = storage.resolve(out_dir)
        self._pm = storage.paths(self.fs)
        self.path: str = storage.url(self.fs, folder)                    #: the folder: absolute path or URL
        self.folder: str = folder                                        #: the folder inside its file system
        self.manifest_path: str = self._pm.join(folder, MANIFEST)        #: its manifest, inside the file system

    def manifest(self) -> Optional[Dict[str, Any]]:
        try:
            with self.fs.open(self.manifest_path, "rb") as f:
                manifest = json.loads(f.read().decode("utf-8"))
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            raise OutputError(f"{self._shown(MANIFEST)}: not a readable okid-fleet manifest ({exc})") from None
        if not isinstance(manifest, dict) or manifest.get("tool") != TOOL:
            raise OutputError(f"{self._shown(MANIFEST)}: not an okid-fleet manifest")
        return manifest

    def _shown(self, name: str) -> str:
        return storage.url(self.fs, self._pm.join(self.folder, name))

    def _listing(self) -> List[str]:
        return storage.listing(self.fs, self.folder)

    def owned(self) -> List[str]:
        """The files of the folder this tool wrote: the manifest, the parts and temporary parts of its runs."""
        manifest = self.manifest()
        if manifest is None:
            return []
        runs = set(manifest.get("runs", []))
        return [name for name in self._listing() if name == MANIFEST or _TMP_MANIFEST.match(name) or any(
            m and m.group("run") in runs for m in (_PART.match(name), _TMP.match(name)))]

    def parts(self) -> List[str]:
        """The whole parts of the tool's runs (paths inside the file system)."""
        return [self._pm.join(self.folder, n) for n in self.owned() if _PART.match(n)]

    def check_inputs(self, inputs: Sequence[str]) -> None:
        """Refuse an output inside an input folder, equal to an input, or holding one."""
        scheme, out, sep = _location(self.path)
        for given in inputs:
            other, real, _ = _location(given)
            if other == scheme and (_is_inside(out, real, sep) or _is_inside(real, out, sep)):
                raise OutputError(f"--out {self.path} and the input {given} overlap: write the output "
                                  "outside the input folders")

    def prepare(self, job_settings: Mapping[str, Any], *, resume: bool, overwrite: bool) -> str:
        """Make the folder ready for a run with JOB_SETTINGS; returns the new run's id."""
        fs, pm = self.fs, self._pm
        if fs.isfile(self.folder):
            raise OutputError(f"--out {self.path} is a file, not a folder: name a new folder")
        if storage.is_local(fs):  # an object store has no folders, only names
            parent = pm.dirname(self.folder)
            while parent and not pm.exists(parent):
                parent = pm.dirname(parent)
            if parent and not pm.isdir(parent):
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
                fs.rm_file(pm.join(self.folder, name))
            manifest = None
        if manifest is not None and resume:
            diff = _differences(manifest.get("settings", {}), dict(job_settings))
            if diff:
                raise OutputError(f"--resume: {self.path} was written with other settings ({'; '.join(diff)}): "
                                  "run with the same settings, or write to another --out")
        fs.makedirs(self.folder, exist_ok=True)
        for name in owned:
            if _TMP.match(name) or _TMP_MANIFEST.match(name):  # a file an interrupted run did not finish
                fs.rm_file(pm.join(self.folder, name))
        run = time.strftime("%Y%m%dT%H%M%S") + "-" + uuid.uuid4().hex[:6]
        runs = (manifest or {}).get("runs", []) + [run]
        self._write_manifest({"tool": TOOL, "format": 1, "settings": dict(job_settings), "runs": runs})
        return run

    def _write_manifest(self, manifest: Mapping[str, Any]) -> None:
        text = json.dumps(manifest, indent=1, sort_keys=True) + "\n"
        storage.write_bytes(self.fs, self.manifest_path, text.encode("utf-8"))


def part_name(run: str, batch: int, record: Optional[int] = None) -> str:
    """A part's name (no suffix): one per task; a record retried alone gets its own."""
    return f"part-{run}-{batch:05d}" + ("" if record is None else f"-{record:04d}")


def write_part(rows: List[Dict[str, Any]], out_dir: str, part: str) -> None:
    """ROWS to OUT_DIR/PART.parquet (a path or URL), whole or not at all (storage.write_bytes)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from .rows import to_table

    fs, folder = storage.resolve(out_dir)
    buffer = pa.BufferOutputStream()
    pq.write_table(to_table(rows), buffer)
    storage.write_bytes(fs, storage.paths(fs).join(folder, part + ".parquet"), buffer.getvalue().to_pybytes())
