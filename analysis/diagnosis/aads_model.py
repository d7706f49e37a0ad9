"""Model-level diagnosis of the AADS simulation: what the AFO model gets wrong, judged across trials.

The AADS pipeline's model of the orthosis is its spring: the torque the static optimisation
recovers should be the spring's torque at the hinge angle, S(θ), known from the hook markers
(theory, eqs 2.1–2.9). Where it is not, candidate extensions of that model, with parameters
shared by all trials of one AFO, are fitted and judged by **held-out prediction across trials**:
fitted on all trials but one, they predict the left-out trial's torque in the fit window; every
trial is left out once. Each trial keeps its own torque zero (a nuisance fitted on that trial
alone, for every model alike).

Extensions (``θ`` the marker angle, ``τ`` the SOP torque, ``ω`` the angular velocity):

- ``hinge_friction``: + (f₀ + μ·S)·tanh(ω/ω_s), a constant plus a load-proportional friction at
  the hinge (N·m and N·m per N·m of spring torque; the width ω_s fitted, 0.25–4 °/s);
- ``shell_compliance``: the hinge turns by θ − c·τ, the shell bending by c·τ (c in °/N·m);
- ``axis_misalignment``: the markers' plane off the hinge's axis turns the hinge by (1 + a)·θ
  (a: the relative angle scale error);
- ``early_stop``: + k_s·max(θ − θ_s, 0), a hinge stop misadjusted to engage inside the fit window
  (θ_s searched 8–20°, k_s ≥ 0 in N·m/°): the stiffness fit then reads the stop, not the spring.

The two extensions that change the hinge angle (shell compliance, axis misalignment) have their
parameters read from the angles: the hook markers sit on the hinge and read its angle, so the
marker angle is regressed on the hook angle and the torque (:func:`_angle_fit`); the others
(friction, stop) and each trial's zero are fitted to the torque. Every model is judged on the
torque it predicts.

Selection is forward: the extension predicting the left-out trials best is named when it
predicts every left-out trial better and the geometric mean of the RMSE ratios is below
``max_heldout_ratio``; a second joins when, beside the first, it passes the same test against the
first alone. Parameters get jackknife intervals over the left-out trials (Student's t, k − 1
degrees of freedom). The report also gives the loading-branch stiffness error against the spring,
raw and with the named effects removed, as Table 2.1 would show it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.stats import t as student_t

from ..aads.stiffness import line_fit
from ..errors import InputError
from .causes import FRICTION_WIDTHS_RAD_S

EXTENSIONS: dict[str, str] = {
    "hinge_friction": "friction at the hinge, constant plus proportional to the spring load",
    "shell_compliance": "the shell bends under load: the hinge turns less than the markers say",
    "axis_misalignment": "the markers' plane is off the hinge's axis: the angle is scaled",
    "early_stop": "the hinge stop engages inside the fit window: the AFO stiffens before its stop angle",
}
PARAMETERS: dict[str, tuple[str, ...]] = {
    "hinge_friction": ("friction_Nm", "friction_per_spring_torque", "friction_width_deg_s"),
    "shell_compliance": ("compliance_deg_per_Nm",),
    "axis_misalignment": ("angle_scale_error",),
    "early_stop": ("stop_angle_deg", "stop_stiffness_Nm_per_deg"),
}
#: the stop angles tried (a bounded refinement follows)
STOP_ANGLE_GRID_DEG = np.arange(8.0, 20.01, 0.5)
PROTOCOL_TO_SEPARATE = {
    frozenset({"shell_compliance", "axis_misalignment"}):
        "bend springs of different stiffness: the shell's share grows with the load, a scale error does not",
}


@dataclass(frozen=True)
class AfoTrialData:
    """One AADS trial as the model-level diagnosis needs it (degrees, N·m, °/s)."""

    angle_deg: np.ndarray
    velocity_deg_s: np.ndarray
    torque_nm: np.ndarray          # the SOP (AFO) torque
    spring_torque_nm: np.ndarray   # the spring's torque from the hook markers (theory)
    hook_angle_deg: np.ndarray     # the hinge angle the theory is computed at
    label: str = ""

    @classmethod
    def from_result(cls, result: Any, label: str = "") -> AfoTrialData:
        """From an :func:`analysis.aads.analyze_trial` result that has its theory."""
        if getattr(result, "theory", None) is None:
            raise InputError("the model-level AFO diagnosis needs the spring's theory (the hook markers) in every trial")
        return cls(np.asarray(result.angle_deg, float), np.asarray(result.velocity_deg_s, float),
                   np.asarray(result.afo_torque_nm, float), np.asarray(result.theory.torque_nm, float),
                   np.asarray(result.theory.angle_deg, float), label)


@dataclass
class _Prepared:
    angle: np.ndarray
    omega: np.ndarray      # rad/s
    torque: np.ndarray
    spring: np.ndarray     # quadratic coefficients of S(θ) (θ in °)
    window: tuple[float, float]
    hook: np.ndarray       # the hinge angle the hook markers read (°)

    def columns(self, names: tuple[str, ...], nl: dict[str, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(target, design, in-window mask): torque − S(hinge angle) against [zero, extension terms]."""
        hinge = self.angle.copy()
        if "shell_compliance" in names:
            hinge = hinge - nl["shell_compliance"] * self.torque
        if "axis_misalignment" in names:
            hinge = hinge * (1.0 + nl["axis_misalignment"])
        s = np.polyval(self.spring, hinge)
        cols = [np.ones_like(s)]
        if "hinge_friction" in names:
            sign = np.tanh(self.omega / nl["hinge_friction"])
            cols += [sign, s * sign]
        if "early_stop" in names:
            cols.append(np.maximum(hinge - nl["early_stop"], 0.0))
        inside = (self.angle >= self.window[0]) & (self.angle <= self.window[1])
        return self.torque - s, np.column_stack(cols), inside


