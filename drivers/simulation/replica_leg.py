"""The replica leg: a knee with linear springs on wrapped paths, turning a rotary torque sensor.

Each spring runs from a thigh anchor to a shank anchor over a pulley of radius r on the knee
axis. With a and b the anchor distances from the axis and Δ the angle between them measured
over the pulley, the path length is the two tangents plus the arc when it wraps, else the
straight chord:

    wraps if Δ > acos(r/a) + acos(r/b):   L = √(a²−r²) + √(b²−r²) + r·(Δ − acos(r/a) − acos(r/b))
    otherwise:                            L = √(a² + b² − 2ab·cos Δ)

Anterior (extensor-side) springs have Δ = Δ0 + θ, posterior ones Δ = Δ0 − θ, θ = knee flexion;
the biarticular springs (BFLH, RECFEM) also cross a hip pulley, adding ±r_hip·hip.
The torque the leg exerts against flexion is Σ k·max(L − L0, 0)·dL/dθ plus the shank's weight
moment (hip at 90°, thigh horizontal: −m·g·d·cos θ pulls toward flexion).

The four springs are named after the muscles whose paths they copy (BFLH, BFSH, VASINT, RECFEM,
Chapter 3). Their paths are the drawing's (``analysis/pmp/data/replica_leg.toml``); their
stiffness and rest length are the rig *as built*, a few per cent off the catalogue values the
drawing lists: the truth an estimator must find.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .world import GRAVITY_M_S2


@dataclass(frozen=True)
class WrappedSpring:
    """One spring: stiffness N/m, rest length m, anchors m, pulley radius m, side, Δ0 rad, hip pulley m."""

    stiffness_n_per_m: float
    rest_length_m: float
    thigh_anchor_m: float
    shank_anchor_m: float
    pulley_radius_m: float
    anterior: bool
    span0_rad: float
    name: str = ""
    hip_pulley_radius_m: float = 0.0
    hip_lengthens_with_flexion: bool = False
    hip_rad: float = np.pi / 2

    def length_m(self, knee_rad: np.ndarray) -> np.ndarray:
        a, b, r = self.thigh_anchor_m, self.shank_anchor_m, self.pulley_radius_m
        span = self.span0_rad + (knee_rad if self.anterior else -knee_rad)
        tangent_angles = np.arccos(r / a) + np.arccos(r / b)
        wrapped = np.sqrt(a * a - r * r) + np.sqrt(b * b - r * r) + r * (span - tangent_angles)
        chord = np.sqrt(a * a + b * b - 2 * a * b * np.cos(span))
        hip = self.hip_pulley_radius_m * self.hip_rad * (1.0 if self.hip_lengthens_with_flexion else -1.0)
        return np.where(span > tangent_angles, wrapped, chord) + hip

    def torque_nm(self, knee_rad: np.ndarray) -> np.ndarray:
        """Torque against flexion (N·m): force times dL/dθ."""
        h = 1e-6
        dl = (self.length_m(knee_rad + h) - self.length_m(knee_rad - h)) / (2 * h)
        force = self.stiffness_n_per_m * np.maximum(self.length_m(knee_rad) - self.rest_length_m, 0.0)
        return force * dl


def default_springs() -> list[WrappedSpring]:
    """The rig as built: BFLH and BFSH behind the knee, VASINT and RECFEM in front (hip 90°)."""
    d = np.deg2rad
    return [
        WrappedSpring(834.0, 0.3712, 0.20, 0.14, 0.030, False, d(177.6), "BFLH", 0.035, True),
        WrappedSpring(1163.0, 0.2375, 0.12, 0.15, 0.025, False, d(174.8), "BFSH"),
        WrappedSpring(1562.0, 0.3262, 0.16, 0.16, 0.030, True, d(166.2), "VASINT"),
        WrappedSpring(968.0, 0.2605, 0.20, 0.15, 0.030, True, d(134.6), "RECFEM", 0.035, False),
    ]


@dataclass
class ReplicaLeg:
    """Knee held at a schedule of angles (0–88° every 8° by default), moved between them slowly."""

    springs: list[WrappedSpring] = field(default_factory=default_springs)
    shank_mass_kg: float = 0.9
    shank_com_m: float = 0.18
    hold_angles_deg: tuple[float, ...] = tuple(float(a) for a in range(0, 90, 8))
    hold_s: float = 2.0
    move_speed_deg_s: float = 16.0
    gravity_m_s2: float = GRAVITY_M_S2

    def knee_deg(self, t_s: np.ndarray) -> np.ndarray:
        """Knee flexion (deg) at times ``t_s``: holds and ramps, repeating."""
        pts_t, pts_a = [0.0], [self.hold_angles_deg[0]]
        for a0, a1 in zip(self.hold_angles_deg, self.hold_angles_deg[1:] + self.hold_angles_deg[:1]):
            pts_t += [pts_t[-1] + self.hold_s, pts_t[-1] + self.hold_s + abs(a1 - a0) / self.move_speed_deg_s]
            pts_a += [a0, a1]
        period = pts_t[-1]
        return np.interp(np.mod(np.asarray(t_s, dtype=float), period), pts_t, pts_a)

    def torque_nm(self, knee_deg: np.ndarray) -> np.ndarray:
        """Torque the leg exerts against flexion at the sensor (N·m)."""
        th = np.deg2rad(np.asarray(knee_deg, dtype=float))
        spring = sum(s.torque_nm(th) for s in self.springs)
        return spring - self.shank_mass_kg * self.gravity_m_s2 * self.shank_com_m * np.cos(th)

    def speed_rpm(self, t_s: np.ndarray) -> np.ndarray:
        """Shaft speed (rpm) at times ``t_s``."""
        h = 1e-3
        deg_s = (self.knee_deg(np.asarray(t_s) + h) - self.knee_deg(np.asarray(t_s) - h)) / (2 * h)
        return deg_s / 6.0
