"""The replica leg: its knee held every 8° from 0 to 88° (hip 90°) on a torque sensor; the springs' ground truth."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from analysis.errors import InputError
from analysis.pmp.replica import (
    Holds,
    ReplicaResult,
    estimate_replica,
    holds_from_samples,
    load_replica_model,
    summary_table,
    text,
    write_plots,
)
from analysis.trial_csv import TrialTable
from drivers import StreamingDevice
from drivers.simulation.replica_leg import ReplicaLeg

from ..errors import ExportError
from .base import (
    REPLICA_SPRINGS,
    Curves,
    LiveView,
    Parameter,
    SetAnalysis,
    TrialKind,
    TrialProtocol,
    diagnosis_line,
    wait_or_stop,
)

#: the hold angles of the dissertation's replica-leg protocol (deg)
HOLD_ANGLES_DEG = tuple(float(a) for a in range(0, 90, 8))


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
    angles_deg: tuple[float, ...] = HOLD_ANGLES_DEG
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
            self.tare_zero_nm = float(devices["torque_sensor"].tare())  # type: ignore[attr-defined]  # a sensor
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
            if wait_or_stop(stop, max(0.0, t0 + end - time.monotonic())):
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


def holds_short_of_readings(tables: Sequence[TrialTable], share: float = 0.5) -> list[float]:
    """The hold angles (deg) at which no table read at least ``share`` of the hold's conversions (a host stalled
    past the transmitter's history: counted, and a spring's rest length between two holds 16° apart is then not
    determined): the trial is repeated, and the repeats' holds pooled. Tables without a numbering transmitter
    (no counts) have no short holds."""
    best: dict[float, float] = {}
    for t in tables:
        for angle, read, window in t.sidecar.get("hold_readings", []):
            best[float(angle)] = max(best.get(float(angle), 0.0), float(read) / max(float(window), 1.0))
    return sorted(a for a, got in best.items() if got < share)


def holds_of(tables: list[TrialTable]) -> Holds:
    """The holds of one or more replica trials (repeats at the same angle are pooled).

    :raises InputError: a table is not a replica trial, or there are too few holds.
    """
    for t in tables:
        if t.sidecar.get("kind") != ReplicaKind.table_kind:
            raise InputError(f"{t.sidecar.get('source', 'a trial')}: not a replica-leg trial ({t.sidecar.get('kind')!r})")
    angle = np.concatenate([t.angle_deg for t in tables])
    torque = np.concatenate([t.torque_nm for t in tables])
    return holds_from_samples(angle, torque)


def analyze_replica(tables: list[TrialTable], metadata: list[dict[str, Any]], model_path: Path | None,
                    out: Path | None) -> tuple[ReplicaResult, dict[str, float] | None, list[Path]]:
    """Fit the springs; the simulator's truth (from the first simulated recording) is compared, never used."""
    model = load_replica_model(model_path)
    # a sensor tared with the shank off reads zero at no load; otherwise its zero is fitted too
    tared = all(t.sidecar.get("sensor_tared_unloaded") for t in tables)
    result = estimate_replica(holds_of(tables), model, sensor_offset_nm=0.0 if tared else None)
    truth = next((m["simulation"]["replica_springs"] for m in metadata
                  if m.get("simulated") and "replica_springs" in m.get("simulation", {})), None)
    files = write_plots(result, out, truth) if out is not None else []
    return result, truth, files


def _start_schedule(lab: Any) -> HoldStart:
    host_time_s = lab.torque_sensor.start_schedule(lead_s=0.1)
    counted = lab.torque_sensor.output_rate_hz is not None
    return HoldStart(host_time_s, lab.torque_sensor.schedule_origin_sample if counted else None)


def _draw(curves: Curves, rings: dict[str, Any], snapshot: Any) -> None:
    if "torque_sensor" not in rings:
        return
    d = rings["torque_sensor"].latest()
    if len(d["time_s"]):
        curves.a.setData(d["time_s"] - d["time_s"][0], d["torque_nm"])
        if "speed_rpm" in d:
            curves.b.setData(d["time_s"] - d["time_s"][0], d["speed_rpm"])


