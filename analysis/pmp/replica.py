"""The replica leg: stiffness and rest length of its four springs from static knee holds.

The replica leg (Chapter 3) replaces the muscles by linear springs on the same kind of path: a
spring of stiffness k and rest length L₀ on a path of length L(θ) over the knee pulley pulls
with F = k·max(L − L₀, 0) and loads the knee with F·dL/dθ. The torque sensor reads what holds the
shank at the locked angle θ (against flexion, N·m):

    τ(θ) = Σ_springs k·max(L(θ) − L₀, 0)·dL/dθ − m·g·d·cos θ          (thigh horizontal, hip 90°)

Path length (pulley radius r, anchors a and b from the knee axis, Δ the angle between them over
the pulley, Δ = Δ₀ + θ anterior, Δ₀ − θ posterior): the two tangents and the arc while the path
wraps (Δ > acos(r/a) + acos(r/b)), the straight chord otherwise; the biarticular springs add
±r_hip·hip. The transition is C¹, so IPOPT sees smooth derivatives; the slack kink max(·, 0) is
replaced by a softplus 0.2 mm wide (its largest torque error is k·0.14 mm·r, under 0.01 N·m).

The estimator is the passive-parameter estimator's problem with the springs in place of the
muscles: at a locked hold the collocated states are constant (q̇ = 0), so the dynamics reduce to
the static balance above and the cost of eq 3.8 to the torque term. Decision variables are the
stiffness and rest length of every spring scaled by the drawing's values, with bounds 0.3–3×
catalogue stiffness and 60 % of the drawn rest length up to the longest path over the holds
(a spring that never stretches contributes nothing and is not estimable). The slack regions cut
the cost into basins; IPOPT starts from the best of a global variable-projection grid search, and
minima the data cannot tell apart (likelihood ratio inside the joint 95 % region) mark the
parameters they disagree on as undetermined. Uncertainty is the
Gauss–Newton covariance s²(JᵀJ)⁻¹ with s² = RSS/(n − p) and Student-t intervals.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats
from scipy.integrate import solve_ivp

from ..constants import GRAVITY_M_S2
from ..errors import DataFileError, InputError
from ..fit import FitStatus

G = GRAVITY_M_S2
DEFAULT_MODEL = Path(__file__).with_name("data") / "replica_leg.toml"
SOFTPLUS_WIDTH_M = 2e-4
REGULARISATION = 1e-3
REL_SE_LIMIT = 0.035


@dataclass(frozen=True)
class ReplicaSpring:
    """One spring and its path (m, N/m, rad); ``anterior`` springs lengthen as the knee flexes."""

    name: str
    stiffness_n_per_m: float
    rest_length_m: float
    thigh_anchor_m: float
    shank_anchor_m: float
    pulley_radius_m: float
    anterior: bool
    span0_rad: float
    hip_pulley_radius_m: float = 0.0
    hip_lengthens_with_flexion: bool = False

    def length_m(self, knee_rad: Any, hip_rad: float, backend: Any = np) -> Any:
        """Path length (m) at knee flexion ``knee_rad``; ``backend`` is numpy or casadi."""
        a, b, r = self.thigh_anchor_m, self.shank_anchor_m, self.pulley_radius_m
        span = self.span0_rad + (knee_rad if self.anterior else -knee_rad)
        tangent = math.acos(r / a) + math.acos(r / b)
        wrapped = math.sqrt(a * a - r * r) + math.sqrt(b * b - r * r) + r * (span - tangent)
        chord = backend.sqrt(a * a + b * b - 2 * a * b * backend.cos(span))
        knee_part = (backend.where(span > tangent, wrapped, chord) if backend is np
                     else backend.if_else(span > tangent, wrapped, chord))
        hip = self.hip_pulley_radius_m * hip_rad * (1.0 if self.hip_lengthens_with_flexion else -1.0)
        return knee_part + hip


@dataclass(frozen=True)
class ReplicaModel:
    """The rig as drawn: springs, shank weight (kg, m from the knee), hip angle (rad)."""

    springs: tuple[ReplicaSpring, ...]
    shank_mass_kg: float
    shank_com_m: float
    shank_inertia_kgm2: float
    hip_rad: float
    hold_angles_rad: tuple[float, ...]
    source: str = "default"

    def parameter_names(self) -> list[str]:
        return [f"{s.name}.{what}" for s in self.springs for what in ("stiffness_n_per_m", "rest_length_m")]

    def nominal(self) -> np.ndarray:
        return np.array([v for s in self.springs for v in (s.stiffness_n_per_m, s.rest_length_m)])

    def with_parameters(self, values: dict[str, float]) -> ReplicaModel:
        """The same rig with some springs' stiffness/rest length replaced (names as ``parameter_names``)."""
        springs = tuple(replace(s, stiffness_n_per_m=values.get(f"{s.name}.stiffness_n_per_m", s.stiffness_n_per_m),
                                rest_length_m=values.get(f"{s.name}.rest_length_m", s.rest_length_m))
                        for s in self.springs)
        return replace(self, springs=springs)

    def torque_nm(self, knee_rad: np.ndarray) -> np.ndarray:
        """Torque against flexion (N·m) at the sensor, hard slack (numpy)."""
        q = np.asarray(knee_rad, dtype=float)
        h = 1e-6
        total = -self.shank_mass_kg * G * self.shank_com_m * np.cos(q)
        for s in self.springs:
            dl = (s.length_m(q + h, self.hip_rad) - s.length_m(q - h, self.hip_rad)) / (2 * h)
            total = total + s.stiffness_n_per_m * np.maximum(s.length_m(q, self.hip_rad) - s.rest_length_m, 0.0) * dl
        return total