def _prepare(trial: AfoTrialData, window: tuple[float, float]) -> _Prepared:
    ok = (np.isfinite(trial.angle_deg) & np.isfinite(trial.velocity_deg_s) & np.isfinite(trial.torque_nm)
          & np.isfinite(trial.spring_torque_nm) & np.isfinite(trial.hook_angle_deg))
    a, h = trial.angle_deg[ok], trial.hook_angle_deg[ok]
    near = (h >= window[0] - 2.0) & (h <= window[1] + 2.0)
    inside = (a >= window[0]) & (a <= window[1])
    if near.sum() < 10 or inside.sum() < 10:
        raise InputError(f"trial {trial.label or '?'} does not cover the fit window {window[0]:g}–{window[1]:g}°")
    spring = np.polyfit(h[near], trial.spring_torque_nm[ok][near], 2)
    return _Prepared(a, np.deg2rad(trial.velocity_deg_s[ok]), trial.torque_nm[ok], spring, window, h)


#: the extensions that change the hinge angle: estimated from the hook markers' angle (see _angle_fit)
ANGLE_EXTENSIONS = ("shell_compliance", "axis_misalignment")


def _angle_fit(trials: list[_Prepared], names: tuple[str, ...]) -> dict[str, float]:
    """The angle-changing extensions' parameters from the angles themselves, shared by ``trials``.

    The hook markers read the hinge angle h; the model says h = (1 + a)·(θ − c·τ), i.e.
    θ = h/(1 + a) + c·τ: a least-squares fit of the marker angle θ on [h, τ] with a zero per trial
    (samples whose hinge angle is in the window). Fitted instead through the torque, c is read from
    the few per cent by which the shell lowers the apparent stiffness, so a 0.1 % error of the
    spring curve or the marker angle's noise moves it tens of times as much: on the benchmark's
    shell trials the torque fit came out 2.3 % low on average at 0.2 mm marker noise (1.1 % at
    0.1 mm, 0.3 % without) with jackknife intervals holding the truth in 5 of 12 sets; read from the
    angles it came out 0.4 % low."""
    fit = [n for n in ANGLE_EXTENSIONS if n in names]
    if not fit:
        return {}
    rows, ys = [], []
    for i, p in enumerate(trials):
        m = (p.hook >= p.window[0]) & (p.hook <= p.window[1])
        zero = np.zeros((int(m.sum()), len(trials)))
        zero[:, i] = 1.0
        cols = [zero]
        if "axis_misalignment" in names:
            cols.append(p.hook[m][:, None])
        if "shell_compliance" in names:
            cols.append(p.torque[m][:, None])
        rows.append(np.hstack(cols))
        # without an axis term the hinge angle's own coefficient is 1: it moves to the left
        ys.append(p.angle[m] - (0.0 if "axis_misalignment" in names else p.hook[m]))
    coef = np.linalg.lstsq(np.vstack(rows), np.concatenate(ys), rcond=None)[0][len(trials):]
    out: dict[str, float] = {}
    if "axis_misalignment" in names:
        out["axis_misalignment"] = float(1.0 / coef[0] - 1.0)
    if "shell_compliance" in names:
        out["shell_compliance"] = max(float(coef[-1]), 0.0)  # a shell only gives way
    return out


