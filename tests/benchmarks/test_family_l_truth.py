"""The twelfth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_l_truth import (
    NOISE_SD_NM,
    eyring,
    gamma_pulse,
    generate_l,
    jogged_strokes,
    packet_latency,
    power_moment,
    read_newest,
    smoothstep_sign,
    staircase_drift,
)


def test_the_power_law_is_zero_before_the_onset_and_grows_as_its_power() -> None:
    x = np.linspace(-5.0, 20.0, 2501)
    m = power_moment(x, 3.0)
    assert np.all(m[x <= 0.0] == 0.0)
    assert power_moment(np.array([2.0]), 3.0)[0] == pytest.approx(8.0)
    inside = x > 1.0
    np.testing.assert_allclose(np.gradient(np.log(m[inside]), np.log(x[inside]))[5:-5], 3.0, rtol=1e-3)


def test_jogged_strokes_revisit_angles_inside_a_stroke_and_end_on_the_range() -> None:
    rate = 200.0
    jogs = 0
    for seed in range(6):
        deg = jogged_strokes(np.random.default_rng(seed), 5.0, 90.0, rate)
        assert deg.min() == pytest.approx(5.0, abs=1e-9) and deg.max() == pytest.approx(90.0, abs=1e-9)
        vel = np.gradient(deg, 1.0 / rate)
        assert np.abs(vel).max() <= 15.0 * 1.6  # a cosine-ramped stroke peaks at most π/2 × its mean speed
        sign = np.sign(np.where(np.abs(vel) > 0.5, vel, 0.0))
        moving = np.flatnonzero(sign)
        turns = moving[1:][np.diff(sign[moving]) != 0]
        jogs += int(np.sum((deg[turns] > 10.0) & (deg[turns] < 85.0)))  # a turn away from either end: a jog-back
    assert jogs >= 6


def test_eyrings_viscosity_has_unit_slope_at_rest_and_thickens_with_speed() -> None:
    v = np.linspace(-3.0, 3.0, 601)
    f = eyring(v, 1.0)
    assert np.gradient(f, v)[300] == pytest.approx(1.0, rel=1e-4)
    assert np.all(np.diff(np.gradient(f, v)[300:]) > 0.0)  # the slope grows with speed
    np.testing.assert_allclose(f, -f[::-1])


def test_the_smoothstep_sign_saturates_outside_its_band_and_is_odd() -> None:
    v = np.linspace(-3.0, 3.0, 601)
    s = smoothstep_sign(v, 1.0)
    assert np.all(s[v <= -1.0] == -1.0) and np.all(s[v >= 1.0] == 1.0) and s[300] == pytest.approx(0.0)
    np.testing.assert_allclose(s, -s[::-1], atol=1e-12)


def test_the_gamma_pulse_peaks_at_one_where_it_says_and_is_zero_before_its_onset() -> None:
    t = np.arange(0.0, 6.0, 1e-3)
    p = gamma_pulse(t, 1.0, 0.5, 7.0)
    assert p.max() == pytest.approx(1.0, abs=1e-6) and t[int(np.argmax(p))] == pytest.approx(1.5, abs=2e-3)
    assert np.all(p[t < 1.0] == 0.0) and p[-1] < 1e-6


def test_a_packetised_link_delays_by_its_latencies_and_never_reads_ahead() -> None:
    rate = 1000.0
    t = np.arange(0.0, 20.0, 1.0 / rate)
    x = t.copy()  # a ramp: what is read is the time it was made
    latency = packet_latency(np.random.default_rng(1), t, 0.2, 6.0, 0.02)
    read = read_newest(t, x, latency)
    assert np.all(read <= t + 1e-12)  # nothing is read before it was made
    lag = (t - read)[t > t[0] + latency.max()]
    assert np.mean(latency) == pytest.approx(0.2, rel=0.1)
    assert 0.5 * np.mean(latency) < np.mean(lag) < np.mean(latency)  # the newest arrived is likelier a quick one
    assert np.all(np.diff(read) >= 0.0)  # the newest sample never goes back


def test_the_staircase_drift_steps_after_each_stroke_and_holds_between() -> None:
    rate = 100.0
    t = np.arange(0.0, 40.0, 1.0 / rate)
    deg = 45.0 - 40.0 * np.cos(2.0 * np.pi * t / 10.0)
    vel = np.gradient(np.radians(deg), t)
    load = np.radians(deg)  # a load growing with the angle, peaking at each stroke's end
    stairs = staircase_drift(t, load, vel, 1.0)
    levels = stairs[(t % 5.0 > 4.5)]  # late in each stroke the step has settled
    assert np.all(np.diff(stairs) >= -1e-12)  # a positive load steps the zero up only
    assert np.ptp(levels) > 0.0 and stairs[0] == 0.0


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_l("ankle", ("time_delay",), s) for s in range(20)]
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_l("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
        g = generate_l("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_l("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"} and all(3.0 <= d["stop_exponent"] <= 4.0 for d in stops)
    comp = [generate_l("knee", ("series_compliance",), s) for s in range(6)]
    assert all(0.03 <= g.effects["series_compliance"] <= 0.12 for g in comp)
