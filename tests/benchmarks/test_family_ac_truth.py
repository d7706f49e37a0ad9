"""The twenty-ninth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ac_truth import (
    NOISE_SD_NM,
    critically_damped,
    encoder_eccentricity,
    generate_ac,
    hgo_fibre,
    minimum_jerk,
    mooney_rivlin_bumper,
    palmgren_friction,
    play,
    ramberg_osgood_give,
    random_targets,
    sag_moment,
    savitzky_golay_endpoint,
    telegraph,
    tent_bends,
    thixotropic_structure,
    wald_pulse,
)


def test_the_fibre_is_flat_before_its_onset_and_follows_the_hgo_law_past_it() -> None:
    assert abs(float(hgo_fibre(np.array(-40.0), 1.0, 20.0, 0.3))) < 1e-12
    # far past the onset (x̄ = x): a stretch of 1.5, λ² − 1 = 1.25
    assert float(hgo_fibre(np.array(10.0), 0.01, 20.0, 0.3)) == pytest.approx(1.25 * np.exp(0.3 * 1.25**2), rel=1e-6)
    # k₂ = 0 leaves λ² − 1; the exponential stiffens it ever more with the stretch
    x = np.linspace(1.0, 30.0, 30)
    ratio = hgo_fibre(x, 0.01, 15.0, 0.3) / hgo_fibre(x, 0.01, 15.0, 0.0)
    assert np.all(np.diff(ratio) > 0.0)


def test_a_minimum_jerk_stroke_starts_and_ends_at_rest_at_its_mean_speed() -> None:
    rate = 1000.0
    deg = np.concatenate([[10.0], minimum_jerk(10.0, 40.0, 5.0, rate)])
    speed = np.diff(deg) * rate
    assert deg[-1] == pytest.approx(40.0) and deg.size - 1 == 6000
    assert np.mean(speed) == pytest.approx(5.0, rel=1e-3) and np.max(speed) == pytest.approx(1.875 * 5.0, rel=1e-3)
    assert speed[0] < 1e-3 and speed[-1] < 0.01


def test_random_targets_reach_each_end_twice_and_stop_between_targets() -> None:
    rate = 200.0
    deg = random_targets(np.random.default_rng(8), 10.0, 80.0, rate)
    assert deg[0] == pytest.approx(45.0) and deg[-1] == pytest.approx(45.0)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(80.0)
    at_low = np.abs(deg - 10.0) < 1e-9
    at_high = np.abs(deg - 80.0) < 1e-9
    # each end touched in two separate visits
    assert np.sum(np.diff(at_low.astype(int)) == 1) == 2 and np.sum(np.diff(at_high.astype(int)) == 1) == 2
    turns = np.flatnonzero(np.diff(np.sign(np.diff(deg)[np.abs(np.diff(deg)) > 0])) != 0)
    assert turns.size >= 3 + 1  # at least the four ends' turns (inserted targets may or may not turn the joint)


def test_tent_bends_rise_then_fall_and_release_faster_than_they_load() -> None:
    rate = 500.0
    deg = tent_bends(np.random.default_rng(6), rate)
    assert abs(deg[0]) < 1e-12 and abs(deg[-1]) < 1e-12 and deg.min() >= -1e-9
    rest = deg < 1e-9
    starts = np.flatnonzero(np.diff(rest.astype(int)) == -1)
    ends = np.flatnonzero(np.diff(rest.astype(int)) == 1)
    peaks = np.array([deg[a:b + 1].max() for a, b in zip(starts, ends, strict=True)])
    assert 6 <= peaks.size <= 10 and 10.0 <= peaks[0] <= 12.0 and 18.0 <= peaks.max() <= 20.0
    top = int(np.argmax(peaks))
    assert np.all(np.diff(peaks[:top + 1]) > 0) and np.all(np.diff(peaks[top:]) < 0)
    step = np.diff(deg) * rate
    assert -np.min(step) > np.max(step)


def test_the_bearings_friction_grows_with_the_speeds_two_thirds_power() -> None:
    v = np.array([-10.0, -5.0, 0.0, 5.0, 10.0])
    f = palmgren_friction(v, 0.01, 0.5)
    assert f[2] == 0.0 and f[4] == pytest.approx(1.5) and f[3] == pytest.approx(1.0 + 0.5 * 0.5 ** (2.0 / 3.0))
    np.testing.assert_allclose(f[:2], -f[4:2:-1])  # odd in the speed


def test_the_structure_breaks_down_in_motion_and_rebuilds_at_rest() -> None:
    t = np.arange(0.0, 40.0, 0.01)
    vel = np.where((t >= 5.0) & (t < 15.0), 0.1, 0.0)
    s = thixotropic_structure(t, vel, 4.0, 20.0)
    assert s[np.searchsorted(t, 4.9)] == pytest.approx(1.0)
    steady = (1.0 / 4.0) / (1.0 / 4.0 + 20.0 * 0.1)
    assert s[np.searchsorted(t, 14.9)] == pytest.approx(steady, rel=1e-3)
    # rebuilt with T_b after the last moving sample (14.99 s)
    assert s[np.searchsorted(t, 19.0)] == pytest.approx(1.0 - (1.0 - steady) * np.exp(-4.01 / 4.0), rel=1e-4)


def test_the_rubber_bumper_stiffens_as_it_is_compressed_and_is_zero_before_contact() -> None:
    h = 1e-5
    for high, sign in ((True, 1.0), (False, -1.0)):
        def k(depth: float, high: bool = high, sign: float = sign) -> float:
            deg = 50.0 + sign * np.array([depth, depth + h])
            return float(abs(np.diff(mooney_rivlin_bumper(deg, 50.0, high, 10.0, 0.3))[0]) / h)
        # small compression: −2(λ − λ⁻²)(1 + r/λ) ≈ 6δ/h·(1 + r)
        assert k(1e-3) == pytest.approx(6.0 / 10.0 * 1.3, rel=1e-2)
        assert k(5.0) > 3.0 * k(1e-3)
        assert float(mooney_rivlin_bumper(np.array(50.0 - sign * 3.0), 50.0, high, 10.0, 0.3)) == 0.0
        assert sign * float(mooney_rivlin_bumper(np.array(50.0 + sign * 2.0), 50.0, high, 10.0, 0.3)) > 0.0


def test_the_savitzky_golay_endpoint_follows_a_parabola_without_lag_and_smooths_noise() -> None:
    t = np.arange(0.0, 5.0, 0.01)
    parabola = 0.3 * t * t - t + 2.0
    out = savitzky_golay_endpoint(parabola, 25)
    np.testing.assert_allclose(out[30:], parabola[30:], atol=1e-9)
    noise = np.random.default_rng(1).normal(0.0, 1.0, 20000)
    assert 0.2 < np.std(savitzky_golay_endpoint(noise, 25)) < 0.7  # the endpoint of a quadratic fit: √(9/25)≈0.6


def test_the_wald_pulse_peaks_at_its_mode_and_is_zero_before_its_start() -> None:
    t = np.arange(0.0, 10.0, 0.0005)
    mean, shape = 0.5, 1.0
    p = wald_pulse(t, 2.0, mean, shape)
    mode = mean * (np.sqrt(1.0 + (1.5 * mean / shape) ** 2) - 1.5 * mean / shape)
    assert p.max() == pytest.approx(1.0) and np.all(p[t <= 2.0] == 0.0)
    assert t[np.argmax(p)] - 2.0 == pytest.approx(mode, abs=0.001)
    # right-skewed: more of it after its peak than before
    assert p[t > t[np.argmax(p)]].sum() > 1.5 * p[t < t[np.argmax(p)]].sum()


def test_the_sag_moment_is_a_second_harmonic_of_the_segments_direction() -> None:
    np.testing.assert_allclose(sag_moment(np.array([0.0, np.pi / 4.0, np.pi / 2.0, -np.pi / 4.0])),
                               [0.0, 0.5, 0.0, -0.5], atol=1e-12)


def test_the_loose_connector_toggles_between_two_levels() -> None:
    t = np.arange(0.0, 100.0, 0.01)
    level = telegraph(t, np.array([20.0, 50.0, 70.0]), 1.0)
    for at, want in ((10.0, 0.0), (35.0, 1.0), (60.0, 0.0), (90.0, 1.0)):
        assert level[np.searchsorted(t, at)] == pytest.approx(want, abs=1e-6)
    rise = t[(level > 0.1) & (level < 0.9) & (t < 30.0)]
    assert rise.max() - rise.min() == pytest.approx(1.0, abs=0.02)


def test_the_ramberg_osgood_strap_gives_more_per_newton_metre_as_it_yields() -> None:
    give = ramberg_osgood_give(np.array([0.01, 5.0, 10.0, -10.0]), 0.1, 10.0, 0.5, 3.0)
    per_nm = give[:3] / np.array([0.01, 5.0, 10.0])
    assert per_nm[0] == pytest.approx(0.1, rel=1e-5) and per_nm[2] == pytest.approx(0.15)
    assert per_nm[0] < per_nm[1] < per_nm[2] and give[3] == -give[2]


def test_the_play_holds_inside_its_gap_and_the_rubber_follows_it() -> None:
    deg = np.concatenate([np.linspace(0.0, 5.0, 51), np.linspace(5.0, 3.0, 21)[1:]])
    out = play(deg, 2.0)
    assert out[0] == 0.0 and out[50] == pytest.approx(4.0)
    assert np.all(out[51:70] == pytest.approx(4.0)) and out[-1] == pytest.approx(4.0)  # 2° back: the gap's width
    t = np.arange(0.0, 3.0, 0.001)
    step = critically_damped(np.where(t > 0.5, 1.0, 0.0), t, 5.0)
    w = 2.0 * np.pi * 5.0
    u = t[t > 0.5] - 0.5
    np.testing.assert_allclose(step[t > 0.5], 1.0 - (1.0 + w * u) * np.exp(-w * u), atol=0.02)
    assert step.max() <= 1.0 + 1e-6  # no overshoot


def test_the_encoders_eccentricity_is_a_once_per_turn_error_of_its_stated_size() -> None:
    theta = np.linspace(-np.pi, np.pi, 3601)
    err = np.degrees(encoder_eccentricity(theta, 0.05, 0.3) - theta)
    assert np.max(np.abs(err)) == pytest.approx(0.05, rel=1e-4)


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ac(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ac("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ac("knee", ("time_delay",), 5)
    assert 0.02 <= delay.effects["time_delay"] <= 0.45
    drift = generate_ac("knee", ("sensor_drift",), 5)
    switches = np.array(drift.details["switch_s"])
    assert 2 <= switches.size <= 5 and np.all(np.diff(switches) >= 0.1 * np.nanmax(drift.time_s) * 0.99)
