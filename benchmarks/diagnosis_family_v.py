"""The diagnosis on the twenty-second generator family (:mod:`benchmarks.family_v_truth`), to be run once on a frozen
engine.

Written (2026-11-29, thirtieth stop) while the twenty-first family was the held-out one for that stop's engine change,
to be the held-out family of the change after it: run once on that change's frozen engine, its figures then committed
as measured, not tuned on. Same effects, seeds, scoring and keys as :mod:`benchmarks.diagnosis_family_b`
(``accuracy``, ``pair_accuracy``, ``false_alarm_rate``, ``magnitude_within_15pct``, ``interval_coverage``,
``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="v")
