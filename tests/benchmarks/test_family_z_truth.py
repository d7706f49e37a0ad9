"""The twenty-sixth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_z_truth import (
    NOISE_SD_NM,
    activation_dynamics,
    coupled_flywheel,
    generate_z,
    kelvin_voigt_stop,
    median_delay,
    ogden_end,
    preloaded_cable_give,
    running_in_friction,
    sine_sweeps,
    softening_leaf,
    squeezed_bushing,
    triangle_bends,
)


def test_the_ogden_end_is_flat_before_its_onset_and_its_slope_past_it_is_the_ogden_laws() -> None:
    assert abs(float(ogden_end(np.array(-40.0), 1.0, 50.0, 8.0))) < 1e-12
    h = 1e-3  # far past the onset the softplus is the angle itself; near zero stretch the slope is 1.5·α/L
    far = ogden_end(np.array([30.0, 30.0 + h]), 0.01, 50.0, 8.0)
    lam = 1.0 + 30.0 / 50.0
    assert (far[1] - far[0]) / h == pytest.approx((8.0 * lam**7 + 4.0 * lam**-5) / 50.0, rel=1e-3)


def test_the_leaf_softens_from_a_linear_start() -> None:
    np.testing.assert_allclose(softening_leaf(np.array([-2.0, 1e-4, 30.0]), 30.0), [0.0, 1e-4, 30.0 * np.tanh(1.0)],
                               rtol=1e-6)


def test_sine_sweeps_span_the_range_at_their_peak_speed() -> None:
    rate = 200.0
    deg = sine_sweeps(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(85.0, abs=0.01)
    speed = np.abs(np.diff(deg)) * rate
    assert 4.0 * 0.99 <= speed.max() <= 9.0 * 1.01


def test_orthosis_bends_are_triangles_smoothed_over_50_ms() -> None:
    rate = 100.0
    deg = triangle_bends(np.random.default_rng(5), rate)
    assert abs(deg[0]) < 1e-9 and abs(deg[-1]) < 1e-9 and 9.0 <= deg.max() <= 20.0 + 1e-9
    speed = np.abs(np.diff(deg)) * rate
    assert speed.max() <= 20.0 + 1e-6 and np.median(speed[speed > 1.0]) >= 8.0 * 0.95


def test_friction_runs_in_with_the_angle_travelled_and_resists_the_motion() -> None:
    deg = np.concatenate([np.linspace(0.0, 50.0, 501), np.linspace(50.0, 0.0, 501)[1:]])
    vel = np.gradient(deg) * 100.0
    f = running_in_friction(deg, vel, 0.5, 0.5)
    assert np.all(np.sign(f[1:-1]) == np.sign(vel[1:-1]))
    assert abs(f[1]) == pytest.approx(vel[1] / (vel[1] + 0.5), rel=1e-3)  # the full level at the start
    assert abs(f[-2]) == pytest.approx((0.6 + 0.4 * np.exp(-2.0)) * abs(vel[-2]) / (abs(vel[-2]) + 0.5), rel=0.01)


def test_the_bushing_damps_more_toward_one_end() -> None:
    d = squeezed_bushing(np.ones(3), np.array([0.0, 45.0, 90.0]), 0.0, 90.0, 0.5)
    np.testing.assert_allclose(d, [0.5, 1.0, 1.5])


def test_the_kelvin_voigt_stop_adds_damping_inside_and_never_pulls() -> None:
    y = kelvin_voigt_stop(np.array([19.0, 22.0, 22.0, 20.5]), np.array([5.0, 5.0, -5.0, -10.0]), 20.0, True, 0.1)
    np.testing.assert_allclose(y, [0.0, 2.5, 1.5, 0.0])
    assert kelvin_voigt_stop(np.array([-23.0]), np.array([-4.0]), -20.0, False, 0.1)[0] == pytest.approx(-3.4)


def test_the_median_delay_lags_a_ramp_by_its_shift_and_half_its_span() -> None:
    rate = 100.0
    x = np.arange(3000.0)
    y, delay = median_delay(x, 0.2, 9, rate)
    assert delay == pytest.approx(0.24)
    assert x[-100] - y[-100] == pytest.approx(24.0)


def test_activation_rises_fast_and_falls_slow_with_peak_one() -> None:
    t = np.arange(0.0, 4.0, 0.001)
    a = activation_dynamics(t, 1.0, 0.5, 0.04, 0.3)
    assert a[t < 1.0].max() == 0.0 and a.max() == pytest.approx(1.0)
    i = np.searchsorted(t, 1.5 + 0.3)  # at the excitation's end it has risen to its peak (0.5 s ≫ 40 ms)
    assert a[i] == pytest.approx(np.exp(-1.0), rel=0.02)


def test_the_cable_gives_only_past_its_preload() -> None:
    np.testing.assert_allclose(preloaded_cable_give(np.array([-5.0, 1.0, 5.0]), 0.1, 2.0), [-0.3, 0.0, 0.3])


def test_the_coupled_flywheel_is_an_inertia_at_low_frequency() -> None:
    t = np.arange(0.0, 20.0, 0.001)
    vel = np.sin(2.0 * np.pi * 0.1 * t)
    acc = np.gradient(vel, t)
    torque = coupled_flywheel(vel, t, 0.05)
    inner = t > 5.0
    assert float(np.dot(torque[inner], acc[inner]) / np.dot(acc[inner], acc[inner])) == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_z(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_compliance_is_reported_below_its_slope_past_the_preload() -> None:
    g = generate_z("ankle", ("series_compliance",), 2)
    assert 0.0 < g.effects["series_compliance"] < g.details["compliance_deg_per_Nm"]