def load_replica_model(path: str | Path | None = None) -> ReplicaModel:
    """The replica-leg drawing from TOML (``analysis/pmp/data/replica_leg.toml`` by default).

    :raises DataFileError: unreadable file or a missing/invalid key (named).
    """
    p = Path(path) if path is not None else DEFAULT_MODEL
    try:
        data = tomllib.loads(p.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as err:
        raise DataFileError(p, f"cannot read the replica-leg model: {err}") from err
    try:
        springs = []
        for s in data["spring"]:
            side = s["side"]
            if side not in ("anterior", "posterior"):
                raise DataFileError(p, f"spring {s.get('name')}: side must be anterior or posterior, not {side!r}")
            sp = ReplicaSpring(str(s["name"]), float(s["stiffness_n_per_m"]), float(s["rest_length_m"]),
                               float(s["thigh_anchor_m"]), float(s["shank_anchor_m"]), float(s["pulley_radius_m"]),
                               side == "anterior", math.radians(float(s["span0_deg"])),
                               float(s.get("hip_pulley_radius_m", 0.0)), bool(s.get("hip_lengthens_with_flexion", False)))
            if not (0 < sp.pulley_radius_m < min(sp.thigh_anchor_m, sp.shank_anchor_m)) or sp.stiffness_n_per_m <= 0 \
                    or sp.rest_length_m <= 0:
                raise DataFileError(p, f"spring {sp.name}: needs 0 < pulley radius < anchors, positive k and rest length")
            springs.append(sp)
        return ReplicaModel(tuple(springs), float(data["shank_mass_kg"]), float(data["shank_com_m"]),
                            float(data.get("shank_inertia_kgm2", 0.035)), math.radians(float(data["hip_flexion_deg"])),
                            tuple(math.radians(float(a)) for a in data.get("hold_angles_deg", range(0, 90, 8))),
                            str(p))
    except KeyError as err:
        raise DataFileError(p, f"missing key {err.args[0]!r}") from err
    except (TypeError, ValueError) as err:
        raise DataFileError(p, f"invalid value: {err}") from err


@dataclass
class Holds:
    """Per-hold knee angle (rad), mean torque (N·m), its SD (N·m) and sample count."""

    knee_rad: np.ndarray
    torque_nm: np.ndarray
    torque_sd_nm: np.ndarray
    samples: np.ndarray


def holds_from_samples(angle_deg: np.ndarray, torque_nm: np.ndarray, *, min_samples: int = 3) -> Holds:
    """Group a replica trial's samples by hold angle (the export writes each hold's angle on its samples).

    :raises InputError: NaNs in the angle, or fewer than 3 holds with ``min_samples`` finite torques.
    """
    a = np.asarray(angle_deg, dtype=float)
    tq = np.asarray(torque_nm, dtype=float)
    if a.shape != tq.shape or not np.all(np.isfinite(a)):
        raise InputError("replica holds need one finite angle per torque sample")
    rows = []
    for angle in np.unique(np.round(a, 6)):
        x = tq[(np.abs(a - angle) < 1e-6) & np.isfinite(tq)]
        if x.size >= min_samples:
            rows.append((math.radians(angle), float(np.mean(x)), float(np.std(x, ddof=1)), x.size))
    if len(rows) < 3:
        raise InputError(f"{len(rows)} usable holds (need at least 3 with {min_samples} samples each)")
    k, t, s, n = (np.array(c) for c in zip(*rows))
    return Holds(k, t, s, n.astype(int))


@dataclass(frozen=True)
class ReplicaResult:
    """Estimates with uncertainty, the fit at each hold and the forward check, with the solver's
    account of itself in SciPy's names (:mod:`analysis.fit`: ``success``, ``status``, ``message``,
    ``nit``, ``fun``, ``x``). When no start converges the result says so (``success=False``, the
    drawing's values, nothing determined) instead of raising."""

    parameters: dict[str, float]
    nominal: dict[str, float]
    lower: dict[str, float]
    upper: dict[str, float]
    standard_error: dict[str, float]
    ci95: dict[str, list[float]]
    determined: list[str]
    undetermined: list[str]
    residual_rms_nm: float
    model_torque_nm: np.ndarray
    holds: Holds
    nit: int
    starts: int
    solve_time_s: float
    success: bool
    status: FitStatus
    message: str
    fun: float
    alternatives: dict[str, list[float]] = field(default_factory=dict)  # span of the equally good minima
    equivalent_minima: int = 1
    sensor_offset_nm: float = 0.0      # the transducer's zero, estimated (or as given)
    sensor_offset_se_nm: float = 0.0   # standard error, or half the spread of equally good fits if larger
    curve_knee_rad: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the fitted rig, finely sampled
    curve_torque_nm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    verification: dict[str, Any] = field(default_factory=dict)

    @property
    def x(self) -> np.ndarray:
        """The estimates (SI) in the order of :attr:`parameters`."""
        return np.array(list(self.parameters.values()), dtype=float)


def _torque_expr(model: ReplicaModel, q: Any, par: Any, width_m: Any) -> Any:
    """Smooth-slack torque against flexion (CasADi) with ``par`` = [k₁, L₀₁, k₂, L₀₂, …] in SI;
    the slack kink is a softplus ``width_m`` wide, written so that it cannot overflow."""
    import casadi as ca

    total = -model.shank_mass_kg * G * model.shank_com_m * ca.cos(q)
    for i, s in enumerate(model.springs):
        length = s.length_m(q, model.hip_rad, ca)
        x = length - par[2 * i + 1]
        stretch = ca.fmax(x, 0) + width_m * ca.log1p(ca.exp(-ca.fabs(x) / width_m))
        total = total + par[2 * i] * stretch * ca.jacobian(length, q)
    return total


def _rest_candidates(model: ReplicaModel, holds: Holds, lo: np.ndarray, hi: np.ndarray) -> list[np.ndarray]:
    """Relative rest lengths that realise every slack pattern of each spring over the holds: the
    path lengths at the holds and the midpoints between them (inside the bounds), plus two below
    the shortest (the spring stretched at every hold)."""
    out = []
    for i, s in enumerate(model.springs):
        lengths = np.unique(s.length_m(holds.knee_rad, model.hip_rad))
        mids = 0.5 * (lengths[1:] + lengths[:-1])
        below = lengths[0] - np.array([0.004, 0.012])
        cand = np.concatenate([below, lengths - 1e-4, mids]) / s.rest_length_m
        out.append(np.unique(np.clip(cand, lo[2 * i + 1], hi[2 * i + 1])))
    return out


def _grid_starts(model: ReplicaModel, holds: Holds, lo: np.ndarray, hi: np.ndarray, count: int,
                 fit_offset: bool = True, chunk: int = 40_000) -> list[np.ndarray]:
    """The ``count`` best starts of a global search over slack patterns (relative parameters, then
    the sensor zero in N·m).

    The slack regions cut the cost into basins, one per pattern of which holds stretch which
    spring. Given the rest lengths the torque is linear in the stiffnesses and the sensor zero
    (variable projection), so every combination of candidate rest lengths (``_rest_candidates``,
    about 25 per spring) is scored by the residual of its least-squares stiffnesses, clipped to
    their bounds, in batched solves; the best distinct patterns seed IPOPT.
    """
    n_s = len(model.springs)
    cands = _rest_candidates(model, holds, lo, hi)
    if count <= 0 or np.prod([c.size for c in cands]) > 5_000_000:
        return []
    q = holds.knee_rad
    y = holds.torque_nm + model.shank_mass_kg * G * model.shank_com_m * np.cos(q) - (0.0 if fit_offset else lo[-1])
    h = 1e-6
    basis = []
    for i, s in enumerate(model.springs):
        length = s.length_m(q, model.hip_rad)
        dl = (s.length_m(q + h, model.hip_rad) - s.length_m(q - h, model.hip_rad)) / (2 * h)
        rest = cands[i][:, None] * s.rest_length_m
        basis.append(np.maximum(length[None, :] - rest, 0.0) * dl[None, :] * s.stiffness_n_per_m)  # per unit relative k
    idx = np.stack(np.meshgrid(*[np.arange(c.size) for c in cands], indexing="ij"), -1).reshape(-1, n_s)
    k_lo, k_hi = lo[0:2 * n_s:2], hi[0:2 * n_s:2]
    rss = np.empty(idx.shape[0])
    coef = np.empty((idx.shape[0], n_s + 1))
    for c0 in range(0, idx.shape[0], chunk):
        ii = idx[c0:c0 + chunk]
        a = np.stack([basis[i][ii[:, i]] for i in range(n_s)], axis=1)   # (combo, spring, hold)
        if fit_offset:                                                     # the sensor zero: one more unknown
            a = np.concatenate([a, np.ones((a.shape[0], 1, q.size))], axis=1)
        gram = np.einsum("csh,cth->cst", a, a) + 1e-9 * np.eye(a.shape[1])
        k = np.linalg.solve(gram, np.einsum("csh,h->cs", a, y)[..., None])[..., 0]
        k[:, :n_s] = np.clip(k[:, :n_s], k_lo, k_hi)
        if fit_offset:
            k[:, n_s] = np.clip(k[:, n_s], lo[-1], hi[-1])
        rss[c0:c0 + chunk] = np.sum((np.einsum("csh,cs->ch", a, k) - y) ** 2, axis=1)
        coef[c0:c0 + chunk, :k.shape[1]] = k
    out: list[np.ndarray] = []
    taken: list[np.ndarray] = []
    for c in np.argsort(rss)[: count * 20]:
        # one start per basin: skip patterns next to one already taken
        if any(np.max(np.abs(idx[c] - t)) <= 1 for t in taken):
            continue
        x = np.empty(2 * n_s + 1)
        x[0:2 * n_s:2] = coef[c, :n_s]
        x[1:2 * n_s:2] = [cands[i][idx[c, i]] for i in range(n_s)]
        x[-1] = coef[c, n_s] if fit_offset else lo[-1]
        out.append(x)
        taken.append(idx[c])
        if len(out) == count:
            break
    return out


def estimate_replica(holds: Holds, model: ReplicaModel | None = None, *, starts: int = 12,
                     sigma_nm: float | None = None, sensor_offset_nm: float | None = None) -> ReplicaResult:
    """Stiffness and rest length of every spring from the holds (CasADi + IPOPT, exact derivatives).

    ``sigma_nm`` is the uncertainty of one hold's mean torque (default: the holds' median standard
    error SD/√n, at least 0.2 mN·m); it scales the residuals, and the reported uncertainty uses
    the residual variance instead when that is larger. Starts: the drawing's values, then
    the ``starts − 1`` best basins of a global grid search (``_grid_starts``); the lowest cost wins.
    The torque transducer's zero is a nuisance parameter (N·m, ±5) estimated with the springs unless
    ``sensor_offset_nm`` gives it (a tare with the shank off): the rig cannot be tared unloaded
    with its springs on, and a zero error would otherwise land in the rest lengths.

    :raises InputError: fewer holds than parameters.
    """
    import time

    import casadi as ca

    model = model or load_replica_model()
    if sigma_nm is None:
        se = holds.torque_sd_nm / np.sqrt(np.maximum(holds.samples, 1))
        sigma_nm = max(float(np.median(se[np.isfinite(se)])) if np.isfinite(se).any() else 0.0, 2e-4)
    names = model.parameter_names()
    nominal = model.nominal()
    n_par = len(names)
    if holds.knee_rad.size < n_par:
        raise InputError(f"{holds.knee_rad.size} holds cannot determine {n_par} spring parameters")
    q = ca.SX.sym("q")
    p_rel = ca.SX.sym("p", n_par)
    width = ca.SX.sym("w")
    tau = _torque_expr(model, q, p_rel * nominal, width)
    torque_fn = ca.Function("tau", [q, p_rel, width], [tau])
    jac_fn = ca.Function("dtau", [q, p_rel, width], [ca.jacobian(tau, p_rel)])
    lo = np.empty(n_par)
    hi = np.empty(n_par)
    grid = np.linspace(min(holds.knee_rad), max(holds.knee_rad), 200)
    for i, s in enumerate(model.springs):
        lo[2 * i], hi[2 * i] = 0.3, 3.0
        longest = float(np.max(s.length_m(grid, model.hip_rad)))
        lo[2 * i + 1] = 0.6
        hi[2 * i + 1] = max(longest - 1e-3, 0.6 * s.rest_length_m + 1e-3) / s.rest_length_m
    fit_offset = sensor_offset_nm is None
    if holds.knee_rad.size < n_par + fit_offset:
        raise InputError(f"{holds.knee_rad.size} holds cannot determine {n_par} spring parameters and the sensor zero")
    zero = 0.0 if sensor_offset_nm is None else float(sensor_offset_nm)
    lo = np.append(lo, -5.0 if fit_offset else zero)
    hi = np.append(hi, 5.0 if fit_offset else zero)
    x = ca.SX.sym("x", n_par + 1)  # relative spring parameters, then the sensor zero (N·m)
    resid = ca.vertcat(*[torque_fn(qq, x[:n_par], width) for qq in holds.knee_rad]) + x[n_par] - holds.torque_nm
    cost = ca.sumsqr(resid / sigma_nm) / holds.knee_rad.size + REGULARISATION * ca.sumsqr(x[:n_par] - 1.0)
    solver = ca.nlpsol("replica", "ipopt", {"x": x, "p": width, "f": cost},
                       {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "max_iter": 300, "tol": 1e-10}})
    inits = [np.clip(np.append(np.ones(n_par), 0.0), lo, hi)] + _grid_starts(model, holds, lo, hi, max(starts, 1) - 1,
                                                                             fit_offset=fit_offset)
    found, iters = [], 0
    t0 = time.perf_counter()
    for k, x0 in enumerate(inits):
        # grid starts sit in their basin already and go straight to the sharp kink; the drawing's
        # values may not, and take a continuation (a blunt kink first) as well
        paths = [(SOFTPLUS_WIDTH_M,)] + ([(5e-3, 1e-3, SOFTPLUS_WIDTH_M)] if k == 0 else [])
        for widths in paths:
            sol: Any = None
            for w in widths:
                sol = solver(x0=x0 if sol is None else sol["x"], p=w, lbx=lo, ubx=hi)
                iters += int(solver.stats().get("iter_count", 0))
            if solver.stats().get("success"):
                found.append(np.asarray(sol["x"]).ravel())
    solve_s = time.perf_counter() - t0
    if not found:  # the drawing's values, nothing determined: the result says why
        names_nan = dict.fromkeys(names, float("nan"))
        return ReplicaResult(dict(zip(names, nominal.tolist())), dict(zip(names, nominal.tolist())),
                             dict(zip(names, (lo[:n_par] * nominal).tolist())), dict(zip(names, (hi[:n_par] * nominal).tolist())),
                             names_nan, {}, [], list(names), float("nan"), np.full(holds.knee_rad.size, np.nan), holds,
                             iters, len(inits), solve_s, success=False, status=FitStatus.NO_START_CONVERGED,
                             message=f"IPOPT did not converge from any of {len(inits)} starts", fun=float("nan"),
                             alternatives={n: [float("nan"), float("nan")] for n in names}, equivalent_minima=0,
                             sensor_offset_nm=zero)

    def predict(xf: np.ndarray) -> np.ndarray:
        return np.array([float(torque_fn(qq, xf[:n_par], SOFTPLUS_WIDTH_M)) for qq in holds.knee_rad]) + xf[n_par]

    scores = [float(np.sum((predict(f) - holds.torque_nm) ** 2)) for f in found]
    best = found[int(np.argmin(scores))]
    offset = float(best[n_par])
    xr = best[:n_par]
    est = xr * nominal
    model_tau = predict(best)
    r = model_tau - holds.torque_nm
    n_fit = n_par + int(fit_offset)
    dof = holds.knee_rad.size - n_fit
    s2 = max(float(r @ r) / dof, sigma_nm**2) if dof > 0 else sigma_nm**2
    jac = np.vstack([np.asarray(jac_fn(qq, xr, SOFTPLUS_WIDTH_M)).ravel() for qq in holds.knee_rad])  # ∂τ/∂p_rel
    if fit_offset:
        jac = np.column_stack([jac, np.ones(holds.knee_rad.size)])
    info = jac.T @ jac
    eig, vecs = np.linalg.eigh(info)
    keep = eig > eig.max() * 1e-10
    cov = s2 * (vecs[:, keep] / eig[keep]) @ vecs[:, keep].T
    se_all = np.sqrt(np.maximum(np.diag(cov), 0.0))
    offset_se = float(se_all[n_par]) if fit_offset else 0.0
    se_rel = se_all[:n_par]
    free = (np.sqrt(np.sum(vecs[:, ~keep] ** 2, axis=1)) if (~keep).any() else np.zeros(n_fit))[:n_par]
    lo, hi = lo[:n_par], hi[:n_par]
    at_bound = (np.abs(xr - lo) < 1e-4 * (hi - lo)) | (np.abs(hi - xr) < 1e-4 * (hi - lo))
    tq = stats.t.ppf(0.975, max(dof, 1))
    # other minima the data cannot tell from the best (likelihood ratio within the joint 95 % region)
    # make the local interval a lie: their span is reported, and those parameters are undetermined
    threshold = float(np.min(scores)) + s2 * stats.chi2.ppf(0.95, n_fit)
    rivals_full = np.array([f for f, sc in zip(found, scores) if sc <= threshold])
    rivals = rivals_full[:, :n_par]
    if fit_offset:  # the zero's uncertainty covers the equally good minima too
        offset_se = max(offset_se, 0.5 * float(np.ptp(rivals_full[:, n_par])))
    span_lo, span_hi = rivals.min(axis=0), rivals.max(axis=0)
    uncertainty = np.maximum(se_rel, 0.5 * (span_hi - span_lo)) / xr  # relative: local SE or the rivals' spread
    det = (uncertainty < REL_SE_LIMIT) & (free < 0.1) & ~at_bound
    # a spring's rest length and stiffness stand or fall together: one undetermined, both reported so
    for i in range(len(model.springs)):
        det[2 * i] = det[2 * i + 1] = bool(det[2 * i] and det[2 * i + 1])
    se = se_rel * nominal
    # the interval covers the local one and every equally good minimum
    ci = {n: [float(min(est[k] - tq * se[k], span_lo[k] * nominal[k])), float(max(est[k] + tq * se[k], span_hi[k] * nominal[k]))]
          for k, n in enumerate(names) if det[k]}
    alternatives = {n: [float(span_lo[k] * nominal[k]), float(span_hi[k] * nominal[k])] for k, n in enumerate(names)}
    parameters = dict(zip(names, est.tolist()))
    fitted = model.with_parameters(parameters)
    curve_knee_rad = np.linspace(float(holds.knee_rad.min()), float(holds.knee_rad.max()), 200)
    return ReplicaResult(parameters, dict(zip(names, nominal.tolist())),
                         dict(zip(names, (lo * nominal).tolist())), dict(zip(names, (hi * nominal).tolist())),
                         dict(zip(names, se.tolist())), ci, [n for n, d in zip(names, det) if d],
                         [n for n, d in zip(names, det) if not d], float(np.sqrt(np.mean(r**2))), model_tau, holds,
                         iters, len(inits), solve_s, success=True, status=FitStatus.CONVERGED,
                         message=f"converged from {len(found)} of {len(inits)} starts", fun=float(np.min(scores)),
                         alternatives=alternatives, equivalent_minima=len(rivals),
                         sensor_offset_nm=offset, sensor_offset_se_nm=offset_se, curve_knee_rad=curve_knee_rad,
                         curve_torque_nm=fitted.torque_nm(curve_knee_rad) + offset,
                         verification=forward_check(fitted, replace(holds, torque_nm=holds.torque_nm - offset)))


