# SPDX-License-Identifier: Apache-2.0
"""CPU time per call for the benchmark scripts (scale_bench.py, ambient_bench.py)."""
import math
import statistics
import time


def timed(call, repeats=3):
    """(median CPU seconds per call over `repeats` batches, the last call's value). A call under
    20 ms is repeated in batches of at least 50 ms and each batch's mean counts: one short call's
    time is mostly cold caches and the scheduler (koma's median on the paper case moved from 10.0
    to 7.3 ms between two single-call runs on a quiet machine), and where process_time ticks in
    milliseconds it says nothing at all (the paper case read 0.001-0.002 s for every method). A call
    over 10 s runs once."""
    t0 = time.process_time()
    value = call()
    first = time.process_time() - t0
    if first > 10:
        return first, value
    batch = max(1, math.ceil(0.05 / max(first, 1e-5))) if first < 0.02 else 1
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(batch):
            value = call()
        times.append((time.process_time() - t0) / batch)
    return statistics.median(times), value
