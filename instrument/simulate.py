"""Simulated trials: a ``SimulatedLab`` configured for a protocol, and real drivers pointed at it."""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from collections.abc import Iterator
from dataclasses import asdict
from typing import Any

from drivers import StreamingDevice, open_dynamometer, open_force_plate, open_marker_stream, open_torque_sensor
from drivers.simulation.aads_jig import AfoProperties
from drivers.simulation.faults import FaultConfig
from drivers.simulation.lab import LabConfig, SimulatedLab
from drivers.simulation.replica_leg import ReplicaLeg
from drivers.simulation.seated_leg import SeatedLeg

from .protocols import AadsProtocol, AnkleProtocol, KneeProtocol, ReplicaProtocol, TrialProtocol

OPENERS = {"force_plate": open_force_plate, "dynamometer": open_dynamometer,
           "torque_sensor": open_torque_sensor, "mocap": open_marker_stream}


def lab_config_for(protocol: TrialProtocol, *, seed: int = 0, faults: FaultConfig | None = None,
                   body_mass_kg: float = 75.0, shank_length_m: float = 0.42, foot_length_m: float = 0.26,
                   afo: AfoProperties | None = None) -> LabConfig:
    """The simulated rig and subject for ``protocol``."""
    f = faults or FaultConfig()
    cfg: dict[str, Any] = {"seed": seed, "plate_faults": f, "dyno_faults": f, "torque_faults": f}
    if isinstance(protocol, AadsProtocol):
        cfg["afo"] = afo or AfoProperties(spring_n_per_m=protocol.spring_n_per_m)
        cfg["operator"] = protocol.operator
    elif isinstance(protocol, KneeProtocol):
        cfg["leg"] = SeatedLeg(joint="knee", hip_flexion_deg=protocol.hip_flexion_deg,
                               ankle_dorsiflexion_deg=protocol.ankle_dorsiflexion_deg, body_mass_kg=body_mass_kg,
                               shank_length_m=shank_length_m, foot_length_m=foot_length_m,
                               arm_mass_kg=protocol.arm_mass_kg, arm_com_m=protocol.arm_com_m)
    elif isinstance(protocol, AnkleProtocol):
        cfg["leg"] = SeatedLeg(joint="ankle", hip_flexion_deg=protocol.hip_flexion_deg,
                               knee_flexion_deg=protocol.knee_flexion_deg, body_mass_kg=body_mass_kg,
                               shank_length_m=shank_length_m, foot_length_m=foot_length_m,
                               arm_mass_kg=protocol.arm_mass_kg, arm_com_m=protocol.arm_com_m)
    elif isinstance(protocol, ReplicaProtocol):
        cfg["replica"] = ReplicaLeg(hold_angles_deg=protocol.angles_deg, hold_s=protocol.hold_s,
                                    move_speed_deg_s=protocol.move_speed_deg_s)
    return LabConfig(**cfg)


@contextmanager
def simulated_devices(protocol: TrialProtocol, config: LabConfig | None = None) -> Iterator[
        tuple[SimulatedLab, dict[str, StreamingDevice]]]:
    """A running simulated lab for ``protocol`` and its (unopened) drivers; both closed on exit."""
    lab = SimulatedLab(config or lab_config_for(protocol))
    devices = {name: OPENERS[name](lab.urls[name]) for name in protocol.devices}
    if isinstance(protocol, ReplicaProtocol) and protocol.first_hold_at_s is None:
        # start at the next cycle of the replica rig's schedule (the simulator's time origin)
        t0 = lab.torque_sensor._t0
        period = protocol.hold_windows()[-1][2] + abs(protocol.angles_deg[-1] - protocol.angles_deg[0]) / protocol.move_speed_deg_s
        protocol.first_hold_at_s = t0 + math.ceil((time.monotonic() + 0.3 - t0) / period) * period
    if isinstance(protocol, AadsProtocol):
        protocol.duration_s = min(protocol.duration_s, lab.jig.profile.duration_s)
    try:
        yield lab, devices
    finally:
        for dev in devices.values():
            dev.close()
        lab.close()


def simulation_metadata(lab: SimulatedLab) -> dict[str, Any]:
    """The simulator's ground truth, stored with a simulated trial (for validation, never for analysis)."""
    c = lab.config
    truth: dict[str, Any] = {"seed": c.seed, "afo": asdict(c.afo), "leg": {k: v for k, v in asdict(c.leg).items()
                                                                          if k != "bursts"},
                             "replica_shank_mass_kg": c.replica.shank_mass_kg,
                             "theoretical_stiffness_nm_per_deg": lab.jig.theoretical_stiffness_nm_per_deg(),
                             "jig_time_origin_s": lab.force_plate.time_origin_s}
    return {"simulated": True, "simulation": truth}
