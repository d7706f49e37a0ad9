"""The fourteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_n_truth import (
    NOISE_SD_NM,
    backlash_dashpot,
    blemker_fibre,
    cable_winding,
    check_strap,
    faded_friction,
    generate_n,
    growing_bends,
    mount_response,
    play_operator,
    staircase,
    startle,
)


def test_blemkers_fibre_is_exponential_then_linear_with_a_continuous_slope() -> None:
    s = np.linspace(-1.0, 6.0, 7001)
    f = blemker_fibre(s, 3.0)
    assert np.all(f[s <= 0.0] == 0.0)
    assert blemker_fibre(np.array([2.0]), 3.0)[0] == pytest.approx(np.expm1(2.0))
    slope = np.gradient(f, s)
    assert slope[np.searchsorted(s, 2.999)] == pytest.approx(np.exp(3.0), rel=1e-2)
    assert slope[np.searchsorted(s, 3.001)] == pytest.approx(np.exp(3.0), rel=1e-2)
    np.testing.assert_allclose(slope[s > 3.1], np.exp(3.0), rtol=1e-6)  # linear past the transition
    # the stiffening rate (slope over force) falls past the transition
    rate = slope / np.maximum(f, 1e-12)
    assert rate[np.searchsorted(s, 5.5)] < rate[np.searchsorted(s, 2.5)]


def test_the_staircase_steps_through_the_range_and_holds_between_steps() -> None:
    rate = 100.0
    deg = staircase(np.random.default_rng(4), 10.0, 80.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(80.0)
    speed = np.abs(np.diff(deg)) * rate
    assert speed.max() <= 20.0 * np.pi / 2 + 1e-6  # a cosine profile peaks at π/2 × its mean speed
    held = speed < 1e-9
    assert 0.2 < held.mean() < 0.9  # holds between steps
    steps = np.diff(np.flatnonzero(np.diff(held.astype(int)) == 1))
    assert steps.size >= 10  # many steps, not one sweep


def test_afo_bends_grow_from_8_degrees_to_their_last_peak() -> None:
    deg = growing_bends(np.random.default_rng(1), 200.0)
    assert deg.min() == 0.0 and 18.0 <= deg.max() <= 20.0
    rising = np.flatnonzero((deg[1:-1] > deg[:-2]) & (deg[1:-1] >= deg[2:]))
    peaks = deg[1:-1][rising]
    assert peaks[0] == pytest.approx(8.0, abs=0.05) and np.all(np.diff(peaks) > 0.0)


def test_friction_fades_with_travel_and_saturates_with_speed() -> None:
    travel = np.linspace(0.0, 1000.0, 11)
    up = faded_friction(np.full(11, 5.0), travel, 0.5, 200.0, 0.5)
    assert up[0] == pytest.approx(1.0) and up[-1] == pytest.approx(0.5 + 0.5 * np.exp(-5.0))
    assert np.all(np.diff(up) < 0.0)
    np.testing.assert_allclose(faded_friction(np.full(11, -5.0), travel, 0.5, 200.0, 0.5), -up)
    assert faded_friction(np.array([0.25]), np.array([0.0]), 0.5, 200.0, 0.5)[0] == pytest.approx(0.5)


def test_the_dashpot_is_slack_for_its_backlash_after_each_reversal() -> None:
    deg = np.concatenate([np.linspace(0.0, 10.0, 101), np.linspace(10.0, 0.0, 101)[1:]])
    vel = np.gradient(deg)
    felt = backlash_dashpot(deg, vel, 2.0)
    assert np.all(felt[deg < 2.0 - 1e-9][:20] == 0.0)  # the first 2° of the first stroke
    down = np.arange(deg.size) > 100
    slack_down = down & (deg > 8.0 + 1e-9)
    assert np.all(felt[slack_down] == 0.0)
    assert np.all(felt[down & (deg < 7.9)] == vel[down & (deg < 7.9)])


def test_a_check_strap_is_slack_before_its_stop_and_pulls_back_past_it() -> None:
    deg = np.linspace(0.0, 30.0, 301)
    high = check_strap(deg, 20.0, True, 20.0)
    assert np.all(high[deg <= 20.0] == 0.0) and np.all(high[deg > 20.0] > 0.0)
    slope = np.gradient(high, deg)
    assert slope[deg > 20.5].min() > 0.5 * slope[deg > 20.5].max()  # a kink, then close to linear
    low = check_strap(-deg, -20.0, False, 20.0)
    np.testing.assert_allclose(low, -high)


def test_the_mount_rings_and_lags_a_slow_ramp_by_its_group_delay() -> None:
    rate = 500.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    y, delay = mount_response(t.copy(), rate, 4.0, 0.4)
    assert delay == pytest.approx(2 * 0.4 / (2 * np.pi * 4.0), rel=0.01)
    assert np.mean((t - y)[t > 5.0]) == pytest.approx(delay, rel=1e-3)
    step, _ = mount_response(np.concatenate([np.zeros(100), np.ones(2000)]), rate, 4.0, 0.4)
    assert step.max() > 1.2  # underdamped: it overshoots
    const, _ = mount_response(np.full(100, 3.0), rate, 4.0, 0.4)
    np.testing.assert_allclose(const, 3.0)


def test_the_startle_rises_fast_and_relaxes_exponentially_to_zero() -> None:
    t = np.arange(0.0, 5.0, 1e-3)
    x = startle(t, 1.0, 0.02, 0.5)
    assert x.max() == pytest.approx(1.0) and x[:900].max() < 0.01
    peak = int(np.argmax(x))
    assert 1.0 <= t[peak] < 1.15
    assert x[np.searchsorted(t, 2.5)] / x[np.searchsorted(t, 2.0)] == pytest.approx(np.exp(-1.0), rel=1e-3)


def test_the_cable_winds_with_travel_and_relaxes_at_rest() -> None:
    t = np.arange(0.0, 200.0, 0.1)
    vel = np.where(t < 50.0, 10.0, 0.0)
    z = cable_winding(t, vel, 20.0)
    assert z[499] == pytest.approx(10.0 * 20.0 * (1 - np.exp(-50.0 / 20.0)), rel=0.01)
    assert z[-1] < 0.01 * z[499]
    np.testing.assert_allclose(cable_winding(t, -vel, 20.0), z)  # travel, either way


def test_the_play_operator_holds_until_the_input_reverses_by_its_width() -> None:
    x = np.concatenate([np.linspace(0.0, 10.0, 101), np.linspace(10.0, 0.0, 101)])
    y = play_operator(x, 2.0)
    assert y[100] == pytest.approx(9.0)
    down = y[101:]
    assert np.all(down[x[101:] > 8.0] == pytest.approx(9.0))
    np.testing.assert_allclose(down[x[101:] < 7.9], x[101:][x[101:] < 7.9] + 1.0)


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_n("ankle", ("time_delay",), s) for s in range(20)]
    assert all(0.01 <= g.effects["time_delay"] <= 0.6 for g in delays)
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_n("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
        g = generate_n("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_n("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    comp = [generate_n("knee", ("series_compliance",), s) for s in range(4)]
    assert all(0.01 <= g.effects["series_compliance"] <= 0.3 for g in comp)
