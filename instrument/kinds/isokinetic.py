"""What the dynamometer's passive isokinetic kinds share (knee, ankle, knee out and back).

The protocol positions the arm, sweeps it at the set speed (5°/s in the dissertation) and halts
it, however the trial ends. Its table is the sweep, with the arm's weight removed using the mass
and centre of mass entered at set-up; its set analysis is the passive muscle-tendon fit with the
model-level diagnosis; its simulated rig is the seated leg of the simulated subject.
"""

from __future__ import annotations

import math
import threading
import time
from abc import abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from analysis.c3d import write_analog_c3d
from analysis.constants import GRAVITY_M_S2
from analysis.errors import AnalysisError
from analysis.pmp.model_diagnosis import folds_of
from analysis.pmp.report import analyse, subject_from, summary_table, text, trial_from_table, write_plots
from analysis.trial_csv import TrialTable
from drivers import DriverError, Dynamometer, StreamingDevice
from drivers.dynamometer import DEFAULT_LIMITS, SUBJECT_MAX_SPEED_DEG_S
from drivers.simulation.demo_subject import demo_subject, passive_table
from drivers.simulation.seated_leg import SeatedLeg, riener_passive_moment_nm

from ..errors import ExportError, ProtocolError
from .base import (
    HALT_RECORD_PERIODS,
    PASSIVE_PARAMETERS,
    POSITIONING_SPEED_DEG_S,
    Curves,
    LiveView,
    Parameter,
    SetAnalysis,
    TrialKind,
    TrialProtocol,
    diagnosis_line,
    wait_or_stop,
)

#: a dynamometer sample is part of the movement when its speed is at least this fraction of the sweep's
MOVING_FRACTION_OF_SWEEP_SPEED = 0.01
#: the model-level diagnosis's candidates in the operator's set analysis (as the demo runs them)
MODEL_CANDIDATES = ("end_range_structures", "limb_mass_error", "torque_offset")


