"""The diagnosis on the eighth generator family (:mod:`benchmarks.family_h_truth`), run once the engine froze.

The seventh family was run once and then used in development with the second to sixth (this round's change: a
shear-thinning damping law, kept only with strong evidence over a friction beside a plain damping). The eighth was
written during that round, before the engine froze, and was not run on the engine until it froze; its figures are
measured, not tuned on. Same effects, seeds, scoring and keys as :mod:`benchmarks.diagnosis_family_b`
(``accuracy``, ``pair_accuracy``, ``false_alarm_rate``, ``magnitude_within_15pct``, ``interval_coverage``,
``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus ``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="h")
