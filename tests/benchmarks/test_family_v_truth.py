"""The twenty-second generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_v_truth import (
    NOISE_SD_NM,
    air_conditioning_drift,
    boxcar_average,
    breakaway_friction,
    cushion_contact,
    generate_v,
    minimum_jerk_bends,
    rippled_isokinetic,
    softening_leaf_spring,
    stiffening_strap_give,
    toe_region,
    travel_since_reversal,
    tremulous_contraction,
    two_stage_stop,
    warming_damper,
    wobbling_acceleration,
)


def test_the_toe_region_is_quadratic_then_linear_and_smooth_at_the_join() -> None:
    y = toe_region(np.array([-5.0, 2.0, 4.0, 10.0]), 4.0)
    np.testing.assert_allclose(y, [0.0, 0.5, 2.0, 8.0], atol=1e-12)
    h = 1e-6  # the slope is 1 on both sides of the toe's end
    assert (toe_region(np.array(4.0), 4.0) - toe_region(np.array(4.0 - h), 4.0)) / h == pytest.approx(1.0, abs=1e-5)


def test_the_leaf_spring_is_slack_before_engagement_and_softens() -> None:
    y = softening_leaf_spring(np.array([0.5, 1.0, 1.01, 41.0]), 1.0, 20.0)
    assert y[0] == y[1] == 0.0
    assert y[2] == pytest.approx(0.01, rel=1e-4)  # linear at first
    assert y[3] == pytest.approx(20.0 * np.tanh(2.0))


def test_isokinetic_strokes_ripple_about_their_speed_and_end_exactly_at_the_range() -> None:
    rate = 200.0
    deg = rippled_isokinetic(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(85.0)
    speed = np.abs(np.diff(deg)) * rate
    cruising = speed[speed > 0.5 * np.median(speed[speed > 0])]
    assert 4.0 * 0.85 - 0.2 <= np.median(cruising) <= 6.0 * 1.15 + 0.2
    assert np.ptp(cruising) > 0.05 * np.median(cruising)  # the speed loop ripples
    turns = np.flatnonzero(np.diff(np.sign(np.diff(deg[deg.size // 10:]))) != 0)
    assert turns.size >= 3  # a full cycle and more, turned smoothly


def test_minimum_jerk_bends_rest_at_zero_and_reach_their_peaks() -> None:
    deg = minimum_jerk_bends(np.random.default_rng(5), 100.0)
    assert deg.min() == 0.0 and 12.0 - 1e-9 <= deg.max() <= 20.0 + 1e-9
    starts = np.flatnonzero((deg[:-1] == 0.0) & (deg[1:] > 0.0))
    assert 6 <= starts.size <= 12
    assert np.max(np.abs(np.diff(deg, 2))) < 0.05  # no corner: the jerk-minimal profile starts and ends at rest


def test_travel_restarts_at_each_reversal() -> None:
    deg = np.array([0.0, 1.0, 2.0, 1.5, 1.0, 2.0])
    vel = np.array([10.0, 10.0, 10.0, -10.0, -10.0, 10.0])
    np.testing.assert_allclose(travel_since_reversal(deg, vel), [0.0, 1.0, 2.0, 0.5, 1.0, 1.0])


def test_the_breakaway_friction_overshoots_after_a_reversal_and_settles_to_its_level() -> None:
    deg = np.linspace(0.0, 20.0, 201)
    f = breakaway_friction(deg, np.full(deg.size, 5.0), 1.0, 1.0, 0.2)
    assert f[1] == pytest.approx((1.0 + np.exp(-0.1)) * np.tanh(25.0))
    assert f[-1] == pytest.approx(np.tanh(25.0), rel=1e-6)


def test_the_warming_damper_loses_its_fade_by_the_end() -> None:
    t = np.array([0.0, 5.0, 10.0])
    np.testing.assert_allclose(warming_damper(t, np.ones(3), 0.3), [1.0, 0.85, 0.7])


def test_the_two_stage_stop_is_soft_over_its_pad_then_stiff() -> None:
    y = two_stage_stop(np.array([19.0, 21.0, 22.0, 23.0]), 20.0, True, 2.0, 6.0)
    np.testing.assert_allclose(y, [0.0, 1.0, 2.0, 8.0])
    np.testing.assert_allclose(two_stage_stop(np.array([-23.0]), -20.0, False, 2.0, 6.0), [-8.0])


def test_the_boxcar_average_delays_a_ramp_by_half_its_window_less_half_a_sample() -> None:
    x = np.arange(100.0)
    y = boxcar_average(x, 10)
    np.testing.assert_allclose(y[20:], x[20:] - 4.5)
    assert y[0] == 0.0


def test_the_contraction_rises_holds_relaxes_and_trembles_about_its_envelope() -> None:
    t = np.arange(0.0, 4.0, 0.001)
    shape, envelope = tremulous_contraction(t, 1.0, 0.2, 0.5, 0.3, 10.0, 0.2)
    assert envelope[t < 1.0].max() == 0.0 and envelope.max() == pytest.approx(1.0)
    held = (t >= 1.2) & (t <= 1.7)
    assert np.allclose(envelope[held], 1.0) and shape[held].max() == pytest.approx(1.2, abs=1e-3)
    assert envelope[np.searchsorted(t, 2.0)] == pytest.approx(np.exp(-1.0), abs=1e-2)


def test_the_cushion_takes_weight_only_near_its_end() -> None:
    c = cushion_contact(np.array([50.0, 60.0, 65.0, 80.0]), 60.0, 10.0, True)
    np.testing.assert_allclose(c, [0.0, 0.0, 0.5, 1.0])
    assert cushion_contact(np.array([5.0]), 15.0, 10.0, False)[0] == 1.0


def test_the_air_conditioning_drift_is_centred_and_of_unit_excursion() -> None:
    t = np.arange(0.0, 90.0, 0.01)
    y = air_conditioning_drift(t, 60.0, 0.3, 0.4)
    assert abs(float(y.mean())) < 1e-9 and float(np.max(np.abs(y))) == pytest.approx(1.0)


def test_the_strap_gives_less_per_newton_metre_as_it_is_loaded() -> None:
    g = stiffening_strap_give(np.array([-10.0, 1.0, 10.0]), 0.1, 5.0)
    np.testing.assert_allclose(g, [-1.0 / 3.0, 0.1 / 1.2, 1.0 / 3.0])


def test_the_wobbling_mass_follows_slow_accelerations_and_rings_after_a_step() -> None:
    t = np.arange(0.0, 3.0, 0.001)
    acc = np.where(t >= 1.0, 1.0, 0.0)
    a = wobbling_acceleration(t, acc, 5.0, 0.2)
    assert a[t < 1.0].max() == 0.0
    assert a[-1] == pytest.approx(1.0, abs=1e-3)   # a steady acceleration: the mass moves with the segment
    assert a.max() > 1.3                           # the step overshoots (ζ 0.2)


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_v(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_boxcars_group_delay() -> None:
    g = generate_v("knee", ("time_delay",), 7)
    assert g.effects["time_delay"] is not None and 0.05 - 0.01 <= g.effects["time_delay"] <= 0.45
