"""Simulated trials: a ``SimulatedLab`` configured for a protocol, and real drivers pointed at it."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, replace
from typing import Any

import numpy as np

from analysis.motion import MotionTrial, cop_from_moment
from drivers import StreamingDevice, open_device
from drivers.simulation.aads_jig import AadsJig, AfoProperties, OperatorStyle
from drivers.simulation.demo_subject import shank_length_m as demo_shank_length_m
from drivers.simulation.faults import FaultConfig
from drivers.simulation.lab import LabConfig, SimulatedLab

from .. import kinds
from ..kinds.aads import AADS_SPRINGS_N_PER_M
from ..kinds.base import TrialProtocol


def lab_config_for(protocol: TrialProtocol, *, seed: int = 0, faults: FaultConfig | None = None,
                   body_mass_kg: float = 75.0, shank_length_m: float | None = None, foot_length_m: float = 0.26,
                   afo: AfoProperties | None = None) -> LabConfig:
    """The simulated rig and subject for ``protocol``; the shank (m) is by default the simulated subject's own
    (the OpenSim model's whose paths made its passive moments)."""
    shank_length_m = demo_shank_length_m() if shank_length_m is None else shank_length_m
    f = faults or FaultConfig()
    cfg: dict[str, Any] = {"seed": seed, "plate_faults": f, "dyno_faults": f, "torque_faults": f}
    subject = {"body_mass_kg": body_mass_kg, "shank_length_m": shank_length_m, "foot_length_m": foot_length_m}
    cfg.update(kinds.get(protocol.name).simulated_rig(protocol, subject, afo))
    return LabConfig(**cfg)


@contextmanager
def simulated_devices(protocol: TrialProtocol, config: LabConfig | None = None) -> Iterator[
        tuple[SimulatedLab, dict[str, StreamingDevice]]]:
    """A running simulated lab for ``protocol`` and its (unopened) drivers; both closed on exit."""
    lab = SimulatedLab(config or lab_config_for(protocol))
    # the simulated transmitter answers over a loopback socket from a thread of this process: on a
    # loaded host a 50 ms poll timeout (the real link's) counts scheduler delays as lost polls
    urls = {**lab.urls, "torque_sensor": lab.urls["torque_sensor"] + "&timeout=0.25"}
    devices = {name: open_device(name, urls[name]) for name in protocol.devices}
    kinds.get(protocol.name).simulated_operator(protocol, lab)
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
                                                                          if k not in ("bursts", "passive_table_deg",
                                                                                       "passive_table_nm")},
                             "replica_shank_mass_kg": c.replica.shank_mass_kg,
                             "replica_springs": {f"{sp.name}.{k}": float(getattr(sp, k)) for sp in c.replica.springs
                                                 for k in ("stiffness_n_per_m", "rest_length_m")},
                             "theoretical_stiffness_nm_per_deg": lab.jig.theoretical_stiffness_nm_per_deg(),
                             "jig_time_origin_s": lab.force_plate.time_origin_s}
    return {"simulated": True, "simulation": truth}


def synthesize_aads_trial(spring: int, operator: int, trial: int, *, seed: int = 0, afo: AfoProperties | None = None,
                          marker_noise_m: float = 2e-4, plate_noise_n: float = 0.25, marker_rate_hz: int = 100,
                          plate_rate_hz: int = 1000, occlusion_rate: float = 0.0,
                          style: OperatorStyle | None = None) -> tuple[MotionTrial, dict[str, Any]]:
    """One AADS trial sampled straight from the jig physics, without streaming it through the devices.

    The same physics the device simulators serve (``AadsJig``), sampled offline so that a 60-trial
    experiment takes seconds rather than an hour of real time. Markers carry Gaussian noise
    (``marker_noise_m`` SD per axis) and occlusions; the plate wrench (about the plate's
    calibration origin) carries ``plate_noise_n`` SD on forces and 5 % of it, in N·m, on moments,
    like ``ForcePlateSimulator``. ``style`` replaces operator ``operator``'s way of bending.
    Returns the trial and the simulator's ground truth.
    """
    spring_n_per_m = AADS_SPRINGS_N_PER_M[spring]
    props = replace(afo, spring_n_per_m=spring_n_per_m) if afo is not None else AfoProperties(spring_n_per_m=spring_n_per_m)
    rng_seed = seed * 1000 + spring * 100 + operator * 10 + trial
    jig = AadsJig(props, operator=style or operator, seed=rng_seed)
    rng = np.random.default_rng(rng_seed + 1)
    duration = jig.profile.duration_s
    t_m = np.arange(int(duration * marker_rate_hz)) / marker_rate_hz
    t_p = np.arange(int(duration * plate_rate_hz)) / plate_rate_hz
    st_m = jig.state(t_m)
    labels = list(st_m.markers_m)
    markers = np.stack([st_m.markers_m[k] for k in labels], axis=1)
    markers = markers + rng.normal(0.0, marker_noise_m, markers.shape)
    if occlusion_rate > 0:
        markers[rng.random(markers.shape[:2]) < occlusion_rate] = np.nan
    st_p = jig.state(t_p)
    sd = np.array([1.0, 1.0, 1.0, 0.05, 0.05, 0.05]) * plate_noise_n
    loads = np.hstack([st_p.force_n, st_p.moment_nm]) + rng.normal(0.0, 1.0, (t_p.size, 6)) * sd
    cop, free = cop_from_moment(loads[:, :3], loads[:, 3:], jig.plate_origin_m)
    motion = MotionTrial(t_m, markers, labels, t_p, loads[:, :3], cop, free, f"sim-s{spring}-o{operator}-t{trial}",
                         {"spring": spring, "operator": operator, "trial": trial})
    truth = {"afo": asdict(props), "spring_n_per_m": spring_n_per_m,
             "theoretical_stiffness_nm_per_deg": jig.theoretical_stiffness_nm_per_deg(),
             "time_s": t_m, "hinge_deg": np.rad2deg(st_m.hinge_rad), "shank_deg": np.rad2deg(st_m.shank_rad),
             "afo_torque_nm": st_m.afo_torque_nm, "spring_torque_nm": st_m.spring_torque_nm,
             "operator_force_n": st_m.operator_force_n}
    return motion, truth
