"""The diagnosis on the thirty-fourth generator family (:mod:`benchmarks.family_ah_truth`), to be run once on a frozen
engine.

Written (2026-12-08, forty-first stop) before that stop's second frozen engine met the thirty-third family, before the next
engine change; held out from that change, its figures to be committed as measured (benchmarks/results/diagnosis_family_ah.json),
not tuned on. Same effects, seeds, scoring and keys as :mod:`benchmarks.diagnosis_family_b` (``accuracy``,
``pair_accuracy``, ``false_alarm_rate``, ``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the
PySINDy peer's ``sindy_*`` twins), plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="ah")
