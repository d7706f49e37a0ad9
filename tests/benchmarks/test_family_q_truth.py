"""The seventeenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_q_truth import (
    NOISE_SD_NM,
    chirp_sweep,
    cosine_bends,
    creeping_give,
    dead_band_damping,
    elastoplastic_friction,
    generate_q,
    sech2_with_undershoot,
    slipping_share,
    smoothstep_stop,
    strapped_mass_torque,
    two_settles,
    veronda_westmann,
    wandering_latency,
)


def test_veronda_westmann_starts_quadratically_and_grows_exponentially() -> None:
    x = np.array([-1.0, 0.0, 0.01, 20.0])
    y = veronda_westmann(x, 0.3)
    assert y[0] == 0.0 and y[1] == 0.0
    assert y[2] == pytest.approx(0.5 * (0.3 * 0.01) ** 2, rel=1e-2)  # no kink at the onset
    assert y[3] == pytest.approx(np.exp(6.0) - 7.0)


def test_the_chirp_sweeps_the_range_faster_as_it_goes() -> None:
    rate = 200.0
    deg = chirp_sweep(np.random.default_rng(3), 10.0, 85.0, rate)
    assert deg[0] == pytest.approx(10.0) and deg.min() >= 10.0 - 1e-9 and deg.max() <= 85.0 + 1e-9
    assert deg.max() > 84.0
    speed = np.abs(np.gradient(deg) * rate)
    half = deg.size // 2
    assert np.percentile(speed[half:], 90) > 1.2 * np.percentile(speed[:half], 90)


def test_afo_bends_are_raised_cosines_with_pauses_at_every_other_top() -> None:
    rate = 200.0
    deg = cosine_bends(np.random.default_rng(5), rate)
    assert deg.min() == pytest.approx(0.0) and 12.0 <= deg.max() <= 19.0
    held = np.flatnonzero((np.diff(deg) == 0.0) & (deg[1:] >= 12.0))
    runs = np.split(held, np.flatnonzero(np.diff(held) > 1) + 1)
    assert len([r for r in runs if r.size >= 0.2 * rate - 2]) >= 2  # paused at every other top


def test_elastoplastic_friction_ramps_over_its_presliding_angle_after_each_reversal() -> None:
    deg = np.concatenate([np.linspace(0.0, 10.0, 1001), np.linspace(10.0, 0.0, 1001)[1:]])
    f = elastoplastic_friction(deg, 1.0)
    assert f[50] == pytest.approx(0.5)  # 0.5° travelled from rest: half the level
    assert np.all(f[200:1001] == 1.0)  # sliding at the level
    back = f[1001:]
    assert back[49] == pytest.approx(0.5) and back[99] == pytest.approx(0.0, abs=1e-9)  # from +1 to −1 over 2°
    assert np.all(back[300:] == -1.0)


def test_damping_has_a_dead_band() -> None:
    v = np.array([-3.0, -0.5, 0.0, 0.5, 3.0])
    np.testing.assert_allclose(dead_band_damping(v, 1.0), [-2.0, 0.0, 0.0, 0.0, 2.0])


def test_the_smoothstep_stop_engages_without_a_kink_and_is_linear_beyond() -> None:
    deg = np.linspace(0.0, 30.0, 30001)
    y = smoothstep_stop(deg, 20.0, True, 2.0)
    assert np.all(y[deg <= 20.0] == 0.0)
    slope = np.gradient(y, deg)
    assert slope[np.searchsorted(deg, 20.001)] < 1e-4  # zero stiffness at contact
    np.testing.assert_allclose(slope[deg > 22.1], 1.0, atol=1e-6)  # one unit per degree past the engagement
    assert y[np.searchsorted(deg, 22.0)] == pytest.approx(1.0, rel=1e-3)  # ∫₀² smoothstep = half the engagement
    np.testing.assert_allclose(smoothstep_stop(-deg, -20.0, False, 2.0), -y)


def test_the_latency_wanders_about_its_mean() -> None:
    t = np.arange(0.0, 120.0, 0.01)
    late, latency = wandering_latency(t.copy(), t, 0.2, 0.3, 40.0, 0.0)
    assert latency.min() == pytest.approx(0.14, abs=1e-3) and latency.max() == pytest.approx(0.26, abs=1e-3)
    inside = t > 1.0
    np.testing.assert_allclose((t - late)[inside], latency[inside], atol=1e-9)  # a ramp read late by the latency


def test_the_pulse_has_its_half_width_and_an_undershoot() -> None:
    t = np.arange(0.0, 10.0, 1e-3)
    y = sech2_with_undershoot(t, 3.0, 0.3, 0.2, 1.0)
    assert y.max() == pytest.approx(1.0, abs=1e-3)
    assert y[np.searchsorted(t, 2.7)] == pytest.approx(0.5, abs=0.01)  # half the peak 0.3 s before it
    assert y.min() == pytest.approx(-0.2, abs=0.02) and t[np.argmin(y)] > 3.0
    assert abs(y[-1]) < 0.01


def test_the_strap_slips_once_and_the_settles_come_twice() -> None:
    t = np.arange(0.0, 100.0, 0.1)
    s = slipping_share(t, 50.0, 2.0)
    assert s[0] < 1e-6 and s[-1] > 1 - 1e-6 and s[np.searchsorted(t, 49.0)] == pytest.approx(0.1, abs=0.01)
    d = two_settles(t, (20.0, 60.0), (10.0, 10.0), (1.0, -1.0))
    assert np.all(d[t <= 20.0] == d[0]) and np.max(np.abs(d - np.mean(d))) == pytest.approx(1.0)
    assert d[np.searchsorted(t, 55.0)] > d[np.searchsorted(t, 95.0)]  # the second settle goes the other way


def test_the_cuffs_give_creeps_under_a_held_torque() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    torque = np.where(t >= 1.0, 10.0, 0.0)
    g = creeping_give(torque, t, 0.5, 2.0)
    assert g[np.searchsorted(t, 1.0)] == pytest.approx(10.0, rel=0.01)  # the instant give
    assert g[-1] == pytest.approx(15.0, rel=1e-3)  # and the creep, half as much again


def test_the_strapped_mass_follows_a_slow_motion_like_an_inertia_and_rings_after_a_jolt() -> None:
    t = np.arange(0.0, 30.0, 0.001)
    acc = 0.2 * np.sin(2.0 * np.pi * 0.1 * t)  # far below the mount's 2 Hz
    y = strapped_mass_torque(acc, t, 1.5, 2.0, 0.1)
    assert float(np.dot(acc, y) / np.dot(acc, acc)) == pytest.approx(1.5, rel=0.02)
    jolt = np.where((t > 5.0) & (t < 5.05), 20.0, 0.0)
    ring = strapped_mass_torque(jolt, t, 1.0, 2.0, 0.1)
    after = ring[(t > 5.5) & (t < 8.0)]
    assert np.sum(np.diff(np.sign(after)) != 0) >= 8  # it rings at about 2 Hz after the jolt


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_q("ankle", ("time_delay",), s) for s in range(12)]
    assert all(0.02 <= g.effects["time_delay"] <= 0.5 for g in delays)
    assert max(g.effects["time_delay"] for g in delays) > 0.3 and min(g.effects["time_delay"] for g in delays) < 0.2
    for s in range(3):
        g = generate_q("knee", ("activation_burst",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["activation_burst"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"]
        g = generate_q("ankle", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["ankle"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["ankle"]
    stops = [generate_q("knee", ("hard_stop",), s).details for s in range(12)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    comp = [generate_q("knee", ("series_compliance",), s) for s in range(3)]
    assert all(0.02 <= g.effects["series_compliance"] <= 0.3 for g in comp)
    friction = generate_q("ankle", ("coulomb_friction",), 1)
    assert 0.2 <= friction.details["presliding_deg"] <= 2.0 and friction.effects["coulomb_friction"] > 0.0
