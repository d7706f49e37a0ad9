"""The eighteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_r_truth import (
    NOISE_SD_NM,
    butterworth_lag,
    gamma_doublet,
    generate_r,
    hunt_crossley_stop,
    linkage_inertia_torque,
    load_dependent_friction,
    minimum_jerk,
    minimum_jerk_bends,
    power_law_damping,
    ramp_hold_strokes,
    stiffening_give,
    stroke_contacts,
    thermal_drift,
    toe_linear,
)


def test_the_toe_region_starts_flat_and_turns_linear() -> None:
    x = np.array([-40.0, 10.0, 40.0, 41.0])
    y = toe_linear(x, 10.0, 3.0)
    assert y[0] < 1e-4  # flat well before the onset
    assert y[1] == pytest.approx(3.0 * np.log(2.0))  # w·ln 2 at the onset
    assert y[3] - y[2] == pytest.approx(1.0, abs=1e-4)  # unit slope past the toe


def test_ramp_and_hold_strokes_stay_in_range_hold_at_their_ends_and_turn_back_early() -> None:
    rate = 200.0
    found_short = False
    for seed in range(6):
        deg = ramp_hold_strokes(np.random.default_rng(seed), 10.0, 85.0, rate)
        assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 85.0 + 1e-9
        speed = np.abs(np.diff(deg)) * rate
        assert speed.max() <= 10.0 + 1e-6  # no stroke faster than its drawn speed
        turns = np.flatnonzero(np.diff(np.sign(np.diff(deg[np.diff(deg, prepend=deg[0]) != 0]))) != 0)
        peaks = deg[np.diff(deg, prepend=deg[0]) != 0][turns + 1]
        found_short |= bool(np.any((peaks > 30.0) & (peaks < 70.0)))
    assert found_short  # some strokes turn back 20–40 % short of an end


def test_minimum_jerk_starts_and_ends_at_rest() -> None:
    path = minimum_jerk(0.0, 10.0, 1001)
    assert path[0] == 0.0 and path[-1] == pytest.approx(10.0) and path[500] == pytest.approx(5.0)
    v = np.gradient(path)
    assert abs(v[0]) < 1e-4 and abs(v[-1]) < 1e-4


def test_afo_bends_reach_their_peaks_and_some_reverse_early() -> None:
    deg = minimum_jerk_bends(np.random.default_rng(2), 200.0)
    assert deg.min() == pytest.approx(0.0, abs=1e-9) and 10.0 <= deg.max() <= 20.0


def test_friction_rises_with_the_load_it_carries() -> None:
    v = np.array([5.0, 5.0, -5.0])
    load = np.array([0.0, 10.0, 10.0])
    np.testing.assert_allclose(load_dependent_friction(v, load, 0.2, 0.03, 0.5), [0.2, 0.5, -0.5], rtol=1e-6)


def test_power_law_damping_equals_viscous_at_the_reference_speed() -> None:
    v = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    np.testing.assert_allclose(power_law_damping(v, 1.0, 1.5), [-2 ** 1.5, -1.0, 0.0, 1.0, 2 ** 1.5])
    np.testing.assert_allclose(power_law_damping(v, 2.0, 0.5)[-1], 2.0)


def test_the_hunt_crossley_stop_pushes_back_past_contact_and_never_pulls() -> None:
    deg = np.array([18.0, 20.0, 21.0, 22.0, 21.0])
    vel = np.array([0.0, 10.0, 10.0, 0.0, -10.0])
    y = hunt_crossley_stop(deg, vel, np.full(5, 20.0), True, 1.5, 0.05)
    assert y[0] == 0.0 and y[1] == 0.0
    assert y[2] == pytest.approx(1.0 * 1.5) and y[3] == pytest.approx(2 ** 1.5)
    assert y[4] == pytest.approx(0.5)  # leaving: less than entering (dissipation)
    low = hunt_crossley_stop(-deg, -vel, np.full(5, -20.0), False, 1.5, 0.05)
    np.testing.assert_allclose(low, -y)
    assert np.all(hunt_crossley_stop(deg, np.full(5, -100.0), np.full(5, 20.0), True, 1.5, 0.05) >= 0.0)


def test_the_contact_is_reseated_on_each_stroke() -> None:
    deg = np.concatenate([np.linspace(0, 10, 50), np.linspace(10, 0, 50)[1:], np.linspace(0, 10, 50)[1:]])
    c = stroke_contacts(deg, 8.0, 1.0, np.random.default_rng(0))
    assert np.all(np.abs(c - 8.0) <= 1.0)
    assert len(np.unique(c)) == 3 and np.unique(c[:45]).size == 1


def test_the_amplifiers_low_pass_delays_by_its_group_delay() -> None:
    rate, cutoff = 1000.0, 4.0
    t = np.arange(0.0, 20.0, 1.0 / rate)
    ramp = 0.3 * t
    late = butterworth_lag(ramp, rate, cutoff, 0.1, t)
    group = np.sqrt(2.0) / (2.0 * np.pi * cutoff)
    assert (ramp[-1] - late[-1]) / 0.3 == pytest.approx(0.1 + group, rel=1e-2)


def test_the_doublet_peaks_at_one_and_its_second_twitch_is_smaller() -> None:
    t = np.arange(0.0, 5.0, 0.001)
    y = gamma_doublet(t, 1.0, 1.5, 0.2, 4.0, 0.6)
    assert y[t < 1.0].max() == 0.0
    assert y[np.searchsorted(t, 1.2)] == pytest.approx(1.0, abs=1e-3)
    assert y[np.searchsorted(t, 2.7)] == pytest.approx(0.6, abs=0.02)


def test_thermal_drift_spans_one_about_its_mean() -> None:
    y = thermal_drift(np.linspace(0.0, 120.0, 2001), 0.5, 90.0, 0.3)
    assert np.max(np.abs(y)) == pytest.approx(1.0) and abs(np.mean(y)) < 1e-12


def test_the_strap_stiffens_as_it_tightens() -> None:
    tau = np.array([-10.0, 0.0, 1.0, 10.0])
    np.testing.assert_allclose(stiffening_give(tau, 10.0), [-5.0, 0.0, 1.0 / 1.1, 5.0])


def test_the_linkage_inertia_changes_with_angle() -> None:
    rad = np.array([0.0, np.pi / 2])
    out = linkage_inertia_torque(rad, np.zeros(2), np.ones(2), 2.0, 0.5, 0.0)
    np.testing.assert_allclose(out, [3.0, 2.0])


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_r(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 5.0


def test_a_delay_is_reported_as_its_transport_plus_the_filters_group_delay() -> None:
    g = generate_r("ankle", ("time_delay",), 7)
    d = g.details
    assert g.effects["time_delay"] == pytest.approx(d["transport_s"] + np.sqrt(2.0) / (2.0 * np.pi * d["cutoff_hz"]))
    assert 0.0 < g.effects["time_delay"] <= 0.35 + np.sqrt(2.0) / (2.0 * np.pi * 1.5)
