"""The diagnosis on the twentieth generator family (:mod:`benchmarks.family_t_truth`), to be run once on a frozen engine.

The nineteenth family was run once (engine 62d202b) and is development data since. The twentieth was written
(2026-11-29, twenty-eighth stop) before the next change to the diagnosis engine, to be run once on that change's frozen
engine; its figures are then committed as measured, not tuned on. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="t")
