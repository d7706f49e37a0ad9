"""The nineteenth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_s_truth import (
    NOISE_SD_NM,
    bilinear_stop,
    catch,
    coupled_limb_acceleration,
    generate_s,
    give_with_play,
    held_polls,
    knocked_cable,
    linkage_spring,
    paced_strokes,
    recruited_fibres,
    running_in_friction,
    springpot,
    tremulous_bends,
)


def test_fibres_are_recruited_one_by_one() -> None:
    x = np.array([-1.0, 0.5, 1.5, 3.0])
    y = recruited_fibres(x, np.array([0.0, 1.0, 2.0]), np.array([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(y, [0.0, 0.5, 1.5 + 1.0, 3.0 + 4.0 + 3.0])


def test_the_linkage_spring_is_preloaded_and_stiffens_with_the_bend() -> None:
    deg = np.array([0.0, 10.0, 20.0])
    tau = linkage_spring(deg, 0.05, 0.1, 0.002, 1000.0)
    assert tau[0] == pytest.approx(1000.0 * 0.002 * 0.05 * 0.1 / np.hypot(0.05, 0.1))  # k·preload·dl/dθ at 0°
    assert tau[0] < tau[1] < tau[2]


def test_paced_strokes_stay_in_range_and_move_at_their_own_speeds() -> None:
    rate = 200.0
    deg = paced_strokes(np.random.default_rng(1), 10.0, 85.0, rate)
    assert deg.min() >= 10.0 and deg.max() <= 85.0 and deg.max() > 84.0
    speed = np.abs(np.diff(deg)) * rate
    assert speed.max() < 2.5 * 12.0  # the raised-cosine ramps and the ripple, nothing faster


def test_bends_have_their_own_peaks_and_a_tremor() -> None:
    deg = tremulous_bends(np.random.default_rng(2), 500.0)
    assert deg.min() == pytest.approx(0.0, abs=1e-9) and 9.8 <= deg.max() <= 20.2
    bent = deg > 5.0
    wiggle = np.diff(np.sign(np.diff(deg[bent])))
    assert np.count_nonzero(wiggle) > 50  # the tremor reverses the angle many times while bent


def test_friction_runs_in() -> None:
    t = np.array([0.0, 30.0, 1e6])
    f = running_in_friction(np.full(3, 10.0), t, 1.0, 0.4, 30.0, 0.5)
    assert f[0] == pytest.approx(np.tanh(20.0)) and f[2] == pytest.approx(0.6 * np.tanh(20.0))
    assert f[1] == pytest.approx((1 - 0.4 * (1 - np.exp(-1))) * np.tanh(20.0))


def test_the_springpot_lies_between_the_angle_and_its_rate() -> None:
    rate = 200.0
    t = np.arange(0.0, 20.0, 1.0 / rate)
    ramp = 0.1 * t
    half = springpot(ramp, rate, 0.5, memory_s=30.0)
    # D^½ of a ramp a·t from rest is a·t^½ / Γ(3/2), with the whole history in memory
    assert half[-1] == pytest.approx(0.1 * np.sqrt(20.0) / 0.8862269, rel=0.01)
    one = springpot(ramp, rate, 1.0)
    assert one[-1] == pytest.approx(0.1, rel=1e-6)  # order 1: the rate


def test_the_bilinear_stop_has_a_pad_and_a_seat() -> None:
    deg = np.array([19.0, 21.0, 22.0, 24.0])
    y = bilinear_stop(deg, 20.0, True, 2.0, 5.0)
    np.testing.assert_allclose(y, [0.0, 1.0, 2.0, 2.0 + 10.0])
    np.testing.assert_allclose(bilinear_stop(-deg, -20.0, False, 2.0, 5.0), -y)


def test_polls_are_held_and_late() -> None:
    t = np.arange(0.0, 2.0, 0.001)
    held = held_polls(t.copy(), t, 10.0, 0.05, 0.0)
    assert held[1234] == pytest.approx(1.2 - 0.05)  # polled at 1.2 s, 50 ms late
    lag = float(np.mean(t[200:] - held[200:]))
    assert lag == pytest.approx(0.05 + 0.05, abs=2e-3)  # transport plus half the poll period


def test_a_catch_rises_linearly_and_decays() -> None:
    t = np.array([0.0, 1.05, 1.1, 1.6])
    np.testing.assert_allclose(catch(t, 1.0, 0.1, 0.5), [0.0, 0.5, 1.0, np.exp(-1.0)])


def test_a_knocked_cable_steps_and_recovers() -> None:
    np.testing.assert_allclose(knocked_cable(np.array([0.0, 10.0, 40.0]), 10.0, 30.0), [0.0, 1.0, np.exp(-1.0)])


def test_the_strap_play_follows_the_torques_side_and_holds_at_zero() -> None:
    np.testing.assert_allclose(give_with_play(np.array([1.0, 0.0, -2.0, 0.0, 3.0]), 0.4), [0.2, 0.2, -0.2, -0.2, 0.2])


def test_the_limb_follows_the_drive_through_its_coupling() -> None:
    rate = 1000.0
    t = np.arange(0.0, 3.0, 1.0 / rate)
    drive = 0.1 * np.sin(2 * np.pi * 0.5 * t)
    acc = coupled_limb_acceleration(drive, rate, 8.0, 0.2)
    expected = -0.1 * (2 * np.pi * 0.5) ** 2 * np.sin(2 * np.pi * 0.5 * t)
    assert np.max(np.abs(acc[1500:] - expected[1500:])) < 0.15 * np.max(np.abs(expected))


@pytest.mark.parametrize("kind", ["afo", "knee", "ankle"])
def test_clean_trials_hold_noise_near_the_drawn_level(kind: str) -> None:
    g = generate_s(kind, (), 4)
    assert g.details["noise_sd_Nm"] == pytest.approx(NOISE_SD_NM[kind], rel=0.3)
    ok = np.isfinite(g.torque_nm)
    assert ok.mean() > 0.99 and np.ptp(g.torque_nm[ok]) > 2.0


def test_a_delay_is_reported_as_its_transport_plus_half_a_poll() -> None:
    g = generate_s("knee", ("time_delay",), 7)
    d = g.details
    assert g.effects["time_delay"] == pytest.approx(d["transport_s"] + 0.5 / d["poll_hz"])
