"""Trial protocols of the dissertation as Qt-free procedures (as pymeasure's ``Procedure``).

A protocol knows which devices it needs, how to set them up, and how to drive one trial; the CLI,
the GUI and the tests run the same objects. Angles are degrees at this edge (as operators set
them); everything recorded is SI.

* ``aads``: the operator bends the AFO on the force plate while motion capture tracks the jig.
* ``knee``: knee flexion 0→90° at 5°/s with the hip at 90, 55 or 15°.
* ``ankle``: dorsiflexion to plantarflexion at 5°/s with the knee at 0, 45 or 90°.
* ``replica``: the replica leg's knee held every 8° from 0 to 88°, a static torque at each hold.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from abc import ABC, abstractmethod
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, ClassVar

from drivers import DriverError, Dynamometer, StreamingDevice
from drivers.dynamometer import DEFAULT_LIMITS

from .errors import ProtocolError

#: the AADS springs of the dissertation (N/m), numbered as in Table 2.1
AADS_SPRINGS_N_PER_M = {1: 9910.0, 2: 15600.0, 3: 25200.0}
#: telemetry periods recorded after the halt, so the trial shows the arm at rest
HALT_RECORD_PERIODS = 10
#: positioning speed between trials (deg/s)
POSITIONING_SPEED_DEG_S = 30.0


class TrialProtocol(ABC):
    """One kind of trial. ``condition()`` is what the store indexes; ``drive()`` runs the trial."""

    name: ClassVar[str]
    devices: ClassVar[tuple[str, ...]]

    @abstractmethod
    def condition(self) -> dict[str, Any]:
        """The trial's condition (JSON), units in the keys."""

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        """Set the devices up before recording starts (positioning, limits). Default: nothing."""

    @abstractmethod
    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        """Run the trial while recording; ``mark(kind, **fields)`` writes an event into the trial."""

    def shutdown(self, devices: dict[str, StreamingDevice], mark: Any) -> None:
        """Leave the devices safe; runs after every trial, however it ended (operator stop, error,
        e-stop, normal end), while the recording still runs. Must not raise. Default: nothing."""

    def expected_duration_s(self) -> float:
        return float("nan")

    def condition_text(self) -> str:
        """The condition in a few words, for progress lines and titles (default: the fixed joint, if any)."""
        fixed = getattr(self, "fixed_joint_text", None)
        return fixed() if callable(fixed) else ""

    # what a trial kind is, asked by the runner, the GUI and the CLI (no isinstance chains there)
    #: the live relaxation check runs on this kind's dynamometer sweep
    relaxation_monitored: ClassVar[bool] = False
    #: the live AADS loop (angle from markers, torque from the plate) is computed for this kind
    live_aads_loop: ClassVar[bool] = False

    def sweep_deg(self) -> tuple[float, float, float] | None:
        """(start °, end °, speed °/s) of the dynamometer motion this trial commands, or None."""
        return None

    def checklist(self) -> list[str]:
        """The set-up items the operator confirms before a trial."""
        return []

    def live_hint(self, snapshot: Any) -> str | None:
        """The operator's guidance while this trial runs (from the runner's live state), or None."""
        return None

    def incomplete_because(self, snapshot: Any) -> str | None:
        """Why a finished trial of this kind should be repeated even without an alarm, or None."""
        return None


@functools.cache
def default_jig_model() -> Any:
    """The default jig model, read once: its fit window and hinge stop are what every AADS trial uses,
    and the live AADS loop re-analyses with it every 0.25 s."""
    from analysis.aads.model import load_jig_model

    return load_jig_model()


def _wait(stop: threading.Event, seconds: float) -> bool:
    """Sleep ``seconds`` unless stopped; True if stopped."""
    return stop.wait(seconds)