@dataclass
class IsokineticProtocol(TrialProtocol):
    """A passive isokinetic sweep of the dynamometer from ``start_deg`` to ``end_deg`` at ``speed_deg_s``
    (and back to ``start_deg`` when the kind returns)."""

    devices: ClassVar[tuple[str, ...]] = ("dynamometer",)
    start_deg: float = 0.0
    end_deg: float = 90.0
    speed_deg_s: float = 5.0
    arm_mass_kg: float = 1.8
    arm_com_m: float = 0.22
    settle_s: float = 0.5
    #: the device's torque ceiling for this trial (N·m); set on the device before anything moves
    max_torque_nm: float = DEFAULT_LIMITS.max_torque_nm
    #: the sweep comes back to its start at the same speed (out and back)
    returns: ClassVar[bool] = False
    relaxation_monitored: ClassVar[bool] = True
    joint: ClassVar[str] = ""

    @abstractmethod
    def fixed_angles_deg(self) -> dict[str, Any]:
        """The other joints' angles (deg), as the seated leg is set: ``{"hip_flexion_deg": 90.0, ...}``."""

    @property
    @abstractmethod
    def set_angle_deg(self) -> float:
        """The study's condition: the angle of the joint the protocol fixes (hip for the knee, knee for the ankle)."""

    def fixed_joint_text(self) -> str:
        """The fixed joint's set-up, as the operator reads it."""
        return ""

    def condition(self) -> dict[str, Any]:
        return {"joint": self.joint, **asdict(self), **({"returns": True} if self.returns else {})}

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        dyno = devices["dynamometer"]
        if not isinstance(dyno, Dynamometer):
            raise ProtocolError(f"{self.name} needs a dynamometer, got {type(dyno).__name__}")
        lo, hi = sorted((self.start_deg, self.end_deg))
        # positioning at 30°/s, or the device's envelope if the lab set it slower
        limits = getattr(dyno, "limits", None)
        cap_deg_s = math.degrees(limits.max_speed_rad_s) if limits is not None else POSITIONING_SPEED_DEG_S
        self._positioning_deg_s = min(POSITIONING_SPEED_DEG_S, cap_deg_s)
        dyno.open()
        dyno.reset()
        dyno.set_range_of_motion(math.radians(lo - 1.0), math.radians(hi + 1.0))
        dyno.set_torque_limit(self.max_torque_nm)
        dyno.set_passive_isokinetic(math.radians(self._positioning_deg_s))

    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        dyno = devices["dynamometer"]
        assert isinstance(dyno, Dynamometer)
        travel = abs(self.end_deg - self.start_deg)
        dyno.move_to(math.radians(self.start_deg))  # positioning (recorded too; the state channel tells)
        positioning = getattr(self, "_positioning_deg_s", POSITIONING_SPEED_DEG_S)
        if wait_or_stop(stop, travel / positioning + 1.5 + self.settle_s):
            return
        dyno.set_passive_isokinetic(math.radians(self.speed_deg_s))
        mark("sweep_start", start_deg=self.start_deg, end_deg=self.end_deg, speed_deg_s=self.speed_deg_s)
        dyno.move_to(math.radians(self.end_deg))
        stopped = wait_or_stop(stop, travel / self.speed_deg_s + 0.5 + self.settle_s)
        if self.returns and not stopped:
            mark("sweep_turn", at_deg=self.end_deg)
            dyno.move_to(math.radians(self.start_deg))
            stopped = wait_or_stop(stop, travel / self.speed_deg_s + 0.5 + self.settle_s)
        mark("sweep_end", completed=not stopped)

    def shutdown(self, devices: dict[str, StreamingDevice], mark: Any) -> None:
        """Halt the arm (a controlled stop; harmless when it already holds or is latched). If the
        device does not acknowledge the halt, the emergency-stop frame goes out instead."""
        dyno = devices.get("dynamometer")
        if not isinstance(dyno, Dynamometer):
            return
        try:
            dyno.halt()
            mark("halted")
            time.sleep(HALT_RECORD_PERIODS * dyno.telemetry_period_s)  # the stopped arm into the recording
        except DriverError as err:
            mark("halt_failed", error=str(err))
            try:
                dyno.emergency_stop()
                mark("emergency_stop", reason=f"halt not acknowledged: {err}")
            except DriverError as err2:
                mark("emergency_stop_failed", error=str(err2))

    def expected_duration_s(self) -> float:
        travel = abs(self.end_deg - self.start_deg)
        legs = 2 if self.returns else 1
        return travel / POSITIONING_SPEED_DEG_S + legs * (travel / self.speed_deg_s + 0.5 + self.settle_s) + 1.5 + \
            self.settle_s

    def sweep_deg(self) -> tuple[float, float, float] | None:
        return self.start_deg, self.end_deg, self.speed_deg_s

    def checklist(self) -> list[str]:
        return ["subject anthropometrics entered (mass, shank and foot length)",
                f"dynamometer axis aligned with the {self.joint} joint centre",
                f"seat and fixation set: {self.fixed_joint_text()}",
                f"arm length and weight entered for gravity compensation ({self.arm_mass_kg:g} kg at {self.arm_com_m:g} m)",
                "subject told to relax and not to resist; emergency stop within reach"]


def _event_time(trial: Any, kind: str) -> float | None:
    for e in trial.events:
        if e.get("kind") == kind:
            return float(e["time_s"])
    return None


def _sweep_speed_rad_s(trial: Any) -> float:
    for e in trial.events:
        if e.get("kind") == "sweep_start" and e.get("speed_deg_s"):
            return float(np.deg2rad(float(e["speed_deg_s"])))
    return 0.0


