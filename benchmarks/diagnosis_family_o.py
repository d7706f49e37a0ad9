"""The diagnosis on the fifteenth generator family (:mod:`benchmarks.family_o_truth`), run once on the engine as it stood.

The fourteenth family was run once (engine 2698951) and then used in development with the second to thirteenth. The
fifteenth was written in the round after, before that round's engine changes, to be run once on the frozen engine
after them; its committed figures are measured, not tuned on. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="o")