@dataclass
class AadsProtocol(TrialProtocol):
    """One AADS trial: spring 1–3 (or a stiffness in N/m), operator 1–4, trial number; ``duration_s`` of bending."""

    name: ClassVar[str] = "aads"
    devices: ClassVar[tuple[str, ...]] = ("force_plate", "mocap")
    spring: int = 2
    operator: int = 1
    trial: int = 1
    duration_s: float = 6.0
    afo: str = "hinged AFO (default jig)"
    #: False where the motion-capture system has no public real-time stream: the trial is guided by
    #: the plate alone and the angle comes afterwards from the lab's C3D export
    live_markers: bool = True
    #: the operator's hand: ``unload(True)`` lifts the AFO off the plate for zeroing, ``unload(False)``
    #: puts it back; a GUI prompt on the bench, the simulator in simulation
    unload: Callable[[bool], None] | None = field(default=None, repr=False, compare=False)
    #: the operator's cue to start bending (a prompt on the bench; the simulated operator starts one
    #: pass of its bends, anchored to the plate's counter, in simulation)
    begin_bends: Callable[[], float] | None = field(default=None, repr=False, compare=False)
    plate_zero_v: list[float] | None = None
    #: the stiffness fit window and the hinge stop (°), from the jig model (`analysis/aads/default_jig.toml`)
    fit_window_deg: tuple[float, float] = field(default_factory=lambda: default_jig_model().fit_window_deg)
    stop_deg: float = field(default_factory=lambda: default_jig_model().stop_deg)

    def __post_init__(self) -> None:
        if self.spring not in AADS_SPRINGS_N_PER_M:
            raise ProtocolError(f"spring must be one of {sorted(AADS_SPRINGS_N_PER_M)}, got {self.spring}")
        if not 1 <= self.operator <= 4:
            raise ProtocolError(f"operator must be 1..4, got {self.operator}")
        if not self.live_markers:
            self.devices = ("force_plate",)  # type: ignore[misc]  # this trial's devices, not the class's

    @property
    def spring_n_per_m(self) -> float:
        return AADS_SPRINGS_N_PER_M[self.spring]

    def condition(self) -> dict[str, Any]:
        return {"spring": self.spring, "spring_n_per_m": self.spring_n_per_m, "operator": self.operator,
                "trial": self.trial, "fit_window_deg": list(self.fit_window_deg), "stop_deg": self.stop_deg, "afo": self.afo,
                "live_markers": self.live_markers, "plate_zeroed_unloaded": self.plate_zero_v is not None}

    def condition_text(self) -> str:
        return f"spring {self.spring}, operator {self.operator}, trial {self.trial}"

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        """Zero the plate with the AFO lifted off, when the operator's hand is available; the
        zeroing samples are dropped, not recorded."""
        if self.unload is None:
            return
        plate = devices["force_plate"]
        self.unload(True)
        try:
            plate.start()
            time.sleep(0.05)  # the lifted AFO settles
            self.plate_zero_v = [float(v) for v in plate.tare(samples=200)]  # type: ignore[attr-defined]
        finally:
            self.unload(False)
        time.sleep(0.05)
        plate.read_available()  # the zeroing stream is not part of the trial

    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        if self.begin_bends is not None:
            self.begin_bends()
        mark("bend_start", operator=self.operator)
        _wait(stop, self.duration_s)
        mark("bend_end")

    def expected_duration_s(self) -> float:
        return self.duration_s

    live_aads_loop: ClassVar[bool] = True

    def checklist(self) -> list[str]:
        return ["force plate zeroed with the AFO unloaded",
                "AFO foot strapped to the plate (no heel lift or slip)",
                f"spring {self.spring} fitted, hinge moves freely to the {self.stop_deg:g}° stop",
                "markers on foot, shank and spring hooks visible to the cameras"]

    def live_hint(self, snapshot: Any) -> str | None:
        if not self.live_markers:
            return ("Recording AADS, force-guided: bend until the plate's load peaks and return; the angle comes "
                    "from the motion-capture system's C3D export (instrument analyze afo FILE.c3d).")
        if not snapshot.aads_angle_deg.size:
            return None
        if snapshot.aads_past_stop:
            return (f"WARNING: bent to {snapshot.aads_peak_deg:.1f}°, past the {self.stop_deg:g}° stop: ease off (the "
                    "stop adds its own stiffness).")
        lo, hi = self.fit_window_deg
        return (f"Recording AADS … peak {snapshot.aads_peak_deg:.1f}°; fit window {lo:g}–{hi:g}° "
                + ("covered." if snapshot.aads_covers_window else "not covered yet: push further."))

    def incomplete_because(self, snapshot: Any) -> str | None:
        if self.live_markers and not snapshot.aads_covers_window:
            return f"bend did not cover the {self.fit_window_deg[0]:g}–{self.fit_window_deg[1]:g}° fit window"
        return None


