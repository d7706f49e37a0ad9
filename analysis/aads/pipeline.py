"""One AADS trial from markers and plate to stiffness: kinematics → static optimisation → fits → theory.

``analyze_trial`` is the whole chapter-2 pipeline for one trial; it returns an ``AadsTrialResult``
whose ``flags`` say everything that limits the numbers (missing markers, unfit frames, a bend
that misses the window, frames past the stop). It raises only when nothing sensible can be
computed (no plate, too few markers, no frame posed).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError
from ..motion import MotionTrial
from .dynamics import SopResult, jig_equations, plate_at_markers, static_optimisation
from .kinematics import AadsKinematics, aads_kinematics
from .model import JigModel
from .stiffness import SpringTheory, StiffnessResult, line_fit, spring_torque, stiffness


@dataclass
class AadsTrialResult:
    """Everything the AADS analysis says about one trial (SI; angles in degrees, stiffness in N·m/°)."""

    source: str
    factors: dict[str, Any]          # spring, operator, trial (whatever is known)
    spring_n_per_m: float | None
    time_s: np.ndarray
    angle_deg: np.ndarray            # hinge angle from the segment markers (the IK angle)
    velocity_deg_s: np.ndarray
    afo_torque_nm: np.ndarray        # static optimisation
    bottom_up_torque_nm: np.ndarray  # foot free body
    sop: SopResult
    kinematics: AadsKinematics
    stiffness: StiffnessResult
    theory: SpringTheory | None
    flags: list[str] = field(default_factory=list)

    @property
    def stiffness_nm_per_deg(self) -> float:
        return self.stiffness.stiffness_nm_per_deg

    @property
    def theoretical_stiffness_nm_per_deg(self) -> float:
        return self.theory.stiffness_nm_per_deg if self.theory is not None else float("nan")

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary (no per-frame arrays)."""
        v = self.sop.valid
        with np.errstate(invalid="ignore"):
            diff = float(np.nanmax(np.abs(self.afo_torque_nm - self.bottom_up_torque_nm))) if v.any() else float("nan")
        q = self.kinematics.quality
        return {
            "source": self.source, **self.factors, "spring_n_per_m": self.spring_n_per_m,
            "frames": int(v.size), "frames_analysed": int(v.sum()),
            "stiffness_nm_per_deg": self.stiffness_nm_per_deg,
            "theoretical_stiffness_nm_per_deg": self.theoretical_stiffness_nm_per_deg,
            "sop": self.stiffness.as_dict(),
            "theory": None if self.theory is None else {
                "fit": self.theory.fit.as_dict() if self.theory.fit else None, "error": self.theory.error},
            "peak_torque_nm": float(np.nanmax(self.afo_torque_nm)) if v.any() else float("nan"),
            "sop_vs_bottom_up_max_nm": diff,
            "max_constraint_residual": float(np.nanmax(self.sop.constraint_residual)) if v.any() else float("nan"),
            "operator_force_max_n": float(np.nanmax(np.linalg.norm(self.sop.operator_force_n, axis=1))) if v.any()
            else float("nan"),
            "marker_rms_mm": q.rms_m * 1e3, "marker_max_mm": q.max_m * 1e3, "marker_fit_accepted": q.accepted,
            "hinge_gap_max_mm": float(np.nanmax(self.kinematics.hinge_gap_m)) * 1e3,
            "flags": self.flags,
        }


def hook_angle_deg(kin: AadsKinematics, model: JigModel, top_m: np.ndarray) -> np.ndarray:
    """Hinge angle (°) read from the shank-strut hook: the turn of A→T about the hinge axis in the foot frame.

    The hooks sit on the hinge struts next to the joint, so this angle follows the hinge itself
    and not the shell above it; both segment frames coincide at 0°, so the model's hook position
    in the shank frame is also its 0° position in the foot frame.
    """
    rel = top_m - kin.foot.origin_m
    v = np.einsum("nji,nj->ni", kin.foot.rotation, rel) - model.hinge_in_foot_m
    v0 = model.spring_top_in_shank_m - model.hinge_in_shank_m
    a = model.hinge_axis_in_foot
    v = v - np.outer(v @ a, a)
    v0 = v0 - (v0 @ a) * a
    return np.rad2deg(np.arctan2(np.cross(v0[None, :], v) @ a, v @ v0))


