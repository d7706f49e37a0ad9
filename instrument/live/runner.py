"""Run one protocol trial in the background, with live checks, for the GUI, the CLI and tests (Qt-free).

``TrialRunner`` records a trial through :func:`record_trial` on a worker thread and, beside it,
watches the stream: the relaxation check on the dynamometer torque (isokinetic trials), the
safety limits (range of motion, speed, torque: a breach stops the dynamometer), and for AADS
trials the torque–angle loop and the fit-window coverage. Nothing here blocks the caller: the
GUI's timer reads :meth:`TrialRunner.snapshot` and the ring buffers; commands to devices run on
their own threads. The emergency stop goes to the dynamometer at once and is written into the
trial; whatever the trial recorded stays on disk.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from drivers import Dynamometer, StreamingDevice

from ..errors import ProtocolError
from ..kinds.base import TrialProtocol
from ..store import SessionStore
from .acquisition import AcquisitionEngine, Sink
from .monitors import AadsLoopWatch, SafetyLimits, monitors_for
from .relaxation import ActivationAlarm, EmgEnvelopeMonitor, RelaxationMonitor
from .session import TrialOutcome, record_trial


def checklist_for(protocol: TrialProtocol) -> list[str]:
    """The set-up items the operator confirms before a trial of ``protocol`` (the protocol's own list)."""
    return protocol.checklist()


@dataclass
class Checklist:
    """Items the operator must confirm; a trial starts only when all are."""

    items: list[str]
    done: set[int] = field(default_factory=set)

    def confirm(self, index: int, value: bool = True) -> None:
        (self.done.add if value else self.done.discard)(index)

    @property
    def complete(self) -> bool:
        return len(self.done) == len(self.items)

    def missing(self) -> list[str]:
        return [it for i, it in enumerate(self.items) if i not in self.done]


@dataclass
class LiveState:
    """What the runner knows now (copied out under a lock)."""

    phase: str = "idle"               # idle, running, done, failed
    elapsed_s: float = 0.0
    alarms: list[ActivationAlarm] = field(default_factory=list)
    limit_breaches: list[str] = field(default_factory=list)
    emergency_stop_s: float | None = None   # time the e-stop command left the host
    estop_confirmed_s: float | None = None  # time the dynamometer's telemetry first showed the stop
    estop_unconfirmed: str | None = None    # why the e-stop is unconfirmed: the operator gets a blocking alarm
    aads_angle_deg: np.ndarray = field(default_factory=lambda: np.zeros(0))
    aads_torque_nm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    aads_peak_deg: float = float("nan")
    aads_covers_window: bool = False
    aads_past_stop: bool = False
    outcome: TrialOutcome | None = None
    error: str | None = None


class TrialRunner:
    """One trial of ``protocol`` on ``devices`` into ``store`` on a worker thread (see the module docstring)."""

    def __init__(self, store: SessionStore, session_id: int, protocol: TrialProtocol,
                 devices: dict[str, StreamingDevice], *, operator: str | None = None, trial_number: int | None = None,
                 extra_metadata: dict[str, Any] | None = None, limits: SafetyLimits | None = None,
                 monitor: RelaxationMonitor | None = None, on_done: Callable[[TrialRunner], None] | None = None,
                 sinks: list[Sink] | None = None) -> None:
        self.store, self.session_id, self.protocol = store, session_id, protocol
        # the protocol's devices, and any other system's streams the lab records beside them (LSL inlets)
        self.devices = {n: d for n, d in devices.items() if n in protocol.devices or d.kind == "lsl"}
        missing = [n for n in protocol.devices if n not in devices]
        if missing:
            raise ProtocolError(f"{protocol.name} needs {', '.join(missing)}")
        self.limits = limits or SafetyLimits()
        problems = self.limits.violations(protocol)
        if problems:
            raise ProtocolError("; ".join(problems))
        self.operator, self.trial_number, self.extra_metadata = operator, trial_number, extra_metadata
        if hasattr(protocol, "max_torque_nm"):  # the device's own ceiling: the stricter of the two
            protocol.max_torque_nm = min(protocol.max_torque_nm, self.limits.max_torque_nm)
        self.engine = AcquisitionEngine(self.devices, ring_seconds=120.0, sinks=sinks)
        # the live monitors (instrument.live.monitors) find; this runner acts on what they find
        self.limit_monitor, self.relaxation_watch = monitors_for(protocol, self.limits, monitor)
        self.monitor = self.relaxation_watch.monitor if self.relaxation_watch is not None else None
        self.aads_watch = AadsLoopWatch(protocol, {}) if protocol.live_aads_loop else None
        #: EMG streams' envelope checks, beside the torque's (made once a stream is open and its channels known)
        self.emg_monitors: dict[str, EmgEnvelopeMonitor] = {}
        self._last_angle_deg = float("nan")
        self.stop_event = threading.Event()
        self._state = LiveState()
        self._lock = threading.Lock()
        self._events: list[tuple[str, dict[str, Any]]] = []
        self._on_done = on_done
        self._t0 = 0.0
        self._worker: threading.Thread | None = None
        self._watcher: threading.Thread | None = None
        #: set while the isokinetic sweep runs (the protocol's ``sweep_start`` … ``sweep_end``)
        self.sweep_started = threading.Event()

    # ------------------------------------------------------------------ control
    def start(self) -> None:
        """Open the devices, apply the limits and start recording (returns at once)."""
        self._t0 = time.monotonic()
        with self._lock:
            self._state.phase = "running"
        self._worker = threading.Thread(target=self._run, name=f"trial-{self.protocol.name}", daemon=True)
        self._worker.start()
        self._watcher = threading.Thread(target=self._watch, name="trial-watch", daemon=True)
        self._watcher.start()

    def request_stop(self) -> None:
        """End the trial early (data kept; the trial is marked interrupted)."""
        self.stop_event.set()

    def emergency_stop(self, reason: str = "operator") -> None:
        """Stop the dynamometer now, mark the trial, end it; never blocks on the device.

        The e-stop frame is handed to the bus on the calling thread (one CAN frame, no
        acknowledgement). A confirming thread then waits for the device to show the stop: not
        confirmed within :data:`ESTOP_CONFIRM_PERIODS` telemetry periods, the frame is re-sent (up
        to :data:`ESTOP_RESENDS` times); still unconfirmed, the arm is halted by command, the host
        heartbeat is withdrawn (the device's watchdog stops any motion), the trial is marked and
        :attr:`LiveState.estop_unconfirmed` says why, for a blocking alarm.
        """
        dyno = self.devices.get("dynamometer")
        now = time.monotonic()
        if isinstance(dyno, Dynamometer):
            sent_s, send_error = now, None
            try:
                sent_s = dyno.emergency_stop()
            except Exception as err:
                send_error = err
            with self._lock:
                first = self._state.emergency_stop_s is None
                if first:
                    self._state.emergency_stop_s = sent_s
            self._mark("emergency_stop", reason=reason, **({"send_error": str(send_error)} if send_error else {}))
            if first:
                threading.Thread(target=self._confirm_estop, args=(dyno, sent_s), daemon=True, name="estop").start()
        else:
            with self._lock:
                if self._state.emergency_stop_s is None:
                    self._state.emergency_stop_s = now
            self._mark("emergency_stop", reason=reason)
            self.stop_event.set()

    def wait(self, timeout_s: float | None = None) -> bool:
        """Wait for the trial to end (for the CLI and tests; the GUI never calls this)."""
        if self._worker is None:
            return True
        self._worker.join(timeout_s)
        if self._watcher is not None:
            self._watcher.join(timeout_s)
        return not self._worker.is_alive()

    def snapshot(self) -> LiveState:
        with self._lock:
            s = self._state
            return LiveState(s.phase, time.monotonic() - self._t0 if s.phase == "running" else s.elapsed_s,
                             list(s.alarms), list(s.limit_breaches), s.emergency_stop_s, s.estop_confirmed_s,
                             s.estop_unconfirmed, s.aads_angle_deg, s.aads_torque_nm, s.aads_peak_deg, s.aads_covers_window,
                             s.aads_past_stop, s.outcome, s.error)

    # ------------------------------------------------------------------ verdict
    def accept(self) -> None:
        out = self._require_outcome()
        self.store.set_status(out.trial_id, "accepted")

    def reject(self, reason: str) -> None:
        """Reject the trial, keeping its data and the reason (e.g. 'muscle activation at 42°')."""
        out = self._require_outcome()
        self.store.set_status(out.trial_id, "rejected", reason)

    def suggested_rejection(self) -> str | None:
        """Why the trial should be repeated, if the live checks found a reason."""
        s = self.snapshot()
        if s.estop_unconfirmed is not None:
            return "emergency stop unconfirmed: " + s.estop_unconfirmed
        if s.emergency_stop_s is not None:
            return "emergency stop"
        if s.alarms:
            a = s.alarms[0]
            # the time in the trial (from its start), not the host's clock
            return (f"muscle activation detected at {a.angle_deg:.1f}° ({a.time_s - self._t0:.1f} s into the "
                    f"trial, {a.what()})")
        if s.limit_breaches:
            return "limit breached: " + s.limit_breaches[0]
        if s.phase == "done":
            return self.protocol.incomplete_because(s)
        return None

    def _require_outcome(self) -> TrialOutcome:
        s = self.snapshot()
        if s.outcome is None:
            raise ProtocolError("the trial has not finished recording")
        return s.outcome

    # ------------------------------------------------------------------ threads
    def _mark(self, kind: str, **fields: Any) -> None:
        writer = self.engine.writer
        if writer is not None:
            writer.log_event(kind, **fields)
        else:
            self._events.append((kind, fields))

    def _confirm_estop(self, dyno: Dynamometer, sent_s: float) -> None:
        """Confirm the e-stop from the device's own report; re-send, then alarm (see :meth:`emergency_stop`)."""
        try:
            window_s = ESTOP_CONFIRM_PERIODS * dyno.telemetry_period_s
            frames, deadline = 1, sent_s + window_s
            while not dyno.stop_latched_since(sent_s):
                if time.monotonic() >= deadline:
                    if frames > ESTOP_RESENDS:
                        break
                    frames += 1
                    try:
                        dyno.emergency_stop()
                    except Exception as err:
                        self._mark("emergency_stop_send_failed", error=str(err))
                    self._mark("emergency_stop_resent", frame=frames)
                    deadline = time.monotonic() + window_s
                time.sleep(0.0005)
            if dyno.stop_latched_since(sent_s):
                with self._lock:
                    self._state.estop_confirmed_s = time.monotonic()
                self._mark("emergency_stop_confirmed", frames=frames)
                return
            why = (f"the dynamometer did not confirm the emergency stop ({frames} frames over "
                   f"{1000 * (time.monotonic() - sent_s):.0f} ms)")
            with self._lock:
                self._state.estop_unconfirmed = why
            self._mark("emergency_stop_unconfirmed", frames=frames)
            try:
                dyno.halt()
                self._mark("halted", by="command after an unconfirmed emergency stop")
            except Exception as err:
                self._mark("halt_failed", error=str(err))
            dyno.suspend_heartbeat(True)  # the device's watchdog stops any motion it still makes
            self._mark("heartbeat_withdrawn")
        except Exception as err:
            with self._lock:
                self._state.estop_unconfirmed = f"emergency stop confirmation failed: {err}"
        finally:
            time.sleep(0.2)  # a few telemetry frames of the stopped arm into the recording
            self.stop_event.set()

    def _run(self) -> None:
        try:
            self.engine.open()
            outcome = record_trial(self.store, self.session_id, self.protocol, self.devices, operator=self.operator,
                                   trial_number=self.trial_number, extra_metadata=self.extra_metadata,
                                   stop=self.stop_event, engine=self.engine, on_event=self._protocol_event)
            with self._lock:
                unconfirmed = self._state.estop_unconfirmed
            if unconfirmed is not None:  # the trial carries the alarm, not only the window
                self.store.set_status(outcome.trial_id, "interrupted", reason=unconfirmed)
                outcome.status, outcome.reason = "interrupted", unconfirmed
            with self._lock:
                self._state.outcome = outcome
                self._state.phase = "done"
        except Exception as err:
            with self._lock:
                self._state.error = f"{type(err).__name__}: {err}"
                self._state.phase = "failed"
        finally:
            with self._lock:
                self._state.elapsed_s = time.monotonic() - self._t0
            self.stop_event.set()
            if self._on_done is not None:
                self._on_done(self)

    def _protocol_event(self, kind: str, fields: dict[str, Any]) -> None:
        if kind == "sweep_start":
            self.sweep_started.set()
        elif kind == "sweep_end":
            self.sweep_started.clear()


    def _watch(self) -> None:
        """Relaxation, limits and the AADS loop, from the ring buffers, every 20 ms until the trial ends."""
        marks = {n: 0 for n in self.devices}
        last_aads = 0.0
        while self._worker is not None and self._worker.is_alive():
            time.sleep(0.02)
            if self._events and self.engine.writer is not None:  # marks made before the file existed
                pending, self._events = self._events, []
                for kind, fields in pending:
                    self.engine.writer.log_event(kind, **fields)
            if "dynamometer" in self.engine.rings:
                data, marks["dynamometer"] = self.engine.rings["dynamometer"].since(marks["dynamometer"])
                if len(data["time_s"]):
                    self._check_dynamometer(data)
            for name in self._emg_streams():
                data, marks[name] = self.engine.rings[name].since(marks[name])
                if len(data["time_s"]):  # the baseline from the set-up, alarms during the sweep
                    self._check_emg(name, data)
            if self.protocol.live_aads_loop and time.monotonic() - last_aads > 0.25:
                last_aads = time.monotonic()
                self._update_aads()
        if self.protocol.live_aads_loop:
            self._update_aads()

    def _emg_streams(self) -> list[str]:
        """The recorded streams that are EMG (LSL type ``EMG``), once open."""
        return [n for n, d in self.devices.items() if getattr(d, "stream_type", "") == "EMG" and n in self.engine.rings]

    def _check_emg(self, name: str, data: dict[str, np.ndarray]) -> None:
        """The EMG envelope check (:class:`~instrument.live.relaxation.EmgEnvelopeMonitor`) on new samples."""
        if name not in self.emg_monitors:
            self.emg_monitors[name] = EmgEnvelopeMonitor(tuple(getattr(self.devices[name], "labels", ())))
        new = self.emg_monitors[name].update(data["time_s"], data["values"], lambda t: self._last_angle_deg,
                                             armed=self.sweep_started.is_set())
        if new:
            with self._lock:
                self._state.alarms.extend(new)
            for a in new:
                self._mark("activation", time_s=a.time_s, angle_deg=a.angle_deg, source=a.source)

    def _check_dynamometer(self, d: dict[str, np.ndarray]) -> None:
        pos = np.rad2deg(d["position_rad"])
        self._last_angle_deg = float(pos[-1])
        vel = np.rad2deg(d["velocity_rad_s"])
        tq = d["torque_nm"]
        breach = self.limit_monitor.check(pos, vel, tq) if self.limit_monitor is not None else None
        if breach is not None and self._state.emergency_stop_s is None:
            with self._lock:
                self._state.limit_breaches.append(breach)
            self.emergency_stop(reason=breach)
            return
        if self.relaxation_watch is not None and self.sweep_started.is_set():
            new = self.relaxation_watch.check(d, pos, vel, tq)
            if new:
                with self._lock:
                    self._state.alarms.extend(new)
                for a in new:
                    self._mark("activation", time_s=a.time_s, angle_deg=a.angle_deg, excess_nm=a.excess_nm)

    def _update_aads(self) -> None:
        """The loop so far (:class:`instrument.live.monitors.AadsLoopWatch`) into the live state."""
        if self.aads_watch is None:
            return
        if {"mocap", "force_plate"} <= set(self.devices):  # as the devices describe themselves once open
            self.aads_watch.identities = {n: self.devices[n].identity() for n in ("mocap", "force_plate")}
        loop = self.aads_watch.check(self.engine.rings)
        if loop is None:
            return
        with self._lock:
            st = self._state
            newly_past = loop.past_stop and not st.aads_past_stop
            st.aads_angle_deg, st.aads_torque_nm, st.aads_peak_deg = loop.angle_deg, loop.torque_nm, loop.peak_deg
            st.aads_covers_window, st.aads_past_stop = loop.covers_window, loop.past_stop
        if newly_past:  # into the trial's record, not only on screen (the stop adds its own stiffness)
            self._mark("past_stop", peak_deg=float(loop.peak_deg), stop_deg=float(self.aads_watch.stop_deg))


#: telemetry periods the device has to show an e-stop before the frame is sent again
ESTOP_CONFIRM_PERIODS = 2
#: re-sends of an unconfirmed e-stop frame before the operator is alarmed
ESTOP_RESENDS = 2


__all__ = ["TrialRunner", "SafetyLimits", "Checklist", "checklist_for", "LiveState"]
