"""Model-level diagnosis of the passive-parameter fit: what the subject's musculoskeletal model gets wrong.

After a subject's fit, each candidate extension of the model is fitted *inside the estimator*
(its terms enter the collocation dynamics, its parameters are decision variables beside the
muscles') and judged by **held-out prediction across trials**: the model is fitted on all trials
but one condition and predicts the left-out condition's torque from its measured motion (inverse
dynamics, I·q̈ − M_muscles − M_gravity − M_extension); every condition is left out once. An
extension is named when it predicts every left-out fold better than the plain model and the
geometric mean of its per-fold RMSE ratios is below ``max_heldout_ratio``; the one with the lowest
wins. When the plain model's held-out error is many times its in-sample error the folds do not
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
  (≈ offset / lever; rad).

Sign convention as the estimator's: moments toward positive angle, q̇ in rad/s.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.stats import t as student_t

from .estimator import PmpResult, PmpTrial, Subject, _eliminate_tendons, _muscles_moment, estimate
from .muscles import LegMuscles

FRICTION_SPEED_RAD_S = math.radians(1.0)
#: when the plain model's held-out error is this many times its in-sample error, the folds do not
#: predict each other (a left-out condition's muscles are extrapolated) and nothing can be judged
INCONCLUSIVE_FACTOR = 5.0
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

    def moment(self, trial: PmpTrial, q: Any, v: Any, p: list[Any], gravity: Any) -> Any:
        return self.term(trial, q, v, p, gravity)

    def joint_angle(self, trial: PmpTrial, q: Any, p: list[Any]) -> Any:
        return self.angle(trial, q, p) if self.angle is not None else q


def _per_joint(trial: PmpTrial, p: list[Any], knee: int, ankle: int) -> Any:
    return p[knee] if trial.joint == "knee" else p[ankle]


def _misaligned(trial: PmpTrial, q: Any, p: list[Any]) -> Any:
    ca = _ca()
    a, b = (p[0], p[1]) if trial.joint == "knee" else (p[2], p[3])
    return q + a * ca.sin(q) + b * ca.cos(q)


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
]}


def is_material(finding: "ExtensionFinding") -> bool:
    """Whether any of the finding's parameters is away from zero (interval and size; :data:`MATERIAL_FRACTION`)."""
    ext = EXTENSIONS.get(finding.name)
    smallest = {}
    if ext:
        smallest = dict(zip(ext.parameters, ext.material or tuple(MATERIAL_FRACTION * v for v in ext.typical)))
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

    def winner(self) -> ExtensionFinding | None:
        return next((c for c in self.candidates if c.name == self.cause), None)

    def text(self) -> str:
        lines = [f"model-level diagnosis (held-out across {len(self.folds)} conditions): {self.message}",
                 f"  {'extension':<20}{'held-out RMSE':>15}{'ratio':>8}  parameters (95 % jackknife interval)"]
        lines.append(f"  {'none':<20}{self.plain_heldout_rmse_nm:>13.3f} N·m{1.0:>8.2f}")
        for c in sorted(self.candidates, key=lambda c: c.heldout_ratio):
            ps = ", ".join(f"{k} = {v:.3g} [{c.ci95[k][0]:.3g}, {c.ci95[k][1]:.3g}]" for k, v in c.parameters.items()
                           if k in c.ci95)
            lines.append(f"  {c.name:<20}{c.heldout_rmse_nm:>13.3f} N·m{c.heldout_ratio:>8.2f}  {ps}"
                         + ("  ← named" if c.named else ""))
        w = self.winner() or next((c for c in sorted(self.candidates, key=lambda c: c.heldout_ratio)
                                   if is_material(c)), None)
        if w is not None:
            moved = sorted(w.parameter_shift_pct.items(), key=lambda kv: -abs(kv[1]))[:5]
            lines.append(f"  with {w.name}, the passive parameters move: " + ", ".join(f"{k} {v:+.1f} %" for k, v in moved))
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return {"cause": self.cause, "message": self.message, "folds": self.folds, "conclusive": self.conclusive,
                "ambiguous_with": self.ambiguous_with,
                "plain_heldout_rmse_Nm": self.plain_heldout_rmse_nm, "plain_fold_rmse_Nm": self.plain_fold_rmse_nm,
                "candidates": [{"name": c.name, "heldout_rmse_Nm": c.heldout_rmse_nm, "heldout_ratio": c.heldout_ratio,
                                "parameters": c.parameters, "ci95": {k: list(v) for k, v in c.ci95.items()},
                                "parameter_shift_pct": c.parameter_shift_pct, "fold_rmse_Nm": c.fold_rmse_nm,
                                "named": c.named} for c in self.candidates]}


