"""The eighth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_h_truth import (
    NOISE_SD_NM,
    _hand_bends,
    _passive,
    _trapezoid_strokes,
    butterworth_low_pass,
    generate_h,
)


def test_the_butterworth_filters_group_delay_is_what_a_ramp_shows() -> None:
    """The delay's truth counts the filter's low-frequency group delay: a slow ramp through the filter lags by it."""
    from scipy.signal import lfilter

    rate = 1000.0
    b, a, delay = butterworth_low_pass(4.0, rate)
    t = np.arange(20000) / rate
    out = lfilter(b, a, t)
    assert out[-1] == pytest.approx(t[-1] - delay, abs=2e-4)
    assert delay == pytest.approx(np.sqrt(2.0) / (2.0 * np.pi * 4.0), rel=0.02)  # √2/ω_c for a 2nd-order Butterworth


def test_the_trapezoidal_profile_holds_its_acceleration_limit_and_its_ends() -> None:
    """The commanded acceleration is the angle's second derivative (a velocity without jumps), never beyond the
    drawn limit, and every stroke ends on its target."""
    rng = np.random.default_rng(4)
    rate = 1000.0
    deg, acc = _trapezoid_strokes(rng, 5.0, 90.0, rate)
    vel = np.gradient(deg, 1.0 / rate)
    assert deg.min() == pytest.approx(5.0, abs=1e-6) and deg.max() == pytest.approx(90.0, abs=0.05)
    assert np.max(np.abs(np.diff(vel))) < 0.3  # deg/s per sample: the speed changes only at the limited rate
    assert np.max(np.abs(acc)) <= 250.0
    numeric = np.gradient(vel, 1.0 / rate)
    corner = np.abs(np.diff(acc, prepend=acc[0])) > 0
    near = np.convolve(corner, np.ones(7), mode="same") > 0  # three samples either side of a corner
    np.testing.assert_allclose(numeric[~near][5:-5], acc[~near][5:-5], atol=2.0)
    bend, bend_acc = _hand_bends(np.random.default_rng(5), rate)
    assert 10.0 <= bend.max() <= 20.0 and bend.min() >= 0.0 and np.all(np.isfinite(bend_acc))


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
        assert 5.0 <= abs(g.details["com_offset_deg"]) <= 30.0
    stops = [generate_h("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    rates = {generate_h("afo", (), s).details["rate_hz"] for s in range(40)}
    assert max(rates) == 2000.0 and min(rates) == 100.0
