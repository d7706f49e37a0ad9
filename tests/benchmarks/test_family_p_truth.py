"""The sixteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_p_truth import (
    NOISE_SD_NM,
    cable_give,
    dip_friction,
    dithered_strokes,
    fir_channel,
    gas_bumper,
    generate_p,
    one_way_flywheel,
    partial_release_bends,
    pink_noise,
    qlv_relaxed,
    tukey_contraction,
    wiechert_damping,
)


def test_qlv_relaxes_a_held_step_to_its_long_term_share_with_its_time_constant() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    elastic = np.where(t >= 1.0, 10.0, 0.0)
    y = qlv_relaxed(elastic, t, 0.9, 2.0)
    step = int(np.searchsorted(t, 1.0))
    assert y[step] == pytest.approx(10.0)  # the instant response is the elastic one
    assert y[step + 200] == pytest.approx(10.0 * (0.9 + 0.1 * np.exp(-1.0)), rel=1e-9)  # 2 s (τ) later
    assert y[-1] == pytest.approx(9.0, rel=1e-3)
    np.testing.assert_allclose(qlv_relaxed(elastic, t, 1.0, 2.0), elastic)  # g∞ = 1: no memory


def test_dithered_strokes_reverse_many_times_within_the_range_and_turn_at_its_ends() -> None:
    rate = 200.0
    deg = dithered_strokes(np.random.default_rng(4), 10.0, 85.0, rate)
    assert deg.min() == pytest.approx(10.0) and deg.max() == pytest.approx(85.0)
    vel = np.gradient(deg) * rate
    moving = np.abs(vel) > 0.2
    reversals = np.sum(np.diff(np.sign(vel[moving])) != 0)
    assert reversals > 12  # the dither reverses the joint inside strokes, not only at the range's ends
    inside = (deg > 20.0) & (deg < 75.0) & moving
    assert np.any(vel[inside] > 0) and np.any(vel[inside] < 0)


def test_afo_bends_release_partly_between_bends_and_fully_every_third() -> None:
    rate = 200.0
    deg = partial_release_bends(np.random.default_rng(5), rate)
    assert deg.min() == pytest.approx(0.0) and 12.0 <= deg.max() <= 19.0
    troughs = [deg[i] for i in range(1, deg.size - 1) if deg[i] < deg[i - 1] and deg[i] <= deg[i + 1]]
    assert any(2.0 - 1e-9 <= v <= 6.0 + 1e-9 for v in troughs)  # a partial release
    assert deg[-1] == 0.0


def test_friction_dips_below_its_kinetic_level_at_moderate_speed_and_differs_by_direction() -> None:
    v = np.array([2.0, 20.0, 200.0, -200.0])
    f = dip_friction(v, 0.5, 2.0, 0.7, 0.2)
    assert f[0] == pytest.approx(0.5 * np.tanh(2.0 / 0.4), rel=1e-9)  # the dip: 1 − d at v_m
    assert 0.5 < f[1] < f[2] <= 1.0  # recovering toward the kinetic level
    assert f[3] == pytest.approx(-0.7 * f[2], rel=1e-6)


def test_the_two_arm_damper_is_the_speed_at_a_steady_speed_and_lags_a_step() -> None:
    t = np.arange(0.0, 20.0, 0.001)
    vel = np.where(t >= 1.0, 3.0, 0.0)
    d = wiechert_damping(vel, t, 0.05, 1.0, 0.4)
    assert d[-1] == pytest.approx(3.0, rel=1e-6)
    at = int(np.searchsorted(t, 1.05))  # one fast time constant in: the fast arm 63 % of the way, the slow 5 %
    assert d[at] == pytest.approx(3.0 * (0.4 * (1 - np.exp(-1.0)) + 0.6 * (1 - np.exp(-0.05))), rel=0.02)


def test_the_gas_bumper_stiffens_toward_its_closed_depth_and_acts_inward() -> None:
    deg = np.linspace(0.0, 30.0, 3001)
    high = gas_bumper(deg, 20.0, True, 8.0, 1.4)
    assert np.all(high[deg <= 20.0] == 0.0)
    assert high[deg == 24.0][0] == pytest.approx(0.5**-1.4 - 1.0)
    slope = np.diff(high[(deg > 20.0) & (deg < 27.5)])  # short of the closed depth (held at 95 % of it)
    assert np.all(np.diff(slope) > -1e-12)  # convex: stiffer the deeper
    np.testing.assert_allclose(gas_bumper(-deg, -20.0, False, 8.0, 1.4), -high)


def test_the_fir_channel_delays_a_ramp_by_half_its_length_with_unit_gain() -> None:
    rate = 500.0
    t = np.arange(0.0, 10.0, 1.0 / rate)
    y, delay = fir_channel(t.copy(), rate, 101, 8.0)
    assert delay == pytest.approx(50.0 / rate)
    np.testing.assert_allclose((t - y)[t > 1.0], delay, atol=1e-9)  # linear phase: every frequency late alike
    const, _ = fir_channel(np.full(300, 2.5), rate, 101, 8.0)
    np.testing.assert_allclose(const, 2.5, rtol=1e-12)
    _, even = fir_channel(t.copy(), rate, 100, 8.0)  # made odd: a whole number of samples late
    assert even == pytest.approx(50.0 / rate)


def test_the_contraction_is_flat_topped_with_tapered_edges_and_fades() -> None:
    t = np.arange(0.0, 10.0, 1e-3)
    y = tukey_contraction(t, 2.0, 3.0, 0.4, 0.3)
    assert y.max() == pytest.approx(1.0) and np.all(y[(t < 2.0) | (t > 5.0)] == 0.0)
    plateau = (t > 2.0 + 0.6) & (t < 5.0 - 0.6)
    assert np.all(np.diff(y[plateau]) <= 1e-12) and y[plateau][-1] < 0.85 * y[plateau][0] + 1e-9


def test_pink_noise_has_a_one_over_f_spectrum_in_its_band() -> None:
    rate, n = 50.0, 2**16
    x = np.mean([np.abs(np.fft.rfft(pink_noise(np.random.default_rng(s), n, rate))) ** 2 for s in range(20)], axis=0)
    f = np.fft.rfftfreq(n, 1.0 / rate)
    band = (f > 0.01) & (f < 0.4)
    slope = np.polyfit(np.log(f[band]), np.log(x[band]), 1)[0]
    assert slope == pytest.approx(-1.0, abs=0.1)
    assert np.all(x[f > 0.55] < 1e-20 * x[band].max())  # nothing above its band


def test_the_cable_gives_more_one_way_than_the_other() -> None:
    tau = np.array([2.0, 2.0, 2.0])
    g = cable_give(tau, np.array([20.0, 0.0, -20.0]), 0.3)
    np.testing.assert_allclose(g, [2.0 * 1.3, 2.0, 2.0 * 0.7], rtol=1e-6)


def test_the_flywheel_couples_only_while_driven_forward_and_speeding_up() -> None:
    vel = np.radians(np.array([10.0, 10.0, -10.0, -10.0]))
    acc = np.radians(np.array([100.0, -100.0, 100.0, -100.0]))
    share = one_way_flywheel(vel, acc)
    assert share[0] == pytest.approx(1.0, abs=1e-6) and np.all(share[1:] < 1e-6)


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_p("ankle", ("time_delay",), s) for s in range(16)]
    assert all(0.0 <= g.effects["time_delay"] <= 0.4 + 1.0 for g in delays)
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.2
    for s in range(4):
        g = generate_p("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
        g = generate_p("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_p("knee", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    comp = [generate_p("knee", ("series_compliance",), s) for s in range(4)]
    assert all(0.005 <= g.effects["series_compliance"] <= 0.3 for g in comp)
    clean = generate_p("knee", (), 7)
    assert 0.8 <= clean.details["relaxation"]["g_inf"] <= 0.95  # the clean trial's passive torque has memory
