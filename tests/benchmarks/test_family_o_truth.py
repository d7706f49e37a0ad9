"""The fifteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import norm

from benchmarks.family_o_truth import (
    NOISE_SD_NM,
    aged_friction,
    chebyshev_channel,
    clutch_stop,
    creeping_bends,
    generate_o,
    logistic_shift,
    ogden_stress,
    preloaded_give,
    ramberg_osgood_torque,
    relief_valve_damper,
    smooth_excess,
    stuck_adc,
    two_speed_strokes,
    weibull_pulse,
)


def test_the_smooth_excess_is_the_mean_positive_part_over_a_normal_slack() -> None:
    x = np.array([-6.0, -1.0, 0.0, 1.5, 8.0])
    slack = norm(0.0, 2.0).rvs(size=400_000, random_state=np.random.default_rng(3))
    expected = [np.mean(np.maximum(v - slack, 0.0)) for v in x]
    np.testing.assert_allclose(smooth_excess(x, 2.0), expected, atol=5e-3)
    assert smooth_excess(np.array([30.0]), 2.0)[0] == pytest.approx(30.0)


def test_ogdens_stress_is_zero_when_slack_and_its_slope_at_rest_is_three_halves_alpha() -> None:
    lam = np.array([0.9, 1.0, 1.0 + 1e-6, 1.3])
    s = ogden_stress(lam, 10.0)
    assert s[0] == 0.0 and s[1] == 0.0
    assert s[2] / 1e-6 == pytest.approx(1.5 * 10.0, rel=1e-4)  # (α − 1) + (α/2 + 1) = 3α/2
    assert s[3] == pytest.approx(1.3**9 - 1.3**-6)


def test_the_ramberg_osgood_shell_is_linear_at_small_bends_and_yields_past_its_yield_torque() -> None:
    k, yield_nm, a, n = 2.0, 8.0, 0.6, 4.0
    bend = np.linspace(0.0, 20.0, 201)
    tau = ramberg_osgood_torque(bend, k, yield_nm, a, n)
    np.testing.assert_allclose(tau / k * (1.0 + a * (tau / yield_nm) ** (n - 1.0)), bend, atol=1e-9)
    assert tau[1] == pytest.approx(k * bend[1], rel=1e-3)
    slope = np.diff(tau)
    assert np.all(slope > 0.0) and np.all(np.diff(slope) < 1e-12)  # increasing and concave: it softens


def test_strokes_run_fast_through_the_middle_third_and_slow_at_the_ends() -> None:
    rate = 200.0
    deg = two_speed_strokes(np.random.default_rng(2), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0, abs=0.05) and deg.max() == pytest.approx(85.0, abs=0.05)
    speed = np.abs(np.gradient(deg)) * rate
    middle = (deg > 40.0) & (deg < 55.0)
    outer = ((deg > 16.0) & (deg < 28.0)) | ((deg > 67.0) & (deg < 79.0))
    assert np.median(speed[middle]) >= 10.0 - 1e-6 and np.median(speed[outer]) <= 6.0 + 1e-6
    assert np.median(speed[middle]) > 1.6 * np.median(speed[outer])
    assert np.sum(np.diff(np.sign(np.diff(deg[speed > 0.1]))) != 0) >= 3  # at least two cycles: up, down, up, down


def test_afo_bends_creep_on_while_held() -> None:
    rate = 200.0
    deg = creeping_bends(np.random.default_rng(1), rate)
    assert deg.min() == pytest.approx(0.0) and 12.0 <= deg.max() <= 20.0
    top = int(np.argmax(deg))
    assert deg[top] > deg[top - int(0.9 * rate)] > deg[top - int(1.0 * rate) - int(0.9 * rate)] - 1e-9


def test_friction_breaks_away_by_the_rest_it_had_and_falls_back_with_travel() -> None:
    rate = 100.0
    t = np.arange(0.0, 20.0, 1.0 / rate)
    vel = np.where((t > 2.0) & (t < 6.0), 5.0, 0.0) + np.where(t > 16.0, 5.0, 0.0)  # rests of 2 s and 10 s
    deg = np.cumsum(vel) / rate
    f = aged_friction(t, vel, deg, 0.5, 0.2, 1.0, 0.5)
    first, second = f[np.searchsorted(t, 2.02)], f[np.searchsorted(t, 16.02)]
    sig = 5.0 / np.sqrt(25.0 + 0.25)
    assert first == pytest.approx(sig * (1.0 + 0.5 * np.log1p(2.0 / 0.2) * np.exp(-0.05)), rel=0.02)
    assert second > first  # a longer rest, a larger breakaway
    assert f[np.searchsorted(t, 5.9)] == pytest.approx(sig, rel=1e-4)  # back to the kinetic level after 19° moved
    assert np.all(f[vel == 0.0] == 0.0)


def test_the_relief_valve_cracks_open_at_its_speed() -> None:
    v = np.linspace(-10.0, 10.0, 2001)
    d = relief_valve_damper(v, 4.0, 0.2)
    np.testing.assert_allclose(d[np.abs(v) <= 4.0], v[np.abs(v) <= 4.0])
    assert d[-1] == pytest.approx(4.0 + 0.2 * 6.0) and d[0] == pytest.approx(-d[-1])


def test_the_clutch_stop_rises_over_its_slip_and_holds() -> None:
    deg = np.linspace(0.0, 30.0, 301)
    high = clutch_stop(deg, 20.0, True, 2.0)
    assert np.all(high[deg <= 20.0] == 0.0) and high[deg == 21.0][0] == pytest.approx(0.5)
    assert np.all(high[deg >= 22.0] == 1.0)
    np.testing.assert_allclose(clutch_stop(-deg, -20.0, False, 2.0), -high)


def test_the_chebyshev_channel_ripples_and_lags_a_ramp_by_its_group_delay() -> None:
    rate = 500.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    y, delay = chebyshev_channel(t.copy(), rate, 3, 1.0, 5.0)
    assert 0.05 < delay < 0.3
    assert np.mean((t - y)[t > 5.0]) == pytest.approx(delay, rel=1e-3)
    for order in (2, 3):  # a steady torque reads right: unit gain at DC whatever the order
        const, _ = chebyshev_channel(np.full(100, 3.0), rate, order, 1.0, 5.0)
        np.testing.assert_allclose(const, 3.0, rtol=1e-9)
    from scipy.signal import cheby1, freqz
    b, a = cheby1(3, 1.0, 5.0, fs=rate)
    gain = np.abs(freqz(b, a, worN=np.linspace(0.1, 4.5, 200), fs=rate)[1])
    assert gain.max() - gain.min() > 0.05  # it ripples in its pass band


def test_the_weibull_pulse_peaks_at_its_mode() -> None:
    t = np.arange(0.0, 5.0, 1e-3)
    x = weibull_pulse(t, 1.0, 2.0, 0.4)
    assert x.max() == pytest.approx(1.0) and np.all(x[t <= 1.0] == 0.0)
    mode = 0.4 * ((2.0 - 1.0) / 2.0) ** 0.5
    assert t[int(np.argmax(x))] == pytest.approx(1.0 + mode, abs=2e-3)


def test_the_drift_rises_from_ten_to_ninety_percent_in_its_rise_time() -> None:
    t = np.linspace(0.0, 100.0, 100_001)
    x = logistic_shift(t, 50.0, 20.0)
    assert t[np.searchsorted(x, 0.9)] - t[np.searchsorted(x, 0.1)] == pytest.approx(20.0, abs=1e-2)


def test_the_strap_gives_only_past_its_preload() -> None:
    tau = np.array([-5.0, -1.0, 0.0, 0.5, 3.0])
    np.testing.assert_allclose(preloaded_give(tau, 1.0), [-4.0, 0.0, 0.0, 0.0, 2.0])


def test_a_stuck_adc_repeats_values_and_changes_nothing_else() -> None:
    x = np.arange(1000.0)
    y = stuck_adc(np.random.default_rng(0), x, 0.05)
    held = y != x
    assert held.any() and np.all(np.diff(y) >= 0.0)
    assert np.all(np.isin(y, x))


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_o("ankle", ("time_delay",), s) for s in range(20)]
    assert all(0.005 <= g.effects["time_delay"] <= 0.7 for g in delays)
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_o("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
        g = generate_o("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_o("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    comp = [generate_o("knee", ("series_compliance",), s) for s in range(4)]
    assert all(0.005 <= g.effects["series_compliance"] <= 0.3 for g in comp)
