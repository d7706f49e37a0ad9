"""How much of this machine the passive fit's numeric work may use: processes for the model-level diagnosis's
fits, threads for CasADi's numeric maps (the muscle moment, the path polynomials, the identifiability's
Jacobian rows, the forward dynamics' tables: each point independent of the others, evaluated by CasADi's own
threads, so a map gives the same numbers serial or threaded).
"""

from __future__ import annotations

import multiprocessing
import os
from typing import Any

#: the most processes (model-level diagnosis) or threads (numeric maps) the fit uses at once
MAX_WORKERS = 2
#: a map of fewer points than this per thread is evaluated on one. Measured on this 2-core host (2026-11-29): the calf's
#: moment with its tendon equilibrium, 16 points 2.6 → 2.0 ms, 128 points 20.5 → 11.0 ms on two threads; a cheap point
#: function (twelve powers of x) is slower on threads at any size (1,024 points 0.73 → 0.98 ms). :func:`mapped` is for
#: point functions of tens of microseconds or more (every caller's: muscle moments, equilibria, spline paths)
MIN_POINTS_PER_THREAD = 64


def workers() -> int:
    """``INSTRUMENT_FIT_WORKERS`` if set (a host already busy with other processes: 1), else one per core this
    process may use, at most :data:`MAX_WORKERS`; 1 inside a daemonic process (a pool's worker: its siblings
    have the other cores)."""
    if multiprocessing.current_process().daemon:
        return 1
    if os.environ.get("INSTRUMENT_FIT_WORKERS", "").strip():
        return max(1, int(os.environ["INSTRUMENT_FIT_WORKERS"]))
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(MAX_WORKERS, cores))


def mapped(function: Any, points: int) -> Any:
    """``function`` (a CasADi Function of one point) mapped over ``points`` columns, on :func:`workers` threads
    when the map is large enough to gain from them."""
    threads = min(workers(), points // MIN_POINTS_PER_THREAD)
    return function.map(points, "thread", threads) if threads > 1 else function.map(points)


__all__ = ["MAX_WORKERS", "MIN_POINTS_PER_THREAD", "mapped", "workers"]