def _grids(names: tuple[str, ...]) -> list[dict[str, float]]:
    out: list[dict[str, float]] = [{}]
    if "hinge_friction" in names:  # the tanh's width: dry friction to a gradual (Stribeck) change of sign
        out = [{**o, "hinge_friction": float(w)} for o in out for w in FRICTION_WIDTHS_RAD_S]
    if "early_stop" in names:
        out = [{**o, "early_stop": float(a)} for o in out for a in STOP_ANGLE_GRID_DEG]
    return out


def _solve(trials: list[_Prepared], names: tuple[str, ...], nl: dict[str, float]) -> tuple[float, np.ndarray]:
    """Least squares at fixed nonlinear parameters: (RSS, the shared linear coefficients)."""
    blocks = [p.columns(names, nl) for p in trials]
    # design: one zero per trial, then the shared columns (friction's two)
    n_shared = blocks[0][1].shape[1] - 1
    rows, ys = [], []
    for i, (y, x, m) in enumerate(blocks):
        zero = np.zeros((int(m.sum()), len(trials)))
        zero[:, i] = 1.0
        rows.append(np.hstack([zero, x[m][:, 1:]]))
        ys.append(y[m])
    design, target = np.vstack(rows), np.concatenate(ys)
    coef, *_ = np.linalg.lstsq(design, target, rcond=None)
    if "early_stop" in names and coef[-1] < 0.0:  # a stop resists: a pulling one is held at zero
        coef = np.append(np.linalg.lstsq(design[:, :-1], target, rcond=None)[0], 0.0)
    r = target - design @ coef
    return float(r @ r), coef[len(trials):len(trials) + n_shared]


def _fit(trials: list[_Prepared], names: tuple[str, ...]) -> tuple[float, dict[str, float], np.ndarray]:
    """Shared extension parameters over ``trials`` (each with its own zero): (RSS, nonlinear, linear shared).

    The angle-changing parameters (compliance, angle scale) from the angles (:func:`_angle_fit`);
    the others (friction width, stop angle) by a grid, then a bounded refinement of each within one
    grid step, so that the folds' estimates, and so the intervals, are not quantised to the grid."""
    fixed = _angle_fit(trials, names)
    best: tuple[float, dict[str, float]] = (math.inf, {})
    for nl in _grids(names):
        rss, _ = _solve(trials, names, {**nl, **fixed})
        if rss < best[0]:
            best = (rss, nl)
    nl = dict(best[1])
    step = float(np.diff(STOP_ANGLE_GRID_DEG)[0])
    for _ in range(2 if len(nl) > 1 else 1):
        for key in list(nl):
            if key == "hinge_friction":  # the width between its grid neighbours (a factor of 2 apart)
                lo, hi = 0.5 * nl[key], 2.0 * nl[key]
            else:
                lo, hi = nl[key] - step, nl[key] + step
            res = minimize_scalar(lambda v, key=key: _solve(trials, names, {**nl, **fixed, key: float(v)})[0],
                                  bounds=(lo, hi), method="bounded", options={"xatol": 1e-7})
            if res.fun <= _solve(trials, names, {**nl, **fixed})[0]:
                nl[key] = float(res.x)
    nl.update(fixed)
    rss, shared = _solve(trials, names, nl)
    return rss, nl, shared


