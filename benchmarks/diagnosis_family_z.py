"""The diagnosis on the twenty-sixth generator family (:mod:`benchmarks.family_z_truth`), run once on the frozen engine
e14732c (thirty-fifth stop).

Written (2026-12-07, thirty-fourth stop) after the twenty-fifth family's run and before any further engine change,
held out from the next change; its figures are committed as measured (benchmarks/results/diagnosis_family_z.json),
not tuned on, and the family is development data from then on. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``, ``magnitude_within_15pct``,
``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="z")