def movement(keep: np.ndarray, velocity_rad_s: np.ndarray, sweep_speed_rad_s: float) -> np.ndarray:
    """The movement that the sweep marks ``keep`` overlap, by the arm's velocity: from the first
    moving sample to the first at rest after the arm stops (its arrival at the end angle).

    The marks are stamped by the host when it commands the move and hears it end, a tick or two
    either side of the movement and differently every run; the movement itself is counted in the
    device's ticks, so the table — and every analysis of it — is the same for the same device
    behaviour."""
    if sweep_speed_rad_s <= 0.0:
        return keep
    moving = np.abs(velocity_rad_s) >= MOVING_FRACTION_OF_SWEEP_SPEED * sweep_speed_rad_s
    inside = np.flatnonzero(keep & moving)
    if len(inside) == 0:
        return keep
    first, last = int(inside[0]), int(inside[-1])
    while first > 0 and moving[first - 1]:
        first -= 1
    while last < len(moving) - 1 and moving[last + 1]:
        last += 1
    out = np.zeros_like(keep)
    out[first:min(last + 2, len(keep))] = True
    return out


def _device_time_s(device: Any, keep: np.ndarray) -> np.ndarray:
    """Time in the sweep (s) from the device's sample counter at its telemetry rate when the recording
    has both (the device's clock spaces the samples; the host's stamps jitter), else the host stamps."""
    rate = float((device.identity or {}).get("telemetry_rate_hz") or 0.0)
    counter = device.channels.get("counter")
    if rate > 0.0 and counter is not None and len(counter) == len(keep):
        c = np.asarray(counter, dtype=np.int64)[keep]
        return (c - c[0]).astype(float) / rate
    t = device.channels["time_s"][keep]
    return t - t[0]


def _draw(curves: Curves, rings: dict[str, Any], snapshot: Any) -> None:
    """A passive sweep is read as torque against angle (upper plot, beside the expected band), the
    angle against time below (the sweep's progress)."""
    if "dynamometer" not in rings:
        return
    d = rings["dynamometer"].latest()
    if not len(d["time_s"]):
        return
    t0 = d["time_s"][0]
    angle = np.rad2deg(d["position_rad"])
    curves.a.setData(angle, d["torque_nm"])
    curves.b.setData(d["time_s"] - t0, angle)
    if snapshot is not None and snapshot.alarms:
        at = np.array([a.time_s for a in snapshot.alarms])
        curves.alarms.setData(np.interp(at, d["time_s"], angle), np.interp(at, d["time_s"], d["torque_nm"]))


#: the expected band's width: Riener & Edrich's subjects' passive moments vary by about this fraction
#: between subjects, plus a floor for the limb's weight and the arm's set-up (N·m)
BAND_FRACTION, BAND_FLOOR_NM = 0.3, 1.5


