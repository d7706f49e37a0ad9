"""Model-level diagnosis of the passive-parameter fit: what the subject's musculoskeletal model gets wrong.

After a subject's fit, each candidate extension of the model is fitted *inside the estimator*
(its terms enter the collocation dynamics, its parameters are decision variables beside the
muscles') and judged by **held-out prediction across trials**: the model is fitted on all trials
but one condition and predicts the left-out condition's torque from its measured motion (inverse
dynamics, I·q̈ − M_muscles − M_gravity − M_extension); every condition is left out once. An
extension is named when it predicts every left-out fold better than the plain model and the
geometric mean of its per-fold RMSE ratios is below ``max_heldout_ratio``; the one with the lowest
wins. Every other candidate is then fitted beside the winner, and the pair is named when it predicts
every fold better than the winner alone by the same margin (compliant tendons *and* a tonic activation;
end-range structures *and* an offset); and so on, a third beside the pair, while one more does.
When the plain model's held-out error is many times its in-sample error the folds do not
predict each other (a left-out condition's muscles are extrapolated), and the report says so
instead of naming anything: the diagnosis then needs repeats. Its parameters get jackknife intervals over the
folds (the spread of the leave-one-out estimates, Student's t with k − 1 degrees of freedom), and the report says how far each
passive parameter moves when the extension is added.

Candidates (what the dissertation's discussion and the dynamometer literature name):

- ``viscous_damping``: −b·q̇ (tissue viscosity; b in N·m·s/rad);
- ``coulomb_friction``: −F·tanh(q̇ / 1°/s) (dynamometer or joint friction; F in N·m);
- ``limb_mass_error``: δ · M_gravity (the limb's weight off by the fraction δ);
- ``torque_offset``: a constant torque per joint (a dynamometer arm-weight compensation error or
  residual activation; N·m);
- ``axis_misalignment``: the joint turns by q + a·sin q + b·cos q when the arm turns by q, and
  the muscles' moment reaches the arm scaled by the derivative (virtual work), a and b per joint
  (≈ offset / lever; rad);
- ``end_range_structures``: joint-level exponential terms at the range's ends (capsule, ligaments,
  muscles the model lacks);
- ``tonic_activation``: a low activation per joint in every muscle crossing it (isometric active
  force–length, DeGroote et al. 2016);
- ``knee_tendon_compliance``: the knee muscles' tendons compliant (one ε_T0 for all of them), as the
  calf's are.

Sign convention as the estimator's: moments toward positive angle, q̇ in rad/s.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.stats import t as student_t

from ..trial_csv import NOMINAL_RANGE_DEG
from .geometry import MUSCLES
from .model import PmpTrial, Subject, eliminate_tendons, muscles_moment, with_set_angles
from .muscles import COMPLIANT, LegMuscles
from .problem import CollocationState, PmpResult, build_problem, estimate, solve
from .workers import mapped, workers

FRICTION_SPEED_RAD_S = math.radians(1.0)
#: when the plain model's held-out error is this many times its in-sample error, the folds do not
#: predict each other (a left-out condition's muscles are extrapolated) and nothing can be judged
INCONCLUSIVE_FACTOR = 5.0
#: a candidate predicting the folds within this ratio of the plain model's, but not better by the naming margin,
#: is "absorbed" when its parameters are material: the muscles' parameters took its place (they move)
ABSORBED_RATIO = 1.05
#: an extension's parameter counts as away from zero when its 95 % interval excludes zero *and* it is
#: at least this fraction of the parameter's typical size: a damping of 1e-7 N·m·s/rad with a tight
#: interval (an optimiser's leftover, 1e-8 N·m at 5°/s) is not a finding
MATERIAL_FRACTION = 0.01
#: what would separate an extension the muscles absorb from them (one-way sweeps at one speed make
#: damping and friction constant offsets, and a weight error a smooth function of angle)
PROTOCOL_TO_SEPARATE = {
    "viscous_damping": "damping needs a second sweep speed or a return sweep (it scales with speed, muscles do not)",
    "coulomb_friction": "friction needs a return sweep (it changes sign with direction, muscles do not)",
    "torque_offset": "an offset needs a return sweep or a hold at a slack mid-range angle",
    "limb_mass_error": "a weight error needs the limb weighed on the dynamometer (a gravity-correction trial)",
    "axis_misalignment": "a misalignment needs the axes aligned by markers or a second attachment point",
    "tonic_activation": "a tonic activation needs EMG on the muscles during the sweep (or a sweep repeated after "
                        "the subject is told to relax), and a second speed (a stretch reflex grows with it)",
    "knee_tendon_compliance": "the knee tendons' compliance needs the sweep further into the stretched end at two hip "
                              "angles (a compliant tendon flattens the curve's steep end, a slack length shifts it)",
    "end_range_structures": "end-range structures are told from the muscles by a sweep further into the range's end "
                            "and a second set angle of the other joint (a two-joint muscle changes with it, a capsule "
                            "does not); a one-joint muscle (soleus at the ankle, the vasti and biceps femoris' short "
                            "head at the knee) by neither: only by its own length (its fascicles by ultrasound)",
}


def _ca() -> Any:
    import casadi as ca
    return ca


@dataclass(frozen=True)
class Extension:
    """A candidate model extension: its parameters (typical size and bounds, SI) and terms.

    ``term(trial, q, v, p, gravity)`` is the extra moment toward positive angle (N·m);
    ``angle(trial, q, p)`` maps the arm's angle to the joint's (default: the same); both take and
    return CasADi expressions (or numbers).
    """

    name: str
    description: str
    parameters: tuple[str, ...]
    typical: tuple[float, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    term: Callable[..., Any] = lambda t, q, v, p, g: 0
    angle: Callable[..., Any] | None = None
    #: the smallest size of each parameter worth reporting (SI); default MATERIAL_FRACTION × typical
    material: tuple[float, ...] | None = None
    #: where the fit starts (SI); default 0 (no extension), held inside the bounds
    start: tuple[float, ...] | None = None
    #: the parameters that size the extension's effect (the others shape it, and mean nothing at size 0)
    sizes: tuple[str, ...] | None = None
    #: ``muscles(trial, p)``: what the extension changes inside the muscles, as keyword arguments of
    #: :func:`analysis.pmp.model.muscles_moment` (a tonic activation, more compliant tendons); default nothing
    muscles: Callable[..., dict[str, Any]] | None = None
    #: ``shape(trial, q, p)``: torque columns (N·m per unit, numpy, one row per angle ``q`` in rad) of how the
    #: extension's shape may differ from its family; in the intervals they are free nuisances at zero (the
    #: parameters told from the extension by its shape only get the width that shape's uncertainty gives them)
    shape: Callable[..., np.ndarray] | None = None

    def shape_columns(self, trial: PmpTrial, q: np.ndarray, p: Any) -> np.ndarray:
        """The extension's shape-uncertainty columns at the angles ``q`` (rad) of ``trial`` (none: ``(n, 0)``)."""
        return self.shape(trial, q, p) if self.shape is not None else np.zeros((np.size(q), 0))

    def moment(self, trial: PmpTrial, q: Any, v: Any, p: list[Any], gravity: Any) -> Any:
        return self.term(trial, q, v, p, gravity)

    def muscle_options(self, trial: PmpTrial, p: list[Any]) -> dict[str, Any]:
        """Keyword arguments of :func:`analysis.pmp.model.muscles_moment` for ``trial`` (empty: the muscles as they are)."""
        return self.muscles(trial, p) if self.muscles is not None else {}

    def joint_angle(self, trial: PmpTrial, q: Any, p: list[Any]) -> Any:
        return self.angle(trial, q, p) if self.angle is not None else q

    def start_values(self) -> tuple[float, ...]:
        """Where a fit starts this extension's parameters (SI): ``start``, else 0 (no extension)."""
        return tuple(self.start) if self.start is not None else (0.0,) * len(self.parameters)

    def smallest(self) -> tuple[float, ...]:
        """The smallest size of each parameter worth reporting (SI): ``material``, else MATERIAL_FRACTION × typical."""
        return tuple(self.material) if self.material is not None else tuple(MATERIAL_FRACTION * v for v in self.typical)