def forward_check(model: ReplicaModel, holds: Holds, *, hold_s: float = 2.0, damping_nm_s_per_rad: float = 0.1) -> dict[str, Any]:
    """Forward dynamics of the fitted rig (``solve_ivp``, RK45: the slack kinks make Radau crawl):
    the shank released at each hold angle with the measured holding torque applied, for
    ``hold_s``, damped by the bearing (0.1 N·m·s/rad). A right model stays put. RMSE of angle (deg) over all holds and of the
    model torque at the measured angles (N·m)."""
    errs = []
    for q0, u in zip(holds.knee_rad, holds.torque_nm):
        def rhs(t: float, x: np.ndarray, u: float = float(u)) -> list[float]:
            # the sensor reads τ(θ) = what holds the shank; released, it accelerates by (u − τ(θ))/I
            return [x[1], (u - float(model.torque_nm(np.array([x[0]]))[0]) - damping_nm_s_per_rad * x[1])
                    / model.shank_inertia_kgm2]

        sol = solve_ivp(rhs, (0.0, hold_s), [float(q0), 0.0], method="RK45", rtol=1e-7, atol=1e-9,
                        t_eval=np.linspace(0.0, hold_s, 41))
        errs.append(sol.y[0] - q0 if sol.success else np.full(41, np.nan))
    e = np.concatenate(errs)
    tq = model.torque_nm(holds.knee_rad) - holds.torque_nm
    return {"angle_rmse_deg": float(np.degrees(np.sqrt(np.mean(e**2)))),
            "angle_max_deg": float(np.degrees(np.max(np.abs(e)))),
            "torque_rmse_nm": float(np.sqrt(np.mean(tq**2)))}


