"""The live monitors of a trial, in one place: they read the stream and return findings; the runner acts.

* :class:`LimitMonitor` — the subject's safety envelope on the dynamometer's telemetry (range of
  motion, speed, torque): a breach is returned as a sentence; the runner stops the arm.
* :class:`RelaxationWatch` — the relaxation check (:class:`instrument.live.relaxation.RelaxationMonitor`)
  on the steady part of an isokinetic sweep: returns activation alarms; the runner flags them.
* :class:`AadsLoopWatch` — the AADS torque–angle loop so far, by the analysis's own static
  optimisation: returns the loop and whether it covers the fit window or went past the stop.

:func:`monitors_for` says which run for a protocol (from the protocol's own flags). No Qt here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from analysis.aads.model import default_jig_model
from drivers.dynamometer import SUBJECT_ENVELOPE_DEG, SUBJECT_MAX_SPEED_DEG_S, SUBJECT_MAX_TORQUE_NM
from drivers.dynamometer.protocol import State

from ..kinds.base import TrialProtocol
from .relaxation import ActivationAlarm, RelaxationMonitor

#: margins beyond the envelope before a reading counts as a breach (encoder and filter overshoot)
ROM_MARGIN_DEG = 2.0
SPEED_MARGIN_DEG_S = 5.0
#: the part of a sweep near its ends (in seconds of travel) where the arm accelerates: not watched
SWEEP_END_MARGIN_S = 0.3
#: a sample is steady when its speed is within this fraction of the set speed
STEADY_SPEED_FRACTION = 0.2


@dataclass(frozen=True)
class SafetyLimits:
    """What the dynamometer may do with a subject: range of motion (deg), speed (deg/s), torque (N·m)."""

    rom_deg: tuple[float, float] = SUBJECT_ENVELOPE_DEG
    max_speed_deg_s: float = SUBJECT_MAX_SPEED_DEG_S
    max_torque_nm: float = SUBJECT_MAX_TORQUE_NM

    def violations(self, protocol: TrialProtocol) -> list[str]:
        """Why ``protocol`` may not start under these limits (empty when it may)."""
        out = []
        sweep = protocol.sweep_deg()
        if sweep is not None:
            lo, hi = sorted(sweep[:2])
            if lo < self.rom_deg[0] or hi > self.rom_deg[1]:
                out.append(f"sweep {lo:g}…{hi:g}° leaves the range of motion {self.rom_deg[0]:g}…{self.rom_deg[1]:g}°")
            if sweep[2] > self.max_speed_deg_s:
                out.append(f"speed {sweep[2]:g}°/s exceeds {self.max_speed_deg_s:g}°/s")
        return out


class LimitMonitor:
    """The envelope on each telemetry block: the first breach, as the operator reads it, or None."""

    def __init__(self, limits: SafetyLimits) -> None:
        self.limits = limits

    def check(self, position_deg: np.ndarray, velocity_deg_s: np.ndarray, torque_nm: np.ndarray) -> str | None:
        lim = self.limits
        if np.any(np.abs(torque_nm) > lim.max_torque_nm):
            return f"torque {np.max(np.abs(torque_nm)):.1f} N·m over {lim.max_torque_nm:g} N·m"
        if np.any((position_deg < lim.rom_deg[0] - ROM_MARGIN_DEG) | (position_deg > lim.rom_deg[1] + ROM_MARGIN_DEG)):
            return f"angle {position_deg[np.argmax(np.abs(position_deg))]:.1f}° outside {lim.rom_deg}"
        if np.any(np.abs(velocity_deg_s) > lim.max_speed_deg_s + SPEED_MARGIN_DEG_S):
            return f"speed {np.max(np.abs(velocity_deg_s)):.0f}°/s over {lim.max_speed_deg_s:g}°/s"
        return None


class RelaxationWatch:
    """The relaxation check on the steady part of the protocol's sweep (moving toward its end at the set
    speed, away from the ends where the arm accelerates, the device reporting MOVING)."""

    def __init__(self, protocol: TrialProtocol, monitor: RelaxationMonitor | None = None) -> None:
        sweep = protocol.sweep_deg()
        if sweep is None:
            raise ValueError(f"{protocol.name} has no sweep to watch")
        self.start_deg, self.end_deg, self.speed_deg_s = sweep
        self.monitor = monitor or RelaxationMonitor()

    def check(self, block: dict[str, np.ndarray], position_deg: np.ndarray, velocity_deg_s: np.ndarray,
              torque_nm: np.ndarray) -> list[ActivationAlarm]:
        speed = self.speed_deg_s
        # moving toward the sweep's end only: a return leg (out and back) is not the sweep the check knows
        toward_end = velocity_deg_s * (1.0 if self.end_deg >= self.start_deg else -1.0)
        steady = np.abs(toward_end - speed) < STEADY_SPEED_FRACTION * speed
        margin = SWEEP_END_MARGIN_S * speed
        lo, hi = sorted((self.start_deg, self.end_deg))
        steady &= (position_deg > lo + margin) & (position_deg < hi - margin)
        if "state" in block:
            steady &= block["state"] == int(State.MOVING)
        if not steady.any():
            return []
        return self.monitor.update(block["time_s"][steady], position_deg[steady], torque_nm[steady])


@dataclass
class AadsLoop:
    """The AADS loop so far: hinge angle (deg) and AFO torque (N·m), its peak, and the window checks."""

    angle_deg: np.ndarray
    torque_nm: np.ndarray
    peak_deg: float
    covers_window: bool
    past_stop: bool


class AadsLoopWatch:
    """The torque–angle loop from the latest markers and plate samples (the analysis's own pipeline)."""

    def __init__(self, protocol: TrialProtocol, identities: dict[str, Any]) -> None:
        self.fit_window_deg: tuple[float, float] = protocol.fit_window_deg  # type: ignore[attr-defined]  # the live AADS loop runs only for protocols that have a fit window
        self.stop_deg: float = protocol.stop_deg  # type: ignore[attr-defined]  # the live AADS loop runs only for protocols that have a stop
        self.identities = identities

    def check(self, rings: dict[str, Any]) -> AadsLoop | None:
        from analysis.aads.pipeline import analyze_trial
        from analysis.errors import AnalysisError

        from .motion import motion_from_channels

        if "mocap" not in rings or "force_plate" not in rings:
            return None
        mk, fp = rings["mocap"].latest(), rings["force_plate"].latest()
        if len(mk["time_s"]) < 50 or len(fp["time_s"]) < 200:
            return None
        try:
            motion = motion_from_channels(mk, self.identities["mocap"], fp, self.identities["force_plate"], "live")
            res = analyze_trial(motion, default_jig_model())
        except (AnalysisError, ValueError, IndexError):
            return None
        ok = res.sop.valid
        angle, torque = res.angle_deg[ok], res.afo_torque_nm[ok]
        peak = float(np.nanmax(angle)) if angle.size else float("nan")
        lo, hi = self.fit_window_deg
        return AadsLoop(angle, torque, peak, bool(angle.size) and float(np.nanmin(angle)) <= lo and peak >= hi,
                        bool(peak > self.stop_deg))


def monitors_for(protocol: TrialProtocol, limits: SafetyLimits,
                 relaxation: RelaxationMonitor | None = None) -> tuple[LimitMonitor | None, RelaxationWatch | None]:
    """The telemetry monitors of ``protocol``: the envelope whenever a dynamometer moves the subject,
    the relaxation check where the protocol asks for it."""
    limit = LimitMonitor(limits) if "dynamometer" in protocol.devices else None
    wanted = protocol.relaxation_monitored or relaxation is not None
    watch = RelaxationWatch(protocol, relaxation) if wanted and protocol.sweep_deg() is not None else None
    return limit, watch


__all__ = ["AadsLoop", "AadsLoopWatch", "LimitMonitor", "RelaxationWatch", "SafetyLimits", "monitors_for"]
