"""A relaxed, seated subject's leg moved by a dynamometer arm: passive moments, gravity, inertia.

Angles in degrees at this module's edges (the dynamometer's own units), SI inside the sums.
The thigh rests horizontal on the seat for every hip angle (the backrest reclines instead).

Passive elastic joint moments are Riener & Edrich (1999), with dorsiflexion positive; the
moving joint's angle is the dynamometer position. Gravity acts on the segments distal to the
moving joint (Winter's anthropometric fractions) and on the dynamometer arm. The shaft torque
the device reports is what it must apply toward positive angles:

    τ_shaft = I·θ̈ + b·θ̇ − M_passive(θ) − M_gravity(θ) + τ_burst(t)

so a limb resisting flexion (or dorsiflexion) reads positive.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .world import GRAVITY_M_S2


def riener_knee_flexion_moment_nm(hip_deg: float, knee_deg: np.ndarray, ankle_df_deg: float) -> np.ndarray:
    """Passive knee moment, flexion positive (N·m); angles in degrees, ankle dorsiflexion positive."""
    k, h, a = np.asarray(knee_deg, dtype=float), hip_deg, ankle_df_deg
    return (np.exp(1.800 + 0.0460 * a - 0.0352 * k + 0.0217 * h)
            - np.exp(-3.971 + 0.0004 * a + 0.0495 * k - 0.0128 * h) - 4.820 + np.exp(2.220 - 0.150 * k))


def riener_ankle_dorsiflexion_moment_nm(knee_deg: float, ankle_df_deg: np.ndarray) -> np.ndarray:
    """Passive ankle moment, dorsiflexion positive (N·m); angles in degrees."""
    a, k = np.asarray(ankle_df_deg, dtype=float), knee_deg
    return np.exp(-7.9763 - 0.1949 * a + 0.0008 * k) - np.exp(2.1016 + 0.0843 * a - 0.0176 * k) + 1.792


@dataclass
class Burst:
    """A muscle activation burst: half-sine of ``amplitude_nm`` lasting ``duration_s`` from ``start_s``."""

    start_s: float
    amplitude_nm: float
    duration_s: float = 0.4

    def torque(self, t_s: np.ndarray) -> np.ndarray:
        u = (np.asarray(t_s) - self.start_s) / self.duration_s
        return np.where((u >= 0) & (u <= 1), self.amplitude_nm * np.sin(np.pi * np.clip(u, 0, 1)), 0.0)


def riener_passive_moment_nm(leg: SeatedLeg, position_deg: np.ndarray) -> np.ndarray:
    """Riener & Edrich's passive moment of ``leg``'s moving joint toward positive angles (N·m), whatever
    table the simulated subject uses (the published normative model, for an expected band)."""
    if leg.joint == "knee":
        return riener_knee_flexion_moment_nm(leg.hip_flexion_deg, position_deg, leg.ankle_dorsiflexion_deg)
    return riener_ankle_dorsiflexion_moment_nm(leg.knee_flexion_deg, position_deg)


@dataclass
class SeatedLeg:
    """The subject and the dynamometer arm.

    :ivar joint: ``"knee"`` (position = knee flexion) or ``"ankle"`` (position = dorsiflexion).
    """

    joint: str = "knee"
    hip_flexion_deg: float = 90.0
    knee_flexion_deg: float = 0.0       # fixed angle for ankle trials
    ankle_dorsiflexion_deg: float = 0.0  # fixed angle for knee trials
    body_mass_kg: float = 75.0
    shank_length_m: float = 0.42
    foot_length_m: float = 0.26
    arm_mass_kg: float = 1.8
    arm_com_m: float = 0.22
    damping_nm_s_per_rad: float = 0.3
    gravity_m_s2: float = GRAVITY_M_S2
    bursts: list[Burst] = field(default_factory=list)
    #: the elastic moment as a table (position deg ascending, N·m toward positive angles) in place
    #: of Riener & Edrich: e.g. a muscle model with a simulated subject's own parameters
    passive_table_deg: tuple[float, ...] = ()
    passive_table_nm: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if self.joint not in ("knee", "ankle"):
            raise ValueError(f"joint must be 'knee' or 'ankle', got {self.joint!r}")
        m = self.body_mass_kg
        self.shank_mass_kg = 0.0465 * m
        self.foot_mass_kg = 0.0145 * m
        self.shank_com_m = 0.433 * self.shank_length_m
        self.foot_com_m = 0.5 * self.foot_length_m

    @property
    def inertia_kgm2(self) -> float:
        """Moment of inertia about the moving joint of everything that turns with the arm."""
        if self.joint == "knee":
            i_shank = self.shank_mass_kg * (0.302 * self.shank_length_m) ** 2 + self.shank_mass_kg * self.shank_com_m**2
            i_foot = self.foot_mass_kg * self.shank_length_m**2
            return i_shank + i_foot + self.arm_mass_kg * self.arm_com_m**2
        return (self.foot_mass_kg * (0.475 * self.foot_length_m) ** 2 + self.foot_mass_kg * self.foot_com_m**2
                + self.arm_mass_kg * self.arm_com_m**2)

    def passive_moment_nm(self, position_deg: np.ndarray) -> np.ndarray:
        """Elastic joint moment toward positive angles (N·m)."""
        if self.passive_table_deg:
            return np.interp(np.asarray(position_deg, dtype=float), self.passive_table_deg, self.passive_table_nm)
        return riener_passive_moment_nm(self, position_deg)

    def gravity_moment_nm(self, position_deg: np.ndarray, include_arm: bool = True) -> np.ndarray:
        """Gravity moment toward positive angles (N·m) of the distal segments (and the arm)."""
        th = np.deg2rad(np.asarray(position_deg, dtype=float))
        if self.joint == "knee":
            # shank horizontal at 0° flexion, hanging at 90°: gravity pulls toward flexion
            limb = ((self.shank_mass_kg * self.shank_com_m + self.foot_mass_kg * self.shank_length_m)
                    * self.gravity_m_s2 * np.cos(th))
            arm = self.arm_mass_kg * self.arm_com_m * self.gravity_m_s2 * np.cos(th)
        else:
            # foot elevation above horizontal = dorsiflexion + 90° − knee flexion; gravity plantarflexes
            elev = th + np.deg2rad(90.0 - self.knee_flexion_deg)
            limb = -self.foot_mass_kg * self.foot_com_m * self.gravity_m_s2 * np.cos(elev)
            arm = -self.arm_mass_kg * self.arm_com_m * self.gravity_m_s2 * np.cos(elev)
        return limb + (arm if include_arm else 0.0)

    def shaft_torque_nm(self, t_s: np.ndarray, position_deg: np.ndarray, velocity_deg_s: np.ndarray,
                        acceleration_deg_s2: np.ndarray) -> np.ndarray:
        """Torque the dynamometer applies toward positive angles (N·m); see the module docstring."""
        vel = np.deg2rad(np.asarray(velocity_deg_s, dtype=float))
        acc = np.deg2rad(np.asarray(acceleration_deg_s2, dtype=float))
        tau = (self.inertia_kgm2 * acc + self.damping_nm_s_per_rad * vel
               - self.passive_moment_nm(position_deg) - self.gravity_moment_nm(position_deg))
        for b in self.bursts:
            direction = np.where(vel < 0, -1.0, 1.0)
            tau = tau + direction * b.torque(t_s)
        return tau
