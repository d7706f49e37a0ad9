"""The twenty-first generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_u_truth import (
    NOISE_SD_NM,
    cam_spring,
    check_valve_damping,
    creep_slips,
    drifting_tempo_bends,
    generate_u,
    preloaded_bumper,
    read_late,
    sliding_weight,
    smooth_hinge_power,
    trapezoid_strokes,
    voluntary_contraction,
    wandering_latency,
    worn_gear_friction,
)


def test_the_smoothed_hinge_is_a_power_of_the_depth_far_past_its_onset_and_small_before_it() -> None:
    y = smooth_hinge_power(np.array([-30.0, 0.0, 40.0]), 4.0)
    assert y[0] < 2e-4
    assert y[1] == pytest.approx((4.0 * np.log(2.0)) ** 1.5)
    assert y[2] == pytest.approx(40.0**1.5, rel=1e-4)


def test_the_cam_spring_is_slack_before_engagement_and_wavy_past_it() -> None:
    y = cam_spring(np.array([0.5, 1.0, 13.5, 26.0]), 1.0, 2.0)
    np.testing.assert_allclose(y, [0.0, 0.0, 12.5 + 2.0 * np.sin(np.pi * 0.5), 25.0], atol=1e-12)


def test_trapezoid_strokes_cruise_accelerate_within_their_limit_and_hold_at_the_ends() -> None:
    rate = 200.0
    deg = trapezoid_strokes(np.random.default_rng(4), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(85.0)
    speed = np.diff(deg) * rate
    assert 3.0 - 1e-6 <= np.max(np.abs(speed)) <= 7.0 + 1e-6
    accel = np.diff(speed) * rate
    assert np.percentile(np.abs(accel), 99) <= 10.0 + 1e-6  # at most 10 °/s², but for the joins of steps
    held = np.flatnonzero(np.diff(deg) == 0.0)
    assert held.size >= 0.5 * rate * 6  # six ends or more held half a second or longer


def test_the_bends_tempo_drifts_and_none_rests() -> None:
    deg = drifting_tempo_bends(np.random.default_rng(9), 100.0)
    starts = np.flatnonzero((deg[:-1] == 0.0) & (deg[1:] > 0.0))
    periods = np.diff(starts)
    assert 8 <= starts.size <= 14
    assert np.all(np.diff(periods) >= -1) or np.all(np.diff(periods) <= 1)  # a steady change, one way


def test_the_worn_gears_friction_repeats_with_the_teeth_and_keeps_its_sign() -> None:
    deg = np.array([0.0, 1.5, 3.0])
    f = worn_gear_friction(deg, np.array([10.0, 10.0, -10.0]), 6.0, 0.4, 0.0, 0.5)
    sign = 10.0 / np.sqrt(100.25)
    np.testing.assert_allclose(f, [sign, 1.4 * sign, -sign], atol=1e-12)


def test_the_check_valve_damps_one_way_less() -> None:
    np.testing.assert_allclose(check_valve_damping(np.array([2.0, -2.0]), 0.5, True), [1.0, -2.0])
    np.testing.assert_allclose(check_valve_damping(np.array([2.0, -2.0]), 0.5, False), [2.0, -1.0])


def test_the_bumper_steps_by_its_preload_then_rises_linearly() -> None:
    y = preloaded_bumper(np.array([19.0, 20.1, 20.2, 21.2]), 20.0, True, 3.0, 0.2)
    np.testing.assert_allclose(y, [0.0, 1.5 + 0.1, 3.2, 4.2], atol=1e-12)
    np.testing.assert_allclose(preloaded_bumper(np.array([-19.0, -21.2]), -20.0, False, 3.0, 0.2), [0.0, -4.2])


def test_the_latency_wanders_about_its_mean_within_its_bound() -> None:
    t = np.arange(0.0, 60.0, 0.01)
    latency = wandering_latency(np.random.default_rng(2), t, 0.2, 0.03, 2.0)
    assert float(np.mean(latency)) == pytest.approx(0.2, abs=1e-9)
    assert float(np.max(np.abs(latency - 0.2))) == pytest.approx(0.03)
    late = read_late(t.copy(), t, latency)
    np.testing.assert_allclose(late[1000:], t[1000:] - latency[1000:], atol=1e-9)


def test_a_voluntary_contraction_is_a_trapezoid() -> None:
    t = np.array([0.0, 1.2, 1.4, 2.0, 2.5, 3.0])
    np.testing.assert_allclose(voluntary_contraction(t, 1.0, 0.4, 0.5, 0.5), [0.0, 0.5, 1.0, 0.8, 0.0, 0.0],
                               atol=1e-12)


def test_the_zero_slips_in_steps_and_is_centred() -> None:
    t = np.arange(0.0, 120.0, 0.01)
    y = creep_slips(np.random.default_rng(1), t, 4.0, 1.0)
    assert abs(float(np.mean(y))) < 1e-9 and float(np.max(np.abs(y))) == pytest.approx(1.0)
    jumps = np.abs(np.diff(y[::100]))  # 1 s apart: a slip shows as a jump between neighbours
    assert np.count_nonzero(jumps > 0.05) >= 2


def test_the_sliding_weight_adds_its_changing_inertia_and_the_velocity_term() -> None:
    out = sliding_weight(np.array([0.0, 1.0]), np.array([0.0, 2.0]), np.array([1.0, 1.0]), 0.5, 0.4, 0.0)
    np.testing.assert_allclose(out, [0.5, 0.5 * 1.4 + 0.5 * 0.5 * 0.4 * 4.0])


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_u(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_time_averaged_latency() -> None:
    g = generate_u("knee", ("time_delay",), 7)
    assert g.effects["time_delay"] is not None and 0.05 - 0.04 <= g.effects["time_delay"] <= 0.45 + 0.04
