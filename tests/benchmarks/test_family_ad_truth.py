"""The thirtieth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_ad_truth import (
    NOISE_SD_NM,
    alpha_beta_tracker,
    behind_gripping_cuff,
    carbon_leaf,
    chirped_zero,
    compensation_error,
    creeping_stop,
    generate_ad,
    gripping_cuff,
    gumbel_pulse,
    hydrodynamic_friction,
    lagged_share,
    linkage_dashpot,
    mooney_rivlin_tension,
    two_step_bends,
    wandering_triangle,
)


def test_the_mooney_rivlin_end_is_flat_before_its_onset_and_follows_the_law_past_it() -> None:
    assert abs(float(mooney_rivlin_tension(np.array(-60.0), 2.0, 20.0, 0.5, 1.0))) < 1e-9
    # far past the onset (x̄ = x): a stretch of 1.5
    lam = 1.5
    want = 2.0 * (lam - lam**-2) * (1.0 + 0.5 / lam) * np.exp(1.0 * 0.5)
    assert float(mooney_rivlin_tension(np.array(10.0), 0.01, 20.0, 0.5, 1.0)) == pytest.approx(want, rel=1e-6)
    # small stretch: 2·3(λ − 1)(1 + r)
    assert float(mooney_rivlin_tension(np.array(0.02), 1e-4, 20.0, 0.5, 1.0)) == pytest.approx(6e-3 * 1.5, rel=1e-2)


def test_the_carbon_leaf_softens_then_its_strap_hardens_it() -> None:
    h = 1e-4

    def k(bend: float) -> float:
        return float(np.diff(carbon_leaf(np.array([bend, bend + h]), 0.0, 1e-3, 30.0, 20.0))[0] / h)
    assert k(0.5) == pytest.approx(1.0, rel=0.05)
    assert k(5.0) < k(0.5) < k(18.0)
    assert abs(float(carbon_leaf(np.array(0.0), 1.0, 0.5, 30.0, 20.0))) < 1e-12


def test_the_triangle_wanders_within_the_range_at_its_speed() -> None:
    rate = 200.0
    deg = wandering_triangle(np.random.default_rng(3), 10.0, 80.0, rate)
    assert deg.min() >= 10.0 - 1e-9 and deg.max() <= 80.0 + 1e-9
    assert deg[0] == pytest.approx(45.0) and deg[-1] == pytest.approx(45.0)
    speed = np.abs(np.diff(deg)) * rate
    moving = speed[speed > 1.0]
    assert 3.0 * 0.99 <= np.median(moving) <= 7.0 * 1.01 and moving.max() <= np.median(moving) * 1.001
    step = np.diff(deg)
    turns = np.flatnonzero(np.sign(step[1:]) * np.sign(step[:-1]) < 0)
    assert turns.size >= 6


def test_bends_pause_partway_and_return_to_zero() -> None:
    rate = 500.0
    deg = two_step_bends(np.random.default_rng(5), rate)
    assert abs(deg[0]) < 1e-12 and abs(deg[-1]) < 1e-12 and 10.0 <= deg.max() <= 20.0 and deg.min() >= -1e-9
    held = np.abs(np.diff(deg)) < 1e-12
    mid_holds = held & (deg[1:] > 3.0)
    assert mid_holds.sum() >= 5 * 0.2 * rate - 5  # each bend's pause partway up


def test_the_bushing_drags_more_with_the_speeds_square() -> None:
    v = np.array([-10.0, 0.0, 5.0, 10.0])
    f = hydrodynamic_friction(v, 0.01, 0.4)
    np.testing.assert_allclose(f, [-1.4, 0.0, 1.0 + 0.4 * 0.25, 1.4])


def test_the_linkage_dashpot_peaks_mid_range() -> None:
    out = linkage_dashpot(np.ones(3), np.array([0.0, 0.5, 1.0]), 0.5)
    np.testing.assert_allclose(out, [1.0, 2.25, 1.0], atol=1e-12)


def test_the_stops_seat_creeps_into_the_range_over_the_trial() -> None:
    t = np.linspace(0.0, 100.0, 101)
    for high, sign in ((True, 1.0), (False, -1.0)):
        at = np.full(t.size, 50.0)
        out = creeping_stop(at, t, 50.0, high, 2.0)
        assert out[0] == 0.0 and sign * out[-1] == pytest.approx(2.0) and sign * out[50] == pytest.approx(1.0)
        assert np.all(creeping_stop(at - sign * 5.0, t, 50.0, high, 2.0) == 0.0)


def test_the_tracker_follows_a_ramp_without_lag_and_overshoots_a_turn() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    ramp = 0.5 * t
    out = alpha_beta_tracker(ramp, t, 0.2)
    np.testing.assert_allclose(out[-200:], ramp[-200:], atol=1e-6)
    turn = np.where(t < 10.0, t, 20.0 - t)
    bent = alpha_beta_tracker(turn, t, 0.2)
    assert bent.max() > turn.max() + 1e-3


def test_the_gumbel_pulse_peaks_at_its_mode_with_a_long_tail() -> None:
    t = np.arange(0.0, 10.0, 0.001)
    p = gumbel_pulse(t, 4.0, 0.3)
    assert p.max() == pytest.approx(1.0, abs=1e-6) and t[np.argmax(p)] == pytest.approx(4.0, abs=0.002)
    assert p[t > 4.0].sum() > 1.5 * p[t < 4.0].sum()


def test_the_share_lags_the_posture() -> None:
    t = np.arange(0.0, 100.0, 0.1)
    out = lagged_share(np.where(t >= 10.0, 1.0, 0.0), t, 20.0)
    assert out[np.searchsorted(t, 30.0)] == pytest.approx(1.0 - np.exp(-1.0), rel=0.01)


def test_the_zeros_period_falls_over_the_trial() -> None:
    t = np.arange(0.0, 600.0, 0.05)
    zero = chirped_zero(t, 100.0, 25.0, 0.0)
    ups = t[np.flatnonzero((zero[:-1] < 0.0) & (zero[1:] >= 0.0))]
    periods = np.diff(ups)
    assert periods[0] > 60.0 and periods[-1] < 35.0 and np.all(np.diff(periods) < 0.0)


def test_the_cuff_grips_then_slides_and_reloads_elastically() -> None:
    up = np.linspace(0.0, 10.0, 101)
    down = np.linspace(10.0, 0.0, 101)[1:]
    tau = np.concatenate([up, down])
    give = gripping_cuff(tau, 0.1, 4.0, 0.25)
    rate = np.diff(give) / np.diff(tau)
    assert rate[10] == pytest.approx(0.1) and rate[90] == pytest.approx(0.1 / 0.25)  # elastic, then sliding
    assert rate[105] == pytest.approx(0.1)  # after the reversal: elastic again
    assert give[-1] > 0.0  # the slip stays where the hardening spring and the grip balance


def test_the_joint_behind_the_cuff_satisfies_the_cuffs_law_and_a_cuff_too_soft_for_a_fixed_point_is_refused() -> None:
    deg = np.concatenate([np.linspace(0.0, 20.0, 201), np.linspace(20.0, 5.0, 151)[1:]])

    def spring(d: np.ndarray) -> np.ndarray:
        return 2.0 * d

    joint = behind_gripping_cuff(deg, spring, 0.1, 8.0, 0.4)  # c/h · k = 0.5
    np.testing.assert_allclose(joint, deg - gripping_cuff(spring(joint), 0.1, 8.0, 0.4), atol=1e-6)
    # at 20°: j + j/5 + (2j − 8)/k_h = 20 with k_h = h/(1 − h)/c = 20/3 N·m/° once past the grip: j = 21.2/1.5 (elastic
    # alone it would be 20/1.2)
    assert np.all(joint <= deg) and joint[200] == pytest.approx(21.2 / 1.5, abs=1e-5)
    with pytest.raises(RuntimeError, match="did not converge"):
        behind_gripping_cuff(deg, spring, 0.6, 8.0, 0.2)  # c/h · k = 6


def test_the_compensation_error_is_the_wrong_inertia_at_low_frequency() -> None:
    t = np.arange(0.0, 20.0, 0.001)
    acc = np.sin(2.0 * np.pi * 0.1 * t)
    out = compensation_error(acc, t, 0.05, 0.4, 1.0)
    slope = float(np.dot(acc[5000:], out[5000:]) / np.dot(acc[5000:], acc[5000:]))
    assert slope == pytest.approx(0.4, rel=0.02)


def test_effects_are_sized_against_the_trials_noise_and_clean_trials_hold_none() -> None:
    for kind in ("afo", "knee", "ankle"):
        clean = generate_ad(kind, (), 5)
        assert clean.effects == {} and NOISE_SD_NM[kind] * 0.8 <= clean.details["noise_sd_Nm"] <= NOISE_SD_NM[kind] * 1.25
    burst = generate_ad("ankle", ("activation_burst",), 5)
    sd = burst.details["noise_sd_Nm"]
    assert 3.0 * sd <= burst.effects["activation_burst"] <= 5.0 * sd
    delay = generate_ad("knee", ("time_delay",), 5)
    assert 0.02 <= delay.effects["time_delay"] <= 0.45
