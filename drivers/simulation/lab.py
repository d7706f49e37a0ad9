"""The simulated lab: all three device simulators at once, each reachable by its driver URL."""

from __future__ import annotations

import itertools
import os
import time
from dataclasses import dataclass, field

import numpy as np

from ..dynamometer.cia402_simulator import Cia402DriveSimulator
from ..dynamometer.simulator import DynamometerSimulator
from ..forceplate.simulator import ForcePlateSimulator
from ..mocap.simulator import MarkerSimulator
from ..torque.simulator import TorqueSensorSimulator
from .aads_jig import AadsJig, AfoProperties
from .faults import FaultConfig
from .replica_leg import ReplicaLeg
from .seated_leg import SeatedLeg

_channel_ids = itertools.count()
#: a bend start no trial reaches (counter ≈ 146 years at 1 kHz): the operator rests until the cue
_NOT_YET = 1 << 52


@dataclass
class LabConfig:
    """What the simulated lab holds (defaults: spring 2, operator 1, knee at hip 90°)."""

    afo: AfoProperties = field(default_factory=AfoProperties)
    operator: int = 1
    leg: SeatedLeg = field(default_factory=SeatedLeg)
    replica: ReplicaLeg = field(default_factory=ReplicaLeg)
    plate_rate_hz: int = 1000
    telemetry_rate_hz: int = 100
    #: where the arm is when the subject is strapped in (deg): the sweep's start, as an operator does
    dyno_start_position_deg: float = 0.0
    mocap_rate_hz: int = 100
    marker_noise_m: float = 2e-4
    occlusion_rate: float = 0.0
    torque_baud: int = 115200
    #: the lab's transmitter converts at 100 Hz and numbers its samples (None: one without a counter)
    torque_output_rate_hz: float | None = 100.0
    plate_faults: FaultConfig = field(default_factory=FaultConfig)
    dyno_faults: FaultConfig = field(default_factory=FaultConfig)
    torque_faults: FaultConfig = field(default_factory=FaultConfig)
    seed: int = 0
    #: the dynamometer's wire: "cia402" (a CANopen CiA 402 servo drive, as research dynamometers are built)
    #: or "frames" (the project's own CAN frame set, kept for the rigs that speak it)
    dynamometer_protocol: str = "cia402"


class SimulatedLab:
    """Starts the force plate, motion capture, dynamometer and torque sensor simulators; ``urls`` names their drivers."""

    def __init__(self, config: LabConfig | None = None) -> None:
        c = self.config = config or LabConfig()
        channel = f"lab-{os.getpid()}-{next(_channel_ids)}"
        self.jig = AadsJig(c.afo, operator=c.operator, seed=c.seed)
        self.force_plate = ForcePlateSimulator(self.jig, c.plate_rate_hz, faults=c.plate_faults, seed=c.seed)
        dyno_class = {"cia402": Cia402DriveSimulator, "frames": DynamometerSimulator}[c.dynamometer_protocol]
        self.dynamometer: Cia402DriveSimulator | DynamometerSimulator = dyno_class(
            c.leg, channel=channel, telemetry_rate_hz=c.telemetry_rate_hz, start_position_deg=c.dyno_start_position_deg,
            faults=c.dyno_faults, seed=c.seed)
        self.mocap = MarkerSimulator(self.jig, c.mocap_rate_hz, noise_m=c.marker_noise_m,
                                     occlusion_rate=c.occlusion_rate, time_origin_s=self.force_plate.time_origin_s,
                                     seed=c.seed, name=f"markers-{channel}")
        self.torque_sensor = TorqueSensorSimulator(c.replica, baud=c.torque_baud, faults=c.torque_faults, seed=c.seed,
                                                   output_rate_hz=c.torque_output_rate_hz)
        self.urls = {
            "force_plate": f"{self.force_plate.url}?rate={c.plate_rate_hz}",
            "dynamometer": (f"canopen://virtual/{channel}?rate={c.telemetry_rate_hz}" if c.dynamometer_protocol == "cia402"
                            else f"virtual://{channel}?rate={c.telemetry_rate_hz}"),
            "torque_sensor": self.torque_sensor.url,
            "mocap": self.mocap.url,
        }

    def hold_bends(self) -> None:
        """The simulated operator holds the AFO at rest until :meth:`begin_bends` (instead of bending
        over and over from power-up, the free-running stream's operator)."""
        plate, cams = self.force_plate, self.mocap
        with plate.lock, cams.lock:
            plate.begin_bends(_NOT_YET)
            cams.bend_origin = _NOT_YET // (plate.rate_hz // cams.rate_hz)

    def begin_bends(self, lead_s: float = 0.05) -> float:
        """The simulated operator starts the trial's bends ``lead_s`` from now, at a plate counter on a
        motion-capture frame (plate and cameras share one time origin); returns the host time (s,
        ``time.monotonic``) of the first bend sample.

        The start is chosen and set while both simulators are held, and never before a sample or
        frame already sent: a host stalled longer than ``lead_s`` (a loaded machine) starts the bends
        later, never with some sent samples showing another pass of the operator than the rest."""
        plate, cams = self.force_plate, self.mocap
        per_frame = plate.rate_hz // cams.rate_hz
        with plate.lock, cams.lock:
            wanted = ((time.monotonic() + lead_s) - plate.time_origin_s) * plate.rate_hz
            first_unsent = max(float(plate.counter), float(cams.frames_served * per_frame))
            counter = int(np.ceil(max(wanted, first_unsent) / per_frame)) * per_frame
            plate.begin_bends(counter)
            cams.bend_origin = counter // per_frame
        return plate.time_origin_s + counter / plate.rate_hz

    def close(self) -> None:
        self.force_plate.close()
        self.mocap.close()
        self.dynamometer.close()
        self.torque_sensor.close()

    def __enter__(self) -> SimulatedLab:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
