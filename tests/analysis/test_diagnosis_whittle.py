"""Whittle's criterion (evidence.whittle_delta_bic): on white noise it is the Gaussian likelihood ratio; beside a slow
misfit it judges a fast effect against the noise at its own frequencies, where one effective sample size for the whole
residual (evidence.bic at evidence.effective_n) drowns it.

The signals are written here: a noise of known spectrum, a slow misfit (a few sinusoids below 0.3 Hz of random phase)
and a fast effect (a train of short pulses, a friction-like square wave of the sweep), each drawn from a seed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from analysis.diagnosis.evidence import bic, effective_n, residual_spectrum, whittle_delta_bic
from analysis.diagnosis.fitting import CauseFit

RATE_HZ = 100.0
SECONDS = 120.0


def _fit(target: np.ndarray, columns: list[np.ndarray]) -> CauseFit:
    """Least squares of ``target`` on ``columns`` (a constant always) as a CauseFit."""
    x = np.column_stack([np.ones_like(target)] + columns)
    coef, *_ = np.linalg.lstsq(x, target, rcond=None)
    prediction = x @ coef
    return CauseFit("test", (), coef, 1, prediction, float(np.sum((target - prediction) ** 2)), target.size, {})


def _slow_misfit(rng: np.random.Generator, t: np.ndarray, rms: float) -> np.ndarray:
    slow = sum(np.sin(2.0 * np.pi * rng.uniform(0.02, 0.3) * t + rng.uniform(0.0, 2.0 * np.pi)) for _ in range(5))
    return rms * slow / np.std(slow)


def _square(t: np.ndarray, period_s: float) -> np.ndarray:
    """A sweep's friction: ± 1 by the sign of the velocity of a triangle wave of ``period_s``."""
    return np.sign(np.sin(2.0 * np.pi * t / period_s))


def _broadband(rng: np.random.Generator, n: int) -> np.ndarray:
    """A regressor with power spread over 0–5 Hz at 100 Hz (white noise through a 20-sample moving mean)."""
    return np.convolve(rng.normal(0.0, 1.0, n + 19), np.ones(20) / 20.0, mode="valid")


@pytest.mark.parametrize("seed", range(6))
def test_on_white_noise_it_is_the_gaussian_likelihood_ratio(seed: int) -> None:
    """An effect whose power is spread over many frequencies, in white noise, near the threshold: Whittle's fit term
    against the Gaussian one, n ln(RSS_large/RSS_small): within a fifth, never more (the effect's power sits in a tenth
    of the bands, where the log of each band's ratio is a little below its first-order term)."""
    rng = np.random.default_rng([7100, seed])
    t = np.arange(0.0, SECONDS, 1.0 / RATE_HZ)
    effect = _broadband(rng, t.size)
    target = rng.uniform(0.05, 0.1) * effect / np.std(effect) + rng.normal(0.0, 0.5, t.size)
    small, large = _fit(target, []), _fit(target, [effect])
    gaussian = t.size * math.log(large.rss / small.rss)
    whittle = whittle_delta_bic(target, large, small) - math.log(t.size)
    assert gaussian < -15.0
    assert 0.8 < whittle / gaussian < 1.02, (whittle, gaussian)  # the log of a band's ratio: a little below, never above


def test_an_effect_in_a_few_harmonics_is_credited_less_never_more() -> None:
    """A sweep's friction (a square wave: 81 % of its power at the fundamental) in white noise: each band is compared
    with itself, so a line far above its band's noise is credited the log of its band's power ratio, less than the
    Gaussian ΔRSS/σ² (on 12 seeds 0.4–0.9 of it), never more; and still far past the threshold."""
    ratios = []
    for seed in range(12):
        rng = np.random.default_rng([7105, seed])
        t = np.arange(0.0, SECONDS, 1.0 / RATE_HZ)
        effect = _square(t, rng.uniform(8.0, 20.0))
        target = rng.uniform(0.02, 0.06) * effect + rng.normal(0.0, 0.5, t.size)
        small, large = _fit(target, []), _fit(target, [effect])
        gaussian = t.size * math.log(large.rss / small.rss)
        whittle = whittle_delta_bic(target, large, small) - math.log(t.size)
        assert whittle < -10.0, (seed, whittle, gaussian)
        ratios.append(whittle / gaussian)
    assert 0.3 < min(ratios) and max(ratios) < 1.05, ratios


