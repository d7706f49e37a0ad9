"""The twentieth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_t_truth import (
    NOISE_SD_NM,
    clonus,
    cubic_stop,
    eccentric_attachment,
    generate_t,
    graded_damping,
    held_bends,
    leaf_spring,
    off_support,
    power_toe,
    rippled_strokes,
    rough_spot_friction,
    sawtooth_drift,
    stepped_latency,
)


def test_the_power_toe_starts_without_a_kink() -> None:
    y = power_toe(np.array([-1.0, 0.0, 0.01, 2.0]), 3.0)
    np.testing.assert_allclose(y, [0.0, 0.0, 1e-6, 8.0])


def test_the_leaf_spring_stiffens_in_large_deflection() -> None:
    y = leaf_spring(np.array([0.0, 1.0, 11.0, 21.0]), 1.0, 5.0)
    assert y[0] == 0.0 and y[1] == 0.0
    assert y[3] - y[2] > y[2] - y[1]  # steeper over the second ten degrees


def test_rippled_strokes_stay_in_range_and_ripple_about_their_speed() -> None:
    rate = 200.0
    deg = rippled_strokes(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 85.0 + 1e-9
    speed = np.abs(np.diff(deg)) * rate
    moving = speed[speed > 1.0]
    assert 1.02 < moving.max() / np.median(moving) < 1.1  # a ripple of 3–8 %, no faster stroke


def test_bends_are_held_at_their_tops() -> None:
    rate = 200.0
    deg = held_bends(np.random.default_rng(5), rate)
    held = np.flatnonzero((np.diff(deg) == 0.0) & (deg[1:] >= 10.0))
    runs = np.split(held, np.flatnonzero(np.diff(held) > 1) + 1)
    assert len(runs) >= 5 and all(r.size >= 0.5 * rate - 2 for r in runs)


def test_friction_is_higher_over_its_rough_spot() -> None:
    f = rough_spot_friction(np.array([10.0, 50.0, 50.0]), np.array([5.0, 5.0, -5.0]), 50.0, 8.0, 0.5, 0.5)
    np.testing.assert_allclose(f, [np.tanh(10.0) * (1 + 0.5 * np.exp(-25.0)), 1.5 * np.tanh(10.0),
                                   -1.5 * np.tanh(10.0)])


def test_damping_changes_along_the_range() -> None:
    y = graded_damping(np.array([0.0, 10.0, 20.0]), np.ones(3), 10.0, 20.0, 0.4)
    np.testing.assert_allclose(y, [0.8, 1.0, 1.2])


def test_the_cubic_stop_pushes_back_past_contact() -> None:
    y = cubic_stop(np.array([19.0, 21.0, 22.0]), 20.0, True)
    np.testing.assert_allclose(y, [0.0, 1.0, 8.0])
    np.testing.assert_allclose(cubic_stop(np.array([-19.0, -21.0, -22.0]), -20.0, False), -y)


def test_the_latency_steps_once() -> None:
    t = np.arange(0.0, 10.0, 0.001)
    late, latency = stepped_latency(t.copy(), t, 0.1, 0.3, 5.0)
    assert late[3000] == pytest.approx(2.9) and late[7000] == pytest.approx(6.7)
    assert float(np.mean(latency)) == pytest.approx(0.2, abs=1e-3)


def test_a_clonus_beats_under_its_envelope() -> None:
    t = np.arange(0.0, 3.0, 0.001)
    y = clonus(t, 1.0, 0.8, 6.0)
    assert y.max() == pytest.approx(1.0) and y[t < 1.0].max() == 0.0 and y[t > 1.8].max() == 0.0
    peaks = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (y[1:-1] > 0.05))
    assert 4 <= peaks.size <= 5  # 0.8 s at 6 Hz


def test_the_weight_comes_off_the_support_past_its_angle() -> None:
    share = off_support(np.array([0.0, 30.0, 60.0]), 30.0, True, 3.0)
    assert share[0] < 1e-6 and share[1] == pytest.approx(0.5) and share[2] > 1 - 1e-6


def test_the_sawtooth_resets() -> None:
    t = np.linspace(0.0, 120.0, 12001)
    y = sawtooth_drift(t, 60.0, 0.0)
    assert np.max(np.abs(y)) == pytest.approx(1.0) and abs(np.mean(y)) < 1e-3
    assert np.count_nonzero(np.diff(y) < -0.5) == 2  # reset at 60 s and 120 s


def test_the_eccentric_attachment_adds_a_centripetal_moment() -> None:
    out = eccentric_attachment(np.array([0.0, np.pi / 2]), np.array([2.0, 2.0]), np.array([1.0, 0.0]), 0.5, 0.1, 0.0)
    np.testing.assert_allclose(out, [0.5, 0.4])


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_t(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_time_averaged_latency() -> None:
    g = generate_t("knee", ("time_delay",), 7)
    first, second = g.details["latencies_s"]
    assert min(first, second) <= g.effects["time_delay"] <= max(first, second)
