"""The burst's scan statistic (evidence.burst_scan): a half-sine slid over a residual, judged against what the same
filter finds elsewhere in the trial, at a familywise level that holds over noise of any spectrum."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from analysis.diagnosis import diagnose
from analysis.diagnosis.evidence import burst_scan, recurs_at_its_angle
from analysis.diagnosis.policy import BURST_SCAN_ALPHA


def _half_sine(t: np.ndarray, start: float, duration: float) -> np.ndarray:
    u = (t - start) / duration
    return np.where((u >= 0) & (u <= 1), np.sin(np.pi * np.clip(u, 0, 1)), 0.0)


def test_the_score_at_each_start_is_the_matched_filters() -> None:
    rng = np.random.default_rng(0)
    t = np.sort(rng.uniform(0.0, 20.0, 3000))  # uneven sampling: rows dropped
    r = rng.normal(size=t.size)
    scan = burst_scan(t, r, 0.5)
    g = _half_sine(t, scan.peak_start_s, 0.5)
    score = float(r @ g) ** 2 / float(g @ g)
    starts = np.arange(t[0], t[-1] - 0.5 + 1e-12, 0.125)
    direct = [float(r @ _half_sine(t, s, 0.5)) ** 2 / float(_half_sine(t, s, 0.5) @ _half_sine(t, s, 0.5)) for s in starts]
    assert score == pytest.approx(max(direct), rel=1e-9)


@pytest.mark.parametrize("rho", [0.0, 0.9, 0.98])
def test_over_noise_alone_the_familywise_level_holds(rho: float) -> None:
    """200 minutes of noise, white or an AR(1): a burst is found in no more than twice the level's share."""
    rng = np.random.default_rng(11)
    t = np.arange(0.0, 60.0, 0.01)
    found = 0
    for _ in range(200):
        noise = lfilter([1.0], [1.0, -rho], rng.normal(size=t.size))
        found += burst_scan(t, noise, float(rng.choice([0.2, 0.5, 1.0]))).unique(BURST_SCAN_ALPHA)
    assert found <= 2 * BURST_SCAN_ALPHA * 200


def test_a_burst_three_times_the_noise_is_found_where_it_is() -> None:
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 60.0, 0.01)
    hits = 0
    for _ in range(50):
        start = float(rng.uniform(5.0, 50.0))
        r = rng.normal(size=t.size) + 3.0 * _half_sine(t, start, 0.5)
        r[rng.random(t.size) < 0.01] = np.nan  # NaN cells are left out
        scan = burst_scan(t, r, 0.5)
        hits += scan.unique(BURST_SCAN_ALPHA) and abs(scan.peak_start_s - start) < 0.25
    assert hits >= 48


def test_a_shape_repeated_at_every_reversal_is_not_one_event() -> None:
    """What a model misses at each reversal (a friction turning over) scores alike at each: none stands out, though
    each alone would be significant."""
    rng = np.random.default_rng(2)
    t = np.arange(0.0, 60.0, 0.01)
    r = 0.1 * rng.normal(size=t.size)
    for turn in np.arange(3.0, 60.0, 6.0):
        r += 0.3 * _half_sine(t, turn, 0.5)
    scan = burst_scan(t, r, 0.5)
    assert scan.peak_p < BURST_SCAN_ALPHA and scan.elsewhere_p < BURST_SCAN_ALPHA
    assert not scan.unique(BURST_SCAN_ALPHA)


def test_a_square_wave_left_everywhere_is_no_burst() -> None:
    """A friction's square wave left whole: every start scores high, the median with them, so nothing is significant."""
    rng = np.random.default_rng(3)
    t = np.arange(0.0, 60.0, 0.01)
    r = 0.5 * np.sign(np.sin(2 * np.pi * t / 12.0)) + 0.1 * rng.normal(size=t.size)
    assert not burst_scan(t, r, 1.0).unique(BURST_SCAN_ALPHA)


def test_a_trial_shorter_than_the_burst_has_nothing_to_scan() -> None:
    t = np.arange(0.0, 0.4, 0.01)
    scan = burst_scan(t, np.ones(t.size), 0.5)
    assert scan.peak_p == 1.0 and not scan.unique(BURST_SCAN_ALPHA)


def test_bursts_in_an_independent_family_drowned_by_slow_structure_are_named_by_the_scan() -> None:
    # spent seventeenth-family knees (a smooth pulse of 3–5× the noise, 0.42 and 0.64 N·m): the whole trial's criterion
    # rejected both (slow structure elsewhere shrank n_eff); the scan names each where it is, sized within 15 %
    from benchmarks.diagnosis_family_b import _trial
    from benchmarks.family_q_truth import generate_q

    for seed in (206, 207):
        g = generate_q("knee", ("activation_burst",), seed)
        d = diagnose(_trial(g))
        assert d.cause == "activation_burst" and not d.also, (seed, d.text())
        truth = g.effects["activation_burst"]
        assert truth is not None
        assert abs(abs(d.parameters["burst_amplitude_Nm"]) - truth) <= 0.15 * truth


def _strokes() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A joint swept 0–1 rad and back every 20 s for 100 s at 100 Hz: (time s, angle rad, angular velocity rad/s)."""
    t = np.arange(0.0, 100.0, 0.01)
    theta = 2.0 * np.abs((t / 20.0) % 1.0 - 0.5)
    return t, theta, np.gradient(theta, t)


def test_a_blip_at_the_same_angle_on_every_pass_up_is_a_function_of_angle_not_a_burst() -> None:
    """A stop's contact crossed on each stroke up: the blip the scan picks once is seen again on the other passes."""
    t, theta, omega = _strokes()
    rng = np.random.default_rng(4)
    r = 0.05 * rng.normal(size=t.size)
    crossings = t[np.flatnonzero((theta[:-1] < 0.5) & (theta[1:] >= 0.5) & (omega[:-1] > 0))]
    for c in crossings:
        r += 0.3 * _half_sine(t, c - 0.15, 0.3)
    scan = burst_scan(t, r, 0.3)
    assert crossings.size == 5
    assert recurs_at_its_angle(t, theta, omega, r, scan.peak_start_s, 0.3, scan.score_scale)


def test_a_burst_once_in_time_is_not_seen_again_at_its_angle() -> None:
    t, theta, omega = _strokes()
    rng = np.random.default_rng(5)
    r = 0.05 * rng.normal(size=t.size) + 0.3 * _half_sine(t, 34.85, 0.3)  # once, on the third stroke up
    scan = burst_scan(t, r, 0.3)
    assert scan.unique(BURST_SCAN_ALPHA) and abs(scan.peak_start_s - 34.85) < 0.15
    assert not recurs_at_its_angle(t, theta, omega, r, scan.peak_start_s, 0.3, scan.score_scale)


def test_a_burst_during_a_hold_is_never_taken_for_a_function_of_angle() -> None:
    t = np.arange(0.0, 60.0, 0.01)
    theta = np.where(t < 30.0, 0.2, 0.2 + 0.01 * (t - 30.0))
    r = 0.3 * _half_sine(t, 10.0, 0.5)
    assert not recurs_at_its_angle(t, theta, np.gradient(theta, t), r, 10.0, 0.5, 0.01)
