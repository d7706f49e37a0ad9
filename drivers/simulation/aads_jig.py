"""Physics of the AADS test: an operator bends a hinged AFO on a force plate.

Lab frame = force plate frame: x anterior (toward the toes), y left, z up, origin at the centre
of the plate's top surface. The AFO foot is strapped to the plate; the shank (with its pylon)
turns about the hinge axis (the y axis through the ankle point A). Dorsiflexion θ is positive
(shank top moving toward +x), i.e. a positive rotation about +y.

Torque path (all about the hinge, N·m, positive resisting dorsiflexion):
- spring: a linear spring (stiffness k N/m) between a hook on the shank strut (T) and one on
  the foot strut (B), slack below its rest length (equal to its length at ``spring_engage_deg``);
  its torque is F·|AD| (dissertation eqs 2.1–2.8);
- hinge friction: (c + μ·|τ_spring|)·tanh(ω/ω_s), opposing motion;
- hinge stop: ``stop_stiffness`` past ``stop_deg`` (21°);
- shell compliance: the shell/pylon bends in series, so the shank markers and the pylon turn by
  θ_m = θ_h + τ/k_shell while the spring hooks follow the hinge angle θ_h.

The operator supplies whatever wrench the prescribed bend needs, plus arbitrary off-axis force
and moment components the hinge carries to the plate. The plate then measures the ground
reaction wrench from the whole jig's Newton–Euler balance: F = Σ m·a − F_op − Σ m·g, and the
matching moments about the plate's calibration origin.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .world import GRAVITY_M_S2


def _rot_y(theta: np.ndarray) -> np.ndarray:
    """Rotation matrices about +y for angles ``theta`` (rad), shape (n, 3, 3)."""
    c, s = np.cos(theta), np.sin(theta)
    z, o = np.zeros_like(theta), np.ones_like(theta)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


@dataclass
class JigGeometry:
    """The dissertation's jig and AFO (metres, kilograms; points relative to the hinge point A)."""

    ankle_m: tuple[float, float, float] = (0.0, 0.0, 0.09)
    foot_mass_kg: float = 0.65
    foot_com_m: tuple[float, float, float] = (0.05, 0.0, -0.04)
    shank_mass_kg: float = 1.7
    shank_com_m: tuple[float, float, float] = (0.0, 0.0, 0.20)
    shank_inertia_kgm2: float = 0.035  # about the COM, about y
    pylon_top_m: tuple[float, float, float] = (0.0, 0.0, 0.45)
    spring_top_m: tuple[float, float, float] = (-0.070, 0.0, 0.10)   # hook on the shank strut (T)
    spring_bottom_m: tuple[float, float, float] = (-0.075, 0.0, -0.045)  # hook on the foot strut (B)
    spring_engage_deg: float = 5.0
    stop_deg: float = 21.0
    #: marker set, segment coordinates relative to A (shank markers at θ = 0)
    foot_markers: dict[str, tuple[float, float, float]] = field(default_factory=lambda: {
        "RTOE1": (0.16, 0.03, -0.075), "RTOE5": (0.13, -0.04, -0.075),
        "RMCUN": (0.08, 0.0, -0.035), "RHEE": (-0.075, 0.0, -0.06)})
    shank_markers: dict[str, tuple[float, float, float]] = field(default_factory=lambda: {
        "RMMAL": (0.0, 0.035, 0.0), "RLMAL": (0.0, -0.035, 0.0),
        "RATIB": (0.045, 0.0, 0.22), "RPTIB": (-0.05, 0.0, 0.26)})


@dataclass
class AfoProperties:
    """The AFO under test: spring and the imperfections the dissertation blamed for its errors."""

    spring_n_per_m: float = 15600.0
    hinge_friction_nm: float = 0.15
    hinge_friction_coeff: float = 0.08       # μ: friction torque per N·m of spring torque
    shell_stiffness_nm_per_deg: float = 10.0  # a very large value (1e9) switches compliance off
    stop_stiffness_nm_per_deg: float = 3.0
    friction_velocity_rad_s: float = 0.02
    #: where this AFO's hinge stop engages (°); ``None``: the jig's (21°). A misadjusted stop engages early
    stop_deg: float | None = None


@dataclass
class OperatorStyle:
    """How one operator bends: peak hinge angle range, cycle time and off-axis sloppiness."""

    peak_deg: tuple[float, float] = (19.0, 23.0)
    cycle_s: tuple[float, float] = (1.6, 2.4)
    lateral_force_n: float = 4.0
    axial_force_n: float = 15.0
    free_moment_nm: float = 0.4


#: the four operators of the simulated experiment (operators 1 and 2 pass the 21° stop)
OPERATORS: dict[int, OperatorStyle] = {
    1: OperatorStyle(peak_deg=(22.0, 26.0), cycle_s=(1.4, 2.0)),
    2: OperatorStyle(peak_deg=(21.5, 24.0), cycle_s=(2.0, 3.0)),
    3: OperatorStyle(peak_deg=(17.0, 20.0), cycle_s=(1.8, 2.6), lateral_force_n=2.0),
    4: OperatorStyle(peak_deg=(19.0, 21.5), cycle_s=(2.5, 3.5), axial_force_n=25.0),
}


