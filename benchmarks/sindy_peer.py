"""The diagnosis's peer: sparse regression over the same candidate terms, as a competent user would run it.

PySINDy's sequentially thresholded least squares (:class:`pysindy.optimizers.STLSQ`, Brunton et
al. 2016) on a library of the baseline's own columns (never thresholded: ``sparse_ind`` covers the
candidate terms only) plus terms for every cause the diagnosis can name:

- Coulomb friction ``tanh(ω / 1°/s)``; viscous damping ``ω``; drift ``t``;
- a hard stop: hinges at 12 angles spread over the whole range (2–98 %), resisting the top of the range
  in its upper half and the bottom in its lower half, where the diagnosis searches its stops;
- a delay of the torque channel ``−dτ/dt`` (Savitzky–Golay derivative of the measured torque, so
  ``τ(t − d) ≈ τ(t) − d τ̇``);
- an activation burst: raised-cosine bumps 0.8 s long every 0.4 s;
- a limb-weight error (knee and ankle): the limb's gravity shape.

Each column is scaled to unit RMS, so every candidate meets the threshold on equal terms (scaled to unit
peak, a hinge or a bump with its energy in a few samples needed a far larger coefficient than a sustained
term of the same energy). The threshold is chosen by blocked cross-validation (the trial cut
into 2 s blocks, longer than the noise's correlation, dealt round-robin into 5 folds; each fold
predicted from a fit on the other four: five contiguous fifths would make every fold extrapolate a
sweep segment the fit never saw) over a grid from 0.1 % to 100 % of the torque's SD: at the minimum of
the held-out error, and, as the one-standard-error variant, the largest threshold whose error is within
one standard error of that minimum. A cause is named when its surviving terms are jointly significant:
the F test of the support with and without them at the 1 % level, the residual's degrees of freedom
counted at its effective sample size (AR(1): n(1 − ρ)/(1 + ρ)), not when any one term survives. Data
are block-averaged to at most 50 Hz first (the effects are below 5 Hz), rows with a NaN are dropped; a
term the baseline columns reproduce (R² > 0.999) is left out, as the diagnosis reports such a cause
untestable rather than naming it.

Nothing here is imported by the instrument; it is the reference the diagnosis benchmark measures
against in the same run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import savgol_filter
from scipy.stats import f as f_dist

from analysis.diagnosis import DiagnosisTrial
from analysis.diagnosis.causes import baseline_columns

CAUSES = ("coulomb_friction", "viscous_damping", "sensor_drift", "hard_stop", "time_delay", "activation_burst",
          "gravity_error")
FOLDS = 5
BLOCK_S = 2.0
#: a term is fitted in a fold when at least this share of its energy lies in the fold's training rows
MIN_TRAIN_ENERGY = 0.5
MAX_RATE_HZ = 50.0
FRICTION_WIDTH_RAD_S = np.deg2rad(1.0)
STOP_HINGES = 12
#: the joint significance (F test, 1 %) a cause's surviving terms need before the peer names it
NAMING_P = 0.01
BUMP_DURATION_S, BUMP_SPACING_S = 0.8, 0.4
THRESHOLD_FRACTIONS = np.concatenate([[0.0], np.logspace(-3, 0, 16)])
#: a candidate term the baseline reproduces to this R² is left out (it cannot be told from the baseline)
MAX_R2_ON_BASELINE = 0.999


@dataclass(frozen=True)
class PeerResult:
    """What the peer names, at the CV minimum and with the one-standard-error rule."""

    named: frozenset[str]
    named_1se: frozenset[str]
    threshold_nm: float
    threshold_1se_nm: float
    #: causes whose every term the baseline reproduces (left out of the library: cannot be told apart)
    untestable: frozenset[str] = frozenset()


def _block_means(trial: DiagnosisTrial) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ok = np.isfinite(trial.time_s) & np.isfinite(trial.angle_rad) & np.isfinite(trial.torque_nm)
    t, th, y = trial.time_s[ok], trial.angle_rad[ok], trial.torque_nm[ok]
    rate = (t.size - 1) / max(t[-1] - t[0], 1e-9)
    m = max(int(rate // MAX_RATE_HZ), 1)
    n = t.size // m * m
    return tuple(a[:n].reshape(-1, m).mean(axis=1) for a in (t, th, y))  # type: ignore[return-value]  # a 3-tuple built from three arrays


def library(trial: DiagnosisTrial) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str], int]:
    """(columns, torque − limb weight (N·m), time (s), the cause of each candidate column, number of
    baseline columns)."""
    t, th, y = _block_means(trial)
    rate = (t.size - 1) / max(t[-1] - t[0], 1e-9)
    sub = DiagnosisTrial(trial.kind, t, th, y, trial.fixed_deg, trial.subject)
    if trial.kind == "afo":  # the spring's engaged range, as the AADS fit takes it
        keep = th >= np.deg2rad(6.0)
    else:
        keep = np.ones(t.size, dtype=bool)
    omega = sub.velocity_rad_s()
    target = y - sub.limb_gravity_nm()
    win = max(int(0.2 * rate) | 1, 5)
    dtau = savgol_filter(y, win, 2, deriv=1, delta=1.0 / rate)
    lo, hi = float(th[keep].min()), float(th[keep].max())
    cols: list[np.ndarray] = [np.tanh(omega / FRICTION_WIDTH_RAD_S), omega, t - t.mean()]
    names = ["coulomb_friction", "viscous_damping", "sensor_drift"]
    for stop in np.linspace(lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo), STOP_HINGES):
        cols.append(np.maximum(th - stop, 0.0) if stop >= 0.5 * (lo + hi) else np.maximum(stop - th, 0.0))
        names.append("hard_stop")
    cols.append(-dtau)
    names.append("time_delay")
    if trial.kind != "afo":
        for centre in np.arange(t[0] + BUMP_SPACING_S, t[-1], BUMP_SPACING_S):
            u = (t - centre) / BUMP_DURATION_S + 0.5
            cols.append(np.where((u >= 0) & (u <= 1), 0.5 * (1 - np.cos(2 * np.pi * np.clip(u, 0, 1))), 0.0))
            names.append("activation_burst")
        cols.append(sub.gravity_shape())
        names.append("gravity_error")
    base = baseline_columns(trial.kind, th, lo, hi)
    x = np.column_stack([base, *cols])[keep]
    scale = np.sqrt(np.mean(x**2, axis=0))
    usable = scale > 1e-12
    usable[: base.shape[1]] = True
    b = x[:, : base.shape[1]]
    for j in range(base.shape[1], x.shape[1]):
        if usable[j]:
            col = x[:, j]
            resid = col - b @ np.linalg.lstsq(b, col, rcond=None)[0]
            usable[j] = float(resid @ resid) > (1.0 - MAX_R2_ON_BASELINE) * float(np.sum((col - col.mean()) ** 2))
    x = x[:, usable] / np.where(scale[usable] > 0, scale[usable], 1.0)
    kept_names = [n for n, u in zip(names, usable[base.shape[1]:], strict=True) if u]
    return x, target[keep], t[keep], kept_names, base.shape[1]



def _fit(x: np.ndarray, y: np.ndarray, n_base: int, threshold: float) -> np.ndarray:
    """STLSQ with the baseline columns outside the thresholding, then least squares on the support
    (PySINDy's ``unbias``, done here: its own fails with ``sparse_ind`` in 2.1)."""
    from pysindy.optimizers import STLSQ

    sparse = list(range(n_base, x.shape[1]))
    if not sparse:  # every candidate term left out (the baseline reproduces it): least squares on the baseline
        return np.linalg.lstsq(x, y, rcond=None)[0]
    opt = STLSQ(threshold=threshold, alpha=1e-6, max_iter=20, sparse_ind=sparse, unbias=False)
    opt.fit(x, y.reshape(-1, 1))
    support = np.ones(x.shape[1], dtype=bool)
    support[sparse] = np.asarray(opt.coef_).ravel() != 0.0
    coef = np.zeros(x.shape[1])
    coef[support] = np.linalg.lstsq(x[:, support], y, rcond=None)[0]
    return coef


def _compressed(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R, Qᵀy) of X = QR: every (ridge) least-squares fit on a subset of X's columns has the same
    solution on these p rows as on X's n rows, so STLSQ runs on them unchanged and n/p times faster."""
    q, r = np.linalg.qr(x)
    return r, q.T @ y


def diagnose_sparse(trial: DiagnosisTrial) -> PeerResult:
    """The peer's diagnosis of one trial."""
    x, y, t, names, n_base = library(trial)
    y = y - y.mean()
    thresholds = THRESHOLD_FRACTIONS * float(np.std(y))
    fold = (np.floor((t - t[0]) / BLOCK_S).astype(int)) % FOLDS
    # a trial shorter than FOLDS blocks leaves some folds empty: the folds with samples only
    present = [j for j in range(FOLDS) if np.any(fold == j)]
    errors = np.zeros((thresholds.size, len(present)))
    for col, j in enumerate(present):
        test, train = np.flatnonzero(fold == j), np.flatnonzero(fold != j)
        # a term with most of its energy in the held-out fold (a bump there) cannot be estimated from
        # the other folds: it is left out of this fold's fit (coefficient 0), not extrapolated
        supported = np.sum(x[train] ** 2, axis=0) >= MIN_TRAIN_ENERGY * np.sum(x**2, axis=0)
        supported[:n_base] = True
        r_train, z_train = _compressed(x[train][:, supported], y[train])
        for i, lam in enumerate(thresholds):
            coef = np.zeros(x.shape[1])
            coef[supported] = _fit(r_train, z_train, n_base, lam)
            errors[i, col] = float(np.mean((y[test] - x[test] @ coef) ** 2))
    mean = errors.mean(axis=1)
    best = int(np.argmin(mean))
    se = float(errors[best].std(ddof=1) / np.sqrt(len(present))) if len(present) > 1 else 0.0
    best_1se = int(np.max(np.flatnonzero(mean <= mean[best] + se)))

    r_all, z_all = _compressed(x, y)

    def rss(support: np.ndarray) -> float:
        coef = np.linalg.lstsq(x[:, support], y, rcond=None)[0]
        return float(np.sum((y - x[:, support] @ coef) ** 2))

    def named(lam: float) -> frozenset[str]:
        coef = _fit(r_all, z_all, n_base, lam)
        support = coef != 0.0
        support[:n_base] = True
        resid = y - x @ coef
        rho = float(np.clip(np.corrcoef(resid[:-1], resid[1:])[0, 1], 0.0, 0.99)) if resid.size > 3 else 0.0
        n_eff = resid.size * (1 - rho) / (1 + rho)
        dof = n_eff - int(support.sum())
        full = float(resid @ resid)
        out = set()
        for cause in {n for n, c in zip(names, coef[n_base:], strict=True) if c != 0.0}:
            mine = np.zeros(x.shape[1], dtype=bool)
            mine[n_base:] = [n == cause and c != 0.0 for n, c in zip(names, coef[n_base:], strict=True)]
            q = int(mine.sum())
            if dof <= 1 or full <= 0:
                continue
            # the naive F (σ² from the residual per sample) deflated by n_eff / n: correlated noise makes a
            # sum-of-squares difference n / n_eff times as variable as independent noise would
            sigma2 = full / max(resid.size - int(support.sum()), 1)
            f_stat = (rss(support & ~mine) - full) / q / sigma2 * (n_eff / resid.size)
            if f_dist.sf(f_stat, q, dof) < NAMING_P:
                out.add(cause)
        return frozenset(out)

    every = set(CAUSES) - (set() if trial.kind != "afo" else {"activation_burst", "gravity_error"})
    return PeerResult(named(float(thresholds[best])), named(float(thresholds[best_1se])),
                      float(thresholds[best]), float(thresholds[best_1se]), frozenset(every - set(names)))


__all__ = ["PeerResult", "diagnose_sparse", "library"]
