"""The tenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from benchmarks.family_j_truth import (
    NOISE_SD_NM,
    _bang_bang,
    fractional_derivative,
    generate_j,
    lognormal_pulse,
    rate_and_state,
    sinc3,
    sling_moment,
    table_moment,
)


def test_the_tabulated_stiffness_is_monotone_zero_before_the_onset_and_held_past_the_table() -> None:
    x = np.linspace(-5.0, 60.0, 6501)
    table = np.array([0.0, 1.0, 2.0, 4.5, 9.0, 20.0])
    m = table_moment(x, 5.0, table)
    slope = np.gradient(m, x)
    assert np.all(m[x <= 0.0] == 0.0)
    assert np.all(np.diff(slope[x > 0.5]) >= -1e-6)  # a monotone cubic through a rising table: never softening
    np.testing.assert_allclose(slope[(x > 0.2) & (x < 24.8)][::50],
                               np.interp(x[(x > 0.2) & (x < 24.8)][::50], 5.0 * np.arange(6), table), rtol=0.35,
                               atol=0.3)
    assert slope[-100] == pytest.approx(20.0, rel=1e-3)


def test_rate_and_state_friction_heals_at_rest_and_weakens_to_its_steady_level_while_sliding() -> None:
    """The aging law: after a hold the level starts high (the state grew) and falls over a slip of a few D_c to its
    steady value 1 + a·ln(1 + v/v*) + b·ln(1 + v*/v) (φ = D_c/v)."""
    rate = 1000.0
    t = np.arange(0.0, 6.0, 1.0 / rate)
    speed = np.where(t < 2.0, 0.0, 5.0)  # deg/s: held 2 s, then sliding
    level = rate_and_state(speed, t, 0.1, 0.2, 0.5)
    steady = 1.0 + 0.1 * math.log1p(5.0) + 0.2 * math.log1p(1.0 / 5.0)
    assert level[-1] == pytest.approx(steady, rel=1e-3)
    assert level[int(2.01 * rate)] > steady + 0.1


def test_the_fractional_derivative_of_a_ramp_is_the_power_law_and_order_one_is_the_velocity() -> None:
    dt = 1e-3
    t = np.arange(0.0, 2.0, dt)
    for order in (0.6, 0.8):
        expected = t ** (1.0 - order) / math.gamma(2.0 - order)
        np.testing.assert_allclose(fractional_derivative(t, order, dt)[200:], expected[200:], rtol=0.01)
    np.testing.assert_allclose(fractional_derivative(np.sin(t), 1.0, dt)[1:], np.cos(t)[1:], atol=2e-3)


def test_the_sinc3_decimator_delays_a_ramp_by_its_group_delay() -> None:
    rate = 1000.0
    t = np.arange(0.0, 3.0, 1.0 / rate)
    out, group = sinc3(t, rate, 20.0)
    assert group == pytest.approx(3 * 49 / 2 / rate)
    np.testing.assert_allclose((t - out)[500:-100], group, atol=2e-3)


def test_the_lognormal_pulse_peaks_where_drawn_and_is_skewed_late() -> None:
    t = np.arange(0.0, 5.0, 1e-3)
    p = lognormal_pulse(t, 1.0, 0.3, 0.4)
    peak = float(t[int(np.argmax(p))])
    assert p.max() == pytest.approx(1.0) and peak == pytest.approx(1.3, abs=2e-3)
    assert np.all(p[t < 1.0] == 0.0)
    half = t[p >= 0.5]
    assert half[-1] - peak > peak - half[0]  # a longer tail after the peak than the rise before it


def test_a_slack_sling_carries_nothing_and_a_taut_one_lifts_the_segment() -> None:
    psi = np.radians(np.linspace(-80.0, 0.0, 81))  # a shank hanging down to horizontal
    anchor = (0.3, 0.5)
    reach = np.hypot(anchor[0] - 0.3 * np.cos(psi), anchor[1] - 0.3 * np.sin(psi))
    assert np.all(sling_moment(psi, 0.3, anchor, float(reach.max()) + 0.01) == 0.0)
    lifting = sling_moment(psi, 0.3, anchor, 0.5 * float(reach.min()))
    assert np.all(lifting > 0.0)  # counter-clockwise: toward raising a segment that points forward


def test_bang_bang_strokes_keep_their_acceleration_and_speed_and_end_on_their_targets() -> None:
    rate = 500.0
    for seed in range(4):
        deg = _bang_bang(np.random.default_rng(seed), 5.0, 90.0, rate)
        vel = np.gradient(deg, 1.0 / rate)
        assert deg.min() == pytest.approx(5.0, abs=1e-6) and deg.max() == pytest.approx(90.0, abs=1e-6)
        assert np.max(np.abs(vel)) <= 25.0 + 0.5


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_j("ankle", ("time_delay",), s) for s in range(20)]
    for g in delays:  # the transport delay plus the decimator's group delay
        assert g.effects["time_delay"] > g.details["transport_delay_s"]
    assert max(g.effects["time_delay"] for g in delays) > 0.35 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_j("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"] * 1.001
    stops = [generate_j("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
