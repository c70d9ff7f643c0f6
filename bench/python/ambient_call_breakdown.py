# SPDX-License-Identifier: Apache-2.0
"""Where okid.identify_ambient's time goes on one benchmark record (docs/ambient.md, "Against the
peers"): the whole call, the binding's call, the sums alone (okid._core.AmbientCore: init and
push_block of the mean-removed record), identify with its result dict, and the AmbientResult's
building; CPU time (time.process_time), median and minimum of REPS calls, one BLAS thread.

  .venv/bin/python bench/python/ambient_call_breakdown.py [--case paper] [--reps 300]
"""
import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

import okid
from okid import _ambient, _core

from ambient_bench import CASES, record


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="paper", choices=sorted(CASES))
    ap.add_argument("--reps", type=int, default=300)
    args = ap.parse_args()
    case = CASES[args.case]
    y = record(case, 1)
    dt, L, n, m = case["dt"], case["L"], case["order"], y.shape[1]
    y0 = np.ascontiguousarray(y - y.mean(axis=0))

    def timed(f):
        ts = []
        for _ in range(args.reps):
            t0 = time.process_time()
            f()
            ts.append(time.process_time() - t0)
        return f"median {np.median(ts) * 1e3:.3f} ms, min {min(ts) * 1e3:.3f} ms"

    def sums():
        core = _core.AmbientCore()
        core.init(m, dt, L, n, [], 2, 0, 0)
        core.push_block(y0, None)

    core = _core.AmbientCore()
    core.init(m, dt, L, n, [], 2, 0, 0)
    core.push_block(y0, None)
    res = core.identify()[1]
    print(f"{args.case}: N = {len(y)}, m = {m}, L = {L}, n = {n}")
    print("okid.identify_ambient          ", timed(lambda: okid.identify_ambient(y, dt, hankel_rows=L, order=n)))
    print("_core.ambient_identify         ", timed(lambda: _core.ambient_identify(y, dt, L, n, [], 2, 0, 0, None)))
    print("sums: init + push_block        ", timed(sums))
    print("identify and its result dict   ", timed(core.identify))
    print("the AmbientResult from the dict", timed(lambda: _ambient._result(res, [], m)))


if __name__ == "__main__":
    main()
