"""A trial as the diagnosis sees it: time, the moving joint's angle and the specimen's torque (SI inside).

Sign convention: the trial CSV's, defined once in :mod:`analysis.trial_csv` (angle positive in
dorsiflexion or knee flexion; torque applied to the specimen toward positive angle, which equals
what the specimen resists with, so a linear spring reads torque = k·angle).
For knee and ankle trials the torque includes the weight of the limb segments distal to the
joint; the limb's gravity is modelled from the subject (Winter's segment fractions), as in the
simulated subject.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.signal import savgol_filter

from ..constants import GRAVITY_M_S2
from ..errors import InputError
from ..timebase import uniform_grid
from ..trial_csv import KINDS, MAX_ROWS_WITHOUT_TIME_FRACTION, TrialTable

G_M_S2 = GRAVITY_M_S2


@dataclass
class DiagnosisTrial:
    """One trial: ``time_s`` (s), ``angle_rad``, ``torque_nm`` and what is known about the set-up."""

    kind: str
    time_s: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray
    fixed_deg: dict[str, float] = field(default_factory=dict)  # hip_flexion_deg, knee_flexion_deg, ...
    subject: dict[str, Any] = field(default_factory=dict)      # mass_kg, shank_length_m, foot_length_m, ...
    source: str = ""
    #: inertia of what turns with the joint besides the limb (the dynamometer's arm), kg·m²; None when
    #: the torque is not a dynamometer's raw torque (no moving inertia is known to be in it)
    rig_inertia_kgm2: float | None = None
    #: rows left out and why ("no time", "angle not finite", "torque not finite"); rows a reader already
    #: left out (a CSV's rows without a time) may be given here and are added to
    rows_left_out: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"{self.source or 'trial'}: kind must be one of {KINDS}, got {self.kind!r}")
        t, a, q = (np.asarray(x, dtype=float) for x in (self.time_s, self.angle_rad, self.torque_nm))
        if not t.shape == a.shape == q.shape or t.ndim != 1:
            raise InputError(f"{self.source or 'trial'}: time, angle and torque must be 1-D columns of one length, "
                             f"got {t.shape}, {a.shape}, {q.shape}")
        timed = np.isfinite(t)
        given_without_time = int(self.rows_left_out.get("no time", 0))
        without_time = int(t.size - timed.sum()) + given_without_time
        if without_time > MAX_ROWS_WITHOUT_TIME_FRACTION * (t.size + given_without_time):
            raise InputError(f"{self.source or 'trial'}: {without_time} of {t.size + given_without_time} rows have no "
                             f"finite time; at most {MAX_ROWS_WITHOUT_TIME_FRACTION:.0%} may be left out")
        counts = dict(self.rows_left_out)
        counts["no time"] = without_time
        counts["angle not finite"] = counts.get("angle not finite", 0) + int((timed & ~np.isfinite(a)).sum())
        counts["torque not finite"] = counts.get("torque not finite", 0) + int(
            (timed & np.isfinite(a) & ~np.isfinite(q)).sum())
        self.rows_left_out = {k: v for k, v in counts.items() if v}
        ok = timed & np.isfinite(a) & np.isfinite(q)
        if ok.sum() < 50:
            raise InputError(f"{self.source or 'trial'}: {int(ok.sum())} finite samples; the diagnosis needs 50")
        order = np.argsort(t[ok], kind="stable")
        self.time_s, self.angle_rad, self.torque_nm = t[ok][order], a[ok][order], q[ok][order]
        if np.any(np.diff(self.time_s) <= 0):
            raise InputError(f"{self.source or 'trial'}: repeated time stamps")

    def left_out_text(self) -> str:
        """One line saying which rows were left out and why ('' when none were)."""
        if not self.rows_left_out:
            return ""
        total = sum(self.rows_left_out.values())
        parts = ", ".join(f"{n} {why}" for why, n in self.rows_left_out.items())
        return f"{total} row(s) left out ({parts}); the rest diagnosed"

    @property
    def rate_hz(self) -> float:
        return 1.0 / float(np.median(np.diff(self.time_s)))

    def decimated(self, max_rate_hz: float) -> DiagnosisTrial:
        """This trial averaged over blocks of consecutive samples so its rate is at most ``max_rate_hz``
        (Hz); the block mean is the anti-alias filter. Passive effects live below 10 Hz."""
        q = int(math.floor(self.rate_hz / max_rate_hz))
        if q <= 1:
            return self
        n = self.time_s.size // q * q
        def mean(x: np.ndarray) -> np.ndarray:
            return x[:n].reshape(-1, q).mean(axis=1)
        # the rows left out were counted on this trial; the block means are all finite
        out = DiagnosisTrial(self.kind, mean(self.time_s), mean(self.angle_rad), mean(self.torque_nm),
                             dict(self.fixed_deg), dict(self.subject), self.source, self.rig_inertia_kgm2)
        out.rows_left_out = dict(self.rows_left_out)
        return out

    def savgol(self, x: np.ndarray, window_s: float = 0.15, order: int = 3, deriv: int = 0) -> np.ndarray:
        """Savitzky–Golay filter of ``x`` (sampled at ``time_s``) over ``window_s`` (s): the value, or its
        ``deriv``-th time derivative (units of x per sᵈᵉʳⁱᵛ).

        The filter assumes even steps. Where samples are missing (dropped rows, NaN rows removed) it
        runs on the signal interpolated to an even grid at the median step and is read back at the
        sample times: applied to the raw rows, a derivative across a gap of one row in 50 reads the
        angle's two-step change as one step. On the independent generator's trials with 2 % dropped
        rows and 0.5 % NaN cells that overstated every velocity by 2–4 % and so understated viscous
        damping by 3.5–5 % (4–12 standard errors; `benchmarks/diagnosis_truth` seeds 150001–150011).
        """
        t = self.time_s
        steps = np.diff(t)
        dt = float(np.median(steps))
        uneven = bool(np.any(np.abs(steps - dt) > 0.01 * dt))
        grid = uniform_grid(float(t[0]), float(t[-1]), 1.0 / dt) if uneven else t
        xg = np.interp(grid, t, x) if uneven else np.asarray(x, dtype=float)
        n = max(order + 2 | 1, int(round(window_s / dt)) | 1)
        n = min(n, xg.size if xg.size % 2 else xg.size - 1)
        y = savgol_filter(xg, n, min(order, n - 1), deriv=deriv, delta=dt)
        return np.interp(t, grid, y) if uneven else y

    def velocity_rad_s(self, window_s: float = 0.15) -> np.ndarray:
        """Angular velocity (rad/s) by a Savitzky–Golay derivative (cubic, ``window_s`` wide)."""
        return self.savgol(self.angle_rad, window_s, 3, 1)

    def limb_gravity_nm(self) -> np.ndarray:
        """The limb's weight as torque against the bending (N·m); zero for AFO and replica trials."""
        m = float(self.subject.get("mass_kg") or 0.0)
        if self.kind == "knee" and m > 0:
            shank = float(self.subject.get("shank_length_m") or 0.42)
            moment = (0.0465 * m * 0.433 * shank + 0.0145 * m * shank) * G_M_S2
            return -moment * np.cos(self.angle_rad)  # gravity pulls toward flexion: the limb helps the bend
        if self.kind == "ankle" and m > 0:
            foot = float(self.subject.get("foot_length_m") or 0.26)
            knee = np.deg2rad(float(self.fixed_deg.get("knee_flexion_deg") or 0.0))
            return 0.0145 * m * 0.5 * foot * G_M_S2 * np.cos(self.angle_rad + np.pi / 2 - knee)
        return np.zeros_like(self.angle_rad)

    def known_inertia_kgm2(self) -> float:
        """What is known to turn with the joint (kg·m²): the limb distal to it from the subject (Winter's
        segment fractions, as the estimator's) and the rig's arm; 0 for AFO and replica trials and when
        the trial does not say its torque is a dynamometer's (``rig_inertia_kgm2`` None). The baseline
        carries it, so the ``inertia`` cause names only an error beyond it."""
        if self.rig_inertia_kgm2 is None or self.kind not in ("knee", "ankle"):
            return 0.0
        from ..pmp.estimator import Subject  # the estimator's own limb model, not a second copy

        limb = Subject(float(self.subject.get("mass_kg") or 0.0), float(self.subject.get("shank_length_m") or 0.42),
                       float(self.subject.get("foot_length_m") or 0.26))
        return limb.inertia_kgm2(self.kind) + float(self.rig_inertia_kgm2)

    def gravity_shape(self) -> np.ndarray:
        """Unit shape of a gravity error (the limb's torque per N·m of weight moment)."""
        if self.kind == "ankle":
            knee = np.deg2rad(float(self.fixed_deg.get("knee_flexion_deg") or 0.0))
            return np.cos(self.angle_rad + np.pi / 2 - knee)
        return -np.cos(self.angle_rad)


def from_table(table: TrialTable, kind: str | None = None) -> DiagnosisTrial:
    """A trial CSV (with its sidecar) as a diagnosis trial; ``kind`` overrides the sidecar's."""
    side = table.sidecar
    k = kind or side.get("kind")
    if k is None:
        raise InputError("the trial's kind is unknown: give --kind or a sidecar with 'kind'")
    fixed = {n: float(side[n]) for n in ("hip_flexion_deg", "knee_flexion_deg", "ankle_dorsiflexion_deg")
             if side.get(n) is not None}
    return DiagnosisTrial(k, table.time_s, np.deg2rad(table.angle_deg), table.torque_nm, fixed,
                          dict(side.get("subject") or {}), str(side.get("source", "")),
                          None if side.get("arm_inertia_kgm2") is None else float(side["arm_inertia_kgm2"]),
                          {"no time": table.rows_without_time} if table.rows_without_time else {})