class ReplicaKind(TrialKind):
    name = ReplicaProtocol.name
    title = "Replica leg"
    order = 40
    summary = "the replica leg's knee held every 8° from 0 to 88° (hip 90°), the torque read at each hold"
    analysis = REPLICA_SPRINGS
    table_kind = "replica"
    opensim_coordinate = "knee_angle_r"
    parameters = (Parameter("hold_s", "Hold per angle", 2.0, unit="s", low=0.2, high=30.0, flag="--hold",
                            help="replica leg: hold time per angle (s)"),)
    view = LiveView(("knee torque (N·m)", "time (s)"), ("shaft speed (rpm)", "time (s)"), _draw)

    def build(self, **values: Any) -> ReplicaProtocol:
        return ReplicaProtocol(**values)

    def instructions(self) -> str:
        return ("Replica leg, hip 90°: lift the shank off for the tare when asked, then the knee is locked "
                "every 8° from 0 to 88°; the torque is read at each hold.")

    def table(self, trial: Any, subject: dict[str, Any] | None = None) -> TrialTable:
        """The samples inside each hold, with the hold's angle."""
        cond = trial.metadata["protocol"]["condition"]
        sensor = trial.devices["torque_sensor"]
        d = sensor.channels
        t = d["time_s"]
        # a transmitter that numbers its samples: each hold is its conversions, taken by the counter
        # and timed by its clock (the host's stamps of the same samples differ from run to run)
        rate = float((sensor.identity or {}).get("output_rate_hz") or 0.0)
        counter = np.asarray(d["counter"], dtype=np.int64) if "counter" in d else None
        by_counter = rate > 0.0 and counter is not None and len(counter) == len(t)
        parts = []
        missed = 0
        readings: list[list[float]] = []  # per hold: angle (deg), conversions read, conversions in its window
        # time in the trial from the first hold's first conversion (or, host-timed, its first sample),
        # counted in whole conversions so that the same conversion has the same time in every run
        first: dict[str, Any] = next((e for e in trial.events if e.get("kind") == "hold"), {})
        origin_sample = int(first["first_sample"]) if by_counter and "first_sample" in first else None
        for e in trial.events:
            if e.get("kind") == "hold":
                if origin_sample is not None and "first_sample" in e:
                    assert counter is not None
                    m = (counter >= int(e["first_sample"])) & (counter <= int(e["last_sample"]))
                    window = int(e["last_sample"]) - int(e["first_sample"]) + 1
                    missed += window - int(m.sum())
                    readings.append([float(e["knee_flexion_deg"]), int(m.sum()), window])
                    when = (counter[m] - origin_sample).astype(float) / rate
                else:
                    m = (t >= e["t_start_s"]) & (t <= e["t_end_s"])
                    when = t[m]
                parts.append((when, np.full(m.sum(), float(e["knee_flexion_deg"])), d["torque_nm"][m]))
        if not parts or sum(len(p[0]) for p in parts) == 0:
            holds = [e for e in trial.events if e.get("kind") == "hold"]
            t0 = float(t[0]) if len(t) else (holds[0]["t_start_s"] if holds else 0.0)  # times in the trial
            span = f"samples {t[0] - t0:.2f}–{t[-1] - t0:.2f} s" if len(t) else "no samples"
            hold_span = (f"holds {holds[0]['t_start_s'] - t0:.2f}–{holds[-1]['t_end_s'] - t0:.2f} s" if holds
                         else "no holds")
            raise ExportError(f"{trial.path}: no torque samples inside any hold ({len(t)} {span}; "
                              f"{len(holds)} {hold_span}, from the first sample)")
        tt, aa, qq = (np.concatenate(x) for x in zip(*parts))
        origin = 0.0 if origin_sample is not None else float(tt[0])
        return TrialTable({"time_s": tt - origin, "angle_deg": aa, "torque_Nm": qq},
                          {"kind": self.table_kind, "hip_flexion_deg": 90.0, "ankle_dorsiflexion_deg": 0.0,
                           "sensor_tared_unloaded": bool(cond.get("sensor_tared_unloaded", False)),
                           "subject": {k: v for k, v in (subject or {}).items() if v is not None},
                           "source": trial.path.name, "trial_status": trial.status,
                           # conversions inside the holds that no poll read (the counter shows them)
                           **({"hold_conversions_missed": missed, "hold_readings": readings} if by_counter else {})})

    def analyse_set(self, protocol: TrialProtocol, trials: Sequence[Any], subject: dict[str, float], *,
                    figures_dir: Path | None = None,
                    progress: Callable[[str], None] | None = None) -> SetAnalysis:
        tables = [t.table() for t in trials]
        result, truth, figures = analyze_replica(tables, [t.metadata for t in trials], None, figures_dir)
        head, columns, rows = summary_table(result, truth)
        line, diagnosis_figures = diagnosis_line(tables, figures_dir)
        short = holds_short_of_readings(tables)
        if short:
            line += (f"\nREPEAT: the hold{'s' * (len(short) > 1)} at {', '.join(f'{a:g}' for a in short)}° read fewer "
                     "than half of their conversions (the host stalled past the transmitter's history); record the "
                     "trial again, the repeats' holds are pooled")
        return SetAnalysis(f"{len(tables)} accepted replica trial{'s' * (len(tables) != 1)}: {head}", columns,
                           tuple(rows), tuple(str(f) for f in figures + diagnosis_figures), text(result, truth) + line)

    def simulated_rig(self, protocol: TrialProtocol, subject: dict[str, float], afo: Any) -> dict[str, Any]:
        assert isinstance(protocol, ReplicaProtocol)
        return {"replica": ReplicaLeg(hold_angles_deg=protocol.angles_deg, hold_s=protocol.hold_s,
                                      move_speed_deg_s=protocol.move_speed_deg_s)}

    def simulated_operator(self, protocol: TrialProtocol, lab: Any) -> None:
        assert isinstance(protocol, ReplicaProtocol)
        # the simulated operator's hand: shank off the sensor for the tare, then back on; the hold
        # schedule started on the protocol's cue (the simulated lab's own, every time: never a previous lab's)
        protocol.unload = lambda off: setattr(lab.torque_sensor, "shank_attached", not off)
        protocol.start_holds = lambda: _start_schedule(lab)


KIND = ReplicaKind()

__all__ = ["HOLD_ANGLES_DEG", "KIND", "HoldStart", "ReplicaKind", "ReplicaProtocol", "analyze_replica", "holds_of",
           "holds_short_of_readings"]
