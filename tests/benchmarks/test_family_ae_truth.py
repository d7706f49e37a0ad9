"""The thirty-first generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ae_truth import (
    NOISE_SD_NM,
    band_over_cam,
    behind_burgers_strap,
    burgers_give,
    cauchy_pulse,
    elliptic_low_pass,
    encoder_play,
    generate_ae,
    jeffreys_damping,
    karnopp_friction,
    magnetic_catch,
    non_circular_gear,
    pink_noise,
    quick_slow_bends,
    triangle_zero,
    van_der_waals_tension,
    varied_strokes,
)


def test_the_van_der_waals_end_is_flat_before_its_onset_and_locks_toward_its_limit() -> None:
    assert abs(float(van_der_waals_tension(np.array(-60.0), 2.0, 20.0, 2.0))) < 1e-9
    lam = 1.5  # far past the onset (x̄ = x)
    eta = np.sqrt((lam**2 + 2 / lam - 3) / (4.0 + 1.0 - 3))
    assert float(van_der_waals_tension(np.array(10.0), 0.01, 20.0, 2.0)) == pytest.approx((lam - lam**-2) / (1 - eta))
    # near the locking stretch the end stiffens without bound (held at η = 0.999)
    near = van_der_waals_tension(np.array([18.0, 19.0, 19.9]), 0.01, 20.0, 2.0)
    assert near[2] > near[1] > near[0] and near[2] > 20.0 * (1.995 - 1.995**-2)


def test_the_band_over_the_cam_is_zero_unbent_and_its_cam_bends_the_curve() -> None:
    assert float(band_over_cam(np.array(0.0), 1.0, 0.5, 0.3)) == pytest.approx(0.0, abs=1e-12)
    straight = band_over_cam(np.array([10.0, 20.0]), 0.0, 1e-3, 0.0)
    assert straight[1] / straight[0] == pytest.approx(2.0, rel=1e-3)  # a circular cam: linear
    growing = band_over_cam(np.array([10.0, 20.0]), 0.0, 1e-3, 0.3)
    assert growing[1] / growing[0] > 2.2  # a radius growing with the bend stiffens it


def test_strokes_stay_in_the_range_and_vary_their_speed() -> None:
    rng = np.random.default_rng(1)
    deg = varied_strokes(rng, 10.0, 90.0, 100.0)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 90.0 + 1e-9 and deg.max() > 87.0 and deg.min() < 13.0
    speed = np.abs(np.diff(deg)) * 100.0
    moving = speed[speed > 0.5]
    assert moving.max() <= 8.0 + 1e-6 and np.percentile(moving, 90) - np.percentile(moving, 10) > 1.0


def test_bends_load_quickly_and_release_slowly() -> None:
    deg = quick_slow_bends(np.random.default_rng(2), 100.0)
    assert deg[0] == 0.0 and 10.0 <= deg.max() <= 20.0 and deg[-1] == pytest.approx(0.0, abs=1e-9)
    step = np.diff(deg)
    assert step.max() > 1.2 * -step.min()  # the fastest loading outruns the fastest release


def test_karnopps_friction_rises_inside_its_band_and_drops_at_its_edge() -> None:
    v = np.array([0.0, 0.25, 0.49, 0.51, 5.0, -5.0])
    f = karnopp_friction(v, 0.5, 1.4)
    assert f[0] == 0.0 and f[1] == pytest.approx(0.7) and f[2] == pytest.approx(1.372)
    assert f[3] == 1.0 and f[4] == 1.0 and f[5] == -1.0


def test_the_jeffreys_body_is_viscous_when_slow_and_relaxes_a_step() -> None:
    t = np.arange(0.0, 40.0, 0.001)
    vel = np.sin(2.0 * np.pi * 0.05 * t)
    acc = np.gradient(vel, t)
    out = jeffreys_damping(vel, acc, t, 0.2, 0.08)
    assert float(np.dot(vel[10000:], out[10000:]) / np.dot(vel[10000:], vel[10000:])) == pytest.approx(1.0, rel=0.01)
    step = jeffreys_damping(np.where(t > 1.0, 1.0, 0.0), np.zeros_like(t), t, 0.2, 0.0)
    assert step[1200] == pytest.approx(1.0 - np.exp(-1.0), rel=0.02)  # one relaxation time after the step


def test_the_magnetic_catch_pulls_before_its_angle_and_pushes_past_it() -> None:
    deg = np.array([15.0, 18.5, 19.9, 20.0, 21.0])
    out = magnetic_catch(deg, 20.0, True, 2.0, 0.2)
    assert out[0] == 0.0 and out[1] < 0.0 and out[2] < out[1] and out[3] == 0.0 and out[4] == pytest.approx(1.0)
    low = magnetic_catch(np.array([-21.0, -19.5]), -20.0, False, 2.0, 0.2)
    assert low[0] == pytest.approx(-1.0) and low[1] > 0.0


def test_the_elliptic_filter_passes_a_slow_signal_late_by_its_group_delay() -> None:
    rate = 500.0
    t = np.arange(0.0, 60.0, 1.0 / rate)
    x = np.sin(2.0 * np.pi * 0.05 * t)
    y, delay = elliptic_low_pass(x, rate, 8.0, 0.5)
    assert 0.0 < delay < 0.2
    late = np.sin(2.0 * np.pi * 0.05 * (t - delay))
    assert np.max(np.abs(y[5000:] - late[5000:])) < 0.01 * 1.12  # within the pass band's ripple


def test_the_cauchy_pulse_peaks_at_its_centre_with_heavy_tails() -> None:
    t = np.linspace(0.0, 10.0, 10001)
    p = cauchy_pulse(t, 5.0, 0.2)
    assert p.max() == pytest.approx(1.0) and t[np.argmax(p)] == pytest.approx(5.0)
    assert p[np.searchsorted(t, 6.0)] == pytest.approx(1.0 / 26.0, rel=1e-3)  # 5 half-widths out: 1/(1 + 25)


def test_the_triangle_zero_ramps_between_its_extremes() -> None:
    t = np.linspace(0.0, 60.0, 6001)
    z = triangle_zero(t, 30.0, 0.0)
    assert z.min() == pytest.approx(-1.0) and z.max() == pytest.approx(1.0)
    assert np.allclose(np.abs(np.diff(z)) * 100.0, 4.0 / 30.0, rtol=1e-6, atol=1e-9)


def test_the_burgers_strap_gives_instantly_then_later_then_flows() -> None:
    t = np.arange(0.0, 20.0, 0.001)
    tau = np.where(t > 1.0, 10.0, 0.0)
    give = burgers_give(tau, t, 0.1, 0.5, 0.5, 0.002)
    assert give[1001] == pytest.approx(1.0, abs=0.01)  # the instant part
    assert give[-1] == pytest.approx(1.0 + 0.5 + 0.002 * 10.0 * 19.0, rel=0.01)  # delayed part settled, flow linear


def test_the_joint_behind_the_strap_satisfies_its_law_and_a_strap_too_soft_is_refused() -> None:
    t = np.arange(0.0, 10.0, 0.01)
    deg = 10.0 + 8.0 * np.sin(2.0 * np.pi * t / 5.0)

    def spring(d: np.ndarray) -> np.ndarray:
        return 2.0 * d

    def strap(tau: np.ndarray) -> np.ndarray:
        return burgers_give(tau, t, 0.1, 0.5, 0.3, 0.001)

    joint = behind_burgers_strap(deg, t, spring, strap)
    np.testing.assert_allclose(joint, deg - strap(spring(joint)), atol=1e-6)
    with pytest.raises(RuntimeError, match="did not converge"):
        behind_burgers_strap(deg, t, spring, lambda tau: burgers_give(tau, t, 0.6, 0.5, 0.3, 0.0))


def test_the_gears_inertia_is_the_motors_times_its_squared_ratio_plus_a_speed_term() -> None:
    rad = np.array([0.0, 0.5])
    out = non_circular_gear(rad, np.zeros(2), np.ones(2), 0.2, 1.0, 0.0)
    assert out[0] == pytest.approx(1.0) and out[1] == pytest.approx((1.0 + 0.2 * np.sin(np.pi)) ** 2)
    spin = non_circular_gear(np.array([0.0]), np.array([1.0]), np.array([0.0]), 0.2, 1.0, 0.0)
    assert spin[0] == pytest.approx(0.2 * 2.0 * np.pi)  # n·n'·θ̇² at n = 1, n' = 2πg/P


def test_the_encoder_lags_by_its_play_after_a_reversal() -> None:
    deg = np.concatenate([np.linspace(0.0, 5.0, 51), np.linspace(5.0, 0.0, 51)[1:]])
    read = encoder_play(deg, 0.1)
    assert read[50] == pytest.approx(4.95) and read[-1] == pytest.approx(0.05)


def test_pink_noise_has_unit_sd_and_more_power_at_low_frequency() -> None:
    x = pink_noise(np.random.default_rng(3), 2**14)
    assert np.std(x) == pytest.approx(1.0)
    power = np.abs(np.fft.rfft(x)) ** 2
    assert power[1:50].mean() > 10.0 * power[-2000:].mean()


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ae(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ae("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ae("knee", ("time_delay",), 5)
    assert 0.0 <= delay.effects["time_delay"] <= 0.45 + 0.2
    compliance = generate_ae("knee", ("series_compliance",), 5)
    assert 0.0 < compliance.effects["series_compliance"] < 0.5
