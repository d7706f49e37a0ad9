"""The twenty-fourth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_x_truth import (
    NOISE_SD_NM,
    bateman_pulse,
    cam_spring,
    critically_damped_strokes,
    drive_bandwidth,
    eight_chain,
    expected_stretch,
    generate_x,
    gripped_pad,
    half_gaussian_smoother,
    heating_dashpot,
    lined_stop,
    melting_share,
    quick_load_slow_release_bends,
    rough_track_friction,
    softening_strap_give,
    thermal_wander,
)


def test_the_eight_chain_starts_with_unit_slope_and_locks_at_its_limit() -> None:
    h = 1e-6
    assert float(eight_chain(np.array(h), 30.0)) / h == pytest.approx(1.0, rel=1e-6)
    assert float(eight_chain(np.array(15.0), 30.0)) == pytest.approx(30.0 * 0.5 * 2.75 / 0.75 / 3.0)
    assert float(eight_chain(np.array(29.7), 30.0)) > 40.0 * float(eight_chain(np.array(15.0), 30.0)) / 15.0


def test_normally_spread_onsets_give_a_smooth_stretch_that_joins_the_hinge_far_from_the_onset() -> None:
    x = np.array([-20.0, 0.0, 20.0])
    s = expected_stretch(x, 2.0)
    assert s[0] < 1e-12 and s[1] == pytest.approx(2.0 / np.sqrt(2.0 * np.pi)) and s[2] == pytest.approx(20.0)
    slope = np.gradient(expected_stretch(np.linspace(-1.0, 1.0, 201), 2.0), 0.01)
    assert np.all(np.diff(slope) > 0.0) and np.max(np.diff(slope)) < 0.003  # the slope rises gradually: no kink


def test_the_cam_spring_ripples_about_a_linear_one() -> None:
    np.testing.assert_allclose(cam_spring(np.array([-2.0, 5.0, 10.0]), 0.1, 20.0), [0.0, 5.0 * (1.0 + 0.1 * np.sin(np.pi / 4)),
                                                                                    11.0])


def test_strokes_approach_each_end_and_end_on_it_after_the_drive_window() -> None:
    rate = 200.0
    deg = critically_damped_strokes(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0, abs=1e-6) and deg.max() == pytest.approx(85.0, abs=1e-6)
    speed = np.abs(np.diff(deg)) * rate
    # at most the fastest stroke's peak: the shape's slope x·e^{−x} peaks at 1/e, over τ = duration/7, so 7/e × the mean
    # speed (8 °/s at most), over the scaling to end at b
    assert speed.max() < 8.0 * 7.0 / np.e / (1.0 - 8.0 * np.exp(-7.0)) * 1.01
    assert np.max(np.abs(np.diff(deg, 2))) * rate * rate < 200.0  # smooth through the drive's window (°/s²)


def test_the_drive_window_keeps_a_constant_and_a_ramp_where_it_is() -> None:
    ramp = np.linspace(0.0, 10.0, 400)
    out = drive_bandwidth(ramp, 100.0)
    np.testing.assert_allclose(out[20:-20], ramp[20:-20], atol=1e-9)
    np.testing.assert_allclose(drive_bandwidth(np.full(50, 3.0), 100.0), 3.0)


def test_orthosis_bends_load_faster_than_they_release_and_rest_low_between() -> None:
    deg = quick_load_slow_release_bends(np.random.default_rng(5), 100.0)
    assert abs(deg[0]) < 1e-9 and abs(deg[-1]) < 1e-9 and 9.0 <= deg.max() <= 20.0 + 1e-9
    v = np.diff(deg)
    assert np.max(v) > 1.2 * np.max(-v)  # loaded faster than released


def test_friction_on_a_rough_track_resists_the_motion_at_a_level_that_wanders_with_the_angle() -> None:
    deg = np.linspace(0.0, 60.0, 6001)
    f_up = rough_track_friction(np.random.default_rng(2), deg, np.full(deg.size, 5.0), 0.3, 3.0, 0.5)
    f_down = rough_track_friction(np.random.default_rng(2), deg, np.full(deg.size, -5.0), 0.3, 3.0, 0.5)
    np.testing.assert_allclose(f_down, -f_up)  # the same track both ways, resisting each
    assert np.all(f_up >= 0.2 * np.tanh(10.0))
    assert 0.15 < float(np.std(f_up)) < 0.45 and abs(float(np.mean(f_up)) - 1.0) < 0.3
    # correlated over a few degrees, not from one sample to the next
    assert float(np.max(np.abs(np.diff(f_up)))) < 0.05
    lag = 600  # 6°, twice the correlation length: e^{-2} of the profile's autocorrelation
    r = np.corrcoef(f_up[:-lag], f_up[lag:])[0, 1]
    assert r < 0.6


def test_the_heating_dashpot_thins_with_the_power_it_has_dissipated() -> None:
    rate = 100.0
    vel = np.ones(10_000)
    d = heating_dashpot(vel, rate, 0.3, 10.0)
    assert d[0] == pytest.approx(1.0, abs=0.01) and d[-1] == pytest.approx(0.7, abs=1e-6)
    assert np.all(np.diff(d) <= 0.0)


def test_the_lined_stop_is_quadratic_at_contact_and_linear_deep_in() -> None:
    y = lined_stop(np.array([19.0, 20.1, 30.0]), 20.0, True, 1.0)
    assert y[0] == 0.0 and y[1] == pytest.approx(0.01 / 1.1) and y[2] == pytest.approx(100.0 / 11.0)
    assert lined_stop(np.array([-22.0]), -20.0, False, 1.0)[0] == pytest.approx(-4.0 / 3.0)


def test_the_half_gaussian_smoother_delays_a_ramp_by_its_group_delay() -> None:
    rate = 100.0
    x = np.arange(3000.0)
    y, delay = half_gaussian_smoother(x, 0.2, 0.05, rate)
    assert y.size == x.size and y[0] == x[0]
    assert delay == pytest.approx(0.2 + 0.05 * np.sqrt(2.0 / np.pi), abs=0.005)
    assert x[-1] - y[-1] == pytest.approx(delay * rate, rel=1e-6)


def test_the_bateman_pulse_peaks_at_one_and_decays_slower_than_it_rises() -> None:
    t = np.arange(0.0, 5.0, 0.001)
    p = bateman_pulse(t, 1.0, 0.05, 0.5)
    assert p[t < 1.0].max() == 0.0 and p.max() == pytest.approx(1.0, abs=1e-4)
    peak = float(t[np.argmax(p)]) - 1.0
    assert peak == pytest.approx(np.log(10.0) * 0.05 * 0.5 / 0.45, abs=0.002)
    assert p[np.searchsorted(t, 1.0 + peak + 0.5)] == pytest.approx(np.exp(-1.0), abs=0.05)


def test_the_cold_pack_melts_away() -> None:
    np.testing.assert_allclose(melting_share(np.array([5.0, 15.0]), 10.0), [1.0, np.exp(-1.0)])


def test_the_thermal_wander_is_centred_of_unit_excursion_and_slow() -> None:
    t = np.arange(0.0, 120.0, 0.01)
    y = thermal_wander(np.random.default_rng(1), t, 30.0, 10.0)
    assert abs(float(y.mean())) < 1e-9 and float(np.max(np.abs(y))) == pytest.approx(1.0)
    assert np.max(np.abs(np.diff(y))) < 0.01  # a lag of 10 s: no step between samples


def test_the_strap_softens_exponentially_with_load() -> None:
    g = softening_strap_give(np.array([-2.0, 1e-6, 2.0]), 0.1, 2.0)
    np.testing.assert_allclose(g, [-0.2 * np.expm1(1.0), 1e-7, 0.2 * np.expm1(1.0)], rtol=1e-6)


def test_the_pad_slips_at_its_grip() -> None:
    np.testing.assert_allclose(gripped_pad(np.array([-3.0, 0.5, 3.0]), 2.0, 4.0), [-4.0, 1.0, 4.0])


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_x(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_the_shift_and_the_kernels_lag() -> None:
    g = generate_x("knee", ("time_delay",), 7)
    assert g.effects["time_delay"] is not None and 0.0 < g.effects["time_delay"] <= 0.4 + 0.08 * 0.8 + 0.01


def test_a_compliance_is_reported_at_least_at_its_zero_load_slope() -> None:
    g = generate_x("ankle", ("series_compliance",), 2)
    c = g.details["compliance_deg_per_Nm"]
    assert c <= g.effects["series_compliance"] <= c * np.e ** 2


def test_a_slipping_pad_reports_less_inertia_than_it_has() -> None:
    g = generate_x("knee", ("inertia",), 3)
    assert 0.0 < g.effects["inertia"] < g.details["pad_inertia_kgm2"]
