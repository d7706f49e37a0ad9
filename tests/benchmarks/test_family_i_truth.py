"""The ninth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_i_truth import NOISE_SD_NM, _knob_strokes, bouc_wen, generate_i, recruited


def test_recruited_fibres_give_a_toe_then_a_line() -> None:
    """The moment's slope is the recruited fraction (the Weibull CDF): zero before the onset, rising through the
    toe, one (all fibres taut) far past it."""
    x = np.linspace(-5.0, 60.0, 6501)
    m = recruited(x, 8.0, 2.5)
    slope = np.gradient(m, x)
    assert np.all(m[x <= 0.0] == 0.0)
    cdf = 1.0 - np.exp(-((np.clip(x, 0, None) / 8.0) ** 2.5))
    np.testing.assert_allclose(slope[100:-100], cdf[100:-100], atol=2e-3)
    assert slope[-200] == pytest.approx(1.0, abs=1e-3)


def test_bouc_wen_saturates_while_sliding_and_turns_over_after_a_reversal() -> None:
    """While sliding z tends to the direction of motion (±1); after a reversal it crosses zero within a few
    presliding widths, sooner for a sharper law (larger n keeps |z| near 1 longer, then turns faster)."""
    path = np.concatenate([np.linspace(0.0, 10.0, 2001), np.linspace(10.0, 0.0, 2001)[1:]])
    for n in (2.0, 4.0):
        z = bouc_wen(path, n, 0.5)
        assert z[2000] == pytest.approx(1.0, abs=0.02) and z[-1] == pytest.approx(-1.0, abs=0.02)
        crossing = int(np.flatnonzero(z[2000:] < 0.0)[0])
        assert 0 < path[2000] - path[2000 + crossing] < 1.5  # degrees after the reversal
    assert np.all(np.abs(bouc_wen(path, 3.0, 0.6)) <= 1.0)


def test_the_knob_strokes_stay_inside_the_drives_limits_and_end_on_their_targets() -> None:
    rate = 500.0
    for seed in range(4):
        deg = _knob_strokes(np.random.default_rng(seed), 5.0, 90.0, rate)
        vel = np.gradient(deg, 1.0 / rate)
        acc = np.gradient(vel, 1.0 / rate)
        assert deg.min() == pytest.approx(5.0, abs=1e-6) and deg.max() == pytest.approx(90.0, abs=1e-6)
        assert np.max(np.abs(vel)) <= 25.0 + 1e-6
        assert np.max(np.abs(acc)) < 100.0  # deg/s²: 60 while braking or following the knob, no spike


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_i("ankle", ("time_delay",), s) for s in range(20)]
    for g in delays:  # the mean lag of a clock drifting from its start
        assert g.effects["time_delay"] >= g.details["lag_start_s"]
    assert max(g.effects["time_delay"] for g in delays) > 0.35 and min(g.effects["time_delay"] for g in delays) < 0.15
    for s in range(5):
        g = generate_i("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"] * 1.001
        assert 20.0 <= g.details["lift_width_deg"] <= 40.0
    stops = [generate_i("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
