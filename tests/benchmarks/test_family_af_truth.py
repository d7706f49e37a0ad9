"""The thirty-second generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_af_truth import (
    NOISE_SD_NM,
    adc_nonlinearity,
    alpha_triplet,
    cam_follower_friction,
    flores_contact,
    generate_af,
    gompertz_zero,
    hart_smith_band,
    kaiser_low_pass,
    knowles_tension,
    pyramid_bends,
    rate_stiffening_compliance,
    sliding_counterweight,
    student_noise,
    two_speed_strokes,
    warming_damper,
)


def test_the_knowles_end_is_flat_before_its_onset_and_neo_hookean_at_unit_exponent() -> None:
    assert abs(float(knowles_tension(np.array(-60.0), 2.0, 20.0, 2.0, 1.0))) < 1e-9
    lam = 1.5  # far past the onset (x̄ = x)
    neo = lam - lam**-2
    assert float(knowles_tension(np.array(10.0), 0.01, 20.0, 1.0, 1.0)) == pytest.approx(neo)
    invariant = lam**2 + 2 / lam
    assert float(knowles_tension(np.array(10.0), 0.01, 20.0, 2.5, 1.5)) == pytest.approx(
        (1 + 1.5 / 2.5 * (invariant - 3)) ** 1.5 * neo)


def test_the_hart_smith_band_is_zero_unbent_and_stiffens_faster_than_the_neo_hookean() -> None:
    assert float(hart_smith_band(np.array(0.0), 1.0, 0.5, 60.0, 1.0)) == pytest.approx(0.0, abs=1e-12)
    plain = hart_smith_band(np.array([10.0, 20.0]), 0.0, 1e-3, 60.0, 0.0)
    stiff = hart_smith_band(np.array([10.0, 20.0]), 0.0, 1e-3, 60.0, 5.0)
    assert stiff[1] / stiff[0] > 1.3 * (plain[1] / plain[0]) and plain[1] / plain[0] == pytest.approx(0.7708 / 0.4319, rel=1e-3)


def test_strokes_run_one_way_slower_than_the_other_and_hold_at_one_end() -> None:
    deg = two_speed_strokes(np.random.default_rng(1), 10.0, 90.0, 100.0)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 90.0 + 1e-9 and deg.max() > 84.0 and deg.min() < 16.0
    speed = np.diff(deg) * 100.0
    up, down = np.percentile(speed[speed > 0.5], 90), np.percentile(-speed[speed < -0.5], 90)
    assert 3.0 - 1e-6 <= min(up, down) <= 5.0 + 1e-6 and 5.0 - 1e-6 <= max(up, down) <= 8.0 + 1e-6


def test_the_bends_rise_and_fall_in_depth() -> None:
    deg = pyramid_bends(np.random.default_rng(2), 100.0)
    assert deg[0] == 0.0 and 18.0 <= deg.max() <= 20.0 and deg[-1] == pytest.approx(0.0, abs=1e-9)
    tops = [float(deg[i]) for i in range(1, deg.size - 1) if deg[i] > 1.0 and deg[i] >= deg[i - 1] and deg[i] > deg[i + 1]]
    peak = int(np.argmax(tops))
    assert np.all(np.diff(tops[:peak + 1]) >= -1e-9) and np.all(np.diff(tops[peak:]) <= 1e-9) and len(tops) >= 6


def test_the_cam_followers_friction_level_follows_the_angle() -> None:
    deg = np.array([0.0, 10.0, 20.0, 30.0])
    f = cam_follower_friction(deg, np.full(4, 50.0), 0.3, 40.0, 0.0, 0.5)
    assert f == pytest.approx([1.0, 1.3, 1.0, 0.7], abs=1e-6)
    assert cam_follower_friction(deg, np.full(4, -50.0), 0.3, 40.0, 0.0, 0.5) == pytest.approx(-f)


def test_the_warming_damper_thins_with_the_work_it_has_dissipated() -> None:
    t = np.linspace(0.0, 10.0, 1001)
    vel = np.ones_like(t)
    d = warming_damper(vel, t, 0.5)
    assert d[1] == pytest.approx(1.0, abs=0.01) and d[-1] == pytest.approx(1.0 / 1.5) and np.all(np.diff(d) <= 1e-12)


def test_flores_contact_pushes_past_its_angle_and_more_while_closing() -> None:
    deg = np.array([40.0, 50.0, 54.0, 54.0])
    vel = np.array([5.0, 5.0, 5.0, -5.0])
    f = flores_contact(deg, vel, 50.0, True, 0.5)
    assert f[0] == 0.0 and f[1] == 0.0
    assert f[3] == pytest.approx(4.0**1.5) and f[2] == pytest.approx(4.0**1.5 * (1 + 8 * 0.5 / 2.5))
    low = flores_contact(np.array([-10.0]), np.array([-5.0]), -6.0, False, 0.9)
    assert float(low[0]) < 0.0


def test_the_kaiser_filter_passes_a_slow_signal_late_by_its_half_length() -> None:
    rate = 200.0
    t = np.arange(0.0, 30.0, 1.0 / rate)
    x = np.sin(2 * np.pi * 0.1 * t)
    y, delay = kaiser_low_pass(x, rate, 4.0, 6.0, 0.1)
    assert delay == pytest.approx(0.1)
    late = t > 5.0
    assert np.max(np.abs(y[late] - np.sin(2 * np.pi * 0.1 * (t[late] - delay)))) < 1e-3


def test_the_alpha_triplet_peaks_three_times_after_its_start() -> None:
    t = np.arange(0.0, 2.0, 0.001)
    s = alpha_triplet(t, 0.5, 0.05, (0.2, 0.2), (1.0, 0.8, 0.5))
    assert np.all(s[t < 0.5] == 0.0)
    assert s[np.argmin(np.abs(t - 0.55))] == pytest.approx(1.0, abs=0.01)
    peaks = [i for i in range(1, t.size - 1) if s[i] > s[i - 1] and s[i] >= s[i + 1]]
    assert len(peaks) == 3


def test_the_gompertz_zero_rises_from_near_zero_to_one_through_its_inflection() -> None:
    t = np.linspace(0.0, 100.0, 1001)
    b = 5.0
    z = gompertz_zero(t, b, np.log(b) / 40.0)
    assert z[0] == pytest.approx(np.exp(-b)) and z[-1] > 0.9 and np.all(np.diff(z) > 0)
    slope = np.gradient(z, t)
    assert t[int(np.argmax(slope))] == pytest.approx(40.0, abs=0.2)


def test_the_strap_gives_less_when_loaded_fast() -> None:
    c = rate_stiffening_compliance(np.array([0.0, 1.0, 100.0]), 0.1, 0.3, 1.0)
    assert c[0] == pytest.approx(0.1) and c[2] == pytest.approx(0.07, abs=1e-6) and c[0] > c[1] > c[2]


def test_the_sliding_counterweights_inertia_grows_along_the_range() -> None:
    rad = np.array([0.0, 1.0])
    out = sliding_counterweight(rad, np.zeros(2), np.ones(2), 0.0, 1.0, 1.0)
    assert out == pytest.approx([1.0, 2.0])
    assert sliding_counterweight(np.array([0.5]), np.array([2.0]), np.zeros(1), 0.0, 1.0, 1.0)[0] == pytest.approx(2.0)


def test_student_noise_has_the_sd_and_heavier_tails_than_gaussian() -> None:
    x = student_noise(np.random.default_rng(3), 200_000, 0.5)
    assert float(np.std(x)) == pytest.approx(0.5, rel=0.05)
    kurtosis = float(np.mean((x / np.std(x)) ** 4))
    assert kurtosis > 3.3


def test_the_adcs_bow_is_zero_at_zero_and_full_scale_and_peaks_at_its_share() -> None:
    torque = np.array([0.0, 10.0, -10.0, 10.0 / np.sqrt(3.0)])
    read = adc_nonlinearity(torque, 10.0, 0.002)
    assert read[:3] == pytest.approx(torque[:3]) and abs(read[3] - torque[3]) == pytest.approx(0.02)


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_af(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_af("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_af("knee", ("time_delay",), 5)
    assert 0.02 <= delay.effects["time_delay"] <= 0.35 + 0.15 + 0.01
    compliance = generate_af("knee", ("series_compliance",), 5)
    assert 0.0 < compliance.effects["series_compliance"] < 0.5
    for seed in range(4):  # a stop anywhere in the last 5–30 % of either end
        stop = generate_af("ankle", ("hard_stop",), seed)
        bottom, top = stop.details["range_deg"]
        into = (top - stop.details["stop_deg"] if stop.details["stop_end"] == "high" else stop.details["stop_deg"] - bottom)
        assert 0.05 - 1e-9 <= into / (top - bottom) <= 0.3 + 1e-9
