"""The twenty-fifth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_y_truth import (
    NOISE_SD_NM,
    alpha_twitch,
    alternating_speed_strokes,
    cubic_stop,
    fung_end,
    generate_y,
    hung_weight,
    load_dependent_friction,
    orifice_damper,
    regrip_bends,
    self_heating,
    servo,
    slack_strap_give,
    torsion_bar,
    two_pole_delay,
)


def test_fungs_end_is_flat_before_its_onset_and_grows_as_the_exponential_of_a_square_past_it() -> None:
    y = fung_end(np.array([-30.0, 20.0, 40.0]), 1.0, 20.0)
    assert 0.0 < y[0] < 1e-20
    assert y[1] == pytest.approx(np.expm1(1.0), rel=1e-6) and y[2] == pytest.approx(np.expm1(4.0), rel=1e-6)


def test_the_torsion_bar_stiffens_cubically_from_a_linear_start() -> None:
    np.testing.assert_allclose(torsion_bar(np.array([-3.0, 1e-4, 15.0]), 15.0), [0.0, 1e-4, 20.0], rtol=1e-6)


def test_the_servo_keeps_a_constant_and_lags_a_ramp_by_its_two_poles() -> None:
    rate = 1000.0
    np.testing.assert_allclose(servo(np.full(100, 4.0), rate, 10.0), 4.0)
    ramp = np.arange(5000.0) / rate
    a = np.exp(-2.0 * np.pi * 10.0 / rate)
    lag_s = 2.0 * a / (1.0 - a) / rate
    assert ramp[-1] - servo(ramp, rate, 10.0)[-1] == pytest.approx(lag_s, rel=1e-6)


def test_strokes_alternate_a_slow_and_a_fast_speed_between_the_ends() -> None:
    rate = 200.0
    deg = alternating_speed_strokes(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0, abs=0.01) and deg.max() == pytest.approx(85.0, abs=0.01)
    speed = np.diff(deg) * rate
    up, down = np.percentile(speed[speed > 0.5], 90), np.percentile(-speed[speed < -0.5], 90)
    assert 2.0 <= up <= 4.05 and 5.0 <= down <= 9.05  # slow up, fast down
    assert np.max(np.abs(np.diff(deg, 2))) * rate * rate < 200.0  # smooth through the servo (°/s²)


def test_orthosis_bends_return_to_zero_and_every_other_one_holds_on_the_way_up() -> None:
    rate = 100.0
    deg = regrip_bends(np.random.default_rng(5), rate)
    assert abs(deg[0]) < 1e-9 and abs(deg[-1]) < 1e-6 and 9.0 <= deg.max() <= 20.0 + 1e-9
    v = np.diff(deg) * rate
    held_high = (np.abs(v) < 0.05) & (deg[1:] > 3.0)
    assert held_high.sum() >= 0.2 * rate  # at least one re-grip hold of 0.2 s, off the rest at 0°


def test_friction_rises_with_the_load_and_resists_the_motion() -> None:
    f = load_dependent_friction(np.array([5.0, 5.0, -5.0, 0.0]), np.array([0.0, 10.0, -10.0, 10.0]), 0.5, 0.5)
    np.testing.assert_allclose(f, [1.0, 1.5, -1.5, 0.0], atol=1e-9)


def test_the_orifice_adds_its_quadratic_share_at_the_peak_speed() -> None:
    vel = np.linspace(-2.0, 2.0, 4001)
    d = orifice_damper(vel, 0.4)
    peak = float(np.percentile(np.abs(vel), 95.0))
    at_peak = float(np.interp(peak, vel, d))
    assert (at_peak - peak) / at_peak == pytest.approx(0.4, rel=1e-3)
    np.testing.assert_allclose(d, -d[::-1])  # odd in the velocity


def test_the_cubic_stop_acts_past_its_angle_toward_the_range_inside() -> None:
    np.testing.assert_allclose(cubic_stop(np.array([19.0, 22.0]), 20.0, True), [0.0, 8.0])
    np.testing.assert_allclose(cubic_stop(np.array([-23.0, -10.0]), -20.0, False), [-27.0, 0.0])


def test_the_two_pole_delay_lags_a_ramp_by_its_group_delay() -> None:
    rate = 100.0
    x = np.arange(3000.0)
    y, delay = two_pole_delay(x, 0.2, 0.02, rate)
    a = np.exp(-1.0 / (0.02 * rate))
    assert delay == pytest.approx(0.2 + 2.0 * a / (1.0 - a) / rate)
    assert x[-1] - y[-1] == pytest.approx(delay * rate, rel=1e-6)


def test_the_alpha_twitch_peaks_at_one_a_time_constant_after_its_start() -> None:
    t = np.arange(0.0, 3.0, 0.001)
    p = alpha_twitch(t, 1.0, 0.2)
    assert p[t < 1.0].max() == 0.0 and p.max() == pytest.approx(1.0, abs=1e-6)
    assert float(t[np.argmax(p)]) == pytest.approx(1.2, abs=0.002)


def test_self_heating_follows_the_squared_torque_through_its_lag() -> None:
    t = np.arange(0.0, 200.0, 0.01)
    torque = np.where(t < 50.0, 0.0, 2.0)
    h = self_heating(torque, t, 20.0)
    assert h[0] == 0.0 and float(np.max(np.abs(h))) == pytest.approx(1.0)
    i = np.searchsorted(t, 70.0)
    assert h[i] == pytest.approx((1.0 - np.exp(-1.0)) * h[-1] / (1.0 - np.exp(-150.0 / 20.0)), rel=0.01)


def test_the_strap_gives_less_per_newton_metre_as_its_slack_is_taken_up() -> None:
    g = slack_strap_give(np.array([-2.0, 1e-6, 2.0, 8.0]), 0.1, 2.0)
    np.testing.assert_allclose(g[:3], [-0.2 * np.log(2.0), 1e-7, 0.2 * np.log(2.0)], rtol=1e-6)
    assert g[3] / 8.0 < g[2] / 2.0 < 0.1


def test_the_hung_weight_follows_a_slow_movement_and_rings_after_a_jerk() -> None:
    rate = 1000.0
    t = np.arange(0.0, 4.0, 1.0 / rate)
    slow = np.radians(10.0) * np.sin(2.0 * np.pi * 0.2 * t)
    acc = np.gradient(np.gradient(slow, t), t)
    y_acc = hung_weight(slow, rate, 4.0, 0.2)
    inner = slice(int(rate), -int(rate))
    assert np.max(np.abs(y_acc[inner] - acc[inner])) < 0.1 * np.max(np.abs(acc))
    step = np.where(t < 1.0, 0.0, np.radians(1.0) * (t - 1.0))  # a sudden start at 1 °/s
    ring = hung_weight(step, rate, 4.0, 0.2)
    after = ring[(t > 1.05) & (t < 2.0)]
    assert np.any(after > 0) and np.any(after < 0)  # it swings about the segment


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_y(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_shift_and_the_poles_lag() -> None:
    g = generate_y("knee", ("time_delay",), 7)
    assert g.effects["time_delay"] is not None and 0.0 < g.effects["time_delay"] <= 0.45 + 2 * 0.04 + 0.01


def test_a_compliance_is_reported_at_most_at_its_zero_load_slope() -> None:
    g = generate_y("ankle", ("series_compliance",), 2)
    c = g.details["compliance_deg_per_Nm"]
    assert 0.0 < g.effects["series_compliance"] < c
