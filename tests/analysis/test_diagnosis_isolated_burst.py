"""A short burst judged as one isolated event at its own time scale (transients.isolated_transient), beside the
criterion at the residual's effective sample size, which slow noise sets.

The hidden-effect trials are the spent generator families' single bursts (3–5 × the noise, each family's own shape and
noise: development data since each family was run once) that the criterion alone missed and this test names: eleven
of 192 knee and ankle trials of the second to twenty-fifth families (seeds 200–203); none of their 192 clean trials
(seeds 100–103) changed its names. A second generator written here, which the engine does not share, makes clean
trials with a slow wander (an ankle swept at 4–6 °/s with smooth turns; passive ends the square of a softplus of the
bend past an onset 30 % of the way out; the limb's weight through the benchmarks' segment tables; white noise plus a
first-order process of 4–12 s at 0.8–1.3 × the white noise's SD): no burst may be named there. With a twitch added
(Gaussian envelope, SD 0.06–0.2 s, peak 3–5 × the noise's whole SD) the least-squares search places the burst on the
wander in most of its eight trials (4 named, 2 of them in place): a limit docs/validation.md states (thirty-fifth
stop).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from analysis.diagnosis import DiagnosisTrial, diagnose
from analysis.diagnosis.causes import BURST_GRID_DURATIONS_S
from analysis.diagnosis.policy import ISOLATED_BURST_ALPHA
from analysis.diagnosis.transients import TransientScan
from analysis.diagnosis.transients import isolated_transient as _isolated
from benchmarks.family_scaffold import GRAVITY, draw_segments, draw_subject, limb_load

RATE_HZ = 200.0


def _wander(rng: np.random.Generator, n: int, tau_s: float, sd: float) -> np.ndarray:
    """A first-order (AR(1)) process of time constant ``tau_s`` and SD ``sd``, at :data:`RATE_HZ`."""
    phi = math.exp(-1.0 / (tau_s * RATE_HZ))
    x = lfilter([1.0], [1.0, -phi], rng.normal(0.0, 1.0, n))
    return sd * (x - x.mean()) / x.std()


def _ankle_trial(seed: int) -> DiagnosisTrial:
    """One clean ankle trial of this module's generator, with its slow wander."""
    rng = np.random.default_rng(seed)
    lo, hi = float(rng.uniform(-28.0, -22.0)), float(rng.uniform(10.0, 16.0))
    speed = float(rng.uniform(4.0, 6.0))
    period = 2.0 * (hi - lo) / speed
    t = np.arange(0.0, 4.5 * period, 1.0 / RATE_HZ)
    phase = (t / period) % 1.0
    triangle = np.where(phase < 0.5, 2.0 * phase, 2.0 - 2.0 * phase)
    smooth = np.convolve(np.pad(triangle, 100, mode="edge"), np.hanning(201) / np.hanning(201).sum(), "same")[100:-100]
    deg = lo + (hi - lo) * smooth
    rad = np.radians(deg)
    fixed = {"knee_flexion_deg": 0.0, "hip_flexion_deg": 90.0}
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    load = limb_load("ankle", rad, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    top, bottom = float(rng.uniform(6.0, 12.0)), float(rng.uniform(2.0, 5.0))
    # smooth ends: the softplus of the bend past an onset, squared (a stiffness rising from zero over a few degrees)
    onset_high, onset_low, width = 0.3 * hi, 0.3 * lo, float(rng.uniform(2.0, 4.0))
    high_end = (width * np.logaddexp(0.0, (deg - onset_high) / width)) ** 2
    low_end = (width * np.logaddexp(0.0, (onset_low - deg) / width)) ** 2
    passive = (top * high_end / float((width * np.logaddexp(0.0, (hi - onset_high) / width)) ** 2)
               - bottom * low_end / float((width * np.logaddexp(0.0, (onset_low - lo) / width)) ** 2))
    white = float(rng.uniform(0.10, 0.16))
    slow = white * float(rng.uniform(0.8, 1.3))
    torque = (passive + load.moment_nm + rng.normal(0.0, white, t.size)
              + _wander(rng, t.size, float(rng.uniform(4.0, 12.0)), slow))
    return DiagnosisTrial("ankle", t, rad, torque, fixed, subject, f"isolated-burst test seed {seed}", 0.0)


def _named(d: object) -> set[str]:
    return ({d.cause} - {"none"}) | {a["cause"] for a in d.also}  # type: ignore[attr-defined]  # a Diagnosis


#: clean trials' seeds (eight until the thirty-eighth stop, none named a burst; four since, for the suite's time)
SEEDS = range(4)
#: (family, kind, seed) of the spent families' single bursts the criterion missed and the isolated-event test names:
#: eleven found when the test was written, every second of them tested since the thirty-eighth stop (the suite's time)
MISSED_BEFORE = (("d", "ankle", 203), ("e", "knee", 202), ("f", "knee", 202), ("k", "ankle", 202), ("n", "knee", 200),
                 ("n", "knee", 201), ("q", "ankle", 200), ("r", "knee", 201), ("y", "knee", 200), ("y", "ankle", 202),
                 ("y", "ankle", 203))[::2]


@pytest.mark.timeout(360)
def test_bursts_the_criterion_missed_in_slow_noise_are_named_alone_and_sized() -> None:
    """Measured when the test was written: all 11 named alone, their intervals holding the truth in 10, within 15 % in
    6 and within 30 % in 10 (the 18th family's knee at seed 201: 0.23 against 0.49 N·m); at the thirty-eighth stop
    (engine eddd6e2) the same, and the six tested here (every second) all named alone, held and within 30 %. The
    tolerance stays one case of each."""
    from benchmarks.diagnosis_family_b import FAMILIES, _trial

    alone, held, within = 0, 0, 0
    for family, kind, seed in MISSED_BEFORE:
        g = FAMILIES[family][0](kind, ("activation_burst",), seed)
        d = diagnose(_trial(g))
        if _named(d) != {"activation_burst"}:
            continue
        alone += 1
        note = next(c.note for c in d.candidates if c.cause == "activation_burst")
        assert "as one event at its own time scale" in note, note  # the report says which test named it
        fitted, truth = abs(d.parameters["burst_amplitude_Nm"]), g.effects["activation_burst"]
        held += abs(fitted - truth) <= 1.96 * d.parameters_se["burst_amplitude_Nm"]
        within += abs(fitted / truth - 1.0) < 0.3
    assert alone == len(MISSED_BEFORE)
    assert held >= len(MISSED_BEFORE) - 1 and within >= len(MISSED_BEFORE) - 1, (held, within)


def test_clean_trials_with_a_slow_wander_name_no_burst() -> None:
    """The wander is a real slow offset (a drift may be named); a burst is not, on any of them."""
    named = [_named(diagnose(_ankle_trial(1000 + seed))) for seed in SEEDS]
    assert all("activation_burst" not in n for n in named), named


def isolated_transient(t: np.ndarray, e: np.ndarray, start_s: float, duration_s: float) -> TransientScan:
    """The scan at the engine's level and over its burst grid's durations."""
    return _isolated(t, e, start_s, duration_s, ISOLATED_BURST_ALPHA, len(BURST_GRID_DURATIONS_S))


def _scan_noise(seed: int, n: int = 12_000) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(n) / RATE_HZ
    return t, rng.normal(0.0, 1.0, n) + _wander(rng, n, float(rng.uniform(2.0, 15.0)), float(rng.uniform(0.5, 3.0)))


def _bump(t: np.ndarray, start: float, duration: float) -> np.ndarray:
    u = (t - start) / duration
    return np.where((u >= 0) & (u <= 1), np.sin(np.pi * np.clip(u, 0.0, 1.0)), 0.0)


def test_noise_alone_passes_the_scan_at_its_largest_window_at_most_at_its_level() -> None:
    """Forty noises (white plus a wander of up to 3 × its SD): the scan placed where it peaks, as a search would place
    a burst, crosses its 1 % family-wise level in none (at most 1 allowed: 0.4 expected)."""
    crossings = 0
    for seed in range(40):
        t, e = _scan_noise(seed)
        duration = 0.5
        m = int(round(duration * RATE_HZ))
        kernel = np.concatenate([np.zeros(m), np.sin(np.pi * np.linspace(0.0, 1.0, m)), np.zeros(m)])
        peak_start = float(t[int(np.argmax(np.abs(np.correlate(e - e.mean(), kernel, "valid")))) + m])
        crossings += isolated_transient(t, e, peak_start, duration).isolated
    assert crossings <= 1


def test_one_bump_stands_out_of_a_strong_wander_and_two_do_not() -> None:
    """A half-sine of 0.4 s at 4 × the white noise on a wander of 3 × it stands out; a second one like it 20 s away
    makes the residual's structure recur, and neither is isolated."""
    t, e = _scan_noise(99)
    one = e + 4.0 * _bump(t, 30.0, 0.4)
    scan = isolated_transient(t, one, 30.0, 0.4)
    assert scan.isolated and scan.z_event > scan.z_critical > scan.z_elsewhere
    two = one + 4.0 * _bump(t, 50.0, 0.4)
    scan_two = isolated_transient(t, two, 30.0, 0.4)
    assert scan_two.z_event > scan_two.z_critical and scan_two.z_elsewhere > scan_two.z_critical
    assert not scan_two.isolated


def test_a_scan_of_too_short_or_empty_data_names_nothing() -> None:
    t = np.arange(50) / RATE_HZ
    assert not isolated_transient(t, np.zeros(50), 0.1, 0.1).isolated  # no spread at all
    assert not isolated_transient(t, np.random.default_rng(0).normal(size=50), 0.05, 0.2).isolated  # too short
    nan = np.full(50, np.nan)
    assert not isolated_transient(t, nan, 0.1, 0.1).isolated