def test_the_spectrum_of_white_noise_is_its_variance_per_bin() -> None:
    rng = np.random.default_rng(7101)
    noise = rng.normal(0.0, 0.3, 20_000)
    spectrum = residual_spectrum(noise)
    assert spectrum.size == noise.size // 2
    assert abs(float(np.mean(spectrum)) / 0.09 - 1.0) < 0.02


def test_a_missing_sample_in_either_model_is_left_out_of_both() -> None:
    rng = np.random.default_rng(7102)
    t = np.arange(0.0, 60.0, 1.0 / RATE_HZ)
    effect = _square(t, 10.0)
    target = 0.2 * effect + rng.normal(0.0, 0.3, t.size)
    small, large = _fit(target, []), _fit(target, [effect])
    whole = whittle_delta_bic(target, large, small)
    large.prediction[:50] = np.nan  # a delay's model predicts nothing before its lag
    cut = whittle_delta_bic(target, large, small)
    assert math.isfinite(cut) and cut < -100 and abs(cut / whole - 1.0) < 0.1
    assert math.isnan(whittle_delta_bic(target[:10], _fit(target[:10], [effect[:10]]), _fit(target[:10], [])))


@pytest.mark.parametrize("seed", range(6))
def test_a_fast_effect_beside_a_slow_misfit_is_seen_where_one_effective_n_drowns_it(seed: int) -> None:
    """Noise SD σ; a slow misfit of 1.5–2.5 σ RMS that neither model holds; a pulse train of 1–1.5 σ (a reflex at each
    reversal, 0.3 s long). At one n_eff for the whole residual the slow misfit's correlation time counts against the
    pulses too; Whittle weighs the pulses' band against the white noise there."""
    rng = np.random.default_rng([7103, seed])
    t = np.arange(0.0, SECONDS, 1.0 / RATE_HZ)
    sigma = 0.2
    period = rng.uniform(8.0, 14.0)
    phase = np.mod(t, period / 2.0)
    pulses = np.where(phase < 0.3, np.sin(np.pi * phase / 0.3) ** 2, 0.0)
    amplitude = rng.uniform(1.0, 1.5) * sigma
    target = amplitude * pulses + _slow_misfit(rng, t, rng.uniform(1.5, 2.5) * sigma) + rng.normal(0.0, sigma, t.size)
    small, large = _fit(target, []), _fit(target, [pulses])
    n_eff = effective_n(target - large.prediction)
    by_one_n_eff = bic(large, n_eff) - bic(small, n_eff)
    by_whittle = whittle_delta_bic(target, large, small)
    assert by_whittle < -10.0, by_whittle
    assert by_one_n_eff > by_whittle + 10.0, (by_one_n_eff, by_whittle)


@pytest.mark.parametrize("seed", range(6))
def test_a_regressor_with_nothing_behind_it_is_not_preferred(seed: int) -> None:
    """The same slow misfit and noise with no pulses: the pulse regressor must not lower the criterion by 10."""
    rng = np.random.default_rng([7104, seed])
    t = np.arange(0.0, SECONDS, 1.0 / RATE_HZ)
    period = rng.uniform(8.0, 14.0)
    phase = np.mod(t, period / 2.0)
    pulses = np.where(phase < 0.3, np.sin(np.pi * phase / 0.3) ** 2, 0.0)
    target = _slow_misfit(rng, t, 0.4) + rng.normal(0.0, 0.2, t.size)
    small, large = _fit(target, []), _fit(target, [pulses])
    assert whittle_delta_bic(target, large, small) > -10.0