def _per_joint(trial: PmpTrial, p: list[Any], knee: int, ankle: int) -> Any:
    return p[knee] if trial.joint == "knee" else p[ankle]


def _misaligned(trial: PmpTrial, q: Any, p: list[Any]) -> Any:
    ca = _ca()
    a, b = (p[0], p[1]) if trial.joint == "knee" else (p[2], p[3])
    return q + a * ca.sin(q) + b * ca.cos(q)


#: the joint range at whose ends non-muscular structures (capsule, ligaments) and muscles the model lacks
#: stiffen a joint (rad): knee 0° (full extension) and 90° flexion, ankle 30° plantarflexion and 15°
#: dorsiflexion: the protocol's sweeps (:data:`analysis.trial_csv.NOMINAL_RANGE_DEG`)
END_RANGE_RAD = {j: tuple(math.radians(v) for v in NOMINAL_RANGE_DEG[j]) for j in ("knee", "ankle")}
#: how far (rad) an end-range structure's engagement angle may lie from the range's end, inside or outside
#: it: an exponential stiffening (Riener & Edrich, Yamaguchi) engages beyond the end, a capsule or a
#: ligament (OpenSim's CoordinateLimitForce) inside it
END_RANGE_ENGAGE_RAD = math.radians(30.0)
#: bounds of the width (rad) over which a structure stiffens: 0.5° (a ligament taut at an angle: a ramp)
#: to 30° (a muscle the model lacks stiffening over much of the range: an exponential)
END_RANGE_WIDTH_RAD = (math.radians(0.5), math.radians(30.0))
#: the joint a structure crossing two joints couples each moving joint to, and the reference angle (rad) of
#: that coupling: the knee's structures to the hip (hamstrings, gracilis, sartorius: Riener & Edrich's
#: hip term), the ankle's to the knee (the gastrocnemii)
END_RANGE_COUPLING = {"knee": ("hip", math.radians(55.0)), "ankle": ("knee", math.radians(45.0))}


def _softplus(x: Any) -> Any:
    ca = _ca()
    return ca.fmax(x, 0) + ca.log1p(ca.exp(-ca.fabs(x)))


def _end_range(trial: PmpTrial, q: Any, v: Any, p: list[Any], g: Any) -> Any:
    """Joint-level passive structures at both ends of the range (N·m toward positive angle): at each end
    k·w·softplus(depth / w)·exp(c·Δ), depth the angle past the engagement angle θ, w the width over which it
    stiffens, k the stiffness once engaged (N·m/rad), Δ the coupled joint's angle from its reference. A
    wide w far from θ is Riener & Edrich's exponential; a narrow one a ligament's ramp (OpenSim's
    CoordinateLimitForce). Parameters per end: k, θ − range end, w, c."""
    ca = _ca()
    lo, hi = END_RANGE_RAD[trial.joint]
    k_lo, th_lo, w_lo, c_lo, k_hi, th_hi, w_hi, c_hi = p[0:8] if trial.joint == "knee" else p[8:16]
    other, ref = END_RANGE_COUPLING[trial.joint]
    d = trial.fixed_rad.get(other, ref) - ref
    low = k_lo * w_lo * _softplus((lo + th_lo - q) / w_lo) * ca.exp(c_lo * d)
    high = k_hi * w_hi * _softplus((q - hi + th_hi) / w_hi) * ca.exp(c_hi * d)
    return low - high


#: the knee's muscles whose tendons the plain model takes as rigid (the calf's are compliant already)
RIGID_TENDONED = tuple(m for m in MUSCLES if m not in COMPLIANT)
#: the tendon strain ε_T0 at which a "compliant" tendon is as good as rigid (0.8 mm of a 0.35 m tendon at
#: a tenth of the muscle's force), the knee-tendon extension's lower bound and start; DeGroote–Fregly's
#: generic tendon is 0.049
NEAR_RIGID_TENDON_STRAIN = 0.01


#: the rates (1/rad) of the exponentials an end-range structure's shape may hold beside its fitted one (its intervals'
#: shape uncertainty): e-folding over 19°, 5.7° and 1.9°, a muscle the model lacks to a ligament's ramp
END_RANGE_SHAPE_RATES_PER_RAD = (3.0, 10.0, 30.0)


def _end_range_shape(trial: PmpTrial, q: np.ndarray, p: Any) -> np.ndarray:
    """Exponentials at each end of the trial's joint range (N·m per unit; :data:`END_RANGE_SHAPE_RATES_PER_RAD`),
    scaled by the fitted coupling to the other joint as the structure's own term is."""
    lo, hi = END_RANGE_RAD[trial.joint]
    p = np.asarray(p, dtype=float)
    c_lo, c_hi = (p[3], p[7]) if trial.joint == "knee" else (p[11], p[15])
    other, ref = END_RANGE_COUPLING[trial.joint]
    d = trial.fixed_rad.get(other, ref) - ref
    q = np.asarray(q, dtype=float)
    cols = [np.exp(-r * (q - lo)) * math.exp(c_lo * d) for r in END_RANGE_SHAPE_RATES_PER_RAD]
    cols += [-np.exp(r * (q - hi)) * math.exp(c_hi * d) for r in END_RANGE_SHAPE_RATES_PER_RAD]
    return np.column_stack(cols)


def _tonic(trial: PmpTrial, p: list[Any]) -> dict[str, Any]:
    return {"activation": _per_joint(trial, p, 0, 1)}


