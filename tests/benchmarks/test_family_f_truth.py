"""The sixth generator family: its own laws and the ranges they are drawn from (the contract every family shares:
test_family_e_f_contract)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.family_f_truth import (
    NOISE_SD_NM,
    _first_order,
    _gent,
    generate_f,
)


def test_friction_follows_the_direction_through_its_lag_and_fades() -> None:
    """The friction's sign follows the direction of motion through a first-order lag: after a reversal it settles
    exponentially with its time constant (exactly, per sample)."""
    t = np.linspace(0.0, 1.0, 1001)
    step = np.where(t >= 0.5, 1.0, -1.0)
    out = _first_order(t, step, 0.05)
    assert out[0] == -1.0 and out[-1] == pytest.approx(1.0, abs=1e-3)
    assert out[550] == pytest.approx(1.0 - 2.0 * np.exp(-0.051 / 0.05), rel=1e-9)  # 51 steps of 1 ms


def test_gent_stiffening_grows_without_bound_toward_its_limit() -> None:
    x = np.array([-1.0, 0.0, 5.0, 9.0, 9.9])
    f = _gent(x, 1.0, 10.0)
    assert f[0] == 0.0 and f[1] == 0.0 and f[2] == pytest.approx(5.0 / 0.75)
    assert f[4] > 10 * f[2] / 5.0 * 9.9  # far steeper than linear near the limit


def test_magnitudes_span_the_documented_ranges() -> None:
    delays = [generate_f("knee", ("time_delay",), s).effects["time_delay"] for s in range(30)]
    assert max(delays) > 0.35 and min(delays) < 0.15
    for s in range(5):
        g = generate_f("knee", ("gravity_error",), s)
        assert 3.0 * 0.8 * NOISE_SD_NM["knee"] <= g.effects["gravity_error"] <= 5.0 * 1.25 * NOISE_SD_NM["knee"] * 1.001
    stops = [generate_f("ankle", ("hard_stop",), s).details for s in range(16)]
    assert {d["stop_end"] for d in stops} == {"low", "high"}
    rates = {generate_f("afo", (), s).details["rate_hz"] for s in range(30)}
    assert max(rates) == 1000.0 and min(rates) == 120.0
