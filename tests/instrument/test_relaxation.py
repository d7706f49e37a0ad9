"""The online relaxation check on simulated isokinetic trials: bursts caught fast, relaxed trials left alone."""

from __future__ import annotations

import numpy as np

from benchmarks.relaxation import trial
from instrument.live.relaxation import RelaxationMonitor


def run(t: np.ndarray, angle: np.ndarray, torque: np.ndarray) -> RelaxationMonitor:
    mon = RelaxationMonitor()
    for k in range(0, t.size, 5):  # 50 ms blocks, as the driver delivers them
        mon.update(t[k:k + 5], angle[k:k + 5], torque[k:k + 5])
    return mon


def test_bursts_of_one_newton_metre_are_caught_within_a_few_hundred_ms() -> None:
    rng = np.random.default_rng(77)
    delays = []
    for i in range(12):
        t, angle, torque, burst = trial(int(rng.integers(1 << 30)), float(rng.uniform(1.0, 4.0)))
        mon = run(t, angle, torque)
        hits = [a for a in mon.alarms if burst.start_s <= a.time_s <= burst.start_s + burst.duration_s + 0.5]
        assert hits, (i, burst)
        assert abs(hits[0].angle_deg - np.interp(hits[0].time_s, t, angle)) < 1e-9  # the alarm says where
        delays.append(hits[0].time_s - burst.start_s)
    assert np.median(delays) < 0.15


def test_relaxed_trials_raise_no_alarm() -> None:
    rng = np.random.default_rng(78)
    flagged = sum(bool(run(*trial(int(rng.integers(1 << 30)), None)[:3]).alarms) for _ in range(20))
    assert flagged == 0


def test_one_burst_raises_one_alarm() -> None:
    """After a burst's hold-off the passive model restarts from where the limb is, not from the
    window before the burst (which, a second later and degrees away, raised a second, false alarm)."""
    rng = np.random.default_rng(79)
    counts = []
    for _ in range(12):
        t, angle, torque, burst = trial(int(rng.integers(1 << 30)), float(rng.uniform(2.0, 5.0)))
        mon = run(t, angle, torque)
        counts.append(len(mon.alarms))
        assert all(a.time_s >= burst.start_s for a in mon.alarms)
    assert counts == [1] * 12, counts