@dataclass
class IsokineticProtocol(TrialProtocol):
    """A passive isokinetic sweep of the dynamometer from ``start_deg`` to ``end_deg`` at ``speed_deg_s``."""

    devices: ClassVar[tuple[str, ...]] = ("dynamometer",)
    start_deg: float = 0.0
    end_deg: float = 90.0
    speed_deg_s: float = 5.0
    arm_mass_kg: float = 1.8
    arm_com_m: float = 0.22
    settle_s: float = 0.5
    #: the device's torque ceiling for this trial (N·m); set on the device before anything moves
    max_torque_nm: float = DEFAULT_LIMITS.max_torque_nm

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        dyno = devices["dynamometer"]
        if not isinstance(dyno, Dynamometer):
            raise ProtocolError(f"{self.name} needs a dynamometer, got {type(dyno).__name__}")
        lo, hi = sorted((self.start_deg, self.end_deg))
        dyno.open()
        dyno.reset()
        dyno.set_range_of_motion(math.radians(lo - 1.0), math.radians(hi + 1.0))
        dyno.set_torque_limit(self.max_torque_nm)
        dyno.set_passive_isokinetic(math.radians(POSITIONING_SPEED_DEG_S))

    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        dyno = devices["dynamometer"]
        assert isinstance(dyno, Dynamometer)
        travel = abs(self.end_deg - self.start_deg)
        dyno.move_to(math.radians(self.start_deg))  # positioning (recorded too; the state channel tells)
        if _wait(stop, travel / POSITIONING_SPEED_DEG_S + 1.5 + self.settle_s):
            return
        dyno.set_passive_isokinetic(math.radians(self.speed_deg_s))
        mark("sweep_start", start_deg=self.start_deg, end_deg=self.end_deg, speed_deg_s=self.speed_deg_s)
        dyno.move_to(math.radians(self.end_deg))
        stopped = _wait(stop, travel / self.speed_deg_s + 0.5 + self.settle_s)
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
        return travel / POSITIONING_SPEED_DEG_S + travel / self.speed_deg_s + 2.0 + 2 * self.settle_s

    relaxation_monitored: ClassVar[bool] = True
    joint: ClassVar[str] = ""

    def sweep_deg(self) -> tuple[float, float, float] | None:
        return self.start_deg, self.end_deg, self.speed_deg_s

    def fixed_joint_text(self) -> str:
        """The fixed joint's set-up, as the operator reads it."""
        return ""

    def checklist(self) -> list[str]:
        return ["subject anthropometrics entered (mass, shank and foot length)",
                f"dynamometer axis aligned with the {self.joint} joint centre",
                f"seat and fixation set: {self.fixed_joint_text()}",
                f"arm length and weight entered for gravity compensation ({self.arm_mass_kg:g} kg at {self.arm_com_m:g} m)",
                "subject told to relax and not to resist; emergency stop within reach"]


@dataclass
class KneeProtocol(IsokineticProtocol):
    """Knee flexion from full extension to 90° at 5°/s; hip at 90, 55 or 15°."""

    name: ClassVar[str] = "knee"
    joint: ClassVar[str] = "knee"
    hip_flexion_deg: float = 90.0
    ankle_dorsiflexion_deg: float = 0.0

    def fixed_joint_text(self) -> str:
        return f"hip at {self.hip_flexion_deg:g}°"

    def __post_init__(self) -> None:
        if self.hip_flexion_deg not in (90.0, 55.0, 15.0):
            raise ProtocolError(f"hip angle must be 90, 55 or 15°, got {self.hip_flexion_deg}")

    def condition(self) -> dict[str, Any]:
        return {"joint": "knee", **asdict(self)}


@dataclass
class AnkleProtocol(IsokineticProtocol):
    """Ankle from full dorsiflexion to plantarflexion at 5°/s; knee at 0, 45 or 90°."""

    name: ClassVar[str] = "ankle"
    joint: ClassVar[str] = "ankle"
    start_deg: float = 15.0
    end_deg: float = -30.0
    knee_flexion_deg: float = 0.0
    hip_flexion_deg: float = 90.0

    def __post_init__(self) -> None:
        if self.knee_flexion_deg not in (0.0, 45.0, 90.0):
            raise ProtocolError(f"knee angle must be 0, 45 or 90°, got {self.knee_flexion_deg}")

    def condition(self) -> dict[str, Any]:
        return {"joint": "ankle", **asdict(self)}

    def fixed_joint_text(self) -> str:
        return f"knee at {self.knee_flexion_deg:g}°"


