"""The thirteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_m_truth import (
    NOISE_SD_NM,
    cascaded_low_pass,
    foam_stop,
    generate_m,
    rippled_friction,
    servo_strokes,
    slowed_by_load,
    thermostat_drift,
    tremor_burst,
    worm_like_chain,
)


def test_the_worm_like_chain_is_zero_before_its_onset_linear_at_first_and_diverges_at_its_contour() -> None:
    x = np.linspace(-5.0, 9.9, 1491)
    f = worm_like_chain(x, 10.0)
    assert np.all(f[x <= 0.0] == 0.0)
    small = np.array([1e-4])
    assert worm_like_chain(small, 10.0)[0] == pytest.approx(1.5 * 1e-5, rel=1e-3)  # slope 3/(2L) at the onset
    assert worm_like_chain(np.array([9.0]), 10.0)[0] == pytest.approx(0.25 / 0.01 - 0.25 + 0.9)
    assert np.all(np.diff(f[x > 0.0]) > 0.0)


def test_a_loaded_servo_is_slower_where_the_load_is_larger_and_follows_the_same_path() -> None:
    rate = 100.0
    path = servo_strokes(np.random.default_rng(2), 0.0, 60.0, rate)
    load = np.clip(path - 40.0, 0.0, None) ** 2  # a load only past 40°
    slowed = slowed_by_load(path, load, 0.5, rate)
    assert slowed.size > path.size  # the loaded part takes longer
    assert slowed.min() == pytest.approx(0.0, abs=1e-9) and slowed.max() == pytest.approx(60.0, abs=1e-6)
    speed = np.abs(np.gradient(slowed, 1.0 / rate))
    cruise_free = np.median(speed[(slowed > 15.0) & (slowed < 30.0)])
    cruise_loaded = np.median(speed[(slowed > 57.0) & (slowed < 59.0)])
    assert cruise_loaded < 0.7 * cruise_free  # 1 − 0.5·(load near the top)/(largest load)
    np.testing.assert_allclose(slowed_by_load(path, np.zeros_like(path), 0.5, rate), path, atol=1e-9)  # no load


def test_the_bearings_friction_ripples_with_the_angle_and_opposes_the_motion() -> None:
    deg = np.linspace(0.0, 20.0, 2001)
    up = rippled_friction(deg, np.full(deg.size, 5.0), 0.4, 10.0, 0.0)
    down = rippled_friction(deg, np.full(deg.size, -5.0), 0.4, 10.0, 0.0)
    np.testing.assert_allclose(up, -down)
    assert up.max() == pytest.approx(1.4) and up.min() == pytest.approx(0.6, abs=1e-4)
    assert up[0] == pytest.approx(up[1000]) == pytest.approx(up[2000])  # its period, 10°
    assert np.all(rippled_friction(deg, np.full(deg.size, 0.01), 0.4, 10.0, 0.0) == 0.0)  # at rest


def test_a_foam_stop_takes_a_set_after_each_contact() -> None:
    deg = np.concatenate([np.linspace(0.0, 12.0, 121), np.linspace(12.0, 0.0, 121)] * 3)
    shape = foam_stop(deg, 10.0, True, 1.5, 0.25)
    assert np.all(shape[deg <= 10.0] == 0.0) and np.all(shape >= 0.0)
    peaks = [shape[k * 242:(k + 1) * 242].max() for k in range(3)]
    # each contact leaves the stop a quarter of its penetration deeper: 2°, 1.5°, 1.125° of penetration
    np.testing.assert_allclose(peaks, [2.0**1.5, 1.5**1.5, 1.125**1.5], rtol=1e-9)
    low = foam_stop(-deg, -10.0, False, 1.5, 0.25)
    np.testing.assert_allclose(low, -shape)


def test_two_cascaded_low_passes_lag_a_slow_ramp_by_their_group_delay() -> None:
    rate = 500.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    y, delay = cascaded_low_pass(t.copy(), 0.1, rate)
    assert delay == pytest.approx(0.2, abs=0.002)
    assert np.mean((t - y)[t > 3.0]) == pytest.approx(delay, rel=1e-6)  # a ramp lags by the DC group delay
    const, _ = cascaded_low_pass(np.full(100, 3.0), 0.1, rate)
    np.testing.assert_allclose(const, 3.0)  # started at rest on its input


def test_the_tremor_burst_rides_on_a_gaussian_envelope_of_peak_one() -> None:
    t = np.arange(0.0, 4.0, 1e-3)
    x = tremor_burst(t, 2.0, 0.3, 10.0, 0.5, 0.0)
    assert np.all(x >= 0.0) and 1.0 < x.max() <= 1.5
    # averaged over whole tremor periods the ripple leaves the envelope
    window = 100
    mean = np.convolve(x, np.ones(window) / window, mode="same")
    assert mean[2000] == pytest.approx(1.0, abs=0.01)
    assert x[:500].max() < 1e-5 and x[-500:].max() < 1e-5  # 5 SD from its centre


def test_the_thermostat_drift_cycles_through_its_lag_about_zero() -> None:
    t = np.arange(0.0, 200.0, 0.1)
    y = thermostat_drift(t, 40.0, 0.5, 5.0, 0.0)
    assert y[0] == 0.0 and np.abs(y).max() < 0.5
    late = y[t > 80.0]
    assert late.max() > 0.3 and late.min() < -0.3  # it swings both ways of its start
    # one period apart the cycle repeats (once the start has settled)
    np.testing.assert_allclose(y[(t > 120.0) & (t < 160.0)], y[(t > 160.0) & (t < 200.0)][:400], atol=1e-3)


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_m("ankle", ("time_delay",), s) for s in range(20)]
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.15
    assert all(0.03 <= g.effects["time_delay"] <= 0.45 for g in delays)
    for s in range(5):
        g = generate_m("knee", ("activation_burst",), s)
        share = g.details["tremor_share"]
        assert (3.0 * 0.8 * NOISE_SD_NM["knee"] / (1.0 + share) <= g.effects["activation_burst"]
                <= 5.0 * 1.25 * NOISE_SD_NM["knee"])
        g = generate_m("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_m("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"} and all(1.2 <= d["stop_exponent"] <= 1.8 for d in stops)
    comp = [generate_m("knee", ("series_compliance",), s) for s in range(4)]
    assert all(0.02 <= g.effects["series_compliance"] <= 0.3 for g in comp)