def truth_error_pct(result: ReplicaResult, truth: dict[str, float]) -> dict[str, float]:
    """Signed error (%) of each estimate against known values (the simulator's, or a bench measurement)."""
    return {n: 100.0 * (result.parameters[n] - truth[n]) / truth[n] for n in result.parameters if n in truth}


def to_json(result: ReplicaResult, truth: dict[str, float] | None = None) -> dict[str, Any]:
    out: dict[str, Any] = {
        "parameters": result.parameters, "nominal": result.nominal, "standard_error": result.standard_error,
        "ci95": result.ci95, "determined": result.determined, "undetermined": result.undetermined,
        "bounds": {n: [result.lower[n], result.upper[n]] for n in result.parameters},
        "residual_rms_nm": result.residual_rms_nm, "iterations": result.nit, "starts": result.starts,
        "success": result.success, "status": int(result.status), "message": result.message,
        "solve_s": result.solve_time_s, "sensor_offset_nm": result.sensor_offset_nm,
        "sensor_offset_se_nm": result.sensor_offset_se_nm, "equivalent_minima": result.equivalent_minima,
        "equally_good_range": result.alternatives, "verification": result.verification,
        "holds": {"knee_deg": np.degrees(result.holds.knee_rad).tolist(), "torque_nm": result.holds.torque_nm.tolist(),
                  "model_torque_nm": result.model_torque_nm.tolist()}}
    if truth:
        out["truth"] = truth
        out["error_pct"] = truth_error_pct(result, truth)
    return out


