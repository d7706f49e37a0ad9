"""The twenty-eighth generator family: its own laws and the ranges they are drawn from (the contract every family
shares: test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ab_truth import (
    NOISE_SD_NM,
    adc_nonlinearity,
    belleville_stop,
    beta_pulse,
    charge_leak,
    demiray_end,
    flyweight_torque,
    foam_liner_give,
    generate_ab,
    growing_strokes,
    held_bends,
    leaf_on_former,
    rolling_centre,
    send_on_delta,
    squeeze_film_damper,
    stick_slip_friction,
)


def test_the_demiray_end_is_flat_before_its_onset_and_follows_demirays_uniaxial_stress_past_it() -> None:
    assert abs(float(demiray_end(np.array(-40.0), 1.0, 20.0, 0.8))) < 1e-12
    # far past the onset (x̄ = x): a stretch of 2, I₁ − 3 = 2, so e^{b}·(4 − 0.5)
    assert float(demiray_end(np.array(20.0), 0.01, 20.0, 0.8)) == pytest.approx(np.exp(0.8) * 3.5, rel=1e-6)
    # b = 0 is the neo-Hookean (λ² − 1/λ); the exponential stiffens it ever more with the stretch
    x = np.linspace(0.0, 30.0, 31)
    ratio = demiray_end(x, 0.01, 15.0, 0.8)[1:] / demiray_end(x, 0.01, 15.0, 0.0)[1:]
    assert np.all(np.diff(ratio) > 0.0)


def test_the_leaf_stiffens_as_it_wraps_onto_its_former() -> None:
    h = 1e-4
    # far past a sharp engagement at 0: the stiffness is (1 − θ/θ_f)^-3
    for bend in (5.0, 15.0):
        k = np.diff(leaf_on_former(np.array([bend, bend + h]), 0.0, 1e-3, 50.0))[0] / h
        assert k == pytest.approx((1.0 - bend / 50.0) ** -3, rel=1e-3)
    assert float(leaf_on_former(np.array(0.0), 1.0, 0.5, 50.0)) == pytest.approx(0.0, abs=1e-12)
    assert float(leaf_on_former(np.array(-5.0), 1.0, 0.5, 50.0)) < 0.01


def test_strokes_grow_to_the_whole_range_at_their_speed() -> None:
    rate = 200.0
    deg = growing_strokes(np.random.default_rng(4), 10.0, 80.0, rate)
    speed = np.abs(np.diff(deg)) * rate
    assert deg.min() == pytest.approx(10.0, abs=1e-6) and deg.max() == pytest.approx(80.0, abs=1e-6)
    assert deg[0] == pytest.approx(45.0) and deg[-1] == pytest.approx(45.0)
    moving = speed[speed > 1.0]
    assert 3.0 * 0.99 <= np.median(moving) <= 7.0 * 1.01 and moving.max() <= np.median(moving) * 1.001
    turns = np.flatnonzero(np.diff(np.sign(np.diff(deg[np.abs(np.diff(deg, append=deg[-1])) > 0]))) != 0)
    tops = deg[np.abs(np.diff(deg, append=deg[-1])) > 0][turns + 1]
    reach = np.abs(tops - 45.0)
    assert reach[0] < 0.7 * 35.0 + 1e-6 and reach[-1] == pytest.approx(35.0, abs=1e-6)
    assert np.all(np.diff(reach[::2]) > 0.0)  # each cycle reaches further


def test_orthosis_bends_are_held_at_their_tops_and_released_faster_than_loaded() -> None:
    rate = 500.0
    deg = held_bends(np.random.default_rng(6), rate)
    assert abs(deg[0]) < 1e-12 and abs(deg[-1]) < 1e-12 and 10.0 <= deg.max() <= 20.0 and deg.min() >= 0.0
    step = np.diff(deg)
    held_high = (np.abs(step) < 1e-12) & (deg[1:] > 9.0)
    assert held_high.sum() >= 5 * 0.3 * rate - 5
    assert np.max(step) * rate <= 1.5 * 20.0 / 1.5 * 1.01  # loading: smoothstep's peak rate 1.5·A/T, T ≥ 1.5 s
    assert np.min(step) * rate < -np.max(step) * rate  # released faster


def test_the_seal_sticks_and_slips_while_it_slides() -> None:
    t = np.arange(0.0, 2.0, 0.001)
    f = stick_slip_friction(t, np.full(t.size, 5.0), 0.3, 2.0, 0.4)
    assert f.min() == pytest.approx(0.8, abs=1e-3) and f.max() == pytest.approx(1.2, abs=1e-3)
    drops = np.flatnonzero(np.diff(f) < -0.3)
    assert drops.size == 3  # a slip at 0.5, 1.0, 1.5 s
    np.testing.assert_allclose(stick_slip_friction(t, np.full(t.size, -5.0), 0.3, 2.0, 0.4), -f)


def test_the_squeeze_film_damps_more_toward_either_end() -> None:
    u = np.array([-0.9, 0.0, 0.9])
    out = squeeze_film_damper(np.ones(3), u, 0.8)
    assert out[1] == pytest.approx(1.0) and out[0] == pytest.approx(out[2])
    assert out[0] == pytest.approx((1.0 - 0.8 * 0.81) ** -1.5)
    assert float(squeeze_film_damper(np.array(-2.0), np.array(0.0), 0.8)) == -2.0


def test_the_disc_springs_soften_through_their_travel_then_go_solid() -> None:
    h = 1e-5
    for high, sign in ((True, 1.0), (False, -1.0)):
        at, unit = 50.0, 0.5

        def k(depth_units: float, high: bool = high, sign: float = sign, at: float = at, unit: float = unit) -> float:
            deg = at + sign * np.array([depth_units, depth_units + h]) * unit
            return float(abs(np.diff(belleville_stop(deg, at, high, unit, 1.2, 6.0))[0]) / h)
        first, middle, solid = k(0.05), k(0.8), k(2.5)
        assert first == pytest.approx(1.2**2 + 1.0, rel=0.1) and middle < 0.5 * first
        assert solid == pytest.approx(6.0 * (1.2**2 + 1.0), rel=1e-3)
        assert float(belleville_stop(np.array(at - sign * 3.0), at, high, unit, 1.2, 6.0)) == 0.0


def test_the_logger_sends_on_change_or_heartbeat_and_delivers_late() -> None:
    rate = 1000.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    torque = np.sin(2.0 * np.pi * 0.3 * t)
    out, delay = send_on_delta(torque, t, 0.02, 0.08, 0.2)
    assert 0.2 < delay < 0.2 + 0.08
    lags = np.arange(0, 400)
    errors = [np.mean((out[400:] - torque[400 - k:t.size - k]) ** 2) for k in lags]
    assert int(np.argmin(errors)) / rate == pytest.approx(delay, abs=0.01)
    flat, flat_delay = send_on_delta(np.zeros(t.size), t, 0.02, 0.08, 0.1)
    assert np.all(flat == 0.0) and flat_delay == pytest.approx(0.1)


def test_the_beta_pulse_peaks_where_its_exponents_put_it_and_is_zero_outside() -> None:
    t = np.arange(0.0, 10.0, 0.001)
    p = beta_pulse(t, 3.0, 2.0, 2.0, 5.0)
    assert p.max() == pytest.approx(1.0, abs=1e-6) and np.all(p[(t <= 3.0) | (t >= 5.0)] == 0.0)
    assert t[np.argmax(p)] == pytest.approx(3.0 + 2.0 * (2.0 - 1.0) / (2.0 + 5.0 - 2.0), abs=0.002)


def test_the_rolling_centre_changes_the_lever_along_the_range() -> None:
    out = rolling_centre(np.array([-1.0, 0.0, 1.0]), np.array([0.0, 0.0, np.pi / 3.0]))
    np.testing.assert_allclose(out, [-1.0, 0.0, 0.5], atol=1e-12)


def test_the_charge_leaks_toward_the_torques_slow_mean() -> None:
    t = np.arange(0.0, 200.0, 0.1)
    torque = np.where(t >= 10.0, 2.0, 0.0)
    leak = charge_leak(torque, t, 40.0)
    assert np.all(leak[t < 10.0] == 0.0)
    assert leak[np.searchsorted(t, 50.0)] == pytest.approx(-2.0 * (1.0 - np.exp(-40.0 / 40.0)), rel=0.01)


def test_the_foam_gives_less_per_newton_metre_as_it_bottoms_out() -> None:
    give = foam_liner_give(np.array([0.01, 10.0, 100.0]), 0.2, 10.0)
    per_nm = give / np.array([0.01, 10.0, 100.0])
    assert per_nm[0] == pytest.approx(0.2, rel=1e-3) and per_nm[0] > per_nm[1] > per_nm[2]
    assert give[2] <= 0.2 * 10.0 and float(foam_liner_give(np.array(-10.0), 0.2, 10.0)) == -give[1]


def test_the_flyweights_add_inertia_with_the_speed() -> None:
    vel = np.array([0.0, 1.0, 2.0])
    out = flyweight_torque(vel, np.ones(3), 0.5)
    np.testing.assert_allclose(out, [1.0, 1.0 + 1.5 * 0.25, 1.0 + 1.5])


def test_the_adcs_non_linearity_is_a_cubic_of_its_stated_peak() -> None:
    x = np.linspace(-10.0, 10.0, 20001)
    err = adc_nonlinearity(x, 10.0, 0.004) - x
    assert np.max(np.abs(err)) == pytest.approx(0.04, rel=1e-4) and abs(err[10000]) < 1e-12


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ab(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ab("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ab("knee", ("time_delay",), 5)
    assert 0.03 <= delay.effects["time_delay"] <= 0.45 + 0.1
