"""A drift must be material: its swing (half its peak-to-peak torque) at least MIN_SWING_TO_NOISE × the residual RMS
on either baseline.

The thirtieth family's slow nuisances (a gain drifting 0.5–1.5 % over the trial, mains hum aliased to a 0.05–0.5 Hz beat
at 0.2–0.4 × the noise) lowered the criterion at a large effective sample size and were named a drift in 12 of its 60
clean trials on df6b331. That family is spent (development data): these are regression cases from it, not a held-out
measurement (docs/validation.md, fortieth stop)."""

from __future__ import annotations

import pytest

from analysis.diagnosis import Diagnosis, diagnose
from benchmarks.diagnosis_family_b import FAMILIES, _trial


def _diagnosed(kind: str, effects: tuple[str, ...], seed: int) -> tuple[Diagnosis, set[str]]:
    d = diagnose(_trial(FAMILIES["ad"][0](kind, effects, seed)))
    return d, ({d.cause} - {"none"}) | {a["cause"] for a in d.also}


@pytest.mark.parametrize(("kind", "seed"), [("knee", 104), ("afo", 102)])
def test_a_slow_nuisance_swinging_less_than_the_noise_is_not_named_a_drift(kind: str, seed: int) -> None:
    """Named a drift on df6b331; the drift alone swings 0.29 and 0.30 (knee), 0.13 and 0.46 (AFO) × the residual RMS
    on the parametric and flexible baselines."""
    d, named = _diagnosed(kind, (), seed)
    assert "sensor_drift" not in named
    # what was left out is said, with its size
    assert any(n.startswith("the torque's zero wanders by about ") and "no drift is named" in n for n in d.notes), d.notes


@pytest.mark.parametrize(("kind", "seed"), [("knee", 204), ("afo", 204)])
def test_a_hidden_drift_swinging_several_times_the_noise_is_still_named(kind: str, seed: int) -> None:
    """Named alone on df6b331; swings of 4.1 (knee) and 3.7 (AFO) × the noise on the parametric baseline."""
    d, named = _diagnosed(kind, ("sensor_drift",), seed)
    assert named == {"sensor_drift"} and not any("zero wanders" in n for n in d.notes)
