"""Helpers: the three simulators with their drivers, and a collector that never hangs."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from drivers import DriverError, StreamingDevice, open_dynamometer, open_force_plate, open_torque_sensor
from drivers.dynamometer.simulator import DynamometerSimulator
from drivers.forceplate.simulator import ForcePlateSimulator
from drivers.simulation.aads_jig import AadsJig
from drivers.simulation.faults import FaultConfig
from drivers.torque.simulator import TorqueSensorSimulator

DEVICES = ("force_plate", "dynamometer", "torque_sensor")
_n = [0]


@contextmanager
def device_with_simulator(kind: str, faults: FaultConfig | None = None, seed: int = 0) -> Iterator[tuple[StreamingDevice,
                                                                                                         object]]:
    faults = faults or FaultConfig()
    if kind == "force_plate":
        sim: object = ForcePlateSimulator(AadsJig(seed=seed), 1000, faults=faults, seed=seed)
        dev: StreamingDevice = open_force_plate(sim.url, silence_timeout_s=0.5)  # type: ignore[attr-defined]  # each simulator has its own url
    elif kind == "dynamometer":
        _n[0] += 1
        channel = f"test-dyno-{_n[0]}"
        sim = DynamometerSimulator(channel=channel, faults=faults, seed=seed)
        dev = open_dynamometer(f"virtual://{channel}", silence_timeout_s=0.5)
    else:
        sim = TorqueSensorSimulator(faults=faults, seed=seed)
        dev = open_torque_sensor(sim.url, silence_timeout_s=0.5)  # type: ignore[attr-defined]  # each simulator has its own url
    try:
        yield dev, sim
    finally:
        dev.close()
        sim.close()  # type: ignore[attr-defined]  # each simulator has close()


def collect(dev: StreamingDevice, seconds: float, until: Any = None,
            max_seconds: float = 15.0) -> tuple[list, list[tuple[float, DriverError]], list[float]]:
    """Stream for ``seconds``: (blocks, [(time, error)], block arrival times).

    With ``until(errors, arrivals)``, keep streaming past ``seconds`` (up to ``max_seconds``) until it
    holds: a loaded host may deliver later, and tests assert on what arrived, not on when.
    """
    blocks, errors, arrivals = [], [], []
    dev.start()
    t0 = time.monotonic()
    while (t := time.monotonic() - t0) < seconds or (
            until is not None and t < max_seconds and not until(errors, arrivals)):
        try:
            blocks.append(dev.read(timeout=0.25))
            arrivals.append(t)
        except DriverError as err:
            if "no data within" not in str(err):
                errors.append((t, err))
    dev.stop()
    more, late_errors = dev.read_available()
    blocks += more
    arrivals += [seconds] * len(more)
    errors += [(seconds, e) for e in late_errors]
    return blocks, errors, arrivals


def counters(blocks: list) -> np.ndarray:
    return np.concatenate([b.counter for b in blocks]) if blocks else np.zeros(0, np.int64)
