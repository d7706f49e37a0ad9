"""The diagnosis on the twenty-third generator family (:mod:`benchmarks.family_w_truth`), to be run once on a frozen
engine.

Written (2026-11-29, thirty-first stop) before that stop's engine change and held out from it, run once on the frozen
engine of that change (4f53208, a joint's stop also named as a kink a free curve in angle cannot follow); its figures
are committed as measured (benchmarks/results/diagnosis_family_w.json), not tuned on, and it is development data
since. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="w")