@dataclass
class BendProfile:
    """Hinge-angle profile of one trial: cycles of push-down and return from the neutral angle."""

    time_s: np.ndarray
    hinge_rad: np.ndarray
    duration_s: float

    @classmethod
    def random(cls, style: OperatorStyle, rng: np.random.Generator, cycles: int = 3,
               neutral_deg: float = 5.0, rest_s: float = 0.6, rate_hz: float = 1000.0) -> BendProfile:
        """Raised-cosine bends with per-cycle peak and duration drawn from ``style``."""
        segments = [np.full(int(rest_s * rate_hz), 0.0)]
        for _ in range(cycles):
            peak = rng.uniform(*style.peak_deg) - neutral_deg
            dur = rng.uniform(*style.cycle_s)
            skew = rng.uniform(0.35, 0.6)  # fraction of the cycle spent loading
            n = int(dur * rate_hz)
            u = np.linspace(0.0, 1.0, n, endpoint=False)
            phase = np.where(u < skew, u / skew * 0.5, 0.5 + (u - skew) / (1 - skew) * 0.5)
            segments.append(peak * 0.5 * (1 - np.cos(2 * np.pi * phase)))
            segments.append(np.full(int(rng.uniform(0.2, 0.5) * rate_hz), 0.0))
        deg = neutral_deg + np.concatenate(segments)
        t = np.arange(deg.size) / rate_hz
        return cls(time_s=t, hinge_rad=np.deg2rad(deg), duration_s=deg.size / rate_hz)

    def at(self, t_s: np.ndarray) -> np.ndarray:
        """Hinge angle (rad) at times ``t_s``, repeating the trial."""
        return np.interp(np.mod(t_s, self.duration_s), self.time_s, self.hinge_rad)


@dataclass
class JigState:
    """Everything the jig does at a set of instants (SI units)."""

    time_s: np.ndarray
    hinge_rad: np.ndarray
    shank_rad: np.ndarray
    afo_torque_nm: np.ndarray
    spring_torque_nm: np.ndarray
    force_n: np.ndarray  # (n, 3) ground reaction force on the jig
    moment_nm: np.ndarray  # (n, 3) about the plate calibration origin
    operator_force_n: np.ndarray
    markers_m: dict[str, np.ndarray]  # name -> (n, 3)


