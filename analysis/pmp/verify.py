"""Forward-dynamics verification of a fitted passive model (Table 3.3): drive it with the measured torque.

The joint's equation of motion, I q̈ = u_m(t) + M_muscles(q) + M_gravity(q) − b q̇, is integrated
with scipy's Radau from the measured initial angle and velocity. ``b`` (0.5 N·m·s/rad, a relaxed
joint's viscous damping) only damps the oscillation an undamped stiff spring would keep; at
5 °/s it moves the torque by 0.04 N·m. The muscle moment is a CasADi function of the angle, with
the calf fibre–tendon equilibrium solved by Newton's method inside it. Reported: the RMSE of the
simulated against the measured angle (°), and of the model's torque at the measured angles
against the measured torque, per body mass (N·m/kg), as the dissertation's Table 3.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .estimator import PmpTrial, Subject, moment_function
from .muscles import LegMuscles

DAMPING_NM_S_PER_RAD = 0.5


@dataclass
class Verification:
    """Forward simulation of one trial."""

    name: str
    time_s: np.ndarray
    simulated_angle_rad: np.ndarray
    model_torque_nm: np.ndarray
    angle_rmse_deg: float
    torque_rmse_nm_per_kg: float


def forward_dynamics(trial: PmpTrial, subject: Subject, parameters: dict[str, float], *,
                     leg: LegMuscles | None = None) -> Verification:
    """Simulate ``trial`` with ``parameters`` driven by its measured torque."""
    f = moment_function(leg or LegMuscles(), trial, parameters)
    inertia = subject.inertia_kgm2(trial.joint)

    def moment(q: float) -> float:
        return float(f(q)) + float(subject.gravity_moment_nm(trial.joint, q, trial.fixed_rad))

    def rhs(t: float, x: np.ndarray) -> list[float]:
        u = float(np.interp(t, trial.time_s, trial.torque_nm))
        return [x[1], (u + moment(x[0]) - DAMPING_NM_S_PER_RAD * x[1]) / inertia]

    sol = solve_ivp(rhs, (trial.time_s[0], trial.time_s[-1]), [trial.angle_rad[0], trial.velocity_rad_s[0]],
                    t_eval=trial.time_s, method="Radau", rtol=1e-6, atol=1e-8)
    q_sim = sol.y[0] if sol.success else np.full(trial.time_s.size, np.nan)
    model_u = np.array([-moment(q) for q in trial.angle_rad])  # the torque holding the measured angles
    return Verification(trial.name, trial.time_s, q_sim, model_u,
                        float(np.rad2deg(np.sqrt(np.mean((q_sim - trial.angle_rad) ** 2)))),
                        float(np.sqrt(np.mean((model_u - trial.torque_nm) ** 2)) / subject.mass_kg))


__all__ = ["forward_dynamics", "Verification", "DAMPING_NM_S_PER_RAD"]
