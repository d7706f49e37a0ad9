"""A study of realistic subjects through ``analyze cohort --diagnose-model``: each subject's model extended by
what its own diagnosis names, bootstrap intervals about the extended fit.

The subjects are :mod:`benchmarks.cohort`'s (OpenSim-made passive moments, one realistic variant each in turn:
matched, compliant knee tendons with tone, end-range structures, unmodelled muscles, a tape error, set angles
off; recorded through the drivers into a store). The same study is fitted twice on a 2-process LocalCluster,
with ``bootstrap`` refits per subject:

* the muscle model alone (``analyze cohort``), the reference of the same run;
* each subject diagnosed first (every extension of :data:`analysis.pmp.model_diagnosis.EXTENSIONS` fitted inside
  the estimator, judged by held-out blocks), then the subject and its resamples fitted with the named extension.

The diagnosis's choice is not resampled; models it left plausible beside the named one (better on every held-out
fold by less than the naming margin) are fitted too and each interval widened to hold their intervals (the hull, as
the single-subject report has it); measurement errors (tape, set angles) are carried by the fit's nuisances and
priors in both runs.

Keys: ``subjects``, ``bootstrap_per_subject``, ``named`` (per subject), ``named_right_rate`` (the subject's
variant's expected extensions, as ``pmp_realistic`` scores them), ``determined_per_subject_median``
(``plain`` and ``diagnosed``), ``coverage_95`` (``plain``, ``diagnosed``), ``determined_with_truth``,
``max_error_determined_pct``, ``by_variant`` (per variant, both runs), ``wall_s`` (both runs), ``failed_solves``.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from analysis.pmp.cohort import DIAGNOSED
from instrument.offline.cohort import CohortRun, MemoryResults, run_cohort, study_from_store
from instrument.sim.study import record_study

from .cohort import by_variant, opensim_draws
from .pmp_realistic import EXPECTED

INTERVALS = 12


def _determined(run: CohortRun) -> dict[str, int]:
    return {s["subject_code"]: sum(bool(r["determined"]) for r in s["parameters"].values()) for s in run.summaries}


def run(quick: bool = False) -> dict[str, Any]:
    subjects = 6 if quick else 12
    bootstrap = 4 if quick else 10
    root = Path(tempfile.mkdtemp(prefix="cohort-diagnosed-"))
    t0 = time.perf_counter()
    draws = opensim_draws(subjects)
    variant_of = {d.subject.code: d.variant for d in draws}
    store = record_study(root / "study", subjects, speed_deg_s=5.0, progress=lambda m: None, draws=draws)
    study = study_from_store(store)
    store.close()
    print(f"{subjects} OpenSim-made subjects recorded in {time.perf_counter() - t0:.0f} s", flush=True)
    runs: dict[str, CohortRun] = {}
    for label, extension in (("plain", None), ("diagnosed", DIAGNOSED)):
        runs[label] = run_cohort(study, MemoryResults(), bootstrap=bootstrap, intervals=INTERVALS, workers=2,
                                 extension=extension)
        print(f"{label}: {runs[label].solves} solves in {runs[label].wall_s:.0f} s", flush=True)
    named = {s["subject_code"]: s.get("extension") or "none" for s in runs["diagnosed"].summaries}
    right = {}
    for code, name in named.items():
        expected = set(EXPECTED[variant_of[code]])
        got = set() if name == "none" else set(name.split("+"))
        right[code] = expected <= got if expected else not got
    det = {label: _determined(r) for label, r in runs.items()}
    result: dict[str, Any] = {
        "quick": quick, "subjects": subjects, "bootstrap_per_subject": bootstrap, "collocation_intervals": INTERVALS,
        "truth_source": "OpenSim (Rajagopal 2016, DeGrooteFregly2016Muscle) in a subprocess",
        "variant_per_subject": variant_of, "named": named, "named_right": right,
        "named_right_rate": float(np.mean(list(right.values()))),
        "determined_per_subject": det,
        "determined_per_subject_median": {label: float(np.median(list(d.values()))) for label, d in det.items()},
        "coverage_95": {label: r.coverage["coverage_95"] for label, r in runs.items()},
        "determined_with_truth": {label: r.coverage["determined_with_truth"] for label, r in runs.items()},
        "max_error_determined_pct": {label: r.coverage["max_error_determined_pct"] for label, r in runs.items()},
        "by_variant": {label: by_variant(r.summaries, variant_of) for label, r in runs.items()},
        "misfit_ratio_per_subject": {label: {s["subject_code"]: s["misfit_ratio"] for s in r.summaries}
                                     for label, r in runs.items()},
        "wall_s": {label: r.wall_s for label, r in runs.items()},
        "failed_solves": {label: r.failed for label, r in runs.items()},
        "cpu_count": os.cpu_count(),
    }
    print(f"{'subject':<8}{'variant':<20}{'named':<42}{'plain':>6}{'diag.':>6}")
    for code in named:
        print(f"{code:<8}{variant_of[code]:<20}{named[code]:<42}{det['plain'].get(code, 0):>6}"
              f"{det['diagnosed'].get(code, 0):>6}")
    print(f"{'variant':<20}{'run':<10}{'determined':>11}{'covered':>8}{'worst %':>9}{'misfit':>8}")
    for label in runs:
        for v, row in result["by_variant"][label].items():
            worst = row["max_error_determined_pct"]
            print(f"{v:<20}{label:<10}{row['determined_with_truth']:>11}{row['covered']:>8}"
                  f"{'—' if worst is None else f'{worst:.2f}':>9}{row['median_misfit_ratio'] or float('nan'):>8.2f}")
    for k in ("named_right_rate", "determined_per_subject_median", "coverage_95", "max_error_determined_pct"):
        print(f"{k:<32} {result[k]}")
    return result