def predict_torque_nm(result: PmpResult, trial: PmpTrial, subject: Subject, leg: LegMuscles,
                      extension: Extension | None = None, points: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """(sample indices, predicted dynamometer torque N·m) for ``trial`` from its measured motion and the
    fitted model: u = I·q̈ − M_muscles − M_gravity − M_extension (inverse dynamics)."""
    ca = _ca()
    idx = np.unique(np.linspace(0, trial.time_s.size - 1, min(points, trial.time_s.size)).astype(int))
    q_s, v_s = ca.SX.sym("q"), ca.SX.sym("v")
    ext = [result.extension_parameters[n] for n in extension.parameters] if extension is not None else []
    q_joint = extension.joint_angle(trial, q_s, ext) if extension is not None else q_s
    moment, residuals, lts = _muscles_moment(leg, trial, q_joint, result.parameters)
    muscles = _eliminate_tendons(moment, residuals, lts, [q_s])
    if extension is not None and extension.angle is not None:
        muscles = muscles * ca.jacobian(q_joint, q_s)
    gravity = subject.gravity_moment_nm(trial.joint, q_s, trial.fixed_rad, ca.cos)
    total = gravity + muscles + (extension.moment(trial, q_s, v_s, ext, gravity) if extension is not None else 0)
    f = ca.Function("m", [q_s, v_s], [total]).map(idx.size)
    m = np.asarray(f(trial.angle_rad[idx][None, :], trial.velocity_rad_s[idx][None, :])).ravel()
    acc = np.gradient(trial.velocity_rad_s, trial.time_s)[idx]
    return idx, subject.inertia_kgm2(trial.joint) * acc - m


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


def diagnose_model(trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None, intervals: int = 24,
                   candidates: list[str] | None = None, max_heldout_ratio: float = 0.9,
                   plain: PmpResult | None = None) -> ModelDiagnosis:
    """Try every candidate extension inside the estimator and judge it by leave-one-condition-out prediction.

    Parameters
    ----------
    trials
        The subject's trials: with repeats, each repeat of every condition is left out in turn; without,
        each condition (moving joint and fixed angles) is (:func:`folds_of`).
    intervals
        Collocation intervals per trial in every fit.
    max_heldout_ratio
        An extension is named when its pooled held-out RMSE is below this fraction of the plain model's.
    plain
        The plain model's fit on all trials, if already made.
    """
    from ..errors import InputError

    folds = folds_of(trials)
    if len(folds) < 2 or len(trials) < 3:
        raise InputError(f"the model-level diagnosis needs repeats or at least 3 conditions; got {len(trials)} "
                         f"trial(s) in {len(folds)} fold(s)")
    leg = leg or LegMuscles()
    names = candidates or list(EXTENSIONS)
    models: list[Extension | None] = [None] + [EXTENSIONS[n] for n in names]
    plain_fit = plain or estimate(trials, subject, leg=leg, intervals=intervals)
    heldout: dict[str, dict[str, float]] = {}
    fold_params: dict[str, list[dict[str, float]]] = {}
    def pooled(errs: dict[str, float]) -> float:
        return float(np.sqrt(np.mean(np.square(list(errs.values())))))

    in_sample = []
    for t in trials:
        idx, pred = predict_torque_nm(plain_fit, t, subject, leg)
        in_sample.append((t.torque_nm[idx] - pred) ** 2)
    in_sample_rms = float(np.sqrt(np.mean(np.concatenate(in_sample))))
    for ext in models:
        key = ext.name if ext else "none"
        errs: dict[str, float] = {}
        fold_params[key] = []
        for label, left in folds:
            fit = estimate([t for j, t in enumerate(trials) if j not in left], subject, leg=leg, intervals=intervals,
                           extension=ext, initial=plain_fit.parameters)
            sq = []
            for j in left:
                idx, pred = predict_torque_nm(fit, trials[j], subject, leg, ext)
                sq.append((trials[j].torque_nm[idx] - pred) ** 2)
            errs[label] = float(np.sqrt(np.mean(np.concatenate(sq))))
            fold_params[key].append(dict(fit.extension_parameters))
        heldout[key] = errs
        if ext is None and pooled(errs) > INCONCLUSIVE_FACTOR * in_sample_rms:
            base = pooled(errs)  # the plain model's folds already show the trials cannot judge an extension
            return ModelDiagnosis("none", base, errs, [],
                                  f"inconclusive: the trials do not predict each other (held-out {base:.3g} N·m against "
                                  f"{in_sample_rms:.3g} N·m in sample): a left-out condition's muscles are not determined "
                                  "by the other conditions; record each condition at least twice so repeats can be left "
                                  "out", [label for label, _ in folds], conclusive=False)

    base = pooled(heldout["none"])
    findings = []
    for ext in models[1:]:
        assert ext is not None
        full = estimate(trials, subject, leg=leg, intervals=intervals, extension=ext, initial=plain_fit.parameters)
        k = len(folds)
        # the jackknife over k folds has k − 1 degrees of freedom: with two repeats the 97.5 % point is
        # 12.7, not 1.96 (at 1.96 a 0.05 N·m knee offset on clean OpenSim trials looked significant)
        t975 = float(student_t.ppf(0.975, k - 1))
        ci = {}
        for p in ext.parameters:
            vals = np.array([fp[p] for fp in fold_params[ext.name]])
            se = math.sqrt((k - 1) / k * float(np.sum((vals - vals.mean()) ** 2)))
            ci[p] = (full.extension_parameters[p] - t975 * se, full.extension_parameters[p] + t975 * se)
        shift = {n: 100.0 * (full.parameters[n] / plain_fit.parameters[n] - 1.0) for n in plain_fit.parameters}
        rmse = pooled(heldout[ext.name])
        # the ratio is the geometric mean of the folds' ratios: one fold whose left-out trial is badly
        # extrapolated must not outweigh the others
        ratios = [heldout[ext.name][k] / heldout["none"][k] for k in heldout["none"] if heldout["none"][k] > 0]
        findings.append(ExtensionFinding(ext.name, rmse, float(np.exp(np.mean(np.log(ratios)))) if ratios else float("nan"),
                                         dict(full.extension_parameters), ci, shift, heldout[ext.name]))
        findings[-1].every_fold_better = bool(ratios) and all(r < 1.0 for r in ratios)
    passing = [f for f in findings if f.heldout_ratio < max_heldout_ratio and f.every_fold_better]
    close: list[str] = []
    if passing:
        best = min(passing, key=lambda f: f.heldout_ratio)
        best.named = True
        close = [f.name for f in passing if f is not best and f.heldout_ratio <= best.heldout_ratio * 1.05]
        message = (f"{best.name} ({EXTENSIONS[best.name].description}): held-out RMSE {base:.3f} → "
                   f"{best.heldout_rmse_nm:.3f} N·m (ratio {best.heldout_ratio:.2f})"
                   + (f"; {', '.join(close)} predict nearly as well (these trials do not separate them: "
                      + "; ".join(PROTOCOL_TO_SEPARATE.get(n, "another protocol") for n in [best.name, *close]) + ")"
                      if close else ""))
        cause = best.name
    else:
        absorbed = [f for f in findings if f.heldout_ratio < 1.05 and is_material(f)]
        message = (f"no extension predicts the left-out trials better than {max_heldout_ratio:.0%} of the plain "
                   f"model's {base:.3f} N·m: the model fits to the noise of these trials")
        if absorbed:
            message += ("; but " + ", ".join(f.name for f in absorbed) + " fit(s) with parameters away from zero and "
                        "the muscles' parameters absorb them (they move: see below): "
                        + "; ".join(PROTOCOL_TO_SEPARATE.get(f.name, "another protocol") for f in absorbed))
        cause = "none"
    return ModelDiagnosis(cause, base, heldout["none"], findings, message, [label for label, _ in folds],
                          ambiguous_with=close)


__all__ = ["folds_of", "EXTENSIONS", "Extension", "ExtensionFinding", "ModelDiagnosis", "diagnose_model", "predict_torque_nm"]