def _knee_tendons(trial: PmpTrial, p: list[Any]) -> dict[str, Any]:
    return {"tendon_strain": {m: p[0] for m in RIGID_TENDONED}}


EXTENSIONS: dict[str, Extension] = {e.name: e for e in [
    Extension("viscous_damping", "torque proportional to angular velocity (tissue viscosity)",
              ("damping_Nm_s_per_rad",), (1.0,), (0.0,), (20.0,), lambda t, q, v, p, g: -p[0] * v),
    Extension("coulomb_friction", "constant torque opposing motion (dynamometer or joint friction)",
              ("friction_Nm",), (1.0,), (0.0,), (10.0,),
              lambda t, q, v, p, g: -p[0] * _ca().tanh(v / FRICTION_SPEED_RAD_S)),
    Extension("limb_mass_error", "the limb's weight off by a fraction (mass or centre of mass)",
              ("limb_weight_error_fraction",), (0.1,), (-0.5,), (0.5,), lambda t, q, v, p, g: p[0] * g),
    Extension("torque_offset", "a constant torque per joint (arm-weight compensation error or residual activation)",
              ("knee_offset_Nm", "ankle_offset_Nm"), (1.0, 1.0), (-20.0, -20.0), (20.0, 20.0),
              lambda t, q, v, p, g: _per_joint(t, p, 0, 1)),
    Extension("axis_misalignment", "the joint's axis off the dynamometer's (joint angle and lever change with angle)",
              ("knee_axis_sin_rad", "knee_axis_cos_rad", "ankle_axis_sin_rad", "ankle_axis_cos_rad"),
              (0.02, 0.02, 0.02, 0.02), (-0.15,) * 4, (0.15,) * 4, angle=_misaligned,
              # 0.01 rad: a 3 mm offset at a 30 cm lever (0.6° of angle), finer than a lab aligns or
              # sees by eye or laser; on clean OpenSim trials the muscle-path mismatch alone fits as
              # 0.0045 rad (a 1.4 mm offset), which is the model's, not the set-up's
              material=(0.01,) * 4),
    Extension("end_range_structures", "joint-level passive structures stiffening the range's ends (capsule, "
              "ligaments, muscles the model lacks)",
              tuple(f"{j}_{end}_end_{what}" for j, ends in (("knee", ("extension", "flexion")),
                                                           ("ankle", ("plantarflexion", "dorsiflexion")))
                    for end in ends for what in ("stiffness_Nm_per_rad", "engage_rad", "width_rad", "coupling_per_rad")),
              # the engagement angle θ counts from the range's end into the range (positive: inside it)
              (30.0, 0.1, 0.1, 1.0) * 4,
              (0.0, -END_RANGE_ENGAGE_RAD, END_RANGE_WIDTH_RAD[0], -3.0, 0.0, -END_RANGE_ENGAGE_RAD,
               END_RANGE_WIDTH_RAD[0], -3.0) * 2,
              (3000.0, END_RANGE_ENGAGE_RAD, END_RANGE_WIDTH_RAD[1], 3.0) * 4, _end_range,
              # a stiffness of 1 N·m/rad (0.017 N·m/°) is below what any dynamometer resolves over a few degrees
              material=(1.0, math.inf, math.inf, math.inf) * 4, start=(5.0, 0.0, 0.1, 0.0) * 4,
              sizes=("knee_extension_end_stiffness_Nm_per_rad", "knee_flexion_end_stiffness_Nm_per_rad",
                     "ankle_plantarflexion_end_stiffness_Nm_per_rad", "ankle_dorsiflexion_end_stiffness_Nm_per_rad"),
              shape=_end_range_shape),
    Extension("tonic_activation", "a low tonic activation of every muscle crossing the joint (relaxed is never "
              "exactly zero): the isometric active force a·f_L(l_M) beside the passive one",
              ("knee_activation", "ankle_activation"), (0.01, 0.01), (0.0, 0.0), (0.05, 0.05), muscles=_tonic,
              # 0.2 % of the maximum force: on the generic leg it moves the knee's moment by up to 0.53 N·m (hip 55°)
              # and the ankle's by up to 0.80 N·m (knee 45°), the size of a dynamometer's noise
              material=(0.002, 0.002)),
    Extension("knee_tendon_compliance", "the knee muscles' tendons stretch (compliant, as the calf's): "
              "one tendon strain at maximum force for all of them",
              ("knee_tendon_strain",), (0.049,), (NEAR_RIGID_TENDON_STRAIN,), (0.12,), muscles=_knee_tendons,
              start=(NEAR_RIGID_TENDON_STRAIN,),
              # never "away from zero" by its interval (a tendon always has a strain): named by held-out prediction only
              material=(math.inf,)),
]}


#: how a model extended by two extensions is named: ``"tonic_activation+knee_tendon_compliance"``
JOIN = "+"


def combine(first: Extension, second: Extension) -> Extension:
    """One extension holding two: their parameters side by side, their moments added, their muscle changes
    merged (at most one of them may map the joint's angle)."""
    if first.angle is not None and second.angle is not None:
        raise ValueError(f"{first.name} and {second.name} both map the joint's angle")
    n = len(first.parameters)

    angle = None
    if first.angle is not None:
        angle = lambda t, q, p: first.joint_angle(t, q, p[:n])  # noqa: E731  # the first's map on its own parameters
    elif second.angle is not None:
        angle = lambda t, q, p: second.joint_angle(t, q, p[n:])  # noqa: E731  # the second's map on its own parameters
    return Extension(
        f"{first.name}{JOIN}{second.name}", f"{first.description}; and {second.description}",
        first.parameters + second.parameters, first.typical + second.typical, first.lower + second.lower,
        first.upper + second.upper,
        lambda t, q, v, p, g: first.moment(t, q, v, p[:n], g) + second.moment(t, q, v, p[n:], g), angle,
        first.smallest() + second.smallest(), first.start_values() + second.start_values(),
        tuple(first.sizes or first.parameters) + tuple(second.sizes or second.parameters),
        lambda t, p: {**first.muscle_options(t, p[:n]), **second.muscle_options(t, p[n:])},
        lambda t, q, p: np.hstack([first.shape_columns(t, q, p[:n]), second.shape_columns(t, q, p[n:])]))


def get_extension(name: str) -> Extension:
    """The extension of that name in :data:`EXTENSIONS`, or several of them joined by :data:`JOIN`."""
    parts = name.split(JOIN)
    return functools.reduce(combine, [EXTENSIONS[p] for p in parts[1:]], EXTENSIONS[parts[0]])


def protocol_to_separate(name: str) -> str:
    """What would separate an extension (each of a pair's) from the muscles: :data:`PROTOCOL_TO_SEPARATE`."""
    return "; ".join(PROTOCOL_TO_SEPARATE.get(n, "another protocol") for n in name.split(JOIN))


