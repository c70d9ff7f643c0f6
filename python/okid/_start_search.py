# SPDX-License-Identifier: Apache-2.0
"""okid.identify(refine=True) without observer_order, hankel_rows or hankel_cols: the CLI's search
for the refinement's start (host_tools/cli/identify_refine.c, identify_choose_start; docs/refinement.md).
OKID/ERA from each (p, alpha = beta) of a grid, cheap first, each refined; the start whose refinement
reaches the lowest cost (the highest likelihood: same record, same order) wins. It stops once two
starts reach the same cost, before the costly ones."""
from __future__ import annotations

import math
import warnings
from typing import Any, Callable, Dict, Optional, Tuple

from ._errors import OkidError
from ._refine import RefinementWarning

START_OBSERVER_ORDERS = (10, 20, 40, 80)
START_HANKEL_BLOCKS = (20, 50, 100)
TIE = 1e-3  # a thousandth of a log-likelihood unit: the earlier, cheaper start keeps it


def choose_start(identify_and_refine: Callable[[Dict[str, Any]], Tuple[Optional[Any], Optional[Any]]],
                 options: Dict[str, Any]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """(options with the chosen observer_order and Hankel size, the JSON's "start_search" object).

    identify_and_refine(options) returns (the Result or None when OKID/ERA failed, its Refinement or
    None when the refinement failed); it may raise OkidError for settings the library refuses."""
    candidates, best, agree = [], -1, 0
    for p in START_OBSERVER_ORDERS:
        for h in START_HANKEL_BLOCKS:
            if agree >= 2:
                break
            trial = dict(options, observer_order=p, hankel_rows=h, hankel_cols=h)
            entry = {"observer_order": p, "hankel_rows": h, "hankel_cols": h, "state": "identify_failed", "cost": None}
            candidates.append(entry)
            try:
                with warnings.catch_warnings():  # the CLI refines each start quietly
                    warnings.simplefilter("ignore", RefinementWarning)
                    result, refined = identify_and_refine(trial)
            except OkidError:
                continue  # a setting the library refuses for this record: like okid_workspace_size failing
            if result is None:
                continue
            entry["state"] = "refine_failed" if refined is None else refined.state
            if refined is None:
                continue
            cost = refined.cost
            entry["cost"] = cost if math.isfinite(cost) else None
            usable = refined.state != "diverged" and math.isfinite(cost)
            if usable and (best < 0 or cost < candidates[best]["cost"] - TIE):
                best = len(candidates) - 1
            # two starts that end in the same optimum: the likely global one
            agree = 0 if best < 0 else sum(
                c["cost"] is not None and abs(c["cost"] - candidates[best]["cost"]) <= TIE for c in candidates)
        if agree >= 2:
            break
    chosen = dict(options)
    if best >= 0:
        c = candidates[best]
        chosen.update(observer_order=c["observer_order"], hankel_rows=c["hankel_rows"], hankel_cols=c["hankel_cols"])
    return chosen, {"chosen": best, "candidates": candidates}
