"""The diagnosis on the twenty-second generator family (:mod:`benchmarks.family_v_truth`), to be run once on a frozen
engine.

Written (2026-11-29, thirtieth stop) while the twenty-first family was the held-out one for that stop's engine change,
and run once on the frozen engine of the change after it (c3d0003, a burst the scan finds not named where it recurs at
its angle); its figures are committed as measured, not tuned on, and it is development data since. Same effects,
seeds, scoring and keys as :mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``,
``false_alarm_rate``, ``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's
``sindy_*`` twins), plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="v")