def summary_table(result: ReplicaResult, truth: dict[str, float] | None = None
                  ) -> tuple[str, tuple[str, ...], list[tuple[str, ...]]]:
    """The spring fit for a results view: a headline, column titles and rows (text; k in N/m, rest length
    in mm). A spring the holds do not determine shows the spread of the equally good fits, marked "?"."""
    if not result.success:
        return f"replica fit failed: {result.message}; nothing determined", (), []
    err = truth_error_pct(result, truth) if truth else {}
    springs = list(dict.fromkeys(n.split(".")[0] for n in result.parameters))
    determined = [s for s in springs if f"{s}.stiffness_n_per_m" in result.ci95 and f"{s}.rest_length_m" in result.ci95]
    head = (f"{len(determined)} of {len(springs)} springs determined; residual {result.residual_rms_nm:.3g} N·m RMS "
            f"over {result.holds.knee_rad.size} holds")
    columns = ("spring", "k (N/m)", "k 95 % interval", "rest (mm)", "rest 95 % interval") + \
        (("error k / rest (%)",) if err else ())
    rows = []
    for name in springs:
        kn, ln = f"{name}.stiffness_n_per_m", f"{name}.rest_length_m"
        if name in determined:
            row = (name, f"{result.parameters[kn]:.0f}", "[{:.0f}, {:.0f}]".format(*result.ci95[kn]),
                   f"{1e3 * result.parameters[ln]:.1f}", "[{:.1f}, {:.1f}]".format(*(1e3 * np.array(result.ci95[ln]))))
            rows.append(row + ((f"{err[kn]:+.1f} / {err[ln]:+.1f}",) if err else ()))
        else:
            spread_k = result.alternatives.get(kn, result.ci95.get(kn, [np.nan, np.nan]))
            spread_l = 1e3 * np.array(result.alternatives.get(ln, result.ci95.get(ln, [np.nan, np.nan])))
            rows.append((name, "not determined", "? {:.0f}–{:.0f}".format(*spread_k), "",
                         "? {:.1f}–{:.1f}".format(*spread_l)) + (("",) if err else ()))
    return head, columns, rows


