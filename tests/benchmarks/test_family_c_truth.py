"""The third generator family: each cause hidden as documented, sized against the noise, with a rig's nuisances."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_c_truth import EFFECTS, MAGNITUDE_KEY, NOISE_SD_NM, generate_c


@pytest.mark.parametrize("kind", list(EFFECTS))
def test_each_cause_is_hidden_with_its_truth_in_a_recording_with_a_labs_damage(kind: str) -> None:
    clean = generate_c(kind, (), 5)
    for cause in EFFECTS[kind]:
        g = generate_c(kind, (cause,), 5)
        assert set(g.effects) == {cause}
        truth = g.effects[cause]
        assert (truth is None) == (MAGNITUDE_KEY[cause] is None)
        assert truth is None or truth > 0
        t = g.time_s[np.isfinite(g.time_s)]
        assert np.all(np.diff(t) > 0) and 0 < (~np.isfinite(g.time_s)).sum() < 0.01 * g.time_s.size
    assert np.isfinite(clean.torque_nm).mean() > 0.99


def test_the_shapes_lie_outside_the_earlier_families_laws() -> None:
    stops = [generate_c("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    assert {d["stop_law"] for d in stops} == {"exponential", "preloaded linear"}
    delays = [generate_c("knee", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.45 and min(delays) < 0.15
    for s in range(5):
        g = generate_c("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
    rates = {generate_c("afo", (), s).details["rate_hz"] for s in range(20)}
    assert max(rates) == 2000.0 and min(rates) == 120.0


def test_a_seed_makes_the_same_trial() -> None:
    a, b = generate_c("knee", ("inertia", "time_delay"), 3), generate_c("knee", ("inertia", "time_delay"), 3)
    assert np.array_equal(a.torque_nm, b.torque_nm, equal_nan=True) and a.effects == b.effects