def _predict_rmse(trial: _Prepared, names: tuple[str, ...], nl: dict[str, float], shared: np.ndarray) -> float:
    """RMSE (N·m) of the left-out trial in the window, its own zero fitted (the only free number)."""
    y, x, m = trial.columns(names, nl)
    r = y[m] - x[m][:, 1:] @ shared
    r = r - r.mean()
    return float(np.sqrt(np.mean(r**2)))


def _named_parameters(names: tuple[str, ...], nl: dict[str, float], shared: np.ndarray) -> dict[str, float]:
    out: dict[str, float] = {}
    if "hinge_friction" in names:
        out["friction_Nm"], out["friction_per_spring_torque"] = float(shared[0]), float(shared[1])
        out["friction_width_deg_s"] = float(np.rad2deg(nl["hinge_friction"]))
    if "shell_compliance" in names:
        out["compliance_deg_per_Nm"] = nl["shell_compliance"]
    if "axis_misalignment" in names:
        out["angle_scale_error"] = nl["axis_misalignment"]
    if "early_stop" in names:
        out["stop_angle_deg"], out["stop_stiffness_Nm_per_deg"] = nl["early_stop"], float(shared[-1])
    return out


@dataclass
class AfoModelFinding:
    """One model (an extension or a pair) as judged on the left-out trials."""

    names: tuple[str, ...]
    heldout_rmse_nm: float
    heldout_ratio: float               # geometric mean of the per-trial RMSE ratios to the reference
    every_trial_better: bool
    parameters: dict[str, float]
    ci95: dict[str, tuple[float, float]]


@dataclass
class AfoModelDiagnosis:
    """What the AFO model gets wrong: ``named`` extensions (empty: the spring model fits to the noise)."""

    named: list[str]
    plain_heldout_rmse_nm: float
    candidates: list[AfoModelFinding]
    stiffness_error_raw_pct: float
    stiffness_error_corrected_pct: float
    message: str
    trials: int
    separate_by: list[str] = field(default_factory=list)
    #: extensions predicting the left-out trials within 5 % as well as the first named one
    ambiguous_with: list[str] = field(default_factory=list)

    def text(self) -> str:
        lines = [f"AFO model-level diagnosis (held-out across {self.trials} trials): {self.message}",
                 f"  {'model':<36}{'held-out RMSE':>15}{'ratio':>8}  parameters (95 % jackknife interval)",
                 f"  {'spring only':<36}{self.plain_heldout_rmse_nm:>11.3f} N·m{1.0:>8.2f}"]
        for c in self.candidates:
            # a stop held at zero stiffness has no angle to report
            shown = {k: v for k, v in c.parameters.items()
                     if not (k == "stop_angle_deg" and c.parameters.get("stop_stiffness_Nm_per_deg") == 0.0)}
            ps = ", ".join(f"{k} = {v:.3g} [{c.ci95[k][0]:.3g}, {c.ci95[k][1]:.3g}]" for k, v in shown.items())
            if len(shown) < len(c.parameters):
                ps += " (no stop engages in the window)"
            lines.append(f"  {' + '.join(c.names):<36}{c.heldout_rmse_nm:>11.3f} N·m{c.heldout_ratio:>8.2f}  {ps}")
        lines.append(f"  loading-branch stiffness error against the spring: {self.stiffness_error_raw_pct:+.1f} % raw, "
                     f"{self.stiffness_error_corrected_pct:+.1f} % with the named effects removed")
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return {"named": self.named, "message": self.message, "trials": self.trials,
                "plain_heldout_rmse_Nm": self.plain_heldout_rmse_nm,
                "stiffness_error_raw_pct": self.stiffness_error_raw_pct,
                "stiffness_error_corrected_pct": self.stiffness_error_corrected_pct, "separate_by": self.separate_by,
                "ambiguous_with": self.ambiguous_with,
                "candidates": [{"names": list(c.names), "heldout_rmse_Nm": c.heldout_rmse_nm,
                                "heldout_ratio": c.heldout_ratio, "every_trial_better": c.every_trial_better,
                                "parameters": c.parameters, "ci95": {k: list(v) for k, v in c.ci95.items()}}
                               for c in self.candidates]}


