# SPDX-License-Identifier: Apache-2.0
"""Where the records and the output live: local paths, or any fsspec URL (``s3://``, ``gs://``, ...).

A local path stays a plain absolute path (made so on the client, the workers' working directory
does not matter); a URL goes through fsspec, whose file system for its scheme must be installed
(s3fs for ``s3://``, gcsfs for ``gs://``) on the client and on every worker. Credentials and the
endpoint come from the usual places of that file system: for S3 the environment variables
``AWS_ACCESS_KEY_ID``, ``AWS_SECRET_ACCESS_KEY``, ``AWS_ENDPOINT_URL`` (a MinIO or other S3 API),
``AWS_DEFAULT_REGION`` or ``~/.aws``; for GCS gcsfs's (``GOOGLE_APPLICATION_CREDENTIALS``, the
metadata server, fsspec's ``FSSPEC_GS_TOKEN``, ``STORAGE_EMULATOR_HOST`` for an emulator); read
by each process for itself: okid-fleet never sends a credential to a worker.

Paths inside a file system are kept in fsspec's form ('/' separated, without the scheme; a local
path is its absolute path), and turned back into what the user would type by ``url``.
"""
from __future__ import annotations

import os
import posixpath
import uuid
from typing import Any, List, Tuple


class StorageError(Exception):
    """A URL whose file system is not installed or not reachable."""


def is_url(path: str) -> bool:
    """A URL with a scheme (``s3://bucket/x``, ``file:///x``), not a local path."""
    return "://" in str(path)


def resolve(path: str) -> Tuple[Any, str]:
    """(fsspec file system, the path inside it) of a local path or a URL."""
    from fsspec.implementations.local import LocalFileSystem

    if not is_url(path):
        return LocalFileSystem(), os.path.abspath(path)
    from fsspec.core import url_to_fs

    try:
        fs, inner = url_to_fs(str(path))
    except (ImportError, ValueError) as exc:  # no file system for the scheme (s3fs not installed, ...)
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise StorageError(f"{path}: {reason}") from None
    if is_local(fs):
        return fs, os.path.abspath(inner)
    return fs, inner.rstrip("/")


def is_local(fs: Any) -> bool:
    from fsspec.implementations.local import LocalFileSystem

    return isinstance(fs, LocalFileSystem)


def url(fs: Any, path: str) -> str:
    """PATH of FS as the user names it: the local path itself, else the full URL."""
    return path if is_local(fs) else fs.unstrip_protocol(path)


def paths(fs: Any):
    """The path functions (join, relpath, dirname, ...) of FS's paths: os.path locally, posixpath else."""
    return os.path if is_local(fs) else posixpath


def listing(fs: Any, folder: str) -> List[str]:
    """The names directly in FOLDER (none when it does not exist), fresh: an object store's listing
    cache would miss the parts the workers wrote since."""
    if not is_local(fs):
        fs.invalidate_cache(folder)
    try:
        if not fs.isdir(folder):
            return []
        return sorted(posixpath.basename(p.rstrip("/")) for p in fs.ls(folder, detail=False))
    except FileNotFoundError:
        return []


def write_bytes(fs: Any, path: str, data: bytes) -> None:
    """DATA to PATH, whole or not at all: locally under a temporary name renamed when written; on an
    object store one upload, which its readers see complete or not at all."""
    if is_local(fs):
        tmp = os.path.join(os.path.dirname(path), f".{os.path.basename(path)}.{uuid.uuid4().hex}.tmp")
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    else:
        fs.pipe_file(path, data)


def local_copy(fs: Any, path: str, folder: str) -> str:
    """A local file holding PATH's bytes (PATH itself when it is local), for readers that need a file
    name (the CLI's CSV reader). The copy goes to FOLDER, which the caller removes."""
    if is_local(fs):
        return path
    local = os.path.join(folder, posixpath.basename(path))
    fs.get_file(path, local)
    return local