def is_material(finding: ExtensionFinding) -> bool:
    """Whether any of the finding's parameters is away from zero (interval and size; :data:`MATERIAL_FRACTION`)."""
    known = all(n in EXTENSIONS for n in finding.name.split(JOIN))
    smallest = dict(zip(ext.parameters, ext.smallest())) if known and (ext := get_extension(finding.name)) else {}
    return any((lo > 0 or hi < 0) and abs(finding.parameters.get(k, 0.0)) >= smallest.get(k, 0.0)
               for k, (lo, hi) in finding.ci95.items())


@dataclass
class ExtensionFinding:
    """One candidate as judged: held-out RMSE (N·m) pooled over the left-out conditions, its ratio to
    the plain model's, the parameters (full fit) with jackknife 95 % intervals, and how far each
    passive parameter moved (%) when it was added."""

    name: str
    heldout_rmse_nm: float
    heldout_ratio: float
    parameters: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    parameter_shift_pct: dict[str, float]
    fold_rmse_nm: dict[str, float]
    named: bool = False
    every_fold_better: bool = False


@dataclass
class ModelDiagnosis:
    """The finding: ``cause`` (an extension's name or ``"none"``), every candidate, and a sentence."""

    cause: str
    plain_heldout_rmse_nm: float
    plain_fold_rmse_nm: dict[str, float]
    candidates: list[ExtensionFinding]
    message: str
    folds: list[str] = field(default_factory=list)
    conclusive: bool = True
    #: extensions that predict the left-out trials nearly as well as the named one (within 5 % of its
    #: held-out ratio): these trials do not separate them, and the message says what would
    ambiguous_with: list[str] = field(default_factory=list)
    #: the named model's fit on every trial (muscles' parameters, the extension's values, set-angle offsets): a start
    #: for the refit that reports it
    named_fit: FitStart | None = None
    #: models the data favour over the named one on every left-out fold but by less than the naming margin (the named
    #: model with one more extension, or a single extension when none is named; the best :data:`MAX_PLAUSIBLE` by
    #: held-out ratio): the parameters' intervals also hold their estimates under these (model uncertainty)
    plausible: list[str] = field(default_factory=list)

    def winner(self) -> ExtensionFinding | None:
        return next((c for c in self.candidates if c.name == self.cause), None)

    def text(self) -> str:
        across = (f"{len(self.folds)} folds of interleaved time blocks" if self.folds and
                  all(f.startswith("blocks") for f in self.folds) else f"{len(self.folds)} left-out repeats or conditions")
        lines = [f"model-level diagnosis (held-out across {across}): {self.message}",
                 f"  {'extension':<20}{'held-out RMSE':>15}{'ratio':>8}  parameters (95 % jackknife interval)"]
        lines.append(f"  {'none':<20}{self.plain_heldout_rmse_nm:>13.3f} N·m{1.0:>8.2f}")
        for c in sorted(self.candidates, key=lambda c: c.heldout_ratio):
            ps = ", ".join(f"{k} = {v:.3g} [{c.ci95[k][0]:.3g}, {c.ci95[k][1]:.3g}]" for k, v in c.parameters.items()
                           if k in c.ci95)
            lines.append(f"  {c.name:<20}{c.heldout_rmse_nm:>13.3f} N·m{c.heldout_ratio:>8.2f}  {ps}"
                         + ("  ← named" if c.named else "")
                         + (f"  (stopped at {list(c.fold_rmse_nm)[-1]}: no better there than the model it extends)"
                            if self.folds and 0 < len(c.fold_rmse_nm) < len(self.folds) else ""))
        if self.plausible:
            lines.append("  plausible beside it (better on every left-out fold, by less than the margin): "
                         + ", ".join(self.plausible) + "; the parameters' intervals hold their estimates under these too")
        w = self.winner() or next((c for c in sorted(self.candidates, key=lambda c: c.heldout_ratio)
                                   if is_material(c)), None)
        if w is not None:
            moved = sorted(w.parameter_shift_pct.items(), key=lambda kv: -abs(kv[1]))[:5]
            lines.append(f"  with {w.name}, the passive parameters move: " + ", ".join(f"{k} {v:+.1f} %" for k, v in moved))
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return {"cause": self.cause, "message": self.message, "folds": self.folds, "conclusive": self.conclusive,
                "ambiguous_with": self.ambiguous_with, "plausible": self.plausible,
                "plain_heldout_rmse_Nm": self.plain_heldout_rmse_nm, "plain_fold_rmse_Nm": self.plain_fold_rmse_nm,
                "candidates": [{"name": c.name, "heldout_rmse_Nm": c.heldout_rmse_nm, "heldout_ratio": c.heldout_ratio,
                                "parameters": c.parameters, "ci95": {k: list(v) for k, v in c.ci95.items()},
                                "parameter_shift_pct": c.parameter_shift_pct, "fold_rmse_Nm": c.fold_rmse_nm,
                                "named": c.named} for c in self.candidates]}


