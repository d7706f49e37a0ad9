"""The twenty-third generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_w_truth import (
    NOISE_SD_NM,
    buckling_pad,
    flexor_spasm,
    generate_w,
    half_cosine_strokes,
    heater_bow,
    lost_motion_friction,
    moving_average_filter,
    ported_damper,
    progressive_spring,
    raised_cosine_bends,
    relaxing_share,
    slack_strap_give,
    sloshing_acceleration,
    travel_since_turn,
    worm_like_chain,
)


def test_the_worm_like_chain_is_linear_at_its_onset_and_steepens_toward_its_contour() -> None:
    y = worm_like_chain(np.array([-3.0, 0.0, 10.0]), 20.0)
    assert y[0] == y[1] == 0.0
    assert y[2] == pytest.approx(20.0 * (0.25 / 0.25 - 0.25 + 0.5))  # u = 1/2: L·(1 − 1/4 + 1/2)
    h = 1e-6  # slope 3/2 at the onset (the series' first term), far steeper near the contour
    assert float(worm_like_chain(np.array(h), 20.0)) / h == pytest.approx(1.5, rel=1e-4)
    near = (worm_like_chain(np.array(18.0 + h), 20.0) - worm_like_chain(np.array(18.0), 20.0)) / h
    assert near > 100.0


def test_spread_onsets_make_the_chain_smooth_where_it_engages() -> None:
    x = np.array([-30.0, -1e-3, 1e-3, 30.0])
    y = worm_like_chain(x, 60.0, 3.0)
    assert y[0] < 1e-3 and y[3] == pytest.approx(float(worm_like_chain(np.array(30.0), 60.0)), rel=1e-3)
    slope = np.gradient(worm_like_chain(np.linspace(-0.5, 0.5, 101), 60.0, 3.0), 0.01)
    assert np.max(np.abs(np.diff(slope))) < 0.01  # no kink at the onset: the slope changes gradually


def test_the_orthosis_spring_is_progressive() -> None:
    y = progressive_spring(np.array([-1.0, 1.0, 2.0]), 1.3)
    np.testing.assert_allclose(y, [0.0, 1.0, 2.0**1.3])


def test_half_cosine_strokes_end_exactly_at_the_range_and_peak_in_speed_mid_stroke() -> None:
    rate = 200.0
    deg = half_cosine_strokes(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(85.0)
    speed = np.abs(np.diff(deg)) * rate
    fast = speed > 0.95 * speed.max()
    assert np.all(np.abs(deg[1:][fast] - 47.5) < 0.3 * 75.0)  # fastest in the middle of the range
    assert 3.0 * 0.85 * np.pi / 2 * 0.9 <= speed.max() <= 7.0 * 1.15 * np.pi / 2 * 1.1


def test_raised_cosine_bends_start_and_end_at_zero_and_return_only_part_way_between() -> None:
    deg = raised_cosine_bends(np.random.default_rng(5), 100.0)
    assert deg[0] == 0.0 and deg[-1] == 0.0 and 10.0 - 1e-9 <= deg.max() <= 20.0 + 1e-9
    troughs = np.flatnonzero((deg[1:-1] < deg[:-2]) & (deg[1:-1] <= deg[2:]))
    assert np.all(deg[1:-1][troughs] <= 3.0 + 1e-9)
    assert np.max(np.abs(np.diff(deg, 2))) < 0.05


def test_travel_restarts_at_each_turn_and_a_still_sample_keeps_its_direction() -> None:
    deg = np.array([0.0, 1.0, 2.0, 2.0, 1.5, 1.0, 2.0])
    vel = np.array([10.0, 10.0, 10.0, 0.0, -10.0, -10.0, 10.0])
    np.testing.assert_allclose(travel_since_turn(deg, vel), [0.0, 1.0, 2.0, 2.0, 0.0, 0.5, 0.0])


def test_friction_behind_lost_motion_waits_for_the_backlash() -> None:
    deg = np.linspace(0.0, 5.0, 501)
    f = lost_motion_friction(deg, np.full(deg.size, 5.0), 1.0, 0.2)
    assert np.all(f[deg < 1.0] == 0.0)
    assert f[-1] == pytest.approx(np.tanh(25.0))
    assert f[np.searchsorted(deg, 1.1)] == pytest.approx(0.5 * np.tanh(25.0), abs=0.01)


def test_the_ported_damper_ripples_with_the_angle_about_its_mean() -> None:
    d = ported_damper(np.array([0.0, 5.0, 10.0]), np.ones(3), 0.4, 20.0, 0.0)
    np.testing.assert_allclose(d, [1.4, 1.0, 0.6], atol=1e-12)


def test_the_buckling_pad_peaks_dips_then_seats() -> None:
    y = buckling_pad(np.array([19.0, 21.0, 22.0, 23.0, 24.0]), 20.0, True, 1.0, 0.3, 2.0, 6.0)
    np.testing.assert_allclose(y, [0.0, 1.0, 0.85, 0.7, 6.7])
    assert buckling_pad(np.array([-21.0]), -20.0, False, 1.0, 0.3, 2.0, 6.0)[0] == pytest.approx(-1.0)


def test_the_moving_average_delays_a_ramp_by_its_group_delay() -> None:
    rate = 100.0
    x = np.arange(2000.0)
    y, delay = moving_average_filter(x, 0.2, rate)
    assert delay == pytest.approx(0.2 - 0.5 / rate, abs=2e-3)
    np.testing.assert_allclose(x[-1] - y[-1], delay * rate, rtol=1e-6)
    assert y[0] == x[0]


def test_the_spasm_rises_linearly_and_is_released_hyperbolically() -> None:
    t = np.arange(0.0, 3.0, 0.001)
    s = flexor_spasm(t, 1.0, 0.2, 0.3)
    assert s[t < 1.0].max() == 0.0 and s.max() == pytest.approx(1.0)
    assert s[np.searchsorted(t, 1.1)] == pytest.approx(0.5, abs=0.01)
    assert s[np.searchsorted(t, 1.5)] == pytest.approx(0.25, abs=0.01)  # (1 + 0.3/0.3)⁻²


def test_the_sleeve_takes_its_share_as_the_subject_relaxes() -> None:
    s = relaxing_share(np.array([10.0, 20.0, 1e4]), 10.0)
    np.testing.assert_allclose(s, [0.0, 1.0 - np.exp(-1.0), 1.0])


def test_the_heater_bow_is_centred_and_of_unit_excursion() -> None:
    y = heater_bow(np.arange(0.0, 90.0, 0.01), 0.4)
    assert abs(float(y.mean())) < 1e-9 and float(np.max(np.abs(y))) == pytest.approx(1.0)


def test_the_strap_gives_less_per_newton_metre_once_its_slack_is_taken_up() -> None:
    g = slack_strap_give(np.array([-10.0, 1.0, 10.0]), 0.1, 4.0, 3.0)
    np.testing.assert_allclose(g, [-0.6, 0.1, 0.6])


def test_the_boot_follows_slow_accelerations_and_lags_a_step_by_its_fluid_share() -> None:
    rate = 1000.0
    acc = np.r_[np.zeros(1000), np.ones(2000)]
    a = sloshing_acceleration(acc, 0.6, 0.1, rate)
    assert a[999] == 0.0 and a[1000] == pytest.approx(0.6 + 0.4 * (1 - np.exp(-0.01)), abs=1e-6)
    assert a[-1] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_w(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_filters_group_delay() -> None:
    g = generate_w("knee", ("time_delay",), 7)
    assert g.effects["time_delay"] is not None and 0.05 - 0.01 <= g.effects["time_delay"] <= 0.5


def test_a_compliance_is_reported_between_its_two_slopes() -> None:
    g = generate_w("ankle", ("series_compliance",), 2)
    c, stiffer = g.details["compliance_deg_per_Nm"], g.details["stiffer"]
    assert c / stiffer <= g.effects["series_compliance"] <= c
