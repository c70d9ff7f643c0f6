# SPDX-License-Identifier: Apache-2.0
"""Dask worker preload of test_fleet.py (dask worker --preload): a record sampled every POISON_DT
seconds kills its worker process inside okid.identify with SIGKILL, as a native crash or the
kernel's out-of-memory killer would; one sampled every HANG_DT seconds hangs there for an hour, as
a native loop that never ends would; one sampled every MEMORY_DT seconds takes memory, 20 MB at a
time, until its worker's nanny kills it past its memory limit (as a record too large for its
worker would; at most 1.2 times the limit, so a worker without a nanny or a limit merely raises
MemoryError). Every other record is identified as usual. Test-only: a preload that nobody loads
by accident."""
import mmap
import os
import signal
import time

import okid

POISON_DT = 0.0421  # [s]: no real record of the tests is sampled so
HANG_DT = 0.0433    # [s]: nor so
MEMORY_DT = 0.0437  # [s]: nor so
CHUNK = 20_000_000  # [bytes] taken at a time, in well under the nanny's 100 ms between looks (Dask's default)

# Dask imports a preload more than once in a process (nanny, worker): wrap the original only once.
_identify = getattr(okid.identify, "original", okid.identify)


def _identify_or_die(u, y, dt, **options):
    if abs(dt - POISON_DT) < 1e-9:
        os.kill(os.getpid(), signal.SIGKILL)
    if abs(dt - HANG_DT) < 1e-9:
        time.sleep(3600)
    if abs(dt - MEMORY_DT) < 1e-9:
        _take_memory()
    return _identify(u, y, dt, **options)


def _take_memory() -> None:
    from distributed import get_worker

    limit = get_worker().memory_manager.memory_limit or 0
    held = []
    while (len(held) + 1) * CHUNK <= 1.2 * limit:
        # resident at once (MAP_POPULATE): ten times faster than writing the pages one by one
        held.append(mmap.mmap(-1, CHUNK, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS | mmap.MAP_POPULATE))
    time.sleep(30)  # the nanny's SIGTERM comes long before
    raise MemoryError(f"fleet_poison.py: {len(held) * CHUNK} bytes held and the worker still alive")


_identify_or_die.original = _identify
okid.identify = _identify_or_die
