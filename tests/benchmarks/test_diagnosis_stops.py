"""The stop oracle of ``benchmarks.diagnosis_stops``: it must see a stop where one clearly is, and its t must
grow with the stop's size (the same trial's seed, larger stop)."""

from __future__ import annotations

import pytest

from benchmarks.diagnosis_stops import oracle_stop_t


@pytest.mark.parametrize("kind", ["afo", "knee"])
def test_the_oracle_sees_a_large_stop_and_less_of_a_small_one(kind: str) -> None:
    small, _ = oracle_stop_t(kind, 4, noise_multiple=(1.0, 1.0))
    large, named = oracle_stop_t(kind, 4, noise_multiple=(12.0, 12.0))
    assert large > 3.5 and named
    assert small < large / 4
