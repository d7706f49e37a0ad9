"""The passive fit's numeric maps on threads: the same numbers as on one."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.pmp.model import PmpTrial, moment_function
from analysis.pmp.muscles import LegMuscles
from analysis.pmp.workers import MIN_POINTS_PER_THREAD, mapped, workers


def test_workers_follow_the_environment_and_stay_at_most_two(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("INSTRUMENT_FIT_WORKERS", "1")
    assert workers() == 1
    monkeypatch.setenv("INSTRUMENT_FIT_WORKERS", "3")
    assert workers() == 3  # the lab's setting is taken as given
    monkeypatch.delenv("INSTRUMENT_FIT_WORKERS")
    assert 1 <= workers() <= 2


def test_a_threaded_map_of_the_muscle_moment_equals_the_serial_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """The calf's tendon equilibrium solved at every angle, on two threads and on one: equal to the last bit."""
    t = np.linspace(0.0, 9.0, 10)
    trial = PmpTrial("ankle", {"hip": np.deg2rad(90.0), "knee": np.deg2rad(45.0)}, t, np.zeros_like(t),
                     np.zeros_like(t), np.zeros_like(t), "ankle knee 45°")
    f = moment_function(LegMuscles(), trial, {})
    angles = np.linspace(np.deg2rad(-30.0), np.deg2rad(15.0), 4 * MIN_POINTS_PER_THREAD).reshape(1, -1)
    monkeypatch.setenv("INSTRUMENT_FIT_WORKERS", "1")
    serial = np.asarray(mapped(f, angles.size)(angles))
    monkeypatch.setenv("INSTRUMENT_FIT_WORKERS", "2")
    threaded_map = mapped(f, angles.size)
    assert threaded_map.name().startswith("threadmap2")  # CasADi's name for a map on two threads
    threaded = np.asarray(threaded_map(angles))
    assert np.all(np.isfinite(serial)) and np.array_equal(serial, threaded)
    assert not mapped(f, MIN_POINTS_PER_THREAD).name().startswith("threadmap")  # too few points: one thread
