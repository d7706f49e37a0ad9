"""Hard stops at their detection threshold, against an oracle that knows where the stop is.

A stop at 3–5× the noise acts over the last 4–8° of a movement; whether one trial can show it at all
depends on how many samples pass the stop and on what the baseline can absorb. This benchmark asks,
for each trial of the independent generator (:mod:`benchmarks.diagnosis_truth`, seeds 13000–13039
per kind, half with nuisances; fast sweeps 14000–14019 for knee and ankle), what an *oracle* would see: the t statistic of a
stop placed at the
true angle (searched within ±2° of it, for the angle offset a nuisance adds) on the diagnosis's own
baseline, with the same effective-sample-size standard error. A stop the oracle cannot lift past
the diagnosis's level (:data:`analysis.diagnosis.engine.LOCAL_STOP_T`) is beyond what any test at
that false-alarm rate can name from this trial; the diagnosis's misses are then split into
"detectable" and "not detectable".

Keys, per kind and ``all``: ``trials``, ``named`` (the stop named, alone), ``oracle_detectable``
(fraction with oracle t > the level), ``named_when_detectable``, ``named_when_not``,
``oracle_t_median``; ``fast_sweeps`` the same for the fast set.
"""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from benchmarks.diagnosis import KINDS, as_trial, named_causes
from benchmarks.diagnosis_truth import generate

SEED = 13000
FAST_SEED = 14000
WINDOW_DEG = 2.0  # the oracle searches this far either side of the true stop angle (angle offsets ≤ 1.5°)


def oracle_stop_t(kind: str, seed: int, noise_multiple: tuple[float, float] = (3.0, 5.0), fast: bool = False
                  ) -> tuple[float, bool]:
    """(oracle t of the hidden stop, whether the diagnosis named the stop alone) for one trial of a stop
    ``noise_multiple`` × the noise (``fast``: sweeps at 20 and 30 °/s)."""
    from analysis.diagnosis import diagnose
    from analysis.diagnosis.causes import Prepared, _stop_column
    from analysis.diagnosis.engine import MAX_RATE_HZ, effective_n

    g = generate(kind, ("hard_stop",), seed, nuisances=bool(seed % 2), noise_multiple=noise_multiple,
                 fast=fast)
    trial = as_trial(g)
    named = named_causes(diagnose(trial)) == {"hard_stop"}
    prep = Prepared.of(trial.decimated(MAX_RATE_HZ), 6.0 if kind == "afo" else None)
    base = prep.baseline()
    ok = np.isfinite(prep.target)
    best = -math.inf
    for stop_deg in g.details["stop_deg"] + np.arange(-WINDOW_DEG, WINDOW_DEG + 1e-9, 0.25):
        x = np.column_stack([base, _stop_column(prep, math.radians(stop_deg))])[ok]
        if not np.any(x[:, -1]):
            continue
        scale = np.maximum(np.abs(x).max(axis=0), 1e-12)
        xs = x / scale
        coef = np.linalg.lstsq(xs, prep.target[ok], rcond=None)[0]
        resid = prep.target[ok] - xs @ coef
        s2 = float(resid @ resid) / max(resid.size - x.shape[1], 1) * resid.size / effective_n(resid)
        var = float(np.linalg.pinv(xs.T @ xs)[-1, -1]) * s2
        if var > 0:
            best = max(best, float(coef[-1]) / math.sqrt(var))
    return best, named


def _job(job: tuple[str, int, bool]) -> tuple[str, float, bool]:
    kind, seed, fast = job
    t, named = oracle_stop_t(kind, seed, fast=fast)
    return kind, t, named


def run(quick: bool = False) -> dict[str, Any]:
    out: dict[str, Any] = {"quick": quick}
    print("protocol sweeps (5 and 10–15 °/s; AFO hand bends):")
    out.update(_score(8 if quick else 40, fast=False))
    print("\nfast sweeps (20 and 30 °/s; knee and ankle):")
    out["fast_sweeps"] = _score(4 if quick else 20, fast=True, kinds=("knee", "ankle"))
    return out


def _score(n: int, fast: bool, kinds: tuple[str, ...] = KINDS) -> dict[str, Any]:
    from analysis.diagnosis.engine import LOCAL_STOP_T

    todo = [(kind, (FAST_SEED if fast else SEED) + s, fast) for kind in kinds for s in range(n)]
    with ProcessPoolExecutor(2) as pool:
        rows = list(pool.map(_job, todo, chunksize=2))
    out: dict[str, Any] = {"level_t": LOCAL_STOP_T}
    print(f"{'kind':<8}{'trials':>7}{'named':>8}{'oracle can':>12}{'named | can':>13}{'named | cannot':>16}{'oracle t':>10}")
    for kind in (*kinds, "all"):
        sel = [(t, named) for k, t, named in rows if kind in ("all", k)]
        t = np.array([s[0] for s in sel])
        named = np.array([s[1] for s in sel])
        can = t > LOCAL_STOP_T
        row = {"trials": int(t.size), "named": float(named.mean()), "oracle_detectable": float(can.mean()),
               "named_when_detectable": float(named[can].mean()) if can.any() else float("nan"),
               "named_when_not": float(named[~can].mean()) if (~can).any() else float("nan"),
               "oracle_t_median": float(np.median(t))}
        out[kind] = row
        print(f"{kind:<8}{row['trials']:>7}{row['named']:>8.2f}{row['oracle_detectable']:>12.2f}"
              f"{row['named_when_detectable']:>13.2f}{row['named_when_not']:>16.2f}{row['oracle_t_median']:>10.1f}")
    return out
