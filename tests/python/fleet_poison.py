# SPDX-License-Identifier: Apache-2.0
"""Dask worker preload of test_fleet.py (dask worker --preload): a record sampled every POISON_DT
seconds kills its worker process inside okid.identify with SIGKILL, as a native crash or the
kernel's out-of-memory killer would; one sampled every HANG_DT seconds hangs there for an hour, as
a native loop that never ends would. Every other record is identified as usual."""
import os
import signal
import time

import okid

POISON_DT = 0.0421  # [s]: no real record of the tests is sampled so
HANG_DT = 0.0433    # [s]: nor so

# Dask imports a preload more than once in a process (nanny, worker): wrap the original only once.
_identify = getattr(okid.identify, "original", okid.identify)


def _identify_or_die(u, y, dt, **options):
    if abs(dt - POISON_DT) < 1e-9:
        os.kill(os.getpid(), signal.SIGKILL)
    if abs(dt - HANG_DT) < 1e-9:
        time.sleep(3600)
    return _identify(u, y, dt, **options)


_identify_or_die.original = _identify
okid.identify = _identify_or_die
