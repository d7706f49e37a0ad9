"""The diagnosis on the ninth generator family (:mod:`benchmarks.family_i_truth`), run once the engine froze.

The eighth family was run once and then used in development with the second to seventh (this round's change after
it: intervals from the larger of the model-based and a block-sandwich covariance, and the saturating damping's
floor at the trial's peak speed). The ninth was written during that round, before the engine froze, and was not
run on the engine until it froze; its figures are measured, not tuned on. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins),
plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="i")
