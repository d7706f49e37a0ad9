"""Forward-dynamics verification of a fitted passive model (Table 3.3): drive it with the measured torque.

The joint's equation of motion, I q̈ = u_m(t) + M_muscles(q) + M_gravity(q) − b q̇, is integrated
from the measured initial angle and velocity by a classical Runge–Kutta scheme built in CasADi
(the measured torque held linear between samples, :data:`SUBSTEPS` steps per sample, the whole
trial one ``mapaccum`` call: no Python in the loop). ``b`` (0.5 N·m·s/rad, a relaxed
joint's viscous damping) only damps the oscillation an undamped stiff spring would keep; at
5 °/s it moves the torque by 0.04 N·m. The muscle moment is a CasADi function of the angle, with
the calf fibre–tendon equilibrium solved by Newton's method inside it. Reported: the RMSE of the
simulated against the measured angle (°), and of the model's torque at the measured angles
against the measured torque, per body mass (N·m/kg), as the dissertation's Table 3.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .estimator import PmpTrial, Subject, moment_function
from .muscles import LegMuscles
from .workers import mapped

DAMPING_NM_S_PER_RAD = 0.5
#: Runge–Kutta steps per measured sample (a 100 Hz trial: 2.5 ms steps)
SUBSTEPS = 4
#: the muscles' moment is tabulated once over the measured angles ± TABLE_MARGIN_RAD at TABLE_STEP_RAD and
#: interpolated by a cubic B-spline inside the integrator and for the holding torque: one equilibrium solve per table
#: point instead of one per Runge–Kutta stage (16 per sample) or per sample. On an exponential moment
#: M(q) = 50 N·m·e^{10 (q − q_top)} over 60° the 0.25° B-spline is off by at most 4.9e-6 N·m (1e-7 M, at the table's
#: ends; linear interpolation at 0.05° is off by k² M h² / 8 ≈ 1e-5 M). Measured against the moment function itself at
#: every stage and sample, on two OpenSim-made subjects' six sweeps with their extensions (compliant knee tendons with
#: tone; end-range structures): simulated angles within 1.4e-4°, holding torques within 7.7e-5 N·m; forward dynamics
#: 8.2 → 1.4 s and 7.6 → 2.0 s (measured beside a running test suite)
TABLE_STEP_RAD = np.deg2rad(0.25)
TABLE_INTERPOLATION = "bspline"
TABLE_MARGIN_RAD = np.deg2rad(10.0)


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
                     leg: LegMuscles | None = None, extension: Any = None,
                     extension_parameters: dict[str, float] | None = None) -> Verification:
    """Simulate ``trial`` with ``parameters`` driven by its measured torque; with ``extension`` (a
    model-level extension's moment term, :class:`analysis.pmp.model_diagnosis.Extension`) and its fitted
    ``extension_parameters`` in the dynamics too (an extension that maps the joint's angle is not
    simulated: its muscles act at the arm's angle)."""
    import casadi as ca

    values = [float((extension_parameters or {})[n]) for n in extension.parameters] if extension is not None else []
    options = extension.muscle_options(trial, values) if extension is not None else {}
    f = moment_function(leg or LegMuscles(), trial, parameters, **options)
    inertia = subject.inertia_kgm2(trial.joint)
    lo, hi = float(np.min(trial.angle_rad)) - TABLE_MARGIN_RAD, float(np.max(trial.angle_rad)) + TABLE_MARGIN_RAD
    grid = np.linspace(lo, hi, int(np.ceil((hi - lo) / TABLE_STEP_RAD)) + 1)
    table = np.asarray(mapped(f, grid.size)(grid.reshape(1, -1))).ravel()
    # the table where the equilibrium has a solution over all of it (else the moment function itself, in SX);
    # beyond the table the simulated leg is ≥ 10° from every measured angle, its RMSE shows that
    tabulated = bool(np.all(np.isfinite(table)))
    sym: Any = ca.MX.sym if tabulated else ca.SX.sym
    muscles = ca.interpolant("muscles", TABLE_INTERPOLATION, [grid.tolist()], table.tolist()) if tabulated else f
    symbols: list[Any] = [sym(n) for n in ("q", "v", "u0", "u1", "dt", "s")]
    q, v, u0, u1, dt, s = symbols

    def total_moment(muscles_of: Any, q: Any, v: Any) -> Any:
        """Muscles, gravity and the extension's term (N·m toward positive angle)."""
        gravity = subject.gravity_moment_nm(trial.joint, q, trial.fixed_rad, ca.cos)
        return muscles_of(q) + gravity + (extension.moment(trial, q, v, values, gravity) if extension is not None else 0)

    moment = total_moment(muscles, q, v)
    accel = ca.Function("a", [q, v, u0, u1, s], [(u0 + (u1 - u0) * s + moment - DAMPING_NM_S_PER_RAD * v) / inertia])
    x = ca.vertcat(q, v)
    h = dt / SUBSTEPS
    state = x
    for k in range(SUBSTEPS):  # RK4 on [q, v], the torque linear in the sample interval
        s0, s1 = k / SUBSTEPS, (k + 0.5) / SUBSTEPS
        s2 = (k + 1) / SUBSTEPS

        def deriv(z: Any, frac: float) -> Any:
            return ca.vertcat(z[1], accel(z[0], z[1], u0, u1, frac))

        k1 = deriv(state, s0)
        k2 = deriv(state + h / 2 * k1, s1)
        k3 = deriv(state + h / 2 * k2, s1)
        k4 = deriv(state + h * k3, s2)
        state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    step = ca.Function("step", [x, ca.vertcat(u0, u1, dt)], [state])
    n = trial.time_s.size
    inputs = np.vstack([trial.torque_nm[:-1], trial.torque_nm[1:], np.diff(trial.time_s)])
    try:
        path = step.mapaccum(n - 1)(ca.DM([trial.angle_rad[0], trial.velocity_rad_s[0]]), inputs)
        q_sim = np.concatenate([[trial.angle_rad[0]], np.asarray(path)[0]])
    except RuntimeError:  # the simulated leg left the range where the calf equilibrium has a solution
        q_sim = np.full(n, np.nan)
    if not np.all(np.isfinite(q_sim)):
        q_sim = np.full(n, np.nan)
    # the torque holding the measured angles at the measured speeds, the muscles' part from the table (within its
    # interpolation error of the moment function; the function itself where there is no table)
    q_s, v_s = sym("q"), sym("v")
    holding = mapped(ca.Function("u", [q_s, v_s], [-total_moment(muscles, q_s, v_s)]), n)
    model_u = np.asarray(holding(trial.angle_rad.reshape(1, -1), trial.velocity_rad_s.reshape(1, -1))).ravel()
    return Verification(trial.name, trial.time_s, q_sim, model_u,
                        float(np.rad2deg(np.sqrt(np.mean((q_sim - trial.angle_rad) ** 2)))),
                        float(np.sqrt(np.mean((model_u - trial.torque_nm) ** 2)) / subject.mass_kg))


__all__ = ["forward_dynamics", "Verification", "DAMPING_NM_S_PER_RAD"]
