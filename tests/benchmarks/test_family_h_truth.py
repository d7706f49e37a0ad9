"""The eighth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_h_truth import (
    NOISE_SD_NM,
    _clonus,
    _hand_bends,
    _passive,
    _s_curve_strokes,
    generate_h,
    zero_order_hold,
)


def test_a_zero_order_hold_lags_a_ramp_by_half_its_period() -> None:
    """The delay's truth counts the hold's low-frequency group delay: a ramp read through a 20 Hz hold lags by
    25 ms on average (the truth's 0.5 / update rate)."""
    t = np.arange(0.0, 20.0, 0.001)
    held = zero_order_hold(t.copy(), t, 20.0, 0.013)
    lag = t - held
    assert np.all(lag[t > 0.013] >= -1e-12) and np.all(lag[t > 0.013] < 0.05 + 1e-9)
    assert float(np.mean(lag[t > 1.0])) == pytest.approx(0.025, abs=5e-4)


def test_the_s_curve_keeps_its_acceleration_limit_a_continuous_velocity_and_its_ends() -> None:
    """The profile's acceleration never passes the drawn limit (≤ 250 °/s²), it ramps (a jerk limit: no step in the
    acceleration larger than the limit's share of a sample), and every stroke ends on its target."""
    rate = 1000.0
    for seed in range(6):
        deg, acc = _s_curve_strokes(np.random.default_rng(seed), 5.0, 90.0, rate)
        vel = np.gradient(deg, 1.0 / rate)
        assert deg.min() == pytest.approx(5.0, abs=1e-6) and deg.max() == pytest.approx(90.0, abs=1e-6)
        assert np.max(np.abs(acc)) <= 250.0 * 1.01
        assert np.max(np.abs(np.diff(vel))) <= 250.0 * 1.01 / rate  # deg/s per sample: no jump in speed
        assert np.max(np.abs(np.diff(acc))) <= 2000.0 * 1.5 / rate + 1e-9  # deg/s² per sample: the jerk limit
    bend, bend_acc = _hand_bends(np.random.default_rng(5), rate)
    assert 10.0 <= bend.max() <= 20.0 and bend.min() >= 0.0 and np.all(np.isfinite(bend_acc))


def test_clonus_beats_at_its_drawn_rate_and_only_pulls() -> None:
    """Clonus is a rectified oscillation: the torque never changes sign and its peaks come at the beat rate."""
    t = np.arange(0.0, 30.0, 0.002)
    unit, info = _clonus(np.random.default_rng(3), t)
    assert unit.min() >= 0.0 and unit.max() == pytest.approx(1.0)
    on = t[unit > 0.0]
    assert on[0] == pytest.approx(info["clonus_onset_s"], abs=0.01)
    assert on[-1] - on[0] <= info["beats"] / info["clonus_hz"] + 0.01
    peaks = np.flatnonzero((unit[1:-1] > unit[:-2]) & (unit[1:-1] >= unit[2:]) & (unit[1:-1] > 0.05)) + 1
    assert np.median(np.diff(t[peaks])) == pytest.approx(1.0 / info["clonus_hz"], abs=0.005)


def test_the_passive_curve_turns_linear_past_its_toe_and_the_afo_spring_engages_smoothly() -> None:
    """Collagen's toe-then-linear shape: far past the toe the slope is constant (not exponential); the slope is
    continuous everywhere. The AFO's spring engages through a softplus."""
    coef = {"t_low": 10.0, "t_high": 2.0, "w_low": 6.0, "w_high": 8.0, "toe_low": 25.0, "toe_high": 70.0,
            "linear": 0.0, "shift": 0.1}
    deg = np.linspace(-60.0, 90.0, 15001)
    tau = _passive("knee", deg, {"hip_flexion_deg": 55.0}, coef, 5.0, 90.0)
    slope = np.diff(tau) / np.diff(deg)
    assert np.max(np.abs(np.diff(slope))) < 1e-3
    assert slope[100] == pytest.approx(slope[1000], rel=1e-3)  # far below the toe: linear
    afo = {"k": 0.5, "engage": 2.0, "soft": 1.0, "arm": 0.0}
    bend = np.linspace(-5.0, 20.0, 2501)
    s = np.diff(_passive("afo", bend, {}, afo, 0.0, 20.0)) / np.diff(bend)
    assert s[0] < 1e-3 and s[-1] == pytest.approx(0.5, rel=1e-3)


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_h("knee", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.4 and min(delays) < 0.15
    for s in range(5):
        g = generate_h("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"] * 1.001
        assert 0.0 < g.details["unknown_mass_kg"] < 2.0  # a cast or a weight, not a second limb
    stops = [generate_h("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    rates = {generate_h("afo", (), s).details["rate_hz"] for s in range(40)}
    assert max(rates) == 2000.0 and min(rates) == 100.0
