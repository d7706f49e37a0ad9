"""The second generator family: each cause is hidden as documented, at 3–5 × the noise, with a lab's nuisances."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_b_truth import EFFECTS, MAGNITUDE_KEY, NOISE_SD_NM, generate_b


@pytest.mark.parametrize("kind", list(EFFECTS))
def test_each_cause_adds_what_its_truth_says_over_the_same_clean_trial(kind: str) -> None:
    for cause in EFFECTS[kind]:
        g = generate_b(kind, (cause,), 5)
        assert set(g.effects) == {cause}
        truth = g.effects[cause]
        assert (truth is None) == (MAGNITUDE_KEY[cause] is None)
        if truth is not None:
            assert truth > 0
        # a lab's recording: some rows without a time, some dropped, the rest increasing
        t = g.time_s[np.isfinite(g.time_s)]
        assert np.all(np.diff(t) > 0) and (~np.isfinite(g.time_s)).sum() < 0.01 * g.time_s.size


def test_effects_are_sized_against_the_noise_and_shapes_lie_outside_one_law() -> None:
    stops = [generate_b("knee", ("hard_stop",), s).details for s in range(12)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}  # either end of the range
    assert {d["stop_law"] for d in stops} == {"hunt-crossley", "quadratic"}
    delays = [generate_b("ankle", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.35 and min(delays) < 0.15  # to half a second, past the first family's 0.3 s
    for s in range(5):
        g = generate_b("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.2 * NOISE_SD_NM["knee"]


def test_a_seed_makes_the_same_trial() -> None:
    a, b = generate_b("afo", ("coulomb_friction", "hard_stop"), 9), generate_b("afo", ("coulomb_friction", "hard_stop"), 9)
    assert np.array_equal(a.torque_nm, b.torque_nm, equal_nan=True) and a.effects == b.effects
