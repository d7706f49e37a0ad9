"""The seventh generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_g_truth import NOISE_SD_NM, _bessel_low_pass, _passive, generate_g


def test_the_bessel_filters_group_delay_is_what_a_step_shows() -> None:
    """The delay's truth counts the filter's low-frequency group delay: a slow ramp through the filter lags by it."""
    from scipy.signal import lfilter

    rate = 500.0
    b, a, delay = _bessel_low_pass(5.0, rate)
    t = np.arange(5000) / rate
    ramp = t.copy()
    out = lfilter(b, a, ramp)
    assert out[-1] == pytest.approx(ramp[-1] - delay, abs=2e-4)
    assert 0.05 < delay < 0.15  # about 0.51 / f_c for this order and normalisation


def test_the_passive_curve_is_smooth_and_the_afo_spring_engages_without_a_kink() -> None:
    """No onset anywhere: the sinh curve's slope is continuous; the AFO's spring engages through a smoothstep, its
    slope rising from 0 to k over the ramp."""
    deg = np.linspace(0.0, 90.0, 9001)
    coef = {"amp": 1.0, "cubic": 0.2, "neutral": 55.0, "width": 25.0, "shift": 0.2, "tilt": -0.4}
    slope = np.diff(_passive("knee", deg, {"hip_flexion_deg": 55.0}, coef))
    assert np.max(np.abs(np.diff(slope))) < 1e-4
    afo = {"k": 0.5, "engage": 2.0, "ramp": 2.0}
    bend = np.linspace(0.0, 10.0, 10001)
    s = np.diff(_passive("afo", bend, {}, afo)) / np.diff(bend)
    assert s[0] == 0.0 and s[-1] == pytest.approx(0.5) and np.max(np.abs(np.diff(s))) < 1e-3


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_g("afo", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.4 and min(delays) < 0.15
    for s in range(5):
        g = generate_g("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"] * 1.001
    stops = [generate_g("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    rates = {generate_g("afo", (), s).details["rate_hz"] for s in range(30)}
    assert max(rates) == 1500.0 and min(rates) == 100.0