def predict_torque_nm(result: PmpResult, trial: PmpTrial, subject: Subject, leg: LegMuscles,
                      extension: Extension | None = None, points: int = 60,
                      indices: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(sample indices, predicted dynamometer torque N·m) for ``trial`` from its measured motion and the
    fitted model: u = I·q̈ − M_muscles − M_gravity − M_extension (inverse dynamics); at ``points`` samples
    spread over the trial, or at ``indices``."""
    ca = _ca()
    idx = (np.unique(np.linspace(0, trial.time_s.size - 1, min(points, trial.time_s.size)).astype(int))
           if indices is None else np.asarray(indices, dtype=int))
    q_s, v_s = ca.SX.sym("q"), ca.SX.sym("v")
    trial = with_set_angles([trial], result.set_angle_offsets_rad)[0]  # at the set angle the fit found
    ext = [result.extension_parameters[n] for n in extension.parameters] if extension is not None else []
    q_joint = extension.joint_angle(trial, q_s, ext) if extension is not None else q_s
    options = extension.muscle_options(trial, ext) if extension is not None else {}
    moment, residuals, lts = muscles_moment(leg, trial, q_joint, result.parameters, **options)
    muscles = eliminate_tendons(moment, residuals, lts, [q_s])
    if extension is not None and extension.angle is not None:
        muscles = muscles * ca.jacobian(q_joint, q_s)
    gravity = subject.gravity_moment_nm(trial.joint, q_s, trial.fixed_rad, ca.cos)
    total = gravity + muscles + (extension.moment(trial, q_s, v_s, ext, gravity) if extension is not None else 0)
    f = mapped(ca.Function("m", [q_s, v_s], [total]), idx.size)
    m = np.asarray(f(trial.angle_rad[idx][None, :], trial.velocity_rad_s[idx][None, :])).ravel()
    acc = np.gradient(trial.velocity_rad_s, trial.time_s)[idx]
    return idx, subject.inertia_kgm2(trial.joint) * acc - m


def fit_extended(trials: list[PmpTrial], subject: Subject, extension: Extension, *, leg: LegMuscles,
                 intervals: int, plain: PmpResult, found: FitStart | None = None) -> PmpResult:
    """The muscle parameters refitted with ``extension``'s terms beside them: from the plain fit, from the generic
    model and, when given, from ``found`` (the model-level diagnosis's fit of this model); the converged fit of
    lowest objective (cost and priors) is kept.

    The extended problem has several basins. The extension's terms can hold what the plain fit pushed into the
    muscles, and from the plain fit's parameters the refit can stay in that basin (a demo subject's soleus ε0 went
    to its bound, at a cost 2 % above the generic start's; an OpenSim-made subject with compliant knee tendons, a
    tone and end-range structures ended at a cost 26 % above the generic start's, rectus femoris' slack length
    8.1 % off against an interval of ±3.2 %, the generic start's 0.2 %).
    """
    problem = build_problem(trials, subject, leg=leg, intervals=intervals, extension=extension)
    starts: list[FitStart] = [(dict(plain.parameters), extension.start_values(), dict(plain.set_angle_offsets_rad), None),
                              (dict(plain.generic), extension.start_values(), {}, None)]
    if found is not None and len(found[1]) == len(extension.parameters):
        starts.append(found)
    fits = []
    for start in starts:
        problem.start_at(*start)
        fits.append(solve(problem))
    return min((f for f in fits if f.success), key=lambda f: f.objective, default=fits[0])


def fit_plausible(trials: list[PmpTrial], subject: Subject, plausible: list[str], *, leg: LegMuscles, intervals: int,
                  plain: PmpResult, named: PmpResult, named_extension: Extension | None,
                  progress: Callable[[str], None] | None = None) -> list[tuple[str, PmpResult, Extension]]:
    """Each model the diagnosis kept as plausible beside the named one (:attr:`ModelDiagnosis.plausible`), fitted on
    every trial as the named one is (:func:`fit_extended`); one that adds an extension to the named model also from
    where the named model's fit ``named`` ended (the added extension at its own start). (name, fit, extension)
    each, for :func:`analysis.pmp.identifiability.with_plausible_models`."""
    out = []
    for name in plausible:
        extension = get_extension(name)
        if progress is not None:
            progress(f"fit with {name} (plausible beside the named model) ...")
        nested = named_extension is not None and name.startswith(named_extension.name + JOIN)
        found = nested_start(found_start(named, named_extension), EXTENSIONS[name.split(JOIN)[-1]]) if nested else None
        out.append((name, fit_extended(trials, subject, extension, leg=leg, intervals=intervals, plain=plain,
                                       found=found), extension))
    return out


def _condition(trial: PmpTrial) -> str:
    fixed = ", ".join(f"{k} {math.degrees(v):.0f}°" for k, v in sorted(trial.fixed_rad.items()))
    return f"{trial.joint} ({fixed})"


def folds_of(trials: list[PmpTrial]) -> list[tuple[str, list[int]]]:
    """(label, indices of the left-out trials) of each fold: every k-th repeat of all conditions when
    each condition was repeated (the model must predict a repeat of what it saw), else each condition
    in turn (it must predict a condition it did not see)."""
    by_condition: dict[str, list[int]] = {}
    for i, t in enumerate(trials):
        by_condition.setdefault(_condition(t), []).append(i)
    repeats = min(len(v) for v in by_condition.values())
    if repeats >= 2:
        return [(f"repeat {r + 1}", [v[r] for v in by_condition.values()] + [i for v in by_condition.values()
                                                                            for i in v[repeats:] if r == 0])
                for r in range(repeats)]
    return [(c, v) for c, v in by_condition.items()]


#: without repeats, the held-out folds are blocks of every trial: each trial is cut into BLOCK_FOLDS ×
#: BLOCKS_PER_FOLD contiguous time blocks and fold k leaves out blocks 1 + k, 1 + k + BLOCK_FOLDS, ... of
#: every trial at once (the first and last blocks, the range's ends, are always fitted). Leaving a whole condition out instead
#: asks the other conditions to extrapolate its
#: muscles: with the hamstrings 1 % off, a left-out hip-90° sweep was predicted 827 N·m off (an OpenSim
#: subject whose in-sample residual was 0.78 N·m), and nothing could be judged
BLOCK_FOLDS = 4
BLOCKS_PER_FOLD = 4


@dataclass(frozen=True)
class Fold:
    """One held-out fold: the trials fitted, the torque windows left out of the fit (per fitted trial,
    s; a left-out repeat is one window over its whole sweep), and the samples predicted (trial index → sample
    indices)."""

    label: str
    fitted: tuple[int, ...]
    held_out_s: tuple[tuple[tuple[float, float], ...], ...] | None
    predicted: dict[int, np.ndarray]


def held_out_folds(trials: list[PmpTrial], points: int = 60) -> list[Fold]:
    """The folds of the model-level diagnosis: with repeats of every condition, each repeat left out in turn
    (:func:`folds_of`); without, interleaved time blocks of every trial (:data:`BLOCK_FOLDS`)."""
    by_condition = folds_of(trials)
    if len(by_condition) >= 2 and all(lbl.startswith("repeat") for lbl, _ in by_condition):
        # a left-out repeat is a window over its whole sweep: its torque is out of the cost, its motion still
        # tracked. Its control is then free, so its states follow the measured motion whatever the parameters
        # are, and the fit is the one of the other trials alone; every fold then shares one built problem
        out = []
        for label, left in by_condition:
            pred = {j: np.unique(np.linspace(0, trials[j].time_s.size - 1, min(points, trials[j].time_s.size)).astype(int))
                    for j in left}
            whole: tuple[tuple[tuple[float, float], ...], ...] = tuple(
                ((float(t.time_s[0]), float(t.time_s[-1])),) if j in left else () for j, t in enumerate(trials))
            out.append(Fold(label, tuple(range(len(trials))), whole, pred))
        return out
    n_blocks = BLOCK_FOLDS * BLOCKS_PER_FOLD
    out = []
    for k in range(BLOCK_FOLDS):
        windows, pred = [], {}
        for j, t in enumerate(trials):
            edges = np.linspace(t.time_s[0], t.time_s[-1], n_blocks + 1)
            # the sweep's first and last blocks are always fitted: held out, they would be extrapolated past
            # the data (a structure engaging over the last degrees cannot be predicted from the rest)
            mine = [(float(edges[b]), float(edges[b + 1])) for b in range(1 + k, n_blocks - 1, BLOCK_FOLDS)]
            windows.append(tuple(mine))
            inside = np.zeros(t.time_s.size, dtype=bool)
            for a, b in mine:
                inside |= (t.time_s >= a) & (t.time_s <= b)
            idx = np.flatnonzero(inside)
            pred[j] = idx[np.unique(np.linspace(0, idx.size - 1, min(points // BLOCK_FOLDS + 1, idx.size)).astype(int))]
        out.append(Fold(f"blocks {k + 1}", tuple(range(len(trials))), tuple(windows), pred))
    return out


def fit_workers() -> int:
    """Processes for the folds' fits (:func:`analysis.pmp.workers.workers`: ``INSTRUMENT_FIT_WORKERS`` if set, else
    one per core, at most two; 1, fit here, inside a pool's worker, which may not start children)."""
    return workers()


_WORKER: dict[str, Any] = {}


def _worker_init(context: dict[str, Any]) -> None:
    _WORKER.update(context)


#: a candidate's job: its name (None: the plain model), the folds, and when to fit it on every trial as well
#: (None: never; else the reference's RMSE per fold, the ratio it must beat, and whether every fold must be better)
WholeRule = tuple[dict[str, float], float, bool] | None
#: where a fit starts (or what it found): the muscles' parameters, the extension's values in its order, the set-angle
#: offsets by label (SI), and the collocation variables per trial (None: the measured motion)
FitStart = tuple[dict[str, float], tuple[float, ...], dict[str, float], tuple[CollocationState, ...] | None]
#: the starts of a job's fits: per fold, then for the fit on every trial, the starts to try (None in a list: the plain
#: fit's parameters and the extension's own start; the fit of lowest objective is kept); None: that default start only
JobStarts = tuple[list[list[FitStart | None]], list[FitStart | None]] | None
FitJob = tuple[str | None, list[Fold], WholeRule, JobStarts]
#: what a job returns: per fold (held-out RMSE N·m, the extension's parameters, the fit's values as a start), and
#: the fit on every trial (the extension's parameters, the muscles', the fit's values) when the rule asked for it
FitOutcome = tuple[list[tuple[float, dict[str, float], FitStart]],
                   tuple[dict[str, float], dict[str, float], FitStart] | None]


def found_start(fit: PmpResult, ext: Extension | None) -> FitStart:
    """A fit's values (its parameters and its collocation variables) as a start for a larger model's fit."""
    values = tuple(float(fit.extension_parameters[n]) for n in ext.parameters) if ext is not None else ()
    return dict(fit.parameters), values, dict(fit.set_angle_offsets_rad), fit.collocation_states or None


def nested_start(found: FitStart, added: Extension) -> FitStart:
    """The start of a model with ``added`` beside the one that found ``found``: where that model ended (its parameters
    and its states and controls, :meth:`analysis.pmp.problem.PmpProblem.start_at`), the added extension at its own
    start (≈ no effect), so the larger model starts at the smaller one's cost."""
    params, values, offsets, states = found
    return params, values + added.start_values(), offsets, states


def fold_ratio(errors: dict[str, float], reference: dict[str, float]) -> tuple[float, bool]:
    """Geometric mean over the folds of the held-out RMSE ratio ``errors`` / ``reference`` (N·m by fold label), and
    whether every fold is better: one fold whose left-out blocks are badly extrapolated must not outweigh the
    others. A candidate whose fits stopped at a worse fold (:func:`_key_fits`) has errors for the folds fitted only:
    its ratio is over those, and not every fold is better. NaN and False when no reference fold has an error."""
    judged = [f for f in reference if reference[f] > 0]
    ratios = [errors[f] / reference[f] for f in judged if f in errors]
    return (float(np.exp(np.mean(np.log(ratios)))) if ratios else float("nan")), bool(ratios) and len(ratios) == len(
        judged) and all(r < 1.0 for r in ratios)


def _heldout_rms(fit: PmpResult, fold: Fold, w: dict[str, Any], ext: Extension | None) -> float:
    sq = []
    for j, idx in fold.predicted.items():
        _, pred = predict_torque_nm(fit, w["trials"][j], w["subject"], w["leg"], ext, indices=idx)
        sq.append((w["trials"][j].torque_nm[idx] - pred) ** 2)
    return float(np.sqrt(np.mean(np.concatenate(sq))))


def _key_fits(job: FitJob, context: dict[str, Any] | None = None) -> FitOutcome:
    """One candidate fitted without each fold in turn, then on every trial when ``job``'s rule asks (its folds
    predict better than the reference's by the ratio). Folds that fit every trial (time blocks, or repeats left
    out as whole-sweep windows) share one built problem (the held-out windows are its parameters: one build
    serves every fold and the fit on every trial, each solved from the same start, so the fits are those of
    separate builds); folds fitting fewer trials are built each.

    When the rule asks every fold to be better, the folds stop at the first that is not: the candidate can then be
    neither named nor plausible whatever the others give (the decision is the one all folds would give; the
    outcome has fewer folds than ``folds``)."""
    key, folds, rule, starts = job
    w = _WORKER if context is None else context
    trials, subject, leg = w["trials"], w["subject"], w["leg"]
    ext = get_extension(key) if key else None
    default: list[FitStart | None] = [None]
    fold_starts: list[list[FitStart | None]] = [default] * len(folds)
    whole_starts = default
    if starts is not None:
        fold_starts, whole_starts = starts
    shared = w.get("built", {}).get(key)  # the problem the caller already built for this model, if any
    if shared is None and all(f.held_out_s is not None and len(f.fitted) == len(trials) for f in folds):
        shared = build_problem(trials, subject, leg=leg, intervals=w["intervals"], extension=ext, initial=w["initial"])
    initial_ext = ext.start_values() if ext is not None else None

    def fit_from(start: FitStart | None, fitted: list[int], held: list[list[tuple[float, float]]] | None) -> PmpResult:
        if shared is not None:
            shared.leave_out(held)
            shared.start_at(*(start if start is not None else (w["initial"], initial_ext, {}, None)))
            return solve(shared)
        started = ext if ext is None or start is None else dataclasses.replace(ext, start=start[1])
        return estimate([trials[j] for j in fitted], subject, leg=leg, intervals=w["intervals"], extension=started,
                        initial=w["initial"] if start is None else start[0], held_out_s=held)

    def best_fit(tries: list[FitStart | None], fitted: list[int], held: list[list[tuple[float, float]]] | None
                 ) -> PmpResult:
        # the same data from each start: the converged fit of lowest objective (the problem has several basins)
        fits = [fit_from(start, fitted, held) for start in tries]
        return min((f for f in fits if f.success), key=lambda f: f.objective, default=fits[0])

    out = []
    for fold, tries in zip(folds, fold_starts, strict=True):
        held = [list(win) for win in fold.held_out_s] if fold.held_out_s is not None else None
        fit = best_fit(tries, list(fold.fitted), held)
        out.append((_heldout_rms(fit, fold, w, ext), dict(fit.extension_parameters), found_start(fit, ext)))
        if rule is not None and rule[2] and fold.label in rule[0] and not out[-1][0] < rule[0][fold.label]:
            break  # not better on this fold: out of the running, the other folds would not change that
    whole = None
    if rule is not None and key is not None:
        reference, below, every = rule
        ratio, all_better = fold_ratio({f.label: rms for f, (rms, _, _) in zip(folds, out)}, reference)
        if len(out) == len(folds) and ratio < below and (all_better or not every):
            fit = best_fit(whole_starts, list(range(len(trials))), None)
            whole = (dict(fit.extension_parameters), dict(fit.parameters), found_start(fit, ext))
    return out, whole


class _FitPool:
    """The model-level diagnosis's fits, in worker processes (spawned: CasADi and its threads are not forked)
    or here. A worker gets the trials, the subject and the leg once (the leg pickles without its compiled
    CasADi functions) and each fit as an extension's name and a fold."""

    def __init__(self, trials: list[PmpTrial], subject: Subject, leg: LegMuscles, intervals: int,
                 initial: dict[str, float], workers: int | None) -> None:
        self.context = {"trials": trials, "subject": subject, "leg": leg, "intervals": intervals,
                        "initial": dict(initial)}
        self.workers = fit_workers() if workers is None else max(1, workers)
        self.pool: Any = None

    def __enter__(self) -> _FitPool:
        if self.workers > 1:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self.pool = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                            initializer=_worker_init, initargs=(self.context,))
        return self

    def __exit__(self, *exc: object) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def fits(self, jobs: list[FitJob]) -> list[FitOutcome]:
        if self.pool is None:
            return [_key_fits(j, self.context) for j in jobs]
        return list(self.pool.map(_key_fits, jobs))


#: the most models kept as plausible beside the named one (each costs the report one more fit)
MAX_PLAUSIBLE = 2


def favoured(ratios: list[tuple[str, float, bool]]) -> list[str]:
    """Of (model, held-out ratio to the named model, every fold better), the models better on every fold: the data
    favour them, by less than the naming margin (else they would be named), so they stay plausible; the best
    :data:`MAX_PLAUSIBLE` by ratio."""
    better = sorted((r, name) for name, r, every in ratios if every and r < 1.0)
    return [name for _, name in better[:MAX_PLAUSIBLE]]


def diagnose_model(trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None, intervals: int = 24,
                   candidates: list[str] | None = None, max_heldout_ratio: float = 0.9,
                   plain: PmpResult | None = None, workers: int | None = None) -> ModelDiagnosis:
    """Try every candidate extension inside the estimator and judge it by leave-one-condition-out prediction.

    Parameters
    ----------
    trials
        The subject's trials: with repeats, each repeat of every condition is left out in turn; without,
        each condition (moving joint and fixed angles) is (:func:`folds_of`).
    intervals
        Collocation intervals per trial in every fit.
    max_heldout_ratio
        An extension is named when the geometric mean of its folds' held-out RMSE ratios to the plain model's is
        below this (and every fold is better); a second one beside it when the pair's ratios to the first alone
        are (the pair is then the cause, named ``first+second``), a third beside the pair likewise, and so on.
    plain
        The plain model's fit on all trials, if already made.
    workers
        Processes fitting the folds side by side (default: :func:`fit_workers`); 1 fits them here, one after
        another. The fits are the same either way (each is deterministic and independent of the others).
    """
    from ..errors import InputError

    if len(trials) < 2:
        raise InputError(f"the model-level diagnosis needs at least 2 trials; got {len(trials)}")
    folds = held_out_folds(trials)
    leg = leg or LegMuscles()
    names = candidates or list(EXTENSIONS)
    built: dict[str | None, Any] = {}
    if plain is None:  # the plain model's folds are then solved on the problem built for this fit (one build)
        built[None] = build_problem(trials, subject, leg=leg, intervals=intervals)
        plain_fit = solve(built[None])
    else:
        plain_fit = plain
    heldout: dict[str, dict[str, float]] = {}
    fold_params: dict[str, list[dict[str, float]]] = {}
    def pooled(errs: dict[str, float]) -> float:
        return float(np.sqrt(np.mean(np.square(list(errs.values())))))

    in_sample = []
    for t in trials:
        idx, pred = predict_torque_nm(plain_fit, t, subject, leg)
        in_sample.append((t.torque_nm[idx] - pred) ** 2)
    in_sample_rms = float(np.sqrt(np.mean(np.concatenate(in_sample))))
    k = len(folds)
    # the jackknife over k folds has k − 1 degrees of freedom: with two repeats the 97.5 % point is
    # 12.7, not 1.96 (at 1.96 a 0.05 N·m knee offset on clean OpenSim trials looked significant)
    t975 = float(student_t.ppf(0.975, k - 1))
    full_fits: dict[str, tuple[dict[str, float], dict[str, float], FitStart]] = {}
    fold_found: dict[str, list[FitStart]] = {}

    def fit_folds(pool: _FitPool, keys: list[str | None], whole: WholeRule = None,
                  starts: dict[str, JobStarts] | None = None, here: dict[str, Any] | None = None) -> None:
        """Each candidate without each fold; then on every trial when ``whole``'s rule holds for it: the
        candidates whose parameters and the muscles' shifts are reported as such, those that predict the folds
        better (named, a close rival, a pair) or nearly as well as the plain model (absorbed by the muscles).
        The others are reported with their folds' mean parameters. ``here``: fit in this process, with these
        entries added to the pool's context (``built``: problems already built, by candidate)."""
        jobs: list[FitJob] = [(key, folds, whole, (starts or {}).get(key or "none")) for key in keys]
        outcomes = pool.fits(jobs) if here is None else [_key_fits(j, {**pool.context, **here}) for j in jobs]
        for key, (per_fold, full) in zip(keys, outcomes, strict=True):
            for fold, (rms, ext_params, found) in zip(folds, per_fold):  # fewer when it stopped at a worse fold
                heldout.setdefault(key or "none", {})[fold.label] = rms
                fold_params.setdefault(key or "none", []).append(ext_params)
                fold_found.setdefault(key or "none", []).append(found)
            if full is not None and key is not None:
                full_fits[key] = full

    def ratio_to(name: str, reference: str) -> tuple[float, bool]:
        return fold_ratio(heldout[name], heldout[reference])

    def finding(ext: Extension) -> ExtensionFinding:
        if ext.name in full_fits:
            full_ext_params, full_params, _ = full_fits[ext.name]
            shift = {n: 100.0 * (full_params[n] / plain_fit.parameters[n] - 1.0) for n in plain_fit.parameters}
        else:  # not fitted whole (fit_whole): the folds' mean, and no shift to report
            full_ext_params = {p: float(np.mean([fp[p] for fp in fold_params[ext.name]])) for p in ext.parameters}
            shift = {}
        ci = {}
        for p in ext.parameters if len(fold_params[ext.name]) == k else ():  # stopped at a worse fold: no jackknife
            vals = np.array([fp[p] for fp in fold_params[ext.name]])
            se = math.sqrt((k - 1) / k * float(np.sum((vals - vals.mean()) ** 2)))
            ci[p] = (full_ext_params[p] - t975 * se, full_ext_params[p] + t975 * se)
        ratio, every = ratio_to(ext.name, "none")
        out = ExtensionFinding(ext.name, pooled(heldout[ext.name]), ratio, dict(full_ext_params), ci, shift,
                               heldout[ext.name])
        out.every_fold_better = every
        return out

    with _FitPool(trials, subject, leg, intervals, plain_fit.parameters, workers) as pool:
        fit_folds(pool, [None], here={"built": built} if built else None)
        if pooled(heldout["none"]) > INCONCLUSIVE_FACTOR * in_sample_rms:
            base = pooled(heldout["none"])  # the plain model's folds already show the trials cannot judge an extension
            return ModelDiagnosis("none", base, heldout["none"], [],
                                  f"inconclusive: the trials do not predict each other (held-out {base:.3g} N·m "
                                  f"against {in_sample_rms:.3g} N·m in sample): a left-out condition's muscles are not "
                                  "determined by the other conditions; record each condition at least twice so "
                                  "repeats can be left out", [f.label for f in folds], conclusive=False)
        fit_folds(pool, list(names), (dict(heldout["none"]), ABSORBED_RATIO, False))
        base = pooled(heldout["none"])
        findings = [finding(EXTENSIONS[n]) for n in names]
        passing = [f for f in findings if f.heldout_ratio < max_heldout_ratio and f.every_fold_better]
        close: list[str] = []
        if not passing:
            plausible = favoured([(f.name, *ratio_to(f.name, "none")) for f in findings])
            absorbed = [f for f in findings if f.heldout_ratio < ABSORBED_RATIO and is_material(f)]
            message = (f"no extension predicts the left-out trials better than {max_heldout_ratio:.0%} of the plain "
                       f"model's {base:.3f} N·m: the model fits to the noise of these trials")
            if absorbed:
                message += ("; but " + ", ".join(f.name for f in absorbed) + " fit(s) with parameters away from zero "
                            "and the muscles' parameters absorb them (they move: see below): "
                            + "; ".join(protocol_to_separate(f.name) for f in absorbed))
            return ModelDiagnosis("none", base, heldout["none"], findings, message, [f.label for f in folds],
                                  plausible=plausible)
        best = min(passing, key=lambda f: f.heldout_ratio)
        close = [f.name for f in passing if f is not best and f.heldout_ratio <= best.heldout_ratio * 1.05]
        # forward selection: every other candidate is added to the model named so far, and the one that predicts every
        # fold better than that model by the same margin is added, while one does (a subject is rarely wrong in one
        # way only: compliant tendons, a tone and end-range structures need all three). Not only those that pass
        # alone: the first can mask the second (compliant knee tendons beside a tonic activation predicted the folds
        # 0.92–0.95 of the plain model's alone)
        singles = list(findings)
        chosen = best
        steps = [best]
        plausible = []
        while True:
            current = get_extension(chosen.name)
            parts = chosen.name.split(JOIN)
            nexts = [combine(current, EXTENSIONS[f.name]) for f in singles if f.name not in parts
                     and (current.angle is None or EXTENSIONS[f.name].angle is None)]
            if not nexts:
                break
            # fitted whole only when it may be named (its folds better than the model so far's by the margin). The
            # problem has several basins: each fit starts from the plain fit and from where the model so far ended on
            # the same data (the added extension at its start), and keeps the lower objective, so the larger model
            # never ends above the smaller one's (from the plain fit alone, compliant tendons beside end-range
            # structures and a tone ended above the pair's cost and predicted the folds worse; from the smaller
            # model's alone, a tone beside end-range structures stayed in its basin)
            whole_so_far = full_fits.get(chosen.name)
            # submitted best single first: the likeliest to be fitted on every fold and whole, the longest job, so
            # it does not start last on a worker (the order of the jobs changes no fit)
            single_ratio = {f.name: f.heldout_ratio for f in singles}
            order: list[str] = sorted((e.name for e in nexts), key=lambda n: single_ratio[n.split(JOIN)[-1]])
            fit_folds(pool, list(order),
                      (dict(heldout[chosen.name]), max_heldout_ratio, True),
                      {e.name: ([[None, nested_start(f, EXTENSIONS[e.name.split(JOIN)[-1]])]
                                 for f in fold_found[chosen.name]],
                                [None] + ([nested_start(whole_so_far[2], EXTENSIONS[e.name.split(JOIN)[-1]])]
                                          if whole_so_far is not None else [])) for e in nexts})
            better = chosen
            step_ratios = []
            for e in nexts:
                findings.append(finding(e))
                ratio, every = ratio_to(e.name, chosen.name)
                step_ratios.append((e.name, ratio, every))
                if ratio < max_heldout_ratio and every and findings[-1].heldout_ratio < better.heldout_ratio:
                    better = findings[-1]
            if better is chosen:
                plausible = favoured(step_ratios)
                break
            chosen = better
            steps.append(better)
    chosen.named = True
    close = [n for n in close if n not in chosen.name.split(JOIN)]  # a close rival named beside the best is no rival
    step = "".join(f"; with {after.name.split(JOIN)[-1]} beside {'it' if i == 0 else 'them'} "
                   f"{before.heldout_rmse_nm:.3f} → {after.heldout_rmse_nm:.3f} N·m"
                   for i, (before, after) in enumerate(zip(steps, steps[1:])))
    message = (f"{chosen.name} ({get_extension(chosen.name).description}): held-out RMSE {base:.3f} → "
               f"{best.heldout_rmse_nm:.3f} N·m with {best.name} (ratio {best.heldout_ratio:.2f}){step}"
               + (f"; {', '.join(close)} predicts nearly as well as {best.name} (these trials do not separate them: "
                  + "; ".join(protocol_to_separate(n) for n in [best.name, *close]) + ")" if close else ""))
    return ModelDiagnosis(chosen.name, base, heldout["none"], findings, message, [f.label for f in folds],
                          ambiguous_with=close, named_fit=full_fits[chosen.name][2] if chosen.name in full_fits else None,
                          plausible=plausible)


__all__ = ["folds_of", "EXTENSIONS", "Extension", "combine", "get_extension",
           "ExtensionFinding", "ModelDiagnosis", "diagnose_model", "predict_torque_nm"]
