"""Sustained rate, losses and CPU of each driver over its simulator, against the link's wire limit.

Each device streams alone (its simulator runs in the same process, so the machine's two cores
are shared with it). ``wire_limit_ratio`` is the received rate over the rate the link could carry
at most: the serial baud / frame bits (force plate), 1 Mbit/s / 135-bit frames (CAN: this is the
bus share the telemetry takes), and the Modbus RTU poll limit at the emulated baud (torque).
CPU is the driver's reader thread only (``time.thread_time`` in that thread).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from drivers import DriverError, open_dynamometer, open_force_plate, open_torque_sensor
from drivers.dynamometer import protocol as dyn_protocol
from drivers.dynamometer.simulator import DynamometerSimulator
from drivers.forceplate import protocol as fp_protocol
from drivers.forceplate.simulator import ForcePlateSimulator
from drivers.simulation.aads_jig import AadsJig
from drivers.torque import registers
from drivers.torque.simulator import TorqueSensorSimulator

PLATE_BAUD = 921600
CAN_BITRATE = 1_000_000
TORQUE_BAUD = 115200


def _stream(dev: Any, seconds: float) -> dict[str, Any]:
    blocks = []
    dev.start()
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        try:
            blocks.append(dev.read(timeout=0.5))
        except DriverError:
            pass
    dev.stop()
    blocks += dev.read_available()[0]
    dev.close()
    s = dev.stats
    c = np.concatenate([b.counter for b in blocks])
    return {"samples": int(c.size), "rate_hz": s.rate_hz(), "lost_samples": s.lost_samples,
            "crc_errors": s.crc_errors, "malformed_frames": s.malformed_frames,
            "cpu_ms_per_1000_samples": 1000.0 * 1000.0 * s.reader_cpu_s / max(1, c.size),
            "contiguous": bool(np.all(np.diff(c) == 1))}


def run(quick: bool = False) -> dict[str, Any]:
    seconds = 3.0 if quick else 20.0
    out: dict[str, Any] = {"seconds_per_device": seconds}

    sim = ForcePlateSimulator(AadsJig(seed=1), 1000)
    r = _stream(open_force_plate(f"{sim.url}?rate=1000"), seconds)
    sim.close()
    limit = fp_protocol.max_sample_rate_hz(PLATE_BAUD)
    out["force_plate"] = {**r, "nominal_hz": 1000.0, "wire_limit_hz": limit, "wire_limit_ratio": r["rate_hz"] / limit}

    sim = DynamometerSimulator(channel="bench-dyno", telemetry_rate_hz=100)
    r = _stream(open_dynamometer("virtual://bench-dyno?rate=100"), seconds)
    sim.close()
    limit = dyn_protocol.max_frame_rate_hz(CAN_BITRATE)
    out["dynamometer"] = {**r, "nominal_hz": 100.0, "wire_limit_hz": limit, "wire_limit_ratio": r["rate_hz"] / limit}

    sim = TorqueSensorSimulator(baud=TORQUE_BAUD)
    r = _stream(open_torque_sensor(sim.url), seconds)
    sim.close()
    limit = registers.max_poll_rate_hz(TORQUE_BAUD)
    out["torque_sensor"] = {**r, "nominal_hz": None, "wire_limit_hz": limit, "wire_limit_ratio": r["rate_hz"] / limit}

    print(f"{'device':<14}{'samples':>9}{'rate Hz':>10}{'wire limit':>12}{'ratio':>8}{'lost':>6}{'CRC':>5}{'CPU ms/1000':>13}")
    for name in ("force_plate", "dynamometer", "torque_sensor"):
        d = out[name]
        print(f"{name:<14}{d['samples']:>9}{d['rate_hz']:>10.1f}{d['wire_limit_hz']:>12.1f}{d['wire_limit_ratio']:>8.3f}"
              f"{d['lost_samples']:>6}{d['crc_errors']:>5}{d['cpu_ms_per_1000_samples']:>13.1f}")
    return out