class AadsJig:
    """The jig, the AFO and an operator, evaluated at arbitrary times (vectorised).

    :param plate_origin_m: plate calibration origin relative to the surface centre (m).
    """

    def __init__(self, afo: AfoProperties | None = None, operator: int | OperatorStyle = 1,
                 geometry: JigGeometry | None = None, seed: int = 0,
                 plate_origin_m: tuple[float, float, float] = (0.0, 0.0, -0.040),
                 gravity_m_s2: float = GRAVITY_M_S2) -> None:
        self.afo = afo or AfoProperties()
        self.gravity_m_s2 = gravity_m_s2
        self.geometry = geometry or JigGeometry()
        self.style = OPERATORS[operator] if isinstance(operator, int) else operator
        self.rng = np.random.default_rng(seed)
        self.profile = BendProfile.random(self.style, self.rng)
        self.plate_origin_m = np.asarray(plate_origin_m, dtype=float)
        g = self.geometry
        self._A = np.asarray(g.ankle_m)
        self._T0 = np.asarray(g.spring_top_m)
        self._B = np.asarray(g.spring_bottom_m)
        self.spring_rest_m = float(np.linalg.norm(_rot_y(np.array([np.deg2rad(g.spring_engage_deg)]))[0] @ self._T0 - self._B))
        # slow random off-axis operator loads (smooth: sums of a few sinusoids)
        self._off_freq = self.rng.uniform(0.2, 1.2, (7, 3))
        self._off_phase = self.rng.uniform(0, 2 * np.pi, (7, 3))

    # -- spring geometry (eqs 2.1-2.8)
    def spring(self, hinge_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Spring length (m), force (N) and moment arm |AD| (m) at hinge angles (rad)."""
        hook_top = np.einsum("nij,j->ni", _rot_y(hinge_rad), self._T0)
        bt = hook_top - self._B
        length = np.linalg.norm(bt, axis=1)
        # eq 2.7 with A at the origin of these coordinates: q = BT·(A−B) / |BT|²
        q = np.einsum("ni,ni->n", bt, -self._B[None, :]) / length**2
        ad = self._B[None, :] + q[:, None] * bt
        arm = np.linalg.norm(ad, axis=1)
        force = self.afo.spring_n_per_m * np.maximum(length - self.spring_rest_m, 0.0)
        return length, force, arm

    def afo_torque(self, hinge_rad: np.ndarray, hinge_rate_rad_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(total hinge torque, spring torque) in N·m resisting dorsiflexion."""
        a = self.afo
        _, force, arm = self.spring(hinge_rad)
        spring_torque = force * arm
        friction = (a.hinge_friction_nm + a.hinge_friction_coeff * spring_torque) * np.tanh(
            hinge_rate_rad_s / a.friction_velocity_rad_s)
        stop_deg = a.stop_deg if a.stop_deg is not None else self.geometry.stop_deg
        over = np.maximum(np.rad2deg(hinge_rad) - stop_deg, 0.0)
        stop = a.stop_stiffness_nm_per_deg * over
        return spring_torque + friction + stop, spring_torque

    def state(self, t_s: np.ndarray) -> JigState:
        """Kinematics, AFO torque, operator load and plate wrench at times ``t_s`` (s)."""
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        g = self.geometry
        dt = 1e-3
        th = self.profile.at(t)
        th_d = (self.profile.at(t + dt) - self.profile.at(t - dt)) / (2 * dt)
        tau, spring_tau = self.afo_torque(th, th_d)
        k_shell = np.rad2deg(self.afo.shell_stiffness_nm_per_deg)  # N·m/rad

        def shank_angle(tt: np.ndarray) -> np.ndarray:
            h = self.profile.at(tt)
            hd = (self.profile.at(tt + dt) - self.profile.at(tt - dt)) / (2 * dt)
            return h + self.afo_torque(h, hd)[0] / k_shell

        phi = th + tau / k_shell
        phi_dd = (shank_angle(t + dt) - 2 * phi + shank_angle(t - dt)) / dt**2
        rot = _rot_y(phi)
        A = self._A
        com_s = np.einsum("nij,j->ni", rot, np.asarray(g.shank_com_m))
        # COM acceleration of the shank (rotation about the fixed hinge): a = α × r − ω² r
        phi_d = (shank_angle(t + dt) - shank_angle(t - dt)) / (2 * dt)
        e_y = np.array([0.0, 1.0, 0.0])
        acc_s = np.cross(phi_dd[:, None] * e_y, com_s) - (phi_d**2)[:, None] * com_s
        m_s, m_f = g.shank_mass_kg, g.foot_mass_kg
        # operator: off-axis components, then the perpendicular force that closes the hinge balance
        wave = np.sin(2 * np.pi * self._off_freq[None] * t[:, None, None] + self._off_phase[None]).mean(1)
        s = self.style
        top = np.einsum("nij,j->ni", rot, np.asarray(g.pylon_top_m))
        lp = float(np.linalg.norm(g.pylon_top_m))
        e_axis = top / lp
        e_perp = np.einsum("nij,j->ni", rot, np.array([1.0, 0.0, 0.0]))
        m_op = np.column_stack([s.free_moment_nm * wave[:, 0], np.zeros_like(t), s.free_moment_nm * wave[:, 2]])
        f_axial = -s.axial_force_n * (0.5 + 0.5 * wave[:, 1])[:, None] * e_axis
        f_lat = (s.lateral_force_n * wave[:, 2])[:, None] * e_y
        # hinge (about +y, through A): I_A·α = τ_op + τ_gravity − τ_afo
        i_a = g.shank_inertia_kgm2 + m_s * float(np.dot(g.shank_com_m, g.shank_com_m))
        gravity = np.array([0.0, 0.0, -self.gravity_m_s2])  # m/s²
        tau_grav = np.cross(com_s, m_s * gravity)[:, 1]
        tau_op = i_a * phi_dd - tau_grav + tau
        f_perp = (tau_op / lp)[:, None] * e_perp
        f_op = f_perp + f_axial + f_lat
        # whole-jig balance: F_plate + F_op + Σ m g = Σ m a (foot is still)
        force = m_s * acc_s - f_op - (m_s + m_f) * gravity
        plate_origin = self.plate_origin_m
        r_s = A + com_s - plate_origin
        r_f = A + np.asarray(g.foot_com_m) - plate_origin
        r_p = A + top - plate_origin
        d_momentum = np.cross(r_s, m_s * acc_s) + (g.shank_inertia_kgm2 * phi_dd)[:, None] * e_y
        moment = d_momentum - (np.cross(r_p, f_op) + m_op) - np.cross(r_s, m_s * gravity) - np.cross(r_f, m_f * gravity)[None, :]
        markers = {name: np.broadcast_to(A + np.asarray(p), (t.size, 3)).copy() for name, p in g.foot_markers.items()}
        for name, p in g.shank_markers.items():
            markers[name] = A + np.einsum("nij,j->ni", rot, np.asarray(p))
        markers["SPRING_TOP"] = A + np.einsum("nij,j->ni", _rot_y(th), self._T0)
        markers["SPRING_BOTTOM"] = np.broadcast_to(A + self._B, (t.size, 3)).copy()
        return JigState(t, th, phi, tau, spring_tau, force, moment, f_op, markers)

    def theoretical_stiffness_nm_per_deg(self, lo_deg: float = 6.0, hi_deg: float = 20.0) -> float:
        """Slope of spring torque against hinge angle over the fit window (N·m/°), from the geometry."""
        deg = np.linspace(lo_deg, hi_deg, 200)
        _, force, arm = self.spring(np.deg2rad(deg))
        return float(np.polyfit(deg, force * arm, 1)[0])
