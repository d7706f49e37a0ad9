"""The diagnosis on the twenty-first generator family (:mod:`benchmarks.family_u_truth`), to be run once on a frozen
engine.

The twentieth family was run once (engine 9555647) and is development data since. The twenty-first was written
(2026-11-29, twenty-ninth stop) before the next change to the diagnosis engine and run once on that change's frozen
engine (f319385, a lone burst also named by a scan statistic); its figures are committed as measured, not tuned on,
and it is development data since. Same effects, seeds, scoring and keys as
:mod:`benchmarks.diagnosis_family_b` (``accuracy``, ``pair_accuracy``, ``false_alarm_rate``,
``magnitude_within_15pct``, ``interval_coverage``, ``seconds_per_trial``, the PySINDy peer's ``sindy_*`` twins), plus
``accuracy_or_untestable_said``.
"""

from __future__ import annotations

from typing import Any

from .diagnosis_family_b import run as run_family


def run(quick: bool = False) -> dict[str, Any]:
    return run_family(quick, family="u")
