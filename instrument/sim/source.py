"""The simulated lab as a device source: one simulated lab per trial, and the people in the room.

The simulated source also plays the subject: it can make the relaxed subject activate a muscle
(a burst of known size, for drills and tests).
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace
from typing import Any

from drivers import StreamingDevice
from drivers.dynamometer.protocol import State
from drivers.simulation.lab import SimulatedLab
from drivers.simulation.seated_leg import Burst

from ..errors import ProtocolError
from ..kinds.base import TrialProtocol
from .simulate import lab_config_for, simulated_devices, simulation_metadata


class SimulatedSource:
    """The simulated lab, one per trial (its physics set by the protocol, ``seed`` advanced per trial)."""

    simulated = True
    live_markers = True

    def __init__(self, seed: int = 0, *, dynamometer_protocol: str = "cia402") -> None:
        self.seed = seed
        #: the simulated dynamometer's wire ("cia402" or "frames", :class:`~drivers.simulation.lab.LabConfig`)
        self.dynamometer_protocol = dynamometer_protocol
        self.lab: SimulatedLab | None = None

    @contextmanager
    def devices(self, protocol: TrialProtocol) -> Iterator[dict[str, StreamingDevice]]:
        config = replace(lab_config_for(protocol, seed=self.seed), dynamometer_protocol=self.dynamometer_protocol)
        with simulated_devices(protocol, config) as (lab, devices):
            self.lab = lab
            try:
                yield devices
            finally:
                self.lab = None
                self.seed += 1

    def metadata(self) -> dict[str, Any]:
        return simulation_metadata(self.lab) if self.lab is not None else {}

    def inject_burst(self, amplitude_nm: float, delay_s: float = 0.3, duration_s: float = 0.4, *,
                     at_movement_s: float | None = None) -> None:
        """Make the simulated subject activate (a half-sine torque burst of ``amplitude_nm`` N·m lasting
        ``duration_s`` s): ``delay_s`` from now, or ``at_movement_s`` s into the arm's current movement
        (counted in the device's ticks: the same angle and phase in every run)."""
        if self.lab is None:
            raise ProtocolError("no simulated trial is running")
        dyno = self.lab.dynamometer
        # the sweep is announced when its START is sent: wait (briefly) for the arm to take it, so that
        # the burst is timed in this movement and not the one before
        deadline = time.monotonic() + 2.0
        while dyno.state != State.MOVING and time.monotonic() < deadline:
            time.sleep(0.001)
        start = at_movement_s if at_movement_s is not None else dyno.movement_time_s + delay_s
        dyno.leg.bursts.append(Burst(start_s=start, amplitude_nm=amplitude_nm, duration_s=duration_s))


__all__ = ["SimulatedSource"]
