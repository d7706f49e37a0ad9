"""AFO torque from the plate wrench and the jig's motion: static optimisation and bottom-up inverse dynamics.

The jig model has 7 degrees of freedom: the foot free in space (6) and the shank on the hinge
(1). The static optimisation (dissertation ch. 2) drives it with 7 actuators — a force
``F_op`` (3) and a moment ``M_op`` (3) at the pylon top, where the operator's hand is, and a
torque ``τ`` on the hinge coordinate (the AFO torque, positive resisting dorsiflexion; it acts as
``−τ ê`` on the shank and ``+τ ê`` on the foot). Its equations of motion, in Kane's form
(Newton–Euler projected on the 7 partial velocities), are linear in the actuator loads:

- whole jig, forces:       ``F_op = Σ m (a − g) − F_plate``
- whole jig, moments at O: ``[P]× F_op + M_op = Σ (r × m (a − g) + Ḣ) − M_plate,O``
- shank about the hinge:   ``ê·((P − A) × F_op + M_op) − τ = ê·((c_s − A) × m_s (a_s − g) + Ḣ_s)``

so each frame is ``K u = b`` with ``u = (F_op, M_op, τ)``. The static optimisation minimises
``Σ (u_i / u_opt,i)²`` subject to it; every frame is solved at once (batched linear algebra),
as the weighted minimum-norm solution ``u = D (K D)⁺ b``, ``D = diag(u_opt)``. With this model
``K`` is square and non-singular, so the minimum is the unique solution and the weights only
matter for models with more actuators than degrees of freedom.

The bottom-up path is the foot's own free body about the hinge axis,
``τ = ê·((c_f − A) × m_f (a_f − g) + Ḣ_f − M_plate,A)``, which uses neither the shank nor the
operator. Both paths are algebraically equal when the whole-jig equations hold, which the free
operator wrench guarantees; their agreement checks the assembly of the equations, and their
difference is reported with every analysis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import GRAVITY_M_S2
from ..errors import InputError
from ..filtering import lowpass
from ..motion import MotionTrial
from .kinematics import AadsKinematics, SegmentMotion
from .model import JigModel

G_M_S2 = np.array([0.0, 0.0, -GRAVITY_M_S2])


def _skew(v: np.ndarray) -> np.ndarray:
    z = np.zeros(v.shape[0])
    return np.stack([np.stack([z, -v[:, 2], v[:, 1]], -1), np.stack([v[:, 2], z, -v[:, 0]], -1),
                     np.stack([-v[:, 1], v[:, 0], z], -1)], -2)


@dataclass
class PlateAtMarkers:
    """Plate wrench on the jig at the marker frames, filtered like the markers (SI, lab frame)."""

    force_n: np.ndarray    # (n, 3)
    moment_nm: np.ndarray  # (n, 3) about the lab origin
    valid: np.ndarray      # (n,)


def plate_at_markers(trial: MotionTrial, time_s: np.ndarray, cutoff_hz: float) -> PlateAtMarkers:
    """Low-pass the plate force and moment (about the lab origin) and interpolate them at ``time_s``.

    :raises InputError: the trial has no force-plate samples.
    """
    if trial.plate_time_s.size < 20 or not np.isfinite(trial.force_n).any():
        raise InputError(f"{trial.source or 'trial'}: no force-plate data; the AADS analysis needs the plate wrench")
    tp = np.asarray(trial.plate_time_s, dtype=float)
    rate = 1.0 / float(np.median(np.diff(tp)))
    f = np.asarray(trial.force_n, dtype=float)
    cop = np.asarray(trial.cop_m, dtype=float)
    m = np.cross(cop, f)
    m[:, 2] += np.asarray(trial.free_moment_nm, dtype=float)
    wrench = np.hstack([f, m])
    # a frame without a centre of pressure carries no moment information: leave it out, do not zero it
    wrench[~np.all(np.isfinite(np.hstack([f, cop])), axis=1)] = np.nan
    smooth = lowpass(wrench, rate, cutoff_hz)
    ok = np.all(np.isfinite(smooth), axis=1)
    out = np.full((time_s.size, 6), np.nan)
    if ok.sum() >= 2:
        idx = np.searchsorted(tp, time_s)
        inside = (time_s >= tp[0]) & (time_s <= tp[-1])
        lo = np.clip(idx - 1, 0, tp.size - 1)
        hi = np.clip(idx, 0, tp.size - 1)
        near_ok = ok[lo] & ok[hi] & inside
        for j in range(6):
            out[:, j] = np.interp(time_s, tp[ok], smooth[ok, j])
        out[~near_ok] = np.nan
    valid = np.all(np.isfinite(out), axis=1)
    return PlateAtMarkers(out[:, :3], out[:, 3:], valid)


def _inertial(seg: SegmentMotion, inertia_local: np.ndarray) -> np.ndarray:
    """Ḣ about the segment's COM in the lab frame: I α + ω × I ω (n, 3), N·m."""
    r = seg.rotation
    i_lab = np.matmul(np.matmul(r, inertia_local), r.transpose(0, 2, 1))
    iw = np.matmul(i_lab, seg.omega_rad_s[:, :, None])[:, :, 0]
    return np.matmul(i_lab, seg.alpha_rad_s2[:, :, None])[:, :, 0] + np.cross(seg.omega_rad_s, iw)