def expected_band(protocol: Any, subject: dict[str, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The shaft torque a relaxed subject is expected to show over the sweep (N·m, held still): Riener &
    Edrich's published passive moments (1999) for the set joint angles, the limb's weight from the entered
    anthropometrics and the arm's weight, ± (30 % of the passive moment + 1.5 N·m). None before the
    anthropometrics are entered."""
    if not isinstance(protocol, IsokineticProtocol) or not all(subject.get(k, 0) > 0 for k in
                                                               ("mass_kg", "shank_length_m", "foot_length_m")):
        return None
    leg = SeatedLeg(joint=protocol.joint, **protocol.fixed_angles_deg(), body_mass_kg=subject["mass_kg"],
                    shank_length_m=subject["shank_length_m"], foot_length_m=subject["foot_length_m"],
                    arm_mass_kg=protocol.arm_mass_kg, arm_com_m=protocol.arm_com_m)
    lo, hi = sorted((protocol.start_deg, protocol.end_deg))
    angle = np.linspace(lo, hi, 60)
    passive = riener_passive_moment_nm(leg, angle)
    middle = -passive - leg.gravity_moment_nm(angle)
    half = BAND_FRACTION * np.abs(passive) + BAND_FLOOR_NM
    return angle, middle - half, middle + half


#: what every isokinetic kind asks (the same parameter in each, so the form and the CLI share it)
SPEED = Parameter("speed_deg_s", "Speed", 5.0, unit="°/s", low=0.5, high=SUBJECT_MAX_SPEED_DEG_S, flag="--speed",
                  help="isokinetic speed (deg/s)")
ARM_MASS = Parameter("arm_mass_kg", "Arm mass", 1.8, unit="kg", low=0.0, high=20.0, flag="--arm-mass",
                     help="the dynamometer arm's mass, for its gravity (kg)")
ARM_COM = Parameter("arm_com_m", "Arm centre of mass", 0.22, unit="m", low=0.0, high=1.0, flag="--arm-com",
                    help="the arm's centre of mass from the axis (m)")
HIP = Parameter("hip_flexion_deg", "Hip flexion", 90.0, unit="°", choices=(90.0, 55.0, 15.0), flag="--hip",
                help="knee trials: hip flexion (deg)")
KNEE = Parameter("knee_flexion_deg", "Knee flexion", 0.0, unit="°", choices=(0.0, 45.0, 90.0), flag="--knee",
                 help="ankle trials: knee flexion (deg)")
KNEE_END = Parameter("end_deg", "Sweep end", 90.0, unit="°", low=5.0, high=90.0, flag="--end",
                     help="knee trials: where the flexion sweep ends (deg)")


class IsokineticKind(TrialKind):
    """A dynamometer sweep of one joint with the subject relaxed."""

    analysis = PASSIVE_PARAMETERS
    needs_anthropometrics = True
    view = LiveView(("torque (N·m)", "angle (°)"), ("angle (°)", "time (s)"), _draw, band=expected_band)

    @abstractmethod
    def arm_gravity_nm(self, angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float,
                       condition: dict[str, Any]) -> np.ndarray:
        """The dynamometer arm's gravity moment toward positive angles (N·m) at ``angle_deg``."""

    def table(self, trial: Any, subject: dict[str, Any] | None = None) -> TrialTable:
        """The sweep (between the protocol's marks, narrowed to the arm's movement) with the arm's weight removed."""
        cond = trial.metadata["protocol"]["condition"]
        d = trial.devices["dynamometer"].channels
        t = d["time_s"]
        t0 = _event_time(trial, "sweep_start")
        t1 = _event_time(trial, "sweep_end")
        keep = (t >= (t0 if t0 is not None else -np.inf)) & (t <= (t1 if t1 is not None else np.inf))
        if not keep.any():
            raise ExportError(f"{trial.path}: no dynamometer samples inside the sweep")
        keep = movement(keep, d["velocity_rad_s"], _sweep_speed_rad_s(trial))
        angle = np.rad2deg(d["position_rad"][keep])
        torque = d["torque_nm"][keep] + self.arm_gravity_nm(angle, cond["arm_mass_kg"], cond["arm_com_m"], cond)
        cols = {"time_s": _device_time_s(trial.devices["dynamometer"], keep), "angle_deg": angle, "torque_Nm": torque,
                "velocity_deg_s": np.rad2deg(d["velocity_rad_s"][keep])}
        fixed = {"hip_flexion_deg": cond["hip_flexion_deg"],
                 "knee_flexion_deg": cond.get("knee_flexion_deg"),
                 "ankle_dorsiflexion_deg": cond.get("ankle_dorsiflexion_deg")}
        fixed.update(measured_fixed_angles(trial, t0, t1))
        return TrialTable(cols, {"kind": self.table_kind, **{k: v for k, v in fixed.items() if v is not None},
                                 **({"movement": "out_and_back"} if cond.get("returns") else {}),
                                 "subject": {k: v for k, v in (subject or {}).items() if v is not None},
                                 "source": trial.path.name, "trial_status": trial.status,
                                 # the arm turns with the limb: its inertia is in the torque (its weight is not)
                                 "arm_inertia_kgm2": float(cond["arm_mass_kg"]) * float(cond["arm_com_m"]) ** 2})

    #: the trial's marks written as C3D events
    C3D_EVENTS = ("sweep_start", "sweep_turn", "sweep_end", "halted", "emergency_stop", "activation")

    def write_c3d(self, trial: Any, out: Path) -> None:
        """The whole recording's dynamometer channels as C3D analog channels, as Vicon Nexus stores a
        dynamometer's: ``Torque`` (the shaft's, Nm), ``TorqueLimb`` (the arm's weight removed, Nm), ``Angle``
        (deg), ``Velocity`` (deg/s), at the telemetry rate; the protocol's marks as events; the condition in
        the ``DYNAMOMETER`` group. Samples the link lost are filled by linear interpolation along the
        device counter and counted (``DYNAMOMETER:FILLED_SAMPLES``)."""
        cond = trial.metadata["protocol"]["condition"]
        d = trial.devices["dynamometer"]
        ch = d.channels
        counter = np.asarray(ch["counter"], dtype=np.int64)
        if counter.size < 2:
            raise ExportError(f"{trial.path}: fewer than two dynamometer samples; nothing to write as C3D")
        grid = np.arange(counter[0], counter[-1] + 1)
        time_s = np.interp(grid, counter, ch["time_s"])
        rate = float(d.identity.get("telemetry_rate_hz") or 0.0) or float(1.0 / np.median(np.diff(time_s)))
        angle = np.rad2deg(np.interp(grid, counter, ch["position_rad"]))
        torque = np.interp(grid, counter, ch["torque_nm"])
        limb = torque + self.arm_gravity_nm(angle, cond["arm_mass_kg"], cond["arm_com_m"], cond)
        velocity = np.rad2deg(np.interp(grid, counter, ch["velocity_rad_s"]))
        events = [(str(e["kind"]), float(e["time_s"]) - float(time_s[0])) for e in trial.events
                  if e.get("kind") in self.C3D_EVENTS and "time_s" in e]
        params: dict[str, float | str] = {"JOINT": str(cond.get("joint", self.name)), "KIND": self.name,
                                          "FILLED_SAMPLES": float(grid.size - counter.size),
                                          "STATUS": str(trial.status)}
        for key in ("speed_deg_s", "hip_flexion_deg", "knee_flexion_deg", "ankle_dorsiflexion_deg", "arm_mass_kg",
                    "arm_com_m", "start_deg", "end_deg"):
            if isinstance(cond.get(key), int | float):
                params[key] = float(cond[key])
        try:
            write_analog_c3d(out, rate, [("Torque", "Nm", torque), ("TorqueLimb", "Nm", limb), ("Angle", "deg", angle),
                                         ("Velocity", "deg/s", velocity)],
                             events=events, group="DYNAMOMETER", parameters=params)
        except AnalysisError as err:
            raise ExportError(f"{trial.path}: {err}") from err

    def analyse_set(self, protocol: TrialProtocol, trials: Sequence[Any], subject: dict[str, float], *,
                    figures_dir: Path | None = None,
                    progress: Callable[[str], None] | None = None) -> SetAnalysis:
        tables = [t.table() for t in trials]
        figures: list[Path] = []
        try:  # a fit that does not converge says so in its own text (success=False)
            fits = [trial_from_table(t) for t in tables]
            # the model-level diagnosis (damping, a limb-mass error, an offset, ... fitted inside the
            # estimator, each judged by predicting a left-out condition) once the set allows it: repeats,
            # or three conditions (the knee at hip 90/55/15°)
            model = len(fits) >= 3 and len(folds_of(fits)) >= 2
            report = analyse(fits, subject_from(subject), intervals=16, diagnose_model=model, model_intervals=12,
                             model_candidates=list(MODEL_CANDIDATES) if model else None, progress=progress)
            head, columns, rows = summary_table(report)
            fitted = text(report)
            if figures_dir is not None:
                figures = [f for f in write_plots(report, figures_dir) if f.suffix == ".png"]
        except AnalysisError as err:  # missing anthropometrics, a rejected trial, ...: say so, show the diagnosis
            head, columns, rows = f"passive parameters not fitted: {err}", (), []
            fitted = head
        line, diagnosis_figures = diagnosis_line(tables, figures_dir)
        return SetAnalysis(f"{len(tables)} accepted {self.name} trial{'s' * (len(tables) != 1)}: {head}", columns,
                           tuple(rows), tuple(str(f) for f in figures + diagnosis_figures), fitted + line)

    def simulated_rig(self, protocol: TrialProtocol, subject: dict[str, Any], afo: Any) -> dict[str, Any]:
        assert isinstance(protocol, IsokineticProtocol)
        # the subject's passive moments are OpenSim's (a model the estimator was not built from) where it has
        # a table for this condition, Riener & Edrich's elsewhere
        table = passive_table(protocol.joint, protocol.set_angle_deg)
        leg = SeatedLeg(joint=protocol.joint, **protocol.fixed_angles_deg(), **subject,
                        arm_mass_kg=protocol.arm_mass_kg, arm_com_m=protocol.arm_com_m)
        if table is not None:
            leg = replace(leg, passive_table_deg=table[0], passive_table_nm=table[1])
        return {"leg": leg, "dyno_start_position_deg": protocol.start_deg}

    def simulated_truth(self, sidecar: dict[str, Any]) -> str | None:
        """The simulated subject's end-range structures (OpenSim's CoordinateLimitForce in ``demo_subject.json``)
        for a trial whose fixed joint was set where the subject has a table; None elsewhere (Riener & Edrich's
        moments there, no stop)."""
        values = {p.name: sidecar[p.name] for p in self.parameters if p.name in sidecar}
        try:
            protocol = self.protocol(**values)
        except ProtocolError:
            return None
        assert isinstance(protocol, IsokineticProtocol)
        if passive_table(protocol.joint, protocol.set_angle_deg) is None:
            return None
        limits = demo_subject()["limit_forces"][protocol.joint]
        return (f"OpenSim CoordinateLimitForce from {limits['upper_deg']:g}° ({limits['upper_stiffness_Nm_per_deg']:g} "
                f"N·m/°) and below {limits['lower_deg']:g}° ({limits['lower_stiffness_Nm_per_deg']:g} N·m/°), "
                f"{limits['transition_deg']:g}° transitions, and muscles the passive model lacks")


#: a goniometer channel measuring a fixed joint (its label) -> the sidecar key of the measured angle
GONIOMETER_CHANNELS = {"hip_flexion": "hip_flexion_measured_deg", "knee_flexion": "knee_flexion_measured_deg"}


def measured_fixed_angles(trial: Any, t0: float | None, t1: float | None) -> dict[str, Any]:
    """The fixed joints' angles as a goniometer stream recorded them during the sweep (median, deg), with the
    stream that measured them: ``{"hip_flexion_measured_deg": 53.2, "hip_flexion_measured_by": "goniometer"}``.
    Only a channel labelled as in :data:`GONIOMETER_CHANNELS` with a unit in degrees counts; none: ``{}``."""
    out: dict[str, Any] = {}
    for name, device in trial.devices.items():
        labels, units = device.identity.get("labels") or [], device.identity.get("units") or []
        if "values" not in device.channels:
            continue
        t = device.channels["time_s"]
        inside = (t >= (t0 if t0 is not None else -np.inf)) & (t <= (t1 if t1 is not None else np.inf))
        for k, (label, unit) in enumerate(zip(labels, units)):
            key = GONIOMETER_CHANNELS.get(label)
            if key is None or unit.lower() not in ("deg", "degree", "degrees") or key in out:
                continue
            values = device.channels["values"][inside, k]
            values = values[np.isfinite(values)]
            if values.size:
                out[key] = float(np.median(values))
                out[key.replace("_deg", "_by")] = name
    return out


def knee_arm_gravity_nm(angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float) -> np.ndarray:
    """Gravity moment of the dynamometer arm toward knee flexion (N·m): the arm is horizontal at 0°
    flexion and hangs at 90°."""
    th = np.deg2rad(np.asarray(angle_deg, dtype=float))
    return arm_mass_kg * GRAVITY_M_S2 * arm_com_m * np.cos(th)


__all__ = ["ARM_COM", "ARM_MASS", "HIP", "KNEE", "KNEE_END", "MODEL_CANDIDATES", "SPEED", "IsokineticKind",
           "IsokineticProtocol", "knee_arm_gravity_nm", "movement"]
