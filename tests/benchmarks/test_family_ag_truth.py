"""The thirty-third generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ag_truth import (
    NOISE_SD_NM,
    check_valve_damper,
    compacting_cuff,
    cycloidal_strokes,
    ex_gaussian,
    generate_ag,
    herschel_bulkley_friction,
    heteroscedastic_noise,
    lankarani_contact,
    misaligned_axis,
    rolling_cantilever,
    running_median,
    shuffled_bends,
    square_root_creep,
    swanson_tension,
    two_mass_angle,
)


def test_the_swanson_end_is_flat_before_its_onset_and_neo_hookean_at_zero_power() -> None:
    assert abs(float(swanson_tension(np.array(-60.0), 2.0, 20.0, 3.0))) < 1e-9
    lam = 1.5  # far past the onset (x̄ = x)
    assert float(swanson_tension(np.array(10.0), 0.01, 20.0, 0.0)) == pytest.approx(lam - lam**-2)
    invariant = lam**2 + 2 / lam
    assert float(swanson_tension(np.array(10.0), 0.01, 20.0, 4.0)) == pytest.approx((lam - lam**-2) * (invariant / 3) ** 4)


def test_the_rolling_cantilever_is_zero_unbent_and_stiffens_as_its_free_length_shortens() -> None:
    assert float(rolling_cantilever(np.array(0.0), 1.0, 0.5, 90.0)) == pytest.approx(0.0, abs=1e-12)
    # the integral of 1/(1 − θ/θm)³ from 0 to 45° of θm = 90°: ½·90·(4 − 1) = 135
    assert float(rolling_cantilever(np.array(45.0), 0.0, 1e-4, 90.0)) == pytest.approx(135.0, rel=1e-3)
    slope = np.gradient(rolling_cantilever(np.linspace(5.0, 20.0, 16), 1.0, 0.5, 60.0))
    assert np.all(np.diff(slope) > 0.0)


def test_strokes_are_cycloids_at_their_own_speeds_turning_short_of_the_ends() -> None:
    deg = cycloidal_strokes(np.random.default_rng(1), 10.0, 90.0, 100.0)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 90.0 + 1e-9 and deg.max() > 84.0 - 1e-9 and deg.min() < 16.0 + 1e-9
    speed = np.abs(np.diff(deg)) * 100.0
    assert speed.max() <= 2.0 * 7.0 * 1.01 and speed.max() > 2.0 * 3.0 * 0.95  # a cycloid peaks at twice its mean
    tops = {round(float(deg[i]), 6) for i in range(1, deg.size - 1) if deg[i] > 60.0 and deg[i] >= deg[i - 1]
            and deg[i] > deg[i + 1]}
    assert len(tops) >= 3  # each turning point drawn anew


def test_the_bends_go_to_depths_in_random_order() -> None:
    deg = shuffled_bends(np.random.default_rng(2), 100.0)
    assert deg[0] == 0.0 and 10.0 <= deg.max() <= 20.0 and deg[-1] == pytest.approx(0.0, abs=1e-9)
    tops = [float(deg[i]) for i in range(1, deg.size - 1) if deg[i] > 1.0 and deg[i] > deg[i - 1] and deg[i] >= deg[i + 1]]
    assert 6 <= len(tops) <= 9 and all(10.0 <= d <= 20.0 for d in tops)
    steps = np.sign(np.diff(tops))
    assert np.any(steps > 0) and np.any(steps < 0)


def test_the_herschel_bulkley_friction_yields_then_grows_as_a_power_of_the_speed() -> None:
    vel = np.array([-40.0, 10.0, 40.0])
    f = herschel_bulkley_friction(vel, 0.2, 0.5, 0.5)
    assert f[2] == pytest.approx(1.2) and f[0] == pytest.approx(-1.2) and f[1] == pytest.approx(1.0 + 0.2 * 0.5)


def test_the_check_valve_damps_one_way_more() -> None:
    d = check_valve_damper(np.array([-2.0, 2.0]), 1.5, True)
    assert d == pytest.approx([-2.0, 3.0])
    assert check_valve_damper(np.array([-2.0, 2.0]), 1.5, False) == pytest.approx([-3.0, 2.0])


def test_the_lankarani_contact_pushes_past_its_angle_and_more_while_closing() -> None:
    deg = np.array([40.0, 50.0, 54.0, 54.0])
    vel = np.array([5.0, 5.0, 5.0, -5.0])
    f = lankarani_contact(deg, vel, 50.0, True, 1.5, 0.6)
    assert f[0] == 0.0 and f[1] == 0.0
    assert f[3] == pytest.approx(4.0**1.5) and f[2] == pytest.approx(4.0**1.5 * (1 + 0.75 * (1 - 0.36)))
    assert float(lankarani_contact(np.array([-10.0]), np.array([-5.0]), -6.0, False, 1.0, 0.9)[0]) < 0.0


def test_the_running_median_passes_a_slow_signal_late_by_half_its_window_and_removes_a_spike() -> None:
    rate = 200.0
    t = np.arange(0.0, 30.0, 1.0 / rate)
    x = np.sin(2 * np.pi * 0.1 * t)
    x[3000] += 50.0
    y, delay = running_median(x, rate, 0.1)
    assert delay == pytest.approx(10 / rate)
    late = t > 5.0
    error = np.abs(y[late] - np.sin(2 * np.pi * 0.1 * (t[late] - delay)))
    # exact where the window is monotone and holds no spike (the spike moves the median by one rank: one sample's
    # change); where the signal turns inside the window, the median is off its centre by < 0.5 %
    spiked = (t[late] >= 15.0) & (t[late] <= 15.0 + 2 * delay + 0.01)
    monotone = (np.abs(np.cos(2 * np.pi * 0.1 * (t[late] - delay))) > 0.2) & ~spiked
    assert np.max(error[monotone]) < 1e-12 and np.max(error) < 5e-3


def test_the_ex_gaussian_burst_starts_after_its_onset_peaks_at_one_and_decays_slower_than_it_rises() -> None:
    t = np.arange(0.0, 4.0, 0.001)
    s = ex_gaussian(t, 1.0, 0.05, 0.4)
    assert float(s.max()) == pytest.approx(1.0) and np.all(s[t < 0.85] < 0.01)
    peak = float(t[int(np.argmax(s))])
    rise = peak - float(t[int(np.argmax(s > 0.5))])
    fall = float(t[int(np.argmax((t > peak) & (s < 0.5)))]) - peak
    assert fall > 2.0 * rise


def test_the_misaligned_axis_error_follows_the_segment_direction() -> None:
    assert misaligned_axis(np.array([0.0, np.pi / 2]), 0.0) == pytest.approx([1.0, 0.0], abs=1e-12)


def test_the_square_root_creep_starts_at_its_onset_and_ends_at_one() -> None:
    t = np.linspace(0.0, 100.0, 101)
    z = square_root_creep(t, 20.0)
    assert np.all(z[t <= 20.0] == 0.0) and z[-1] == pytest.approx(1.0) and z[60] == pytest.approx(np.sqrt(40 / 80))


def test_the_cuff_gives_linearly_at_small_torques_and_less_at_large() -> None:
    give = compacting_cuff(np.array([1e-3, 10.0, -10.0]), 0.1, 2.0)
    assert give[0] == pytest.approx(1e-4, rel=1e-5) and give[1] == pytest.approx(0.1 * 2.0 * np.arcsinh(5.0))
    assert give[1] < 0.1 * 10.0 and give[2] == pytest.approx(-give[1])


def test_the_two_mass_angle_follows_slow_motion_and_rings_at_its_resonance() -> None:
    rate = 1000.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    slow = np.sin(2 * np.pi * 0.2 * t)
    follow = two_mass_angle(slow, rate, 10.0, 0.2)
    assert np.max(np.abs(follow[t > 2.0] - slow[t > 2.0])) < 0.01
    step = two_mass_angle((t > 1.0).astype(float), rate, 10.0, 0.2)
    assert float(step.max()) > 1.4  # a step overshoots by e^(−πζ/√(1−ζ²)) ≈ 0.53 at ζ = 0.2


def test_heteroscedastic_noise_has_the_sd_and_grows_with_the_torque() -> None:
    torque = np.concatenate([np.zeros(100_000), np.full(100_000, 10.0)])
    x = heteroscedastic_noise(np.random.default_rng(3), torque, 0.5)
    assert float(np.sqrt(np.mean(x**2))) == pytest.approx(0.5, rel=0.02)
    assert float(np.std(x[100_000:])) > 1.2 * float(np.std(x[:100_000]))


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ag(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ag("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ag("knee", ("time_delay",), 5)
    assert 0.02 <= delay.effects["time_delay"] <= 0.4 + 0.15 + 0.01
    compliance = generate_ag("knee", ("series_compliance",), 5)
    assert 0.0 < compliance.effects["series_compliance"] < 0.5
    assert generate_ag("knee", ("inertia",), 5).effects["inertia"] > 0.0
    for seed in range(4):  # a stop anywhere in the last 5–30 % of either end
        stop = generate_ag("ankle", ("hard_stop",), seed)
        bottom, top = stop.details["range_deg"]
        into = (top - stop.details["stop_deg"] if stop.details["stop_end"] == "high" else stop.details["stop_deg"] - bottom)
        assert 0.05 - 1e-9 <= into / (top - bottom) <= 0.3 + 1e-9