def spring_theory(kin: AadsKinematics, model: JigModel, stiffness_n_per_m: float) -> SpringTheory:
    """Eqs 2.1–2.9 from the hook markers; raises ``InputError`` if the file lacks them."""
    missing = [k for k in (model.spring_top_marker, model.spring_bottom_marker) if k not in kin.markers_m]
    if missing:
        raise InputError(f"no spring hook markers {missing}: the theoretical stiffness needs them")
    top, bottom = kin.markers_m[model.spring_top_marker], kin.markers_m[model.spring_bottom_marker]
    ankle = kin.foot.point_m(model.hinge_in_foot_m)
    length, ext, force, arm, torque = spring_torque(top, bottom, ankle, model.spring_rest_length_m, stiffness_n_per_m)
    angle = hook_angle_deg(kin, model, top)
    with np.errstate(invalid="ignore"):
        inside = (angle >= model.fit_window_deg[0]) & (angle <= model.fit_window_deg[1]) & np.isfinite(torque)
    try:
        fit, err = line_fit(angle[inside], torque[inside], model.fit_window_deg), ""
    except Exception as exc:  # FitError
        fit, err = None, str(exc)
    return SpringTheory(length, ext, force, arm, torque, angle, fit, err)


def analyze_trial(trial: MotionTrial, model: JigModel, *, spring_n_per_m: float | None = None,
                  factors: dict[str, Any] | None = None) -> AadsTrialResult:
    """Run the AADS pipeline on one trial.

    :param spring_n_per_m: the spring's stiffness (N/m) for the theoretical torque; ``None`` looks
        up ``factors['spring']`` in the model's springs, and without either the theory is skipped.
    :raises InputError: no plate data, a segment without 3 markers, or no frame that can be posed.
    """
    factors = dict(factors or {})
    if spring_n_per_m is None and factors.get("spring") is not None:
        spring_n_per_m = model.spring_n_per_m(factors["spring"])
    kin = aads_kinematics(trial, model)
    plate = plate_at_markers(trial, kin.time_s, model.filter_cutoff_hz)
    flags = list(kin.flags)
    # frames the plate's recording does not span (the two devices start and stop a few ms apart) are
    # not gaps: they are left out without a flag
    tp = np.asarray(trial.plate_time_s, dtype=float)
    spanned = (kin.time_s >= tp[0]) & (kin.time_s <= tp[-1]) if tp.size else np.zeros_like(kin.valid)
    lost = int(np.sum(kin.valid & ~plate.valid & spanned))
    if lost:
        flags.append(f"{lost} posed frames have no plate wrench (gaps or a centre of pressure missing); left out")
    eq = jig_equations(kin, plate, model)
    if not eq.valid.any():
        raise InputError(f"{trial.source or 'trial'}: no frame has both a pose and a plate wrench")
    sop = static_optimisation(eq, model)
    angle = np.where(sop.valid, kin.hinge_angle_deg, np.nan)
    velocity = np.where(sop.valid, kin.hinge_velocity_deg_s, np.nan)
    st = stiffness(angle, velocity, sop.afo_torque_nm, window_deg=model.fit_window_deg, stop_deg=model.stop_deg,
                   min_speed_deg_s=model.branch_min_speed_deg_s, reported_branch=model.reported_branch)
    flags += st.flags
    theory = None
    if spring_n_per_m is None:
        flags.append("spring stiffness unknown: no theoretical stiffness")
    else:
        try:
            theory = spring_theory(kin, model, spring_n_per_m)
            if theory.fit is None:
                flags.append(f"no theoretical stiffness: {theory.error}")
        except InputError as err:
            flags.append(str(err))
    return AadsTrialResult(trial.source, factors, spring_n_per_m, kin.time_s, angle, velocity, sop.afo_torque_nm,
                           sop.bottom_up_torque_nm, sop, kin, st, theory, flags)
