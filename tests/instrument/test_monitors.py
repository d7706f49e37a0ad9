"""The live monitors return findings (the runner acts on them): envelope, relaxation, which run for which kind."""

from __future__ import annotations

import numpy as np
import pytest

from drivers.dynamometer.protocol import State
from instrument import kinds
from instrument.kinds.ankle import AnkleProtocol
from instrument.kinds.knee import KneeProtocol
from instrument.live.monitors import LimitMonitor, RelaxationWatch, SafetyLimits, monitors_for


def test_the_envelope_names_the_first_breach() -> None:
    m = LimitMonitor(SafetyLimits(rom_deg=(-35.0, 95.0), max_speed_deg_s=30.0, max_torque_nm=150.0))
    ok = (np.array([10.0, 20.0]), np.array([5.0, 5.0]), np.array([10.0, -20.0]))
    assert m.check(*ok) is None
    assert m.check(ok[0], ok[1], np.array([10.0, -151.0])) == "torque 151.0 N·m over 150 N·m"
    assert "outside (-35.0, 95.0)" in (m.check(np.array([10.0, 97.5]), ok[1], ok[2]) or "")
    assert m.check(np.array([10.0, 96.5]), ok[1], ok[2]) is None  # within the 2° encoder margin
    assert m.check(ok[0], np.array([5.0, 36.0]), ok[2]) == "speed 36°/s over 30°/s"


@pytest.mark.parametrize("name", kinds.names())
def test_each_kind_gets_the_monitors_it_asks_for(name: str) -> None:
    proto = kinds.get(name).protocol()
    limit, watch = monitors_for(proto, SafetyLimits())
    assert (limit is not None) == ("dynamometer" in proto.devices)
    assert (watch is not None) == proto.relaxation_monitored


def test_relaxation_watch_reads_only_the_steady_part_of_the_sweep() -> None:
    proto = KneeProtocol(start_deg=0.0, end_deg=60.0, speed_deg_s=5.0)
    watch = RelaxationWatch(proto)
    seen: list[np.ndarray] = []
    watch.monitor.update = lambda t, a, q: seen.append(np.asarray(a)) or []  # type: ignore[method-assign]  # a spy in place of the monitor's update
    t = np.arange(0.0, 12.0, 0.01)
    pos = np.clip(5.0 * t, 0.0, 60.0)
    vel = np.where(pos < 60.0, 5.0, 0.0)
    vel[:20] = 1.0  # the arm accelerating
    state = np.full(t.size, int(State.MOVING))
    state[500:550] = int(State.HOLDING)
    watch.check({"time_s": t, "state": state}, pos, vel, np.zeros(t.size))
    a = np.concatenate(seen)
    assert a.min() > 1.5 and a.max() < 58.5  # away from the ends (0.3 s of travel at 5°/s)
    assert not np.any((a >= pos[500]) & (a <= pos[549]))  # nor where the device was not moving
    with pytest.raises(ValueError):
        RelaxationWatch(kinds.get("replica").protocol())
    assert RelaxationWatch(AnkleProtocol()).speed_deg_s == 5.0
