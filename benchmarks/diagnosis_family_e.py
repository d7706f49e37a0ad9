"""The diagnosis on the fifth generator family (:mod:`benchmarks.family_e_truth`), run once the engine froze.

The fourth family was run once and then used in development (its findings led to this round's changes: Dahl's
friction law of the path, a drift judged on the held-out blocks it interpolates; engine of 193e037). The fifth
was written after those changes were committed and is run here once; its figures are measured, not tuned on.
Same effects, seeds, scoring and keys as :mod:`benchmarks.diagnosis_family_b` (``accuracy``,
``pair_accuracy``, ``false_alarm_rate``, ``magnitude_within_15pct``, ``interval_coverage``,
``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="e")
