"""The eleventh generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_k_truth import (
    NOISE_SD_NM,
    _stretch_and_return,
    causal_median,
    first_order_lag,
    fung_moment,
    generate_k,
    ramp_contraction,
    sls_bumper,
    telegraph,
)


def test_fungs_law_is_zero_before_the_onset_and_stiffens_faster_than_any_single_exponential() -> None:
    x = np.linspace(-5.0, 30.0, 3501)
    m = fung_moment(x, 10.0)
    assert np.all(m[x <= 0.0] == 0.0)
    log_slope = np.gradient(np.log(m[x > 1.0]), x[x > 1.0])  # d ln M / dx = 1/x + 2x/w²: rising past x = w/√2
    past = x[x > 1.0] > 10.0 / np.sqrt(2.0) + 0.5
    assert np.all(np.diff(log_slope[past]) > 0.0)
    assert fung_moment(np.array([10.0]), 10.0)[0] == pytest.approx(10.0 * np.e)


def test_stretch_and_return_strokes_are_slow_one_way_quick_the_other_and_end_on_the_range() -> None:
    rate = 500.0
    for seed in range(4):
        deg = _stretch_and_return(np.random.default_rng(seed), 5.0, 90.0, True, rate)
        vel = np.gradient(deg, 1.0 / rate)
        assert deg.min() == pytest.approx(5.0, abs=1e-9) and deg.max() == pytest.approx(90.0, abs=1e-9)
        up, down = vel[vel > 0.5].max(), -vel[vel < -0.5].min()
        assert up <= 8.0 * 1.05 and 12.0 * 0.95 <= down  # slow toward the stretching end (here up), quick back


def test_the_sls_bumper_relaxes_while_held_and_never_pulls() -> None:
    rate = 1000.0
    t = np.arange(0.0, 4.0, 1.0 / rate)
    pen = np.interp(t, [0.0, 0.5, 2.5, 3.0, 4.0], [0.0, 2.0, 2.0, 0.0, 0.0])  # press, hold, release
    f = sls_bumper(pen, t, 1.0, 2.0, 0.3)
    at_press, held = f[int(0.5 * rate)], f[int(2.5 * rate) - 1]
    assert at_press > held == pytest.approx(2.0, rel=5e-3)  # the Maxwell arm relaxed: only k∞·δ is left
    assert np.all(f >= 0.0) and np.all(f[t > 3.0] == 0.0)


def test_the_causal_median_delays_a_ramp_by_half_its_window_and_removes_a_spike() -> None:
    x = np.arange(1000.0)
    np.testing.assert_allclose((x - causal_median(x, 21))[30:], 10.0)
    spiky = np.zeros(200)
    spiky[100] = 50.0
    assert np.all(causal_median(spiky, 5) == 0.0)


def test_the_ramp_contraction_rises_linearly_and_is_released_quickly() -> None:
    t = np.arange(0.0, 5.0, 1e-3)
    p = ramp_contraction(t, 1.0, 0.8, 0.05)
    assert p.max() == pytest.approx(1.0) and t[int(np.argmax(p))] == pytest.approx(1.8, abs=2e-3)
    assert p[int(1.4e3)] == pytest.approx(0.5, abs=2e-3)
    assert np.all(p[t < 1.0] == 0.0) and np.all(p[t > 1.851] == 0.0)


def test_the_first_order_lag_settles_on_a_step_with_its_time_constant() -> None:
    t = np.arange(0.0, 1.0, 1e-3)
    y = first_order_lag(np.where(t > 0.0, 1.0, 0.0), t, 0.1)
    assert y[100] == pytest.approx(1.0 - np.exp(-1.0), abs=1e-3)


def test_telegraph_noise_takes_two_values_and_switches_at_its_rate() -> None:
    rate, hz = 1000.0, 1.0
    x = telegraph(np.random.default_rng(0), 200000, rate, hz)
    assert set(np.unique(x)) == {-1.0, 1.0}
    switches = np.count_nonzero(np.diff(x))
    assert 200 * 0.8 < switches < 200 * 1.2  # 200 s at 1 Hz


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_k("ankle", ("time_delay",), s) for s in range(20)]
    for g in delays:  # the transport delay plus half the median's window
        assert g.effects["time_delay"] >= g.details["transport_delay_s"]
    assert max(g.effects["time_delay"] for g in delays) > 0.35 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_k("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
    for s in range(5):  # the recline found for the drawn size (or 45° when the limb is too light for it)
        g = generate_k("knee", ("gravity_error",), s)
        assert 0.5 <= abs(g.details["recline_deg"]) <= 45.0
    stops = [generate_k("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