@dataclass(frozen=True)
class HoldStart:
    """When the replica leg's first hold starts.

    :ivar host_time_s: host monotonic time (s).
    :ivar device_sample: the torque transmitter's sample counter at that moment, when the rig knows
        it exactly (the simulated rig does); else the driver estimates it from its newest sample.
    """

    host_time_s: float
    device_sample: int | None = None


@dataclass
class ReplicaProtocol(TrialProtocol):
    """Replica leg, hip 90°: the knee locked at each of ``angles_deg`` for ``hold_s``, torque read at each.

    The holds' timing comes from the rig: ``start_holds()`` (the operator's hand: a GUI prompt on the
    bench, the replica-leg simulator in simulation) starts the schedule once the recording runs and
    returns the :class:`HoldStart` of the first hold. Without it the first hold starts when the
    recording does. With a transmitter that numbers its samples, each hold is also marked by its
    first and last device sample (``first_sample``, ``last_sample``): the reading is then the same
    conversions whatever the host's timing, and the export takes them by the counter.
    """

    name: ClassVar[str] = "replica"
    devices: ClassVar[tuple[str, ...]] = ("torque_sensor",)
    angles_deg: tuple[float, ...] = tuple(float(a) for a in range(0, 90, 8))
    hold_s: float = 2.0
    move_speed_deg_s: float = 16.0
    start_holds: Callable[[], HoldStart] | None = field(default=None, repr=False, compare=False)
    #: the operator's hand: ``unload(True)`` takes the shank (and springs) off the sensor,
    #: ``unload(False)`` puts it back; a GUI prompt on the bench, the simulator in simulation
    unload: Callable[[bool], None] | None = field(default=None, repr=False, compare=False)
    tare_zero_nm: float | None = None

    def condition(self) -> dict[str, Any]:
        return {"joint": "knee", "hip_flexion_deg": 90.0, "angles_deg": list(self.angles_deg), "hold_s": self.hold_s,
                "sensor_tared_unloaded": self.tare_zero_nm is not None}

    def condition_text(self) -> str:
        return f"{len(self.angles_deg)} holds at hip 90°"

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        """Tare the sensor with the shank off, when the operator's hand is available: the rig can
        never be unloaded with the springs on, and an untared zero would otherwise have to be fitted."""
        if self.unload is None:
            return
        self.unload(True)
        try:
            self.tare_zero_nm = float(devices["torque_sensor"].tare())  # type: ignore[attr-defined]
        finally:
            self.unload(False)

    def hold_windows(self) -> list[tuple[float, float, float]]:
        """(angle deg, start s, end s) of each hold, relative to the first hold."""
        out, t = [], 0.0
        for i, a in enumerate(self.angles_deg):
            if i:
                t += abs(a - self.angles_deg[i - 1]) / self.move_speed_deg_s
            out.append((a, t, t + self.hold_s))
            t += self.hold_s
        return out

    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        # called here, with the recording running, so every hold lies inside it
        origin = self.start_holds() if self.start_holds is not None else HoldStart(time.monotonic())
        t0 = origin.host_time_s
        sensor = devices.get("torque_sensor")
        rate = getattr(sensor, "output_rate_hz", None)
        k0 = origin.device_sample
        for angle, start, end in self.hold_windows():
            if _wait(stop, max(0.0, t0 + end - time.monotonic())):
                return
            # the reading is the middle 60% of the hold (away from the moves)
            pad = 0.2 * (end - start)
            fields: dict[str, Any] = {"knee_flexion_deg": angle, "t_start_s": t0 + start + pad, "t_end_s": t0 + end - pad}
            if rate and k0 is None:
                k0 = sensor.sample_at(t0)  # type: ignore[union-attr]  # a transmitter with a rate has it
            if rate and k0 is not None:
                fields["first_sample"] = k0 + math.ceil((start + pad) * rate - 1e-6)
                fields["last_sample"] = k0 + math.floor((end - pad) * rate + 1e-6)
            mark("hold", **fields)

    def expected_duration_s(self) -> float:
        return self.hold_windows()[-1][2]

    def checklist(self) -> list[str]:
        return ["hip locked at 90°, ankle at 0°",
                "springs BFLH, BFSH, VASINT, RECFEM attached on their paths",
                "shank can be lifted off the sensor for the tare"]


PROTOCOLS: dict[str, type[TrialProtocol]] = {
    "aads": AadsProtocol, "knee": KneeProtocol, "ankle": AnkleProtocol, "replica": ReplicaProtocol}