@dataclass
class JigEquations:
    """The per-frame linear system ``K u = b`` of the static optimisation and the terms of the foot free body."""

    matrix: np.ndarray        # (n, 7, 7)
    rhs: np.ndarray           # (n, 7)
    foot_torque_nm: np.ndarray  # (n,) bottom-up AFO torque
    valid: np.ndarray         # (n,)


def jig_equations(kin: AadsKinematics, plate: PlateAtMarkers, model: JigModel) -> JigEquations:
    """Assemble the equations of motion of every frame (vectorised)."""
    foot, shank = kin.foot, kin.shank
    m_f, m_s = model.foot.mass_kg, model.shank.mass_kg
    axis = foot.rotation @ model.hinge_axis_in_foot
    hinge = foot.point_m(model.hinge_in_foot_m)
    top = shank.point_m(model.pylon_top_in_shank_m)
    load_f = m_f * (foot.com_acc_m_s2 - G_M_S2)   # m (a − g): what the forces on the segment must supply
    load_s = m_s * (shank.com_acc_m_s2 - G_M_S2)
    hdot_f = _inertial(foot, model.foot.inertia_kgm2)
    hdot_s = _inertial(shank, model.shank.inertia_kgm2)
    n = kin.time_s.size
    k = np.zeros((n, 7, 7))
    b = np.zeros((n, 7))
    eye = np.eye(3)
    k[:, 0:3, 0:3] = eye
    b[:, 0:3] = load_f + load_s - plate.force_n
    k[:, 3:6, 0:3] = _skew(top)
    k[:, 3:6, 3:6] = eye
    b[:, 3:6] = (np.cross(foot.com_m, load_f) + hdot_f + np.cross(shank.com_m, load_s) + hdot_s - plate.moment_nm)
    k[:, 6, 0:3] = np.cross(top - hinge, axis)  # ê·((P − A) × F) = ((P − A) × ê)·F... sign below
    k[:, 6, 0:3] *= -1.0                          # ê·(r × F) = (ê × r)·F = −(r × ê)·F
    k[:, 6, 3:6] = axis
    k[:, 6, 6] = -1.0
    b[:, 6] = np.einsum("ni,ni->n", axis, np.cross(shank.com_m - hinge, load_s) + hdot_s)
    m_plate_a = plate.moment_nm - np.cross(hinge, plate.force_n)
    foot_tau = np.einsum("ni,ni->n", axis, np.cross(foot.com_m - hinge, load_f) + hdot_f - m_plate_a)
    valid = kin.valid & plate.valid & np.all(np.isfinite(b), axis=1) & np.all(np.isfinite(k), axis=(1, 2))
    k[~valid] = np.eye(7)
    b[~valid] = 0.0
    return JigEquations(k, b, np.where(valid, foot_tau, np.nan), valid)


@dataclass
class SopResult:
    """Static-optimisation loads per frame (SI): operator force and moment at the pylon top, AFO torque."""

    operator_force_n: np.ndarray   # (n, 3)
    operator_moment_nm: np.ndarray  # (n, 3)
    afo_torque_nm: np.ndarray      # (n,)
    bottom_up_torque_nm: np.ndarray  # (n,)
    constraint_residual: np.ndarray  # (n,) max |K u − b| (N or N·m)
    valid: np.ndarray


def solve_min_norm(matrix: np.ndarray, rhs: np.ndarray, optimal: np.ndarray) -> np.ndarray:
    """Per frame, the ``u`` minimising ``Σ (u_i / optimal_i)²`` subject to ``K u = b`` (all frames at once)."""
    kd = matrix * optimal[None, None, :]
    if kd.shape[1] == kd.shape[2]:
        try:
            return np.linalg.solve(kd, rhs[..., None])[..., 0] * optimal[None, :]
        except np.linalg.LinAlgError:
            pass  # a singular frame: fall back to the pseudo-inverse for all
    return np.einsum("nij,nj->ni", np.linalg.pinv(kd), rhs) * optimal[None, :]


def static_optimisation(eq: JigEquations, model: JigModel) -> SopResult:
    """Solve the static optimisation of every frame."""
    u = solve_min_norm(eq.matrix, eq.rhs, model.optimal_forces())
    resid = np.max(np.abs(np.einsum("nij,nj->ni", eq.matrix, u) - eq.rhs), axis=1)
    u[~eq.valid] = np.nan
    return SopResult(u[:, 0:3], u[:, 3:6], u[:, 6], eq.foot_torque_nm, np.where(eq.valid, resid, np.nan), eq.valid)


def static_optimisation_per_frame(eq: JigEquations, model: JigModel, frames: np.ndarray | None = None) -> np.ndarray:
    """Reference: one SLSQP call per frame, as OpenSim's static-optimisation tool works (returns u, (n, 7)).

    Used by the benchmark and tests to check the batched solution; far slower by design.
    """
    from scipy.optimize import minimize

    opt = model.optimal_forces()
    idx = np.flatnonzero(eq.valid) if frames is None else np.asarray(frames)
    out = np.full((eq.rhs.shape[0], 7), np.nan)
    for i in idx:
        kd = eq.matrix[i] * opt[None, :]
        bi = eq.rhs[i]
        res = minimize(lambda a: float(a @ a), np.zeros(7), jac=lambda a: 2.0 * a, method="SLSQP",
                       constraints=[{"type": "eq", "fun": lambda a, kd=kd, bi=bi: kd @ a - bi,
                                     "jac": lambda a, kd=kd: kd}],
                       options={"ftol": 1e-14, "maxiter": 200})
        out[i] = res.x * opt
    return out