def text(result: ReplicaResult, truth: dict[str, float] | None = None) -> str:
    """The spring table as the operator reads it (k in N/m, rest length in mm)."""
    if not result.success:
        return f"replica fit failed: {result.message}; the springs are not estimated (nothing determined)"
    err = truth_error_pct(result, truth) if truth else {}
    lines = ["95% CI, or for a spring the holds do not determine, '?' and the spread of the equally good fits",
             f"{'spring':8s} {'k (N/m)':>16s} {'95% CI':>17s} {'rest (mm)':>16s} {'95% CI':>15s}"
             + ("  error k / rest" if err else "")]
    for name in dict.fromkeys(n.split(".")[0] for n in result.parameters):
        kn, ln = f"{name}.stiffness_n_per_m", f"{name}.rest_length_m"
        # undetermined: the spread of the equally good fits, marked with "?" (not an interval)
        ck = "[{:.0f}, {:.0f}]".format(*result.ci95[kn]) if kn in result.ci95 else \
            "? {:.0f}–{:.0f}".format(*result.alternatives[kn])
        cl = "[{:.1f}, {:.1f}]".format(*(1e3 * np.array(result.ci95[ln]))) if ln in result.ci95 else \
            "? {:.1f}–{:.1f}".format(*(1e3 * np.array(result.alternatives[ln])))
        if kn in result.ci95 and ln in result.ci95:
            row = (f"{name:8s} {result.parameters[kn]:8.0f} ± {result.standard_error[kn]:5.0f} {ck:>17s} "
                   f"{1e3 * result.parameters[ln]:8.1f} ± {1e3 * result.standard_error[ln]:4.1f} {cl:>15s}")
            if err:
                row += f"  {err[kn]:+5.1f}% / {err[ln]:+5.1f}%"
        else:  # which of the equally good fits the solver ended in says nothing: no point value, no error
            row = f"{name:8s} {'not determined':>16s} {ck:>17s} {'':>16s} {cl:>15s}"
            if truth and kn in truth and ln in truth:
                spreads = {n: sorted(result.alternatives.get(n, result.ci95.get(n, (np.nan, np.nan)))) for n in (kn, ln)}
                inside = all(lo - 1e-9 * abs(lo) <= truth[n] <= hi + 1e-9 * abs(hi) for n, (lo, hi) in spreads.items())
                row += "  truth " + ("inside" if inside else "outside") + " the spread"
        lines.append(row)
    v = result.verification
    lines.append(f"sensor zero {result.sensor_offset_nm:+.3f} ± {result.sensor_offset_se_nm:.3f} N·m")
    lines.append(f"residual RMS {result.residual_rms_nm:.4f} N·m over {result.holds.knee_rad.size} holds; forward check: "
                 f"angle RMSE {v.get('angle_rmse_deg', float('nan')):.3f}°, "
                 f"torque RMSE {v.get('torque_rmse_nm', float('nan')):.4f} N·m")
    return "\n".join(lines)


