"""The twenty-seventh generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_aa_truth import (
    NOISE_SD_NM,
    battery_sag,
    clonus,
    drive_noise,
    eddy_current_brake,
    generate_aa,
    hand_bends,
    held_late,
    locking_strap_give,
    off_axis_weight,
    paused_ramps,
    strap_joined_spring,
    two_stage_stop,
    venous_pooling,
    worn_bearing_friction,
    yeoh_end,
)


def test_the_yeoh_end_is_flat_before_its_onset_and_follows_yeohs_uniaxial_stress_past_it() -> None:
    assert abs(float(yeoh_end(np.array(-40.0), 1.0, 20.0, 0.3, 0.2))) < 1e-12
    # far past the onset (x̄ = x): at a stretch of 2, I₁ − 3 = 4 + 1 − 3 = 2, so 2·(4 − 0.5)·(1 + 4c₂ + 12c₃)
    assert float(yeoh_end(np.array(20.0), 0.01, 20.0, 0.3, 0.2)) == pytest.approx(7.0 * (1.0 + 1.2 + 2.4), rel=1e-6)
    # c₂ = c₃ = 0 is the neo-Hookean 2(λ² − 1/λ); the Yeoh terms stiffen it ever more with the stretch
    x = np.linspace(0.0, 30.0, 31)
    ratio = yeoh_end(x, 0.01, 15.0, 0.3, 0.2)[1:] / yeoh_end(x, 0.01, 15.0, 0.0, 0.0)[1:]
    assert np.all(np.diff(ratio) > 0.0)


def test_the_strap_joins_the_spring_past_its_angle_and_adds_its_stiffness() -> None:
    h = 1e-4
    below = strap_joined_spring(np.array([1.0, 1.0 + h]), 8.0, 0.5, 0.2)
    above = strap_joined_spring(np.array([14.0, 14.0 + h]), 8.0, 0.5, 0.2)
    assert (below[1] - below[0]) / h == pytest.approx(1.0, abs=1e-6)
    assert (above[1] - above[0]) / h == pytest.approx(1.5, rel=1e-6)
    assert float(strap_joined_spring(np.array(-3.0), 8.0, 0.5, 1.0)) == 0.0
    assert float(strap_joined_spring(np.array(0.0), 8.0, 0.5, 1.0)) == pytest.approx(0.0, abs=1e-12)


def test_ramps_pause_at_every_turn_and_run_at_their_speed_with_a_ripple() -> None:
    rate = 200.0
    deg = paused_ramps(np.random.default_rng(4), 10.0, 80.0, rate)
    speed = np.abs(np.diff(deg)) * rate
    assert deg.min() == pytest.approx(10.0, abs=0.01) and deg.max() == pytest.approx(80.0, abs=0.01)
    moving = speed[speed > 1.0]
    assert 3.0 * 0.95 <= np.median(moving) <= 7.0 * 1.05 and moving.max() <= 7.0 * 1.04 + 1e-6
    still = speed < 1e-6
    runs = np.diff(np.flatnonzero(np.diff(np.concatenate([[0], still.astype(int), [0]]))))[::2]
    assert (runs >= 0.2 * rate - 0.15 * rate).sum() >= 6  # a pause at every turn (less the smoothing's share)


def test_orthosis_bends_start_and_end_at_zero_and_reach_their_peaks_smoothly() -> None:
    rate = 500.0
    deg = hand_bends(np.random.default_rng(6), rate)
    assert abs(deg[0]) < 1e-12 and abs(deg[-1]) < 1e-12 and 10.0 <= deg.max() <= 20.0 and deg.min() >= 0.0
    peaks = np.flatnonzero((deg[1:-1] > deg[:-2]) & (deg[1:-1] >= deg[2:]) & (deg[1:-1] > 9.0))
    assert 5 <= peaks.size <= 9  # one top per bend, no tremor's wiggles
    # a half cosine of amplitude A over T peaks at π·A/(2·T) per second: A ≤ 20°, T ≥ 1 s
    assert np.max(np.abs(np.diff(deg))) * rate <= np.pi * 20.0 / 2.0 * 1.01


def test_the_worn_bearing_resists_the_motion_with_a_level_varying_with_the_angle() -> None:
    deg = np.linspace(0.0, 40.0, 401)
    f = worn_bearing_friction(deg, np.full(deg.size, 5.0), 0.4, 20.0, 0.5)
    assert np.all(f > 0)
    assert f.max() / f.min() == pytest.approx(1.4 / 0.6, rel=1e-2)
    assert np.all(worn_bearing_friction(deg, np.full(deg.size, -5.0), 0.4, 20.0, 0.5) < 0)


def test_the_eddy_current_brake_is_linear_at_low_speed_and_peaks_at_its_critical_speed() -> None:
    v = np.array([1e-4, 1.0, 2.0, 4.0])
    out = eddy_current_brake(v, 2.0)
    assert out[0] == pytest.approx(1e-4, rel=1e-6) and out[2] == pytest.approx(1.0) and out[2] > out[1] > out[0]
    assert out[3] < out[2]
    np.testing.assert_allclose(eddy_current_brake(-v, 2.0), -out)


def test_the_bumper_is_soft_through_its_pad_and_stiff_past_it() -> None:
    h = 1e-4
    for high, sign in ((True, 1.0), (False, -1.0)):
        at = 50.0
        pad = np.array([at + sign * 0.5, at + sign * (0.5 + h)])
        past = np.array([at + sign * 4.0, at + sign * (4.0 + h)])
        k_pad = abs(np.diff(two_stage_stop(pad, at, high, 2.0, 6.0))[0]) / h
        k_past = abs(np.diff(two_stage_stop(past, at, high, 2.0, 6.0))[0]) / h
        assert k_pad == pytest.approx(1.0, abs=0.05) and k_past == pytest.approx(7.0, rel=2e-3)  # joined over 0.3°
        assert float(two_stage_stop(np.array(at - sign * 3.0), at, high, 2.0, 6.0)) == 0.0


def test_the_bus_delivers_held_samples_late_and_never_out_of_order() -> None:
    rate = 1000.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    torque = np.sin(2.0 * np.pi * 0.3 * t)
    out, delay = held_late(torque, t, 0.2, 0.01, 25.0, np.random.default_rng(1))
    assert delay == pytest.approx(0.2 + 0.02)
    lags = np.arange(0, 600)
    errors = [np.mean((out[600:] - torque[600 - k:t.size - k]) ** 2) for k in lags]
    assert int(np.argmin(errors)) / rate == pytest.approx(delay, abs=0.015)
    changes = np.flatnonzero(np.diff(out) != 0)
    assert np.all(np.diff(changes) >= 1)  # a step at most every sample: held values


def test_clonus_beats_under_its_envelope_and_is_zero_outside() -> None:
    t = np.arange(0.0, 10.0, 0.001)
    c = clonus(t, 3.0, 1.5, 6.0)
    assert c.max() == pytest.approx(1.0) and np.all(c[(t < 3.0) | (t > 4.5)] == 0.0) and np.all(c >= 0.0)
    inside = (t > 3.3) & (t < 4.2)
    spectrum = np.abs(np.fft.rfft(c[inside] - c[inside].mean()))
    freqs = np.fft.rfftfreq(int(inside.sum()), 0.001)
    assert 4.5 <= freqs[np.argmax(spectrum[freqs > 2.0]) + np.flatnonzero(freqs > 2.0)[0]] <= 7.5


def test_a_running_down_battery_stays_flat_then_rises_ever_faster_to_one_at_the_end() -> None:
    t = np.linspace(0.0, 100.0, 1001)
    sag = battery_sag(t, 100.0, 0.8)
    assert sag[0] == 0.0 and sag[-1] == pytest.approx(1.0) and np.all(np.diff(sag, 2) > 0.0)
    assert sag[500] == pytest.approx((1.0 / 0.6 - 1.0) / 4.0)  # at half time: a sixth of the way


def test_pooling_blood_adds_weight_that_settles_with_its_time_constant() -> None:
    t = np.array([0.0, 60.0, 600.0])
    np.testing.assert_allclose(venous_pooling(t, 60.0), [0.0, 1.0 - np.exp(-1.0), 1.0 - np.exp(-10.0)])


def test_the_drive_noise_grows_with_the_speed() -> None:
    vel = np.concatenate([np.zeros(20000), np.full(20000, 0.1)])
    noise = drive_noise(np.random.default_rng(3), vel, 0.2)
    rest, moving = float(np.std(noise[:20000])), float(np.std(noise[20000:]))
    assert rest == pytest.approx(0.2, rel=0.03) and 1.3 * 0.97 <= moving / rest <= 1.8 * 1.03


def test_the_locking_strap_gives_less_per_newton_metre_under_load() -> None:
    give = locking_strap_give(np.array([0.1, 10.0, 100.0]), 0.2, 10.0)
    per_nm = give / np.array([0.1, 10.0, 100.0])
    assert per_nm[0] == pytest.approx(0.2, rel=1e-3) and per_nm[0] > per_nm[1] > per_nm[2]
    assert abs(give[2]) <= 0.2 * 10.0 + 1e-12


def test_the_off_axis_weights_inertia_changes_along_the_range_with_its_centripetal_term() -> None:
    rad = np.linspace(0.0, 1.0, 11)
    zero_vel = off_axis_weight(rad, np.zeros(11), np.ones(11), 0.0, 1.0, 0.3)
    np.testing.assert_allclose(zero_vel, 1.0 + 0.3 * (2.0 * rad - 1.0))
    no_acc = off_axis_weight(rad, np.full(11, 2.0), np.zeros(11), 0.0, 1.0, 0.3)
    np.testing.assert_allclose(no_acc, 0.5 * 0.6 * 4.0)


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_aa(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_aa("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_aa("knee", ("time_delay",), 5)
    assert 0.03 + 0.5 / 50.0 - 1e-9 <= delay.effects["time_delay"] <= 0.4 + 0.5 / 20.0 + 1e-9
