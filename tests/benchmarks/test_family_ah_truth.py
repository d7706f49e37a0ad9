"""The thirty-fourth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ah_truth import (
    NOISE_SD_NM,
    brownian_part,
    carroll_tension,
    clipped,
    gas_spring,
    generate_ah,
    held_bends,
    missing_codes,
    mounted_mass,
    preloaded_stop,
    rayleigh_pulse,
    running_in_friction,
    stiffness_proportional_damping,
    thiran_allpass,
    triangle_strokes,
    two_slope_cable,
    underdamped_settling,
)


def test_the_carroll_end_is_flat_before_its_onset_and_follows_its_invariants_past_it() -> None:
    assert abs(float(carroll_tension(np.array(-60.0), 2.0, 20.0, 5e-4, 0.5))) < 1e-9
    lam = 1.5  # far past the onset (x̄ = x)
    i1, i2 = lam**2 + 2 / lam, 2 * lam + lam**-2
    expected = 2 * (lam - lam**-2) * (1 + 4 * 5e-4 * i1**3 + 0.5 / (2 * lam * np.sqrt(i2)))
    assert float(carroll_tension(np.array(10.0), 0.01, 20.0, 5e-4, 0.5)) == pytest.approx(expected)


def test_the_gas_spring_is_zero_unbent_and_stiffens_toward_its_closing_angle() -> None:
    assert float(gas_spring(np.array(0.0), 1.0, 0.5, 60.0, 1.3)) == pytest.approx(0.0, abs=1e-12)
    assert float(gas_spring(np.array(30.0), 0.0, 1e-4, 60.0, 1.0)) == pytest.approx(1.0, rel=1e-3)  # (1 − ½)^−1 − 1
    slope = np.gradient(gas_spring(np.linspace(5.0, 20.0, 16), 1.0, 0.5, 50.0, 1.2))
    assert np.all(np.diff(slope) > 0.0)


def test_strokes_are_triangles_in_speed() -> None:
    deg = triangle_strokes(np.random.default_rng(1), 10.0, 90.0, 100.0)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 90.0 + 1e-9
    speed = np.abs(np.diff(deg)) * 100.0
    assert speed.max() <= 12.0 * 1.01 and speed.max() >= 6.0 * 0.95
    accel = np.diff(deg, 2) * 100.0**2
    moving = speed[1:] > 0.5
    assert np.percentile(np.abs(accel[moving]), 90) < 10.0  # uniform: no jerks bigger than the turn


def test_the_bends_hold_at_their_bottom() -> None:
    deg = held_bends(np.random.default_rng(2), 100.0)
    assert deg[0] == 0.0 and 12.0 <= deg.max() <= 20.0 and deg[-1] == pytest.approx(0.0, abs=1e-9)
    held = np.diff(deg) == 0.0
    assert np.sum(held & (deg[1:] > 11.0)) / 100.0 >= 4 * 1.5 - 0.1


def test_the_friction_runs_in_over_the_trial() -> None:
    t = np.linspace(0.0, 100.0, 1001)
    f = running_in_friction(t, np.full(t.size, 50.0), 0.3, 20.0, 0.5)
    assert f[0] == pytest.approx(1.0) and f[-1] == pytest.approx(1.0 - 0.3 * (1 - np.exp(-5.0))) and np.all(np.diff(f) < 0)
    assert running_in_friction(t[:1], np.array([-50.0]), 0.3, 20.0, 0.5)[0] == pytest.approx(-1.0)


def test_the_structural_damping_follows_the_local_stiffness() -> None:
    d = stiffness_proportional_damping(np.array([0.0, 1.0, 3.0]), np.array([1.0, 1.0, -1.0]))
    mean = 4.0 / 3.0
    assert d == pytest.approx([0.1 * mean, 1.0 + 0.1 * mean, -(3.0 + 0.1 * mean)])


def test_the_preloaded_stop_steps_at_contact_then_rises_linearly() -> None:
    f = preloaded_stop(np.array([40.0, 49.0, 51.0, 55.0]), 50.0, True, 0.5)
    assert f[0] == 0.0 and f[1] < 0.2 and f[2] == pytest.approx(10.0 + 1.0, abs=0.05) and f[3] == pytest.approx(15.0, abs=1e-3)
    assert float(preloaded_stop(np.array([-10.0]), -6.0, False, 0.4)[0]) < 0.0


def test_the_thiran_allpass_delays_a_slow_signal_by_its_fractional_delay() -> None:
    rate = 100.0
    t = np.arange(0.0, 60.0, 1.0 / rate)
    x = np.sin(2 * np.pi * 0.2 * t)
    y = thiran_allpass(x, 4, 4.4)
    late = t > 5.0
    assert np.max(np.abs(y[late] - np.sin(2 * np.pi * 0.2 * (t[late] - 4.4 / rate)))) < 1e-3


def test_the_rayleigh_pulse_peaks_at_one_a_width_after_its_start() -> None:
    t = np.arange(0.0, 5.0, 0.001)
    s = rayleigh_pulse(t, 1.0, 0.3)
    assert np.all(s[t < 1.0] == 0.0) and float(s.max()) == pytest.approx(1.0, abs=1e-6)
    assert float(t[int(np.argmax(s))]) == pytest.approx(1.3, abs=0.002)


def test_the_settling_zero_overshoots_and_settles_at_one() -> None:
    t = np.linspace(0.0, 500.0, 5001)
    z = underdamped_settling(t, 50.0, 150.0)
    assert z[0] == pytest.approx(0.0) and z.max() > 1.0 and z[-1] == pytest.approx(1.0, abs=0.01)


def test_the_cable_gives_less_past_its_knee() -> None:
    give = two_slope_cable(np.array([1.0, 4.0, -4.0]), 0.1, 2.0, 4.0)
    assert give == pytest.approx([0.1, 0.2 + 0.05, -0.25])


def test_the_mass_is_mounted_partway() -> None:
    share = mounted_mass(np.array([0.0, 50.0, 100.0]), 50.0)
    assert share[0] < 1e-6 and share[1] == pytest.approx(0.5) and share[2] > 1 - 1e-6


def test_the_nuisances_brownian_part_missing_codes_and_clipping() -> None:
    part = brownian_part(np.random.default_rng(4), 20_000, 100.0, 0.02)
    assert float(np.sqrt(np.mean(part**2))) == pytest.approx(0.02)
    read = missing_codes(np.arange(0.0, 1.0, 0.01), 0.01, 32)
    assert 0.32 not in np.round(read, 6) and read[33] == pytest.approx(0.33)
    assert clipped(np.array([-10.0, 5.0, 8.0]), 0.9).tolist() == [-9.0, 5.0, 8.0]


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ah(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ah("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ah("knee", ("time_delay",), 5)
    assert 0.0 < delay.effects["time_delay"] <= 0.45 + 7 / 100 + 1e-9
    compliance = generate_ah("knee", ("series_compliance",), 5)
    assert 0.0 < compliance.effects["series_compliance"] < 0.5
    assert generate_ah("ankle", ("inertia",), 5).effects["inertia"] > 0.0
    for seed in range(4):  # a stop anywhere in the last 5–30 % of either end
        stop = generate_ah("ankle", ("hard_stop",), seed)
        bottom, top = stop.details["range_deg"]
        into = (top - stop.details["stop_deg"] if stop.details["stop_end"] == "high" else stop.details["stop_deg"] - bottom)
        assert 0.05 - 1e-9 <= into / (top - bottom) <= 0.3 + 1e-9