def _judge(prep: list[_Prepared], names: tuple[str, ...], reference: list[float]) -> tuple[AfoModelFinding, list[float]]:
    k = len(prep)
    folds, fold_params = [], []
    for i in range(k):
        _, nl, shared = _fit([p for j, p in enumerate(prep) if j != i], names)
        folds.append(_predict_rmse(prep[i], names, nl, shared))
        fold_params.append(_named_parameters(names, nl, shared))
    _, nl, shared = _fit(prep, names)
    full = _named_parameters(names, nl, shared)
    t975 = float(student_t.ppf(0.975, k - 1))
    ci = {}
    for p, v in full.items():
        vals = np.array([fp[p] for fp in fold_params])
        se = math.sqrt((k - 1) / k * float(np.sum((vals - vals.mean()) ** 2)))
        ci[p] = (v - t975 * se, v + t975 * se)
    ratios = [f / r for f, r in zip(folds, reference) if r > 0]
    return AfoModelFinding(names, float(np.sqrt(np.mean(np.square(folds)))), float(np.exp(np.mean(np.log(ratios)))),
                           all(x < 1.0 for x in ratios), full, ci), folds


def _stiffness_error_pct(trials: list[AfoTrialData], names: tuple[str, ...], params: dict[str, float],
                         window: tuple[float, float], min_speed_deg_s: float = 2.0) -> float:
    """Mean loading-branch stiffness error (%) against the spring, with the ``names`` effects removed."""
    errs = []
    for t in trials:
        ok = np.isfinite(t.angle_deg) & np.isfinite(t.torque_nm) & np.isfinite(t.velocity_deg_s) & \
            np.isfinite(t.spring_torque_nm) & np.isfinite(t.hook_angle_deg)
        a, v, tq = t.angle_deg[ok], t.velocity_deg_s[ok], t.torque_nm[ok]
        h, s = t.hook_angle_deg[ok], t.spring_torque_nm[ok]
        inside = (h >= window[0]) & (h <= window[1])
        k_theory = line_fit(h[inside], s[inside], window).slope_nm_per_deg
        if "hinge_friction" in names:
            spring = np.polyfit(h[(h >= window[0] - 2) & (h <= window[1] + 2)], s[(h >= window[0] - 2) & (h <= window[1] + 2)], 2)
            sign = np.tanh(np.deg2rad(v) / np.deg2rad(params["friction_width_deg_s"]))
            tq = tq - (params["friction_Nm"] + params["friction_per_spring_torque"] * np.polyval(spring, a)) * sign
        if "shell_compliance" in names:
            a = a - params["compliance_deg_per_Nm"] * t.torque_nm[ok]
        if "axis_misalignment" in names:
            a = a * (1.0 + params["angle_scale_error"])
        if "early_stop" in names:
            tq = tq - params["stop_stiffness_Nm_per_deg"] * np.maximum(a - params["stop_angle_deg"], 0.0)
        load = (a >= window[0]) & (a <= window[1]) & (v > min_speed_deg_s)
        errs.append(100.0 * (line_fit(a[load], tq[load], window).slope_nm_per_deg / k_theory - 1.0))
    return float(np.mean(errs))