def write_plots(result: ReplicaResult, out_dir: str | Path, truth: dict[str, float] | None = None) -> list[Path]:
    """Torque at the holds against the fitted model (left) and each spring's estimate over the
    drawing's value with its interval, truth marked when known (right, Figure 3.12's content)."""
    import json

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(11, 4), layout="constrained")
    FigureCanvasAgg(fig)
    a, b = fig.subplots(1, 2)
    deg = np.degrees(result.holds.knee_rad)
    a.errorbar(deg, result.holds.torque_nm, yerr=result.holds.torque_sd_nm, fmt="o", color="0.3", ms=4,
               label="measured (hold mean ± SD)")
    a.plot(np.degrees(result.curve_knee_rad), result.curve_torque_nm, "-", color="C0", label="fitted springs")
    a.set_xlabel("knee flexion (°)")
    a.set_ylabel("torque against flexion (N·m)")
    a.legend(fontsize=8)
    names = list(result.parameters)
    ratio = np.array([result.parameters[n] / result.nominal[n] for n in names])
    err = np.array([result.standard_error[n] / result.nominal[n] for n in names])
    colors = ["C0" if n in result.determined else "0.75" for n in names]
    x = np.arange(len(names))
    b.bar(x, ratio, yerr=1.96 * err, color=colors, capsize=3)
    if truth:
        b.plot(x, [truth[n] / result.nominal[n] for n in names], "k_", ms=18, mew=2, label="truth")
        b.legend(fontsize=8)
    b.axhline(1.0, color="k", lw=0.6)
    b.set_xticks(x, [n.replace(".stiffness_n_per_m", " k").replace(".rest_length_m", " L0") for n in names],
                 rotation=45, fontsize=8)
    b.set_ylabel("estimate / drawing (grey: not determined)")
    files = [out / "replica_fit.png", out / "replica_report.json"]
    fig.savefig(files[0], dpi=100)
    files[1].write_text(json.dumps(to_json(result, truth), indent=2, default=float))
    return files


__all__ = ["write_plots", "ReplicaSpring", "ReplicaModel", "load_replica_model", "Holds", "holds_from_samples", "ReplicaResult",
           "estimate_replica", "forward_check", "truth_error_pct", "to_json", "text", "DEFAULT_MODEL"]
