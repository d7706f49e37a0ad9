"""The fifth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_e_truth import (
    NOISE_SD_NM,
    _maxwell_damping,
    _maxwell_slip,
    generate_e,
)


def test_maxwell_slip_friction_slides_at_its_level_and_turns_gradually() -> None:
    """Past the largest element's reach the friction is the level (no ripple drawn on this seed's branch is
    checked by the ratio to the level's bounds); just after a reversal it has not yet turned fully."""
    rng = np.random.default_rng(3)
    deg = np.concatenate([np.linspace(0.0, 20.0, 2001), np.linspace(20.0, 0.0, 2001)[1:]])
    f = _maxwell_slip(rng, deg, 1.0)
    assert 0.79 <= f[1500] <= 1.21 and -1.21 <= f[-200] <= -0.79  # sliding, at the level within its ripple
    turn = f[2001:2011]  # the first 0.1° back: the corner is gradual, not a jump
    assert turn[0] > 0.0 > f[-200] and np.all(np.diff(turn) < 0)


def test_maxwell_damping_is_damping_k_tau_at_low_speed() -> None:
    t = np.linspace(0.0, 20.0, 20001)
    vel = np.full(t.size, 0.1)
    f = _maxwell_damping(t, vel, 50.0, 0.1)
    assert f[-1] == pytest.approx(50.0 * 0.1 * 0.1, rel=1e-6)
    assert f[50] < 0.5 * f[-1]  # 0.05 s in it is still relaxing toward k·τ·v


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_e("knee", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.35 and min(delays) < 0.1
    for s in range(5):
        g = generate_e("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"] * 1.001
    stops = [generate_e("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    rates = {generate_e("afo", (), s).details["rate_hz"] for s in range(30)}
    assert max(rates) == 2000.0 and min(rates) == 100.0