def diagnose_afo_model(trials: list[AfoTrialData], *, window_deg: tuple[float, float] = (6.0, 20.0),
                       candidates: list[str] | None = None, max_heldout_ratio: float = 0.9) -> AfoModelDiagnosis:
    """Fit each extension of the spring model across ``trials`` of one AFO and judge it by leave-one-trial-out.

    Parameters
    ----------
    trials
        Trials of the same orthosis (its properties are shared), at least three.
    window_deg
        The AADS fit window (°): the jig model's.
    max_heldout_ratio
        An extension is named when it predicts every left-out trial better and the geometric mean of
        its RMSE ratios is below this.

    :raises InputError: fewer than three trials, or a trial not covering the window.
    """
    if len(trials) < 3:
        raise InputError(f"the AFO model-level diagnosis needs at least 3 trials of one AFO; got {len(trials)}")
    names = candidates or list(EXTENSIONS)
    prep = [_prepare(t, window_deg) for t in trials]
    plain, plain_folds = _judge(prep, (), [1.0] * len(prep))
    singles = {n: _judge(prep, (n,), plain_folds) for n in names}
    found = [f for f, _ in singles.values()]
    passing = [n for n in names if singles[n][0].every_trial_better and singles[n][0].heldout_ratio < max_heldout_ratio]
    named: tuple[str, ...] = ()
    separate: list[str] = []
    if passing:
        first = min(passing, key=lambda n: singles[n][0].heldout_ratio)
        named = (first,)
        best_pair: tuple[float, tuple[str, ...]] | None = None
        for other in names:
            if other == first:
                continue
            pair, _ = _judge(prep, (first, other), singles[first][1])
            found.append(pair)
            if pair.every_trial_better and pair.heldout_ratio < max_heldout_ratio and \
                    (best_pair is None or pair.heldout_ratio < best_pair[0]):
                best_pair = (pair.heldout_ratio, (first, other))
        if best_pair is not None:
            named = best_pair[1]
        close = [n for n in passing if n not in named
                 and singles[n][0].heldout_ratio <= 1.05 * singles[first][0].heldout_ratio]
        for n in close:
            hint = PROTOCOL_TO_SEPARATE.get(frozenset({first, n}))
            if hint:
                separate.append(hint)
    chosen = next((f for f in found if f.names == named), None)
    raw = _stiffness_error_pct(trials, (), {}, window_deg)
    corrected = _stiffness_error_pct(trials, named, chosen.parameters, window_deg) if chosen else raw
    ambiguous = [n for n in passing if n not in named
                 and singles[n][0].heldout_ratio <= 1.05 * singles[named[0]][0].heldout_ratio] if named else []
    def gain_text() -> str:
        assert chosen is not None  # an extension is named only when one was chosen
        return (f": held-out RMSE {plain.heldout_rmse_nm:.3f} → {chosen.heldout_rmse_nm:.3f} N·m "
                f"(ratio {chosen.heldout_ratio:.2f} against the spring alone)")

    if named and ambiguous:
        message = (f"{named[0]} or {', '.join(ambiguous)} (these trials cannot separate them: "
                   + "; ".join(separate or ["another protocol"]) + "); "
                   + " and ".join(f"{n} ({EXTENSIONS[n]})" for n in named)
                   + gain_text())
    elif named:
        message = (" and ".join(f"{n} ({EXTENSIONS[n]})" for n in named)
                   + gain_text())
    else:
        message = (f"no extension predicts the left-out trials better than {max_heldout_ratio:.0%} of the spring "
                   f"model's {plain.heldout_rmse_nm:.3f} N·m: the spring model fits to the noise of these trials")
    return AfoModelDiagnosis(list(named), plain.heldout_rmse_nm, found, raw, corrected, message, len(trials), separate,
                             ambiguous)


__all__ = ["AfoTrialData", "AfoModelDiagnosis", "AfoModelFinding", "diagnose_afo_model", "EXTENSIONS"]
