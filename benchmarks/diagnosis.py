"""Diagnosis accuracy: confusion matrix over hidden causes, and accuracy against effect size.

For each trial kind and each hidden cause (and none), trials are drawn from seeds with the
magnitude scaled to 0.25, 0.5 and 1 × the low end of the cause's realistic range (and draws from
the whole range); the diagnosis names a cause for each. Reported: the confusion matrix
(hidden → named) per kind, the accuracy and median magnitude error per scale, the smallest
scale found in ≥ 90 % of seeds, the rate of ``none`` without an effect, and seconds per trial.
"""

from __future__ import annotations

import time
from collections import Counter, defaultdict
from typing import Any

import numpy as np

from analysis.diagnosis import diagnose, magnitude
from analysis.diagnosis.synthetic import RANGES, causes_for, make_trial, truth_magnitude

SCALES = (0.25, 0.5, 1.0)


def run(quick: bool = False) -> dict[str, Any]:
    seeds = 4 if quick else 12
    kinds = ("afo", "ankle", "replica") if quick else ("afo", "ankle", "knee", "replica")
    confusion: dict[str, dict[str, dict[str, int]]] = {}
    by_scale: dict[str, dict[str, dict[str, Any]]] = defaultdict(dict)
    none_rate: dict[str, float] = {}
    t0 = time.perf_counter()
    trials = 0
    for kind in kinds:
        table: dict[str, Counter] = {}
        for cause in ["none"] + causes_for(kind):
            named: Counter = Counter()
            scales = (None,) if cause == "none" else (*SCALES, None)
            for scale in scales:
                right, errs = 0, []
                for s in range(seeds):
                    mag = None if scale is None else scale * RANGES[cause][kind][0]
                    trial, hidden = make_trial(kind, cause, 10_000 + 97 * s + int(100 * (scale or 0)), magnitude=mag)
                    d = diagnose(trial)
                    trials += 1
                    named[d.cause] += 1
                    if d.cause == cause:
                        right += 1
                        if cause != "none":
                            errs.append(abs(magnitude(d) / truth_magnitude(hidden) - 1))
                if cause != "none":
                    key = "range" if scale is None else f"{scale:g}x_low"
                    by_scale[f"{kind}/{cause}"][key] = {"accuracy": right / seeds,
                                                         "median_magnitude_error": float(np.median(errs)) if errs else None}
            if cause == "none":
                none_rate[kind] = named["none"] / seeds
            table[cause] = named
        confusion[kind] = {c: dict(v) for c, v in table.items()}
    elapsed = time.perf_counter() - t0
    smallest = {}
    for key, rows in by_scale.items():
        ok = [s for s in SCALES if rows[f"{s:g}x_low"]["accuracy"] >= 0.9]
        smallest[key] = min(ok) if ok else None
    for kind, table in confusion.items():
        causes = list(table)
        print(f"\n{kind}: hidden (rows) → named (columns), {seeds} seeds per magnitude")
        print(f"{'':<20}" + "".join(f"{c[:10]:>11}" for c in causes))
        for c in causes:
            print(f"{c:<20}" + "".join(f"{table[c].get(n, 0):>11}" for n in causes))
    print(f"\n{'cause':<30}" + "".join(f"{k:>12}" for k in ("0.25x_low", "0.5x_low", "1x_low", "range")) + "  smallest reliable")
    for key, rows in by_scale.items():
        print(f"{key:<30}" + "".join(f"{rows[k]['accuracy']:>12.2f}" for k in ("0.25x_low", "0.5x_low", "1x_low", "range"))
              + f"  {smallest[key]}")
    out = {"quick": quick, "seeds_per_cell": seeds, "confusion": confusion, "accuracy_by_scale": dict(by_scale),
           "smallest_reliable_scale_of_range_low": smallest, "none_rate": none_rate,
           "accuracy_at_range": float(np.mean([r["range"]["accuracy"] for r in by_scale.values()])),
           "seconds_per_trial": elapsed / trials, "trials": trials}
    print(f"\nnone rate {none_rate}; mean accuracy over the realistic ranges {out['accuracy_at_range']:.3f}; "
          f"{out['seconds_per_trial']:.2f} s per trial")
    return out
