"""Dynamometer safety: limits refused before anything is sent, watchdog on lost heartbeat, e-stop."""

from __future__ import annotations

import math
import time

import can
import numpy as np
import pytest

from drivers import DriverError, LimitViolationError
from drivers.dynamometer import DynamometerLimits, open_dynamometer
from drivers.dynamometer import protocol as p
from drivers.dynamometer.simulator import DynamometerSimulator

_n = [0]


@pytest.fixture
def rig():
    _n[0] += 1
    channel = f"safety-{_n[0]}"
    sim = DynamometerSimulator(channel=channel)
    limits = DynamometerLimits.from_degrees(0.0, 90.0, 10.0, 100.0)
    dyno = open_dynamometer(f"virtual://{channel}", limits=limits)
    spy = can.Bus(interface="virtual", channel=channel)
    dyno.start()
    yield dyno, sim, spy
    dyno.close()
    spy.shutdown()
    sim.close()


def _commands_seen(spy: can.BusABC, command_id: int) -> list[bytes]:
    seen = []
    end = time.monotonic() + 0.2
    while time.monotonic() < end:
        msg = spy.recv(timeout=0.05)
        if msg is not None and msg.arbitration_id == command_id:
            seen.append(bytes(msg.data))
    return seen


@pytest.mark.parametrize("action", [
    lambda d: d.move_to(math.radians(95.0)),
    lambda d: d.move_to(math.radians(-1.0)),
    lambda d: d.set_passive_isokinetic(math.radians(10.5)),
    lambda d: d.set_passive_isokinetic(0.0),
    lambda d: d.set_range_of_motion(math.radians(-5.0), math.radians(80.0)),
    lambda d: d.set_torque_limit(120.0),
])
def test_out_of_limit_commands_never_reach_the_bus(rig, action) -> None:
    dyno, _, spy = rig
    _commands_seen(spy, dyno.ids["command"])
    with pytest.raises(LimitViolationError):
        action(dyno)
    assert _commands_seen(spy, dyno.ids["command"]) == []


def test_in_limit_move_runs_at_the_set_speed(rig) -> None:
    dyno, sim, _ = rig
    dyno.set_passive_isokinetic(math.radians(10.0))
    dyno.set_range_of_motion(0.0, math.radians(90.0))
    dyno.move_to(math.radians(20.0))
    time.sleep(1.2)
    blocks, _ = dyno.read_available()
    vel = np.rad2deg(np.concatenate([b.velocity_rad_s for b in blocks]))
    assert vel.max() == pytest.approx(10.0, abs=0.05)
    assert sim.state == p.State.MOVING


def test_lost_heartbeat_stops_the_device(rig) -> None:
    dyno, sim, _ = rig
    dyno.set_passive_isokinetic(math.radians(10.0))
    dyno.move_to(math.radians(80.0))
    time.sleep(0.3)
    dyno.suspend_heartbeat()
    time.sleep(p.WATCHDOG_TIMEOUT_S + 0.4)
    assert sim.state == p.State.FAULT and p.Fault.WATCHDOG in sim.fault
    frozen = sim.position_deg
    time.sleep(0.3)
    assert sim.position_deg == frozen and sim.velocity_deg_s == 0.0
    with pytest.raises(DriverError):
        dyno.move_to(math.radians(60.0))  # latched until reset
    dyno.suspend_heartbeat(False)
    time.sleep(0.15)
    dyno.reset()
    dyno.move_to(math.radians(60.0))


def test_emergency_stop_within_one_telemetry_period(rig) -> None:
    dyno, sim, _ = rig
    dyno.set_passive_isokinetic(math.radians(10.0))
    dyno.move_to(math.radians(80.0))
    time.sleep(0.4)
    dyno.read_available()
    dyno.emergency_stop()
    t_sent = time.monotonic()
    while sim.state != p.State.ESTOP and time.monotonic() - t_sent < 1.0:
        time.sleep(0.0005)
    latency = time.monotonic() - t_sent
    assert sim.state == p.State.ESTOP
    # the device acts on the next tick: within one telemetry period (10 ms) plus scheduling slack
    assert latency < 2 * (1.0 / sim.rate_hz)
    time.sleep(0.1)
    blocks, _ = dyno.read_available()
    assert np.all(np.concatenate([b.velocity_rad_s for b in blocks])[-3:] == 0.0)
    with pytest.raises(DriverError):
        dyno.move_to(math.radians(10.0))
