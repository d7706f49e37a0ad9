"""The diagnosis on the sixteenth generator family (:mod:`benchmarks.family_p_truth`), to be run once on a frozen engine.

The fifteenth family was run once (engine 24ca33a) and is development data since. The sixteenth was written in the
round after (2026-11-29), before that round's engine changes, to be run once on the frozen engine after them; its
figures are then committed as measured, not tuned on. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="p")
