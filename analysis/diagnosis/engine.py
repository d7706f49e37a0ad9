"""Diagnose a trial: fit the baseline, try every candidate cause, choose by held-out error and an honest criterion.

Selection, in order:

1. every candidate is fitted jointly with the baseline (least squares; nonlinear parameters by a
   grid and a bounded refinement);
2. held-out error: the trial is cut into ``folds`` contiguous time blocks; each block is
   predicted by the model fitted on the others (neighbouring samples are correlated, so random
   splits would flatter every model). A transient cause (a burst) cannot be predicted from other
   blocks, so for it only the criterion below decides;
3. criterion: BIC with the effective sample size n_eff = n / τ, τ the integrated autocorrelation
   time of the best model's residual (neighbouring samples are not independent evidence);
4. a cause is accepted when it lowers the criterion by more than ``min_delta_bic`` against the
   baseline and (unless transient) lowers the held-out RMSE to below ``max_heldout_ratio`` of the
   baseline's; the accepted cause with the lowest criterion wins, otherwise ``none``;
5. a cause whose effect the baseline can mimic (R² > ``max_absorbed_r2`` of its effect direction
   on the baseline basis) is not testable in this trial: it is never named, and the report says
   what the trial would need;
6. a trial may carry two effects: pairs of the three best-fitting causes are fitted too; a second
   cause joins the winner when the pair passes the same two tests against the winner alone;
7. accepted causes whose fitted effects are nearly the same curve (correlation > 0.9) within
   ``ambiguity_bic`` of the winner, or whose RMSE is within ``ambiguity_rmse`` (5 %) of it (a
   difference no real trial's unmodelled detail would leave intact), make the result ambiguous: the report names them and the
   protocol change that would separate them, rather than guessing.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from .causes import ARGUMENT_CAUSES, CAUSES, SEPARATE_BY, UNTESTABLE_HINT, Cause, Prepared, baseline_columns, compound
from .data import DiagnosisTrial


@dataclass
class CauseFit:
    """One model fitted to (part of) a trial."""

    cause: str
    nonlinear: tuple[float, ...]
    coef: np.ndarray
    n_base: int
    prediction: np.ndarray     # torque prediction (N·m), with the known gravity added back; NaN where invalid
    rss: float
    n: int
    params: dict[str, float]

    @property
    def n_params(self) -> int:
        return self.coef.size + len(self.nonlinear)


def _solve(prep: Prepared, cause: Cause, nl: tuple[float, ...], mask: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, int, np.ndarray]:
    base, ext, valid = cause.columns(prep, nl)
    x = np.hstack([base, ext])
    use = mask & valid
    xs = x[use]
    scale = np.maximum(np.abs(xs).max(axis=0), 1e-12)
    xs = xs / scale
    y = prep.target[use]
    try:  # normal equations on scaled columns: ~30× faster than an SVD solve, accurate to ~1e-8 here
        coef = np.linalg.solve(xs.T @ xs, xs.T @ y)
        if not np.all(np.isfinite(coef)):
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:
        coef, *_ = np.linalg.lstsq(xs, y, rcond=None)
    signs = np.zeros(x.shape[1])
    signs[base.shape[1]:base.shape[1] + len(cause.signs)] = cause.signs
    held = np.zeros(x.shape[1], dtype=bool)
    while np.any(signs * coef < 0):  # a passive cause with the wrong sign: its best physical value is 0
        held |= signs * coef < 0     # (active set: the convex optimum lies on that bound)
        free = ~held
        coef = np.zeros(x.shape[1])
        sub = xs[:, free]
        try:
            coef[free] = np.linalg.solve(sub.T @ sub, sub.T @ y)
        except np.linalg.LinAlgError:
            coef[free] = np.linalg.lstsq(sub, y, rcond=None)[0]
    coef = coef / scale
    pred = x @ coef
    rss = float(np.sum((prep.target[use] - pred[use]) ** 2))
    return rss, coef, np.where(valid, pred, np.nan), base.shape[1], use


def fit_cause(prep: Prepared, cause: Cause, mask: np.ndarray | None = None, refine: bool = True) -> CauseFit:
    """Least-squares fit of baseline + ``cause`` on the samples in ``mask`` (default all)."""
    mask = np.ones(prep.t.size, dtype=bool) if mask is None else mask
    grids = cause.grid(prep)
    combos = [tuple(row) for row in grids] if isinstance(grids, np.ndarray) else \
        (list(itertools.product(*grids)) if grids else [()])
    best: tuple[float, tuple[float, ...]] = (math.inf, ())
    for nl in combos:
        nl = tuple(float(v) for v in nl)
        rss, _, _, _, use = _solve(prep, cause, nl, mask)
        score = rss / max(int(use.sum()), 1)  # mean square: a delay drops the first samples
        if score < best[0]:
            best = (score, nl)
    nl = best[1]
    if refine and not isinstance(grids, np.ndarray) and len(grids) == 1:
        g = grids[0]
        i = int(np.argmin(np.abs(g - nl[0])))
        lo, hi = g[max(i - 1, 0)], g[min(i + 1, g.size - 1)]
        if hi > lo:
            res = minimize_scalar(lambda v: _solve(prep, cause, (v,), mask)[0], bounds=(lo, hi), method="bounded",
                                  options={"xatol": 1e-6 * max(abs(hi), 1e-3)})
            if res.fun <= _solve(prep, cause, nl, mask)[0]:
                nl = (float(res.x),)
    elif refine and len(nl) == 2:
        res = minimize(lambda v: _solve(prep, cause, (v[0], max(v[1], 0.05)), mask)[0], np.array(nl),
                       method="Nelder-Mead", options={"xatol": 1e-3, "fatol": 1e-9, "maxiter": 200})
        cand = (float(res.x[0]), float(max(res.x[1], 0.05)))
        if res.fun <= _solve(prep, cause, nl, mask)[0]:
            nl = cand
    rss, coef, pred, n_base, use = _solve(prep, cause, nl, mask)
    return CauseFit(cause.name, nl, coef, n_base, pred + prep.gravity, rss, int(use.sum()), cause.report(coef[n_base:], nl))


def absorbed_by_baseline(prep: Prepared, cause: Cause, fit: CauseFit) -> float:
    """R² of the cause's effect direction regressed on the baseline basis (1: the baseline can mimic it exactly).

    The direction is the extension's columns, or for a cause that changes the baseline's
    argument (delay, compliance), the derivative of the prediction with respect to its parameter.
    """
    base, ext, valid = cause.columns(prep, fit.nonlinear)
    if ext.shape[1]:
        j = ext[:, 0]
    else:
        step = {"time_delay": 0.02, "series_compliance": np.deg2rad(0.02)}.get(cause.name, 1e-3)
        nl = tuple(v + step for v in fit.nonlinear)
        b2, _, v2 = cause.columns(prep, nl)
        valid = valid & v2
        j = (b2 - base) @ fit.coef[: base.shape[1]] / step
    b0 = baseline_columns(prep.trial.kind, prep.theta, prep.lo, prep.hi)[valid]
    j = j[valid]
    if np.std(j) == 0:
        return 1.0
    coef, *_ = np.linalg.lstsq(b0, j, rcond=None)
    r = j - b0 @ coef
    return float(1.0 - np.sum(r**2) / np.sum((j - j.mean()) ** 2))


def parameter_se(prep: Prepared, cause: Cause, fit: CauseFit, n_eff: float) -> dict[str, float]:
    """Standard errors of the reported parameters: least-squares covariance of the coefficients and the
    curvature of the profiled residual sum of squares for the nonlinear ones, both inflated by n / n_eff."""
    if cause.name == "none":
        return {}
    base, ext, valid = cause.columns(prep, fit.nonlinear)
    x = np.hstack([base, ext])[valid]
    dof = max(fit.n - fit.n_params, 1)
    s2 = fit.rss / dof * (fit.n / n_eff)
    scale = np.maximum(np.abs(x).max(axis=0), 1e-12)
    try:
        cov = np.linalg.inv((x / scale).T @ (x / scale)) / np.outer(scale, scale) * s2
    except np.linalg.LinAlgError:
        return {}
    se_c = np.sqrt(np.maximum(np.diag(cov), 0.0))[fit.n_base:]
    ref = cause.report(fit.coef[fit.n_base:], fit.nonlinear)
    var = {k: 0.0 for k in ref}
    for i in range(se_c.size):
        c = fit.coef[fit.n_base:].copy()
        c[i] += se_c[i]
        for k, v in cause.report(c, fit.nonlinear).items():
            var[k] += (v - ref[k]) ** 2
    for j, v0 in enumerate(fit.nonlinear):
        h = max(abs(v0) * 1e-3, 1e-4)
        nl_p = list(fit.nonlinear); nl_p[j] = v0 + h
        nl_m = list(fit.nonlinear); nl_m[j] = v0 - h
        rss = [_solve(prep, cause, tuple(nl), np.ones(prep.t.size, bool))[0] for nl in (nl_m, fit.nonlinear, nl_p)]
        curv = (rss[0] - 2 * rss[1] + rss[2]) / h**2
        if curv <= 0:
            continue
        se_nl = math.sqrt(2 * s2 / curv)
        nl_se = list(fit.nonlinear); nl_se[j] = v0 + se_nl
        for k, v in cause.report(fit.coef[fit.n_base:], tuple(nl_se)).items():
            var[k] += (v - ref[k]) ** 2
    return {k: math.sqrt(v) for k, v in var.items()}


def systematic_regions(prep: Prepared, residual: np.ndarray, n_eff: float, bins: int = 10) -> list[dict[str, Any]]:
    """Angle bins (per branch: loading, unloading, still) where the mean residual exceeds 3 standard errors."""
    ok = np.isfinite(residual)
    edges = np.linspace(prep.lo, prep.hi, bins + 1)
    sd = float(np.std(residual[ok])) if ok.any() else 0.0
    inflate = prep.t.size / n_eff
    out = []
    moving = np.deg2rad(1.0)
    for branch, mask in (("loading", prep.omega > moving), ("unloading", prep.omega < -moving),
                         ("still", np.abs(prep.omega) <= moving)):
        for a, b in zip(edges[:-1], edges[1:]):
            sel = ok & mask & (prep.theta >= a) & (prep.theta <= b)
            n = int(sel.sum())
            if n < 10 or sd == 0:
                continue
            mean = float(residual[sel].mean())
            se = sd * math.sqrt(inflate / n)
            if abs(mean) > 3 * se:
                out.append({"branch": branch, "angle_deg": [float(np.rad2deg(a)), float(np.rad2deg(b))],
                            "mean_residual_Nm": mean, "standard_error_Nm": se})
    return out


def _blocks(n: int, folds: int) -> list[np.ndarray]:
    edges = np.linspace(0, n, folds + 1).astype(int)
    return [np.arange(edges[i], edges[i + 1]) for i in range(folds)]


def heldout_rmse(prep: Prepared, cause: Cause, folds: int = 5) -> float:
    """RMSE (N·m) of each contiguous time block predicted by the model fitted on the other blocks."""
    err = []
    for block in _blocks(prep.t.size, folds):
        train = np.ones(prep.t.size, dtype=bool)
        train[block] = False
        fit = fit_cause(prep, cause, train, refine=False)
        pred = fit.prediction[block]
        ok = np.isfinite(pred)
        err.append((prep.torque[block][ok] - pred[ok]) ** 2)
    e = np.concatenate(err)
    return float(np.sqrt(e.mean())) if e.size else float("nan")


def effective_n(residual: np.ndarray) -> float:
    """n / τ, τ = 1 + 2 Σ ρ_k the integrated autocorrelation time of the residual, summed until ρ_k first
    turns negative (the initial-positive-sequence estimator used for MCMC effective sample sizes).

    It suits both AR(1)-like noise and low-pass-filtered signals (an AR(1) formula would count a
    6 Hz-filtered torque at 100 Hz as a third of its real information).
    """
    r = residual[np.isfinite(residual)]
    r = r - r.mean()
    n = r.size
    if n < 3 or not np.any(r):
        return float(max(n, 1))
    f = np.fft.rfft(r, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n]
    acf = acf / acf[0]
    neg = np.flatnonzero(acf[1:] < 0)
    k = int(neg[0]) if neg.size else n - 1
    tau = 1.0 + 2.0 * float(np.sum(acf[1:k + 1]))
    return float(min(n, max(10.0, n / max(tau, 1.0))))


@dataclass
class Candidate:
    """A cause as tried: its fit on the whole trial, held-out RMSE and criterion."""

    cause: str
    params: dict[str, float]
    rmse_nm: float
    heldout_rmse_nm: float
    bic: float
    delta_bic: float
    heldout_ratio: float
    accepted: bool
    note: str = ""

    def as_dict(self) -> dict[str, Any]:
        def clean(v: Any) -> Any:
            return None if isinstance(v, float) and not math.isfinite(v) else v
        return {k: (clean(v) if not isinstance(v, dict) else {a: clean(b) for a, b in v.items()})
                for k, v in self.__dict__.items()}


@dataclass
class Diagnosis:
    """The finding for one trial."""

    kind: str
    cause: str
    parameters: dict[str, float]
    baseline_rmse_nm: float
    extended_rmse_nm: float
    baseline_heldout_rmse_nm: float
    extended_heldout_rmse_nm: float
    heldout_rmse_ratio: float
    delta_bic: float
    effective_n: float
    candidates: list[Candidate]
    ambiguous_with: list[str] = field(default_factory=list)
    separate_by: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    fits: dict[str, CauseFit] = field(default_factory=dict, repr=False)
    prepared: Prepared | None = field(default=None, repr=False)
    also: list[dict[str, Any]] = field(default_factory=list)  # a second effect found with the first
    parameters_se: dict[str, float] = field(default_factory=dict)
    systematic: list[dict[str, Any]] = field(default_factory=list)  # where the baseline's residual is not noise

    def as_dict(self) -> dict[str, Any]:
        def clean(v: float) -> float | None:
            return v if math.isfinite(v) else None
        return {"kind": self.kind, "cause": self.cause, "parameters": self.parameters,
                "parameters_se": self.parameters_se, "baseline_systematic_regions": self.systematic,
                "baseline_rmse_Nm": clean(self.baseline_rmse_nm), "extended_rmse_Nm": clean(self.extended_rmse_nm),
                "baseline_heldout_rmse_Nm": clean(self.baseline_heldout_rmse_nm),
                "extended_heldout_rmse_Nm": clean(self.extended_heldout_rmse_nm),
                "heldout_rmse_ratio": clean(self.heldout_rmse_ratio), "delta_bic": clean(self.delta_bic),
                "effective_n": self.effective_n, "ambiguous_with": self.ambiguous_with,
                "separate_by": self.separate_by, "notes": self.notes, "also": self.also,
                "candidates": [c.as_dict() for c in self.candidates]}

    def text(self) -> str:
        lines = [f"cause: {self.cause}" + (f" (cannot be told from {', '.join(self.ambiguous_with)})" if self.ambiguous_with else "")]
        for k, v in self.parameters.items():
            se = self.parameters_se.get(k)
            lines.append(f"  {k} = {v:.4g}" + (f" ± {se:.2g} (SE)" if se is not None else ""))
        if self.systematic:
            regions = "; ".join(f"{r['branch']} {r['angle_deg'][0]:.0f}–{r['angle_deg'][1]:.0f}° "
                                f"({r['mean_residual_Nm']:+.2f} N·m)" for r in self.systematic[:6])
            lines.append(f"  baseline systematically off at: {regions}" + (" …" if len(self.systematic) > 6 else ""))
        lines.append(f"  RMSE baseline {self.baseline_rmse_nm:.3f} N·m → extended {self.extended_rmse_nm:.3f} N·m; "
                     f"held-out {self.baseline_heldout_rmse_nm:.3f} → {self.extended_heldout_rmse_nm:.3f} "
                     f"(ratio {self.heldout_rmse_ratio:.2f}); ΔBIC {self.delta_bic:.1f} at n_eff {self.effective_n:.0f}")
        for a in self.also:
            lines.append(f"  and also: {a['cause']} " + ", ".join(f"{k} = {v:.4g}" for k, v in a["parameters"].items())
                         + f" (RMSE {a['rmse_Nm']:.3f} N·m, ΔBIC {a['delta_bic_vs_single']:.1f} against the first alone)")
        for s in self.separate_by:
            lines.append(f"  to separate them: {s}")
        for n in self.notes:
            lines.append(f"  note: {n}")
        lines.append(f"  {'candidate':<20}{'RMSE':>8}{'held-out':>10}{'ratio':>7}{'ΔBIC':>10}  accepted")
        for c in sorted(self.candidates, key=lambda c: c.bic):
            lines.append(f"  {c.cause:<20}{c.rmse_nm:>8.3f}{c.heldout_rmse_nm:>10.3f}{c.heldout_ratio:>7.2f}"
                         f"{c.delta_bic:>10.1f}  {'yes' if c.accepted else ''} {c.note}")
        return "\n".join(lines)


def diagnose(trial: DiagnosisTrial, *, causes: list[str] | None = None, folds: int = 5, min_delta_bic: float = 10.0,
             max_heldout_ratio: float = 0.95, ambiguity_bic: float = 10.0, max_absorbed_r2: float = 0.995,
             min_angle_deg: float = 6.0, ambiguity_rmse: float = 0.05) -> Diagnosis:
    """Name what the baseline model of ``trial`` gets wrong (see the module docstring).

    AFO trials are diagnosed at angles ≥ ``min_angle_deg`` (the spring is slack below its
    engagement, a region no spring model describes).

    :raises InputError: the trial has no usable samples.
    """
    prep = Prepared.of(trial, min_angle_deg if trial.kind == "afo" else None)
    names = [c for c in (causes or list(CAUSES)) if trial.kind in CAUSES[c].kinds]
    if "none" not in names:
        names.insert(0, "none")
    notes: list[str] = []
    moving = np.abs(prep.omega) > np.deg2rad(0.5)
    both_ways = (prep.omega[moving] > 0).mean() if moving.any() else 0.0
    if moving.sum() < 0.05 * prep.t.size:
        notes.append("the angle barely moves: velocity-dependent causes are not testable; record a movement")
        names = [n for n in names if n not in ("coulomb_friction", "viscous_damping", "time_delay")]
    elif not 0.05 < both_ways < 0.95:
        notes.append("the joint moves one way only: friction, damping and a delay are offsets here and cannot be "
                     "seen; record a return movement")
        names = [n for n in names if n not in ("coulomb_friction", "viscous_damping", "time_delay")]
    fits = {n: fit_cause(prep, CAUSES[n]) for n in names}
    # pairs of the three causes that fit best: a trial may carry two effects (the AFO: friction and a stop)
    top = sorted((n for n in fits if n != "none"), key=lambda n: fits[n].rss / fits[n].n)[:3]
    pairs: dict[str, tuple[Cause, CauseFit]] = {}
    for a, b in itertools.combinations(top, 2):
        if a in ARGUMENT_CAUSES and b in ARGUMENT_CAUSES:
            continue
        cause = compound(CAUSES[a], CAUSES[b])
        pairs[frozenset((a, b))] = (cause, fit_cause(prep, cause, refine=False))
    # the noise's correlation is judged on the best model's residual, pairs included
    best_rss = min([*fits.values(), *(f for _, f in pairs.values())], key=lambda f: f.rss / max(f.n, 1))
    n_eff = effective_n(prep.torque - best_rss.prediction)
    if n_eff <= 20:
        notes.append(f"the residual holds only about {n_eff:.0f} independent samples (a short or heavily filtered "
                     "trial, or several effects at once): record a longer trial with more bends before trusting "
                     "a 'none'")
    def bic(f: CauseFit) -> float:
        return n_eff * math.log(max(f.rss / f.n, 1e-300)) + f.n_params * math.log(n_eff)
    base = fits["none"]
    base_ho = heldout_rmse(prep, CAUSES["none"], folds)
    cands = []
    absorbed = {n: absorbed_by_baseline(prep, CAUSES[n], f) for n, f in fits.items() if n != "none"}
    for n, r2 in absorbed.items():
        if r2 > max_absorbed_r2:
            notes.append(f"{n} cannot be told from the baseline in this trial (its effect is {100 * r2:.2f} % the "
                         f"baseline's own shape); it needs {UNTESTABLE_HINT.get(n, 'another protocol')}")
    for n, f in fits.items():
        ho = base_ho if n == "none" else (float("nan") if CAUSES[n].transient else heldout_rmse(prep, CAUSES[n], folds))
        ratio = ho / base_ho if math.isfinite(ho) and base_ho > 0 else float("nan")
        d = bic(f) - bic(base)
        ok = (n != "none" and d < -min_delta_bic and (CAUSES[n].transient or ratio < max_heldout_ratio)
              and absorbed.get(n, 0.0) <= max_absorbed_r2)
        cands.append(Candidate(n, f.params, math.sqrt(f.rss / f.n), ho, bic(f), d, ratio, ok,
                               "transient: judged by the criterion only" if CAUSES[n].transient else ""))
    accepted = [c for c in cands if c.accepted]
    if not accepted:
        winner = next(c for c in cands if c.cause == "none")
    else:
        winner = min(accepted, key=lambda c: c.bic)
    ambiguous, separate = [], []
    if winner.cause != "none":
        effect_w = fits[winner.cause].prediction - base.prediction
        for c in accepted:
            close = c.bic - winner.bic <= ambiguity_bic or c.rmse_nm <= (1.0 + ambiguity_rmse) * winner.rmse_nm
            if c.cause == winner.cause or not close:
                continue
            effect_c = fits[c.cause].prediction - base.prediction
            ok = np.isfinite(effect_w) & np.isfinite(effect_c)
            if ok.sum() > 10 and np.std(effect_w[ok]) > 0 and np.std(effect_c[ok]) > 0:
                if abs(np.corrcoef(effect_w[ok], effect_c[ok])[0, 1]) > 0.9:
                    ambiguous.append(c.cause)
                    hint = SEPARATE_BY.get(frozenset({winner.cause, c.cause}))
                    if hint:
                        separate.append(hint)
    also: list[dict[str, Any]] = []
    if winner.cause != "none":
        wf = fits[winner.cause]
        w_ho = winner.heldout_rmse_nm
        best_pair = None
        for key, (cause, pf) in pairs.items():
            if winner.cause not in key:
                continue
            other = next(iter(key - {winner.cause}))
            if absorbed.get(other, 0.0) > max_absorbed_r2:
                continue
            d = bic(pf) - bic(wf)
            transient = CAUSES[other].transient or CAUSES[winner.cause].transient
            ho = float("nan") if transient else heldout_rmse(prep, cause, folds)
            ratio = ho / w_ho if math.isfinite(ho) and math.isfinite(w_ho) and w_ho > 0 else float("nan")
            if d < -min_delta_bic and (transient or ratio < max_heldout_ratio):
                if best_pair is None or d < best_pair[0]:
                    best_pair = (d, other, pf, ratio)
        if best_pair is not None:
            d, other, pf, ratio = best_pair
            extra = {k: v for k, v in pf.params.items() if k not in wf.params or CAUSES[other].magnitude_key == k}
            also.append({"cause": other, "parameters": extra, "delta_bic_vs_single": d,
                         "heldout_ratio_vs_single": ratio if math.isfinite(ratio) else None,
                         "rmse_Nm": math.sqrt(pf.rss / pf.n)})
    f = fits[winner.cause]
    se = parameter_se(prep, CAUSES[winner.cause], f, n_eff)
    systematic = systematic_regions(prep, prep.torque - base.prediction, n_eff)
    return Diagnosis(trial.kind, winner.cause, f.params, math.sqrt(base.rss / base.n), math.sqrt(f.rss / f.n), base_ho,
                     winner.heldout_rmse_nm if math.isfinite(winner.heldout_rmse_nm) else float("nan"),
                     winner.heldout_ratio if winner.cause != "none" else 1.0, winner.delta_bic, n_eff, cands,
                     ambiguous, separate, notes, fits, prep, also, se, systematic)


def magnitude(d: Diagnosis) -> float:
    """The fitted size of the named cause (the parameter the tests compare), NaN for ``none``."""
    key = CAUSES[d.cause].magnitude_key
    return float(d.parameters.get(key, float("nan"))) if key else float("nan")


__all__ = ["diagnose", "Diagnosis", "Candidate", "CauseFit", "fit_cause", "magnitude"]
