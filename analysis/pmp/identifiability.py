"""What a fit determined: intervals with the residual's own variance, its effective sample size, the
model's error allowance and the measured inputs' uncertainties; the misfit test that says when nothing is."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .geometry import model_segment_lengths_m
from .model import (
    PmpTrial,
    Subject,
    eliminate_tendons,
    muscles_moment,
    other_joint,
    set_angle_condition,
    set_angle_label,
    with_set_angles,
)
from .muscles import LegMuscles
from .problem import PmpResult
from .workers import mapped

#: the residual may be at most this many times the measurement noise for anything to count as determined
MISFIT_LIMIT = 3.0
#: the model-error allowance (N·m, RMS per sample): a residual whose systematic part is within it passes the misfit
#: test whatever its ratio to the noise. Until 2026-11-27 every interval's bias bound was sized by it too (now by the
#: residual's own systematic part, below); that bound's history: the muscle model is 0.021 N·m off OpenSim at worst,
#: the allowance is for the mismatch a fit can still pass the misfit test with. Measured on `python -m benchmarks pmp_opensim`
#: (10 OpenSim-made subjects, rigid and "realistic" variants): at 0.03 N·m, 36 parameters called
#: determined and 35 held the truth (the miss: a realistic-variant subject with unmodelled activation,
#: misfit 2.7×); at 0.25 N·m, 22 called and 22 held (max error 0.65 %). Before the calf fibres' ε₀ was
#: estimated, 0.03 N·m gave 18 of 24 (errors to 73 %): their ε₀ went into ε_T0
MODEL_ERROR_RMS_NM = 0.25
#: the estimator's own physics against OpenSim's at the true parameters (N·m RMS, the worst of 10 subjects' knee
#: trials; the ankle's < 0.0001): the model error a fit keeps when nothing is missing from the model
MODEL_PHYSICS_ERROR_NM = 0.021


@dataclass(frozen=True)
class Identifiability:
    """Which parameters a fit's trials determine, and how well (the result of :func:`identifiability`).

    Attributes
    ----------
    determined, undetermined : parameter names (``muscle.quantity``)
    relative_se : each parameter's standard error relative to its value (noise, measurement and model error)
    ci95 : each determined parameter's 95 % interval (its own unit: m, or dimensionless strain)
    model_error_bound_rel : the bias the model-error allowance can cause, relative to the value
    free_combinations : the directions the trials do not determine (eigenvalue and leading components)
    rank, parameters : determined directions, and parameters in all
    at_bound : parameters the fit left at a bound
    residual_rms_nm, noise_nm, misfit_ratio : residual and measurement noise (N·m RMS) and their ratio
    systematic_residual_nm : the part of the residual the noise does not explain (N·m RMS)
    effective_samples, samples : independent samples (from the residual's autocorrelation) and samples
    not_determined_because : why nothing is determined, if nothing is
    uncertainty : how the intervals were made, in words
    measurement_se_rel : each parameter's relative SE from the measured inputs (shank, set angles, mass)
    measurement_nuisances : the measured inputs propagated
    extension : the model extension fitted jointly, if any
    thigh_would_determine : parameters a tape measure of the thigh would determine (when it was not measured)
    model_misfit : whether the residual's systematic part exceeds what the intervals allow for (the model lacks
        something these trials show; one of ``not_determined_because``)
    """

    determined: list[str]
    undetermined: list[str]
    relative_se: dict[str, float]
    ci95: dict[str, list[float]]
    model_error_bound_rel: dict[str, float]
    free_combinations: list[dict[str, Any]]
    rank: int
    parameters: int
    at_bound: list[str]
    residual_rms_nm: float
    noise_nm: float
    misfit_ratio: float
    systematic_residual_nm: float
    effective_samples: float
    samples: int
    not_determined_because: list[str]
    uncertainty: str
    measurement_se_rel: dict[str, float]
    measurement_nuisances: list[str]
    extension: str | None
    model_misfit: bool = False
    #: parameters a tape measure of the thigh would determine (the thigh not measured: its muscles' intervals
    #: carry adults' spread of thigh to shank proportions)
    thigh_would_determine: list[str] = dataclasses.field(default_factory=list)
    #: models the data could not reject beside the fitted one (:func:`with_plausible_models`): the intervals hold
    #: the parameters' estimates under these too
    model_alternatives: list[str] = dataclasses.field(default_factory=list)
    #: with an extension: the share (0–1) of each parameter's effect on the torque that the extension's terms
    #: reproduce (the R² of its sensitivity on theirs); near 1, the parameter is told from the extension by the
    #: curves' shapes only (a one-joint muscle beside a joint-level structure at its joint)
    extension_share: dict[str, float] = dataclasses.field(default_factory=dict)
    #: parameters the extension's own family would have determined that its shape's uncertainty leaves open
    #: (:meth:`analysis.pmp.model_diagnosis.Extension.shape_columns` profiled out too): told from the extension by
    #: a shape the data cannot vouch for
    shape_limited: list[str] = dataclasses.field(default_factory=list)

    def as_dict(self) -> dict[str, Any]:
        """The fields as a JSON-ready dict (the report's and the cohort store's form)."""
        return dataclasses.asdict(self)


#: a determined parameter whose effect on the torque the fitted extension's terms reproduce to more than this share
#: (:attr:`Identifiability.extension_share`) is reported as told from the extension by the curves' shapes only. Not a
#: decision: on development subjects (OpenSim-made, seeds 52000–52309) soleus' slack length beside the ankle's
#: end-range structures had shares 0.37–0.99, and its errors did not follow them (−3.19 % at 0.95, −0.03 % at 0.99)
SHAPE_ONLY_SHARE = 0.9

#: a parameter within this fraction of a bound is at the bound
AT_BOUND_REL = 1e-3


def parameters_at_bound(result: PmpResult, names: list[str] | None = None) -> list[str]:
    """The parameters among ``names`` (default: all) that a fit left at (within :data:`AT_BOUND_REL` of) a bound."""
    p, lo, hi = result.parameters, result.lower, result.upper
    return [n for n in (p if names is None else names)
            if p[n] <= lo[n] * (1 + AT_BOUND_REL) or p[n] >= hi[n] * (1 - AT_BOUND_REL)]


#: the model's parameter Jacobian (and its finite differences in shank, set angle and mass) is evaluated at every
#: JACOBIAN_STRIDE-th sample and at the last, and interpolated between by a cubic spline in the sample index; the
#: model's torque itself at every sample (tabulated in angle: TORQUE_TABLE_STEP_RAD). Each Jacobian row solves the calf
#: tendons' equilibrium and its sensitivity (≈ 0.4 ms a sample): every sample took 5 s of a plain report's 20 s on six
#: 5 °/s sweeps (measured 2026-11-27: 7.4 → 3.5 s, 5.2 → 3.8 s on two OpenSim-made subjects, 1.6 → 0.9 s on the
#: synthetic one). Samples 4 apart are 0.2° at 5 °/s, where the rows are smooth: the 95 % intervals moved by at most
#: 1.7e-6 of their width, the same parameters determined, the same misfit (tests/analysis/test_pmp_estimator.py holds
#: it to 1e-4)
JACOBIAN_STRIDE = 4
#: the model's torque at every sample is tabulated over the trial's angles at this step (rad) and interpolated by a cubic
#: spline in angle, where the model has no velocity term: one equilibrium solve per 0.25° instead of per sample (a 5 °/s
#: sweep at 100 Hz has 20 samples per degree). On an exponential moment M(q) = 50 N·m·e^{10 (q − q_top)} over 60° the
#: spline is off by at most 4.9e-6 N·m (at the table's ends; the test holds it to 1e-5). On the same two subjects as
#: verify.TABLE_STEP_RAD's: every number of the identifiability (intervals, bounds, misfit) within 2.3e-6 of its value
#: with every sample evaluated, the same parameters determined; 9.9 → 6.2 s on the compliant-tendon subject's extended
#: fit (measured beside a running test suite)
TORQUE_TABLE_STEP_RAD = float(np.deg2rad(0.25))


def _torque_at_every_sample(symbols: list[Any], model_u: Any, angle: np.ndarray,
                            at: Callable[[np.ndarray, list[Any]], list[np.ndarray]]) -> np.ndarray:
    """The model's torque ``model_u`` (N·m) at every sample: where it is a function of the angle alone (no velocity
    term in the model), tabulated over the trial's angles at :data:`TORQUE_TABLE_STEP_RAD` and interpolated by a cubic
    spline in angle; else (or where the table has no value) evaluated at each sample by ``at`` (indices, outputs)."""
    import casadi as ca
    from scipy.interpolate import CubicSpline

    lo, hi = float(np.min(angle)), float(np.max(angle))
    points = int(np.ceil((hi - lo) / TORQUE_TABLE_STEP_RAD)) + 1
    if not ca.depends_on(model_u, symbols[1]) and 4 <= points < angle.size:
        grid = np.linspace(lo, hi, points)
        f = ca.Function("u", symbols, [model_u])
        table = np.asarray(mapped(f, points)(grid.reshape(1, -1), np.zeros((1, points)),
                                             ca.repmat(ca.DM.ones(symbols[2].numel()), 1, points),
                                             ca.DM.zeros(symbols[3].numel(), points))).ravel()
        if np.all(np.isfinite(table)):
            return np.asarray(CubicSpline(grid, table)(angle))
    return at(np.arange(angle.size), [model_u])[0].ravel()


def _model_and_sensitivities(symbols: list[Any], model_u: Any, derived: list[Any], angle: np.ndarray,
                             velocity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The model's torque ``model_u`` (N·m, of ``symbols`` q, v, p_rel, e_rel) at every sample, and the rows
    ``derived`` = (its Jacobian in (p_rel, e_rel), then its values at each measured-quantity step, as
    differences from it) at every :data:`JACOBIAN_STRIDE`-th sample, interpolated; every sample's own where a
    row is not finite (the equilibrium failed: those samples are counted by the caller)."""
    import casadi as ca
    from scipy.interpolate import CubicSpline

    n_rel = int(symbols[2].numel() + symbols[3].numel())

    def at(idx: np.ndarray, outputs: list[Any]) -> list[np.ndarray]:
        out = mapped(ca.Function("u", symbols, outputs), idx.size)(
            angle[idx].reshape(1, -1), velocity[idx].reshape(1, -1), ca.repmat(ca.DM.ones(symbols[2].numel()), 1, idx.size),
            ca.DM.zeros(symbols[3].numel(), idx.size))
        return [np.asarray(o) for o in (out if isinstance(out, (list, tuple)) else [out])]

    def rows(out: list[np.ndarray]) -> np.ndarray:
        u = out[0].ravel()
        jac = out[1].reshape(-1, n_rel)  # the map lays the rows side by side
        return np.hstack([jac, np.column_stack([o.ravel() - u for o in out[2:]])])

    n = angle.size
    every = np.arange(n)
    sub = np.unique(np.r_[np.arange(0, n, JACOBIAN_STRIDE), n - 1])
    if sub.size >= 4 and sub.size < n:
        coarse = rows(at(sub, [model_u, *derived]))
        if np.all(np.isfinite(coarse)):
            return _torque_at_every_sample(symbols, model_u, angle, at), CubicSpline(sub, coarse, axis=0)(every)
    out = at(every, [model_u, *derived])
    return out[0].ravel(), rows(out)


def identifiability(result: PmpResult, trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None,
                    rel_se_limit: float = 0.035, stride: int = 1, misfit_limit: float = MISFIT_LIMIT,
                    model_error_nm: float | None = None, extension: Any = None) -> Identifiability:
    """Which parameters the trials determine, with honest 95 % intervals.

    Uncertainty: the torque residuals e = u_model(q) − u_measured at every measured sample
    (quasi-static model, as the sweeps are slow) are linearised in the relative parameters (J from
    CasADi's exact derivatives). The covariance is the least-squares one with the residual's own
    variance σ̂² (not an assumed sensor noise, so a model that misses the data gets wide
    intervals) inflated by n / n_eff, the residual's effective sample size from its integrated
    autocorrelation time (systematic misfit is correlated, and counts as few samples):
    C = σ̂² (JᵀJ)⁺ · n / n_eff, restricted to the directions the data constrain. The model's own
    error can bias the estimate by at most |a_k|·|δ| for parameter k (a_k the row of the least-squares
    solution operator, |δ| = RMS·√n), its RMS the residual's systematic part √(RMS² − noise²) (what the
    fit shows of it; at least :data:`MODEL_PHYSICS_ERROR_NM`, the physics' own error against OpenSim); the
    95 % interval is ±(1.96·SE + that bound).

    A parameter is *determined* when (1) the fit converged; (2) the residual is consistent with
    the measurement noise or within the model error the intervals allow for: its RMS is at most
    ``misfit_limit`` × the noise seen in the torque's second differences, or its systematic part
    at most ``model_error_nm`` (default :data:`MODEL_ERROR_RMS_NM`; otherwise the report says the model does not fit
    well enough to determine anything, and by how much); (3) its 95 % interval is within ± ``rel_se_limit``
    (3.5 %, the dissertation's accuracy); (4) no parameter of its muscle is at a bound; and (5)
    every parameter of its synergists (other muscles crossing the same joints with the same
    moment-arm signs) is determined too — otherwise they can share the load in ways the local
    curvature does not see. The eigenvectors of the information with eigenvalues below
    1/limit² are the combinations the data leave free, listed with their largest components.

    With ``extension`` (the one ``result`` was fitted with), its terms are in the model and its
    parameters are nuisances fitted jointly: the muscles' information is the Schur complement
    I_mm − I_mn I_nn⁺ I_nm (the nuisances profiled out, to first order: a muscle parameter that
    trades against the extension gets the wider interval it deserves), and the least-squares
    solution operator is the one with the nuisances free. The extension's shape is a family's, not the
    structure's: its shape columns (:meth:`analysis.pmp.model_diagnosis.Extension.shape_columns`, e.g. more
    exponentials at a range's end) are profiled out beside its parameters, free at zero, so a parameter told from
    the extension only by the family's shape is not determined (:attr:`Identifiability.shape_limited`).
    """
    import casadi as ca

    leg = leg or LegMuscles()
    model_error_nm = MODEL_ERROR_RMS_NM if model_error_nm is None else model_error_nm
    names = list(result.parameters)
    values = np.array([result.parameters[n] for n in names])
    prel = ca.SX.sym("p", len(names))
    par = {n: values[i] * prel[i] for i, n in enumerate(names)}
    ext_names = list(extension.parameters) if extension is not None else []
    ext_size = np.asarray(extension.typical, dtype=float) if extension is not None else np.zeros(0)
    ext_values = np.array([result.extension_parameters.get(n, 0.0) for n in ext_names])
    # a nuisance moves by its typical size per unit of its symbol (its value may be 0)
    erel = ca.SX.sym("e", len(ext_names))
    ext_par = [float(ext_values[i]) + float(ext_size[i]) * erel[i] for i in range(len(ext_names))]
    q, v = ca.SX.sym("q"), ca.SX.sym("v")
    # what was measured, not fitted, as nuisances with their measurement SD as prior: the shank (it scales
    # every path; a 5 mm tape error moved both determined slack lengths by 1.3 %, outside intervals of
    # ±0.4 % that took the shank as exact), each fixed joint's set angle, and the body mass (limb weight)
    conditions = sorted({set_angle_condition(t) for t in trials})
    # and the thigh's scale over the shank's (the thigh's muscles follow it: measured by tape, or unknown within
    # adults' proportions; a thigh 8.5 % longer than the shank's scale moved rectus femoris' slack by −7 %)
    measured = ["shank_length_scale"] + [set_angle_label(c) for c in conditions] + ["mass_kg", "thigh_over_shank"]
    # set angles the fit estimated (PmpResult.set_angle_offsets_rad) are nuisances fitted with their prior: the
    # model is evaluated at them and they are profiled out of the muscles' information with the prior's precision
    set_angles_fitted = bool(result.set_angle_offsets_rad)
    condition_of = [set_angle_condition(t) for t in trials]
    trials = with_set_angles(trials, result.set_angle_offsets_rad)
    prior_sd = np.array([subject.shank_length_sd_m / subject.shank_length_m]
                        + [subject.set_angle_sd_rad] * len(conditions) + [subject.mass_sd_kg, subject.thigh_over_shank_sd()])

    def model_u_of(t: PmpTrial, use_leg: LegMuscles, fixed: dict[str, float], mass_kg: float) -> Any:
        tt = PmpTrial(t.joint, fixed, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name)
        q_joint = extension.joint_angle(tt, q, ext_par) if extension is not None else q
        options = extension.muscle_options(tt, ext_par) if extension is not None else {}
        moment = eliminate_tendons(*muscles_moment(use_leg, tt, q_joint, par, **options), [q, prel, erel])
        if extension is not None and extension.angle is not None:  # virtual work, as in the fit
            moment = moment * ca.jacobian(q_joint, q)
        body = Subject(mass_kg, subject.shank_length_m, subject.foot_length_m, subject.arm_inertia_kgm2)
        gravity = body.gravity_moment_nm(t.joint, q, fixed, ca.cos)
        return -(moment + gravity + (extension.moment(tt, q, v, ext_par, gravity) if extension is not None else 0))

    step_scale, step_angle, step_mass = 1e-4, 1e-4, 1e-2
    # a shank measured long scales every path; a thigh measured too keeps its own length, so its muscles' relative
    # scale falls by as much (unmeasured, the thigh follows the shank)
    scaled_leg = leg.rescaled(1.0 + step_scale, 1.0 if subject.thigh_length_m is None else 1.0 / (1.0 + step_scale))
    thigh_leg = leg.rescaled(1.0, 1.0 + step_scale)
    rows, residual_parts, noise_parts = [], [], []
    shape_parts: list[np.ndarray] = []  # the extension's shape uncertainty: free columns at zero (Extension.shape_columns)
    undefined = 0
    for t, condition in zip(trials, condition_of, strict=True):
        model_u = model_u_of(t, leg, t.fixed_rad, subject.mass_kg)
        angle = smoothed(t.angle_rad)[::stride]  # angle noise must not pass for torque misfit on steep curves
        velocity = smoothed(t.velocity_rad_s)[::stride]
        both = ca.vertcat(prel, erel)
        other = other_joint(t)
        shifted = dict(t.fixed_rad)
        shifted[other] = t.fixed_rad.get(other, 0.0) + step_angle
        variants = [model_u_of(t, scaled_leg, t.fixed_rad, subject.mass_kg), model_u_of(t, leg, shifted, subject.mass_kg),
                    model_u_of(t, leg, t.fixed_rad, subject.mass_kg + step_mass),
                    model_u_of(t, thigh_leg, t.fixed_rad, subject.mass_kg)]
        u_pred, sensitivities = _model_and_sensitivities([q, v, prel, erel], model_u,
                                                          [ca.jacobian(model_u, both), *variants], angle, velocity)
        cols = np.zeros((angle.size, len(measured)))
        cols[:, 0] = sensitivities[:, -4] / step_scale
        cols[:, 1 + conditions.index(condition)] = sensitivities[:, -3] / step_angle
        cols[:, -2] = sensitivities[:, -2] / step_mass
        cols[:, -1] = sensitivities[:, -1] / step_scale
        shape = (np.asarray(extension.shape_columns(t, angle, ext_values), dtype=float).reshape(angle.size, -1)
                 if extension is not None else np.zeros((angle.size, 0)))
        shape_parts.append(shape)
        rows.append(np.hstack([sensitivities[:, :-4], cols]))
        residual = u_pred - t.torque_nm[::stride]
        # where the fitted model has no value (the calf tendons without an equilibrium, an overflow) the sample
        # is left out and counted; any such sample makes nothing determined (below)
        defined = np.isfinite(residual) & np.isfinite(rows[-1]).all(axis=1)
        undefined += int((~defined).sum())
        rows[-1] = rows[-1][defined]
        shape_parts[-1] = shape_parts[-1][defined]
        residual_parts.append(residual[defined])
        # white noise from second differences (the smooth moment curve hardly has any): var(Δ²e) = 6σ²
        noise_parts.append(np.diff(t.torque_nm, 2) / np.sqrt(6.0))
    j_all = np.vstack(rows)
    j, j_nuis = j_all[:, :len(names)], j_all[:, len(names):]
    n_samples, k = j.shape
    residual_rms = float(np.sqrt(np.mean(np.concatenate(residual_parts) ** 2)))
    noise = float(1.4826 * np.median(np.abs(np.concatenate(noise_parts))))  # robust σ of white noise
    sigma2 = float(np.sum(np.concatenate(residual_parts) ** 2) / max(n_samples - k - len(ext_names), 1))
    n_eff = float(sum(e.size / autocorrelation_time(e) for e in residual_parts))
    scale_c = sigma2 * n_samples / max(n_eff, 1.0)
    j_ext, j_meas = j_nuis[:, :len(ext_names)], j_nuis[:, len(ext_names):]
    # the residual's systematic part (beyond the white noise): the model error this fit shows. The bias bound's RMS is
    # that part (the error the parameters absorbed taken as no larger than the part they left), at least the
    # physics' own error against OpenSim
    systematic = math.sqrt(max(residual_rms**2 - noise**2, 0.0))
    model_error_rms = max(MODEL_PHYSICS_ERROR_NM, systematic)
    widths = {p.shape[1] for p in shape_parts}
    shape_cols = np.vstack(shape_parts) if ext_names and len(widths) == 1 and widths != {0} else None

    def interval_terms(j_ext: np.ndarray, j: np.ndarray, j_meas: np.ndarray, prior_sd: np.ndarray) -> dict[str, Any]:
        """The intervals' terms with the nuisance columns ``j_ext`` profiled out (the extension's own, and its shape's)."""
        extension_share: dict[str, float] = {}
        if j_ext.shape[1]:
            # the extension's parameters profiled out (fitted jointly, first order): the muscles' columns (and the
            # set angles') made orthogonal to the extension's
            project = np.linalg.pinv(j_ext.T @ j_ext, rcond=1e-10) @ j_ext.T
            explained = j_ext @ (project @ j)
            # how much of each parameter's effect on the torque the extension's terms reproduce (R² of its column on
            # theirs): near 1, the two are told apart by the curves' shapes only
            own = np.sum(j**2, axis=0)
            share = np.where(own > 0, np.sum(explained**2, axis=0) / np.where(own > 0, own, 1.0), 0.0)
            extension_share = {n: float(np.clip(v, 0.0, 1.0)) for n, v in zip(names, share, strict=True)}
            j = j - explained
            j_meas = j_meas - j_ext @ (project @ j_meas)
        n_set = len(conditions)
        if set_angles_fitted:
            # the set angles profiled out with their prior (joint covariance, first order): the muscles' information
            # is the Schur complement I_mm − I_ms (I_ss + 1/σ²)⁻¹ I_sm, the solution operator the one with them free
            j_set = j_meas[:, 1:1 + n_set]
            j_meas, prior_sd = j_meas[:, [0, -2, -1]], prior_sd[[0, -2, -1]]
            info_ss = j_set.T @ j_set / scale_c + np.eye(n_set) / subject.set_angle_sd_rad**2
            info_ms = j.T @ j_set / scale_c
            gain_s = np.linalg.solve(info_ss, info_ms.T)  # (n_set, k)
            operator = j.T - gain_s.T @ j_set.T  # the muscles' normal equations with the set angles eliminated
            info = j.T @ j / scale_c - info_ms @ gain_s
        else:
            operator = j.T
            info = j.T @ j / scale_c
        info_finite = n_samples > 0 and bool(np.all(np.isfinite(info)))
        if not info_finite:
            info = np.zeros_like(info)  # nothing is constrained: every parameter undetermined (the reasons say why)
        w, vecs = np.linalg.eigh(info)
        keep = w > 1.0 / rel_se_limit**2
        cov = (vecs[:, keep] / w[keep]) @ vecs[:, keep].T
        se = np.sqrt(np.maximum(np.diag(cov), 0.0))
        # the forward model's error biases the fit by at most |a_k|·|δ| for parameter k (a_k: row k of the
        # least-squares solution operator, restricted to the constrained directions; |δ| = RMS·√n): a bound added to
        # the interval, its RMS model_error_rms (below)
        solve_rows = (vecs[:, keep] / w[keep]) @ vecs[:, keep].T @ operator / scale_c
        bias = np.sqrt(np.sum(solve_rows**2, axis=1)) * model_error_rms * np.sqrt(n_samples)
        # a parameter is determined only if it has (almost) no part in the unconstrained directions
        free_part = np.sqrt(np.sum(vecs[:, ~keep] ** 2, axis=1)) if (~keep).any() else np.zeros(len(names))
        # the measured quantities (shank, set angles, mass) enter as they were entered; an error Δ in one shifts the
        # estimate by C·Jᵀ·J_Δ·Δ / c (the fit's response to the torque it causes): their SDs propagated to first
        # order (delta method) and added to the variance. Profiled into the information instead, the shank took
        # the slack lengths' information with it and the model-error bound (≈ 90 × the SE) made nothing determined
        sensitivity = cov @ operator @ j_meas / scale_c
        measurement_var = np.sum((sensitivity * prior_sd[None, :]) ** 2, axis=1)
        se_total = np.sqrt(se**2 + measurement_var)
        half_width = 1.96 * se_total + bias
        determined = (half_width < rel_se_limit) & (free_part < 0.1)
        # what a tape on the thigh would add: the parameters determined were the thigh's scale known to its tape's SD
        # (first order: the shank's nuisance would then also move the thigh's muscles less)
        thigh_var = (sensitivity[:, -1] * prior_sd[-1]) ** 2
        measured_sd = subject.thigh_length_sd_m / model_segment_lengths_m()["thigh_length_m"]
        with_thigh = (1.96 * np.sqrt(se**2 + measurement_var - thigh_var * (1.0 - (measured_sd / prior_sd[-1]) ** 2))
                      + bias < rel_se_limit) & (free_part < 0.1)
        return {"extension_share": extension_share, "info_finite": info_finite, "w": w, "vecs": vecs, "keep": keep,
                "bias": bias, "measurement_var": measurement_var, "se_total": se_total, "half_width": half_width,
                "determined": determined, "with_thigh": with_thigh}

    # the extension's shape uncertainty (Extension.shape_columns: free columns at zero) profiled out too; what the
    # extension's own family would have determined is kept, to say which parameters its shape leaves open
    within_family = interval_terms(j_ext, j, j_meas, prior_sd)
    terms = (within_family if shape_cols is None else
             interval_terms(np.hstack([j_ext, shape_cols]), j, j_meas, prior_sd))
    # the share the extension's own terms reproduce (its family's, as SHAPE_ONLY_SHARE reads it)
    extension_share = within_family["extension_share"]
    info_finite, w, vecs, keep = terms["info_finite"], terms["w"], terms["vecs"], terms["keep"]
    bias, measurement_var, se_total = terms["bias"], terms["measurement_var"], terms["se_total"]
    half_width = terms["half_width"]
    determined, with_thigh = terms["determined"], terms["with_thigh"]
    shape_limited = [n for n, a, b in zip(names, within_family["determined"], determined, strict=True) if a and not b]
    misfit_ratio = residual_rms / max(noise, 1e-12)
    # a residual whose systematic part stays within model_error_nm is consistent with the intervals even when the
    # noise is small (a 0.05 N·m sensor shows a 0.14 N·m model error as 3×)
    reasons = []
    if not info_finite:
        reasons.append("the fit's information is not finite: nothing can be determined from it")
    if not result.success:
        reasons.append(f"the fit did not converge ({result.message})")
    if undefined:
        reasons.append(f"the fitted model has no value at {undefined} of {n_samples + undefined} samples (the calf "
                       "tendons without an equilibrium there, or an overflow): its parameters are not trusted")
    model_misfit = misfit_ratio > misfit_limit and systematic > model_error_nm
    if model_misfit:
        reasons.append(f"the model does not fit the data well enough to determine anything: residual RMS "
                       f"{residual_rms:.3g} N·m is {misfit_ratio:.1f}× the measurement noise ({noise:.3g} N·m; "
                       f"at most {misfit_limit:g}× allowed), its systematic part {systematic:.3g} N·m more than the "
                       f"{model_error_nm:g} N·m model error the intervals allow for")
    if reasons:
        determined[:] = False
    at_bound = parameters_at_bound(result, names)
    mid = {"hip": np.deg2rad(50.0), "knee": np.deg2rad(45.0), "ankle": 0.0}

    def signature(m: str) -> tuple:
        return tuple((j, bool(np.sign(leg.moment_arm_m(m, j, **mid)) > 0)) for j in leg.paths[m].joints)

    muscles = sorted({n.split(".")[0] for n in names})
    det = dict(zip(names, determined))
    pinned = {n.split(".")[0] for n in at_bound}
    undetermined_muscles = {n.split(".")[0] for n in names if not det[n]}
    for m in muscles:
        others = [g for g in muscles if g != m and signature(g) == signature(m)]
        if m in pinned or any(g in undetermined_muscles for g in others):
            for n in names:
                if n.split(".")[0] == m:
                    det[n] = False
    determined = np.array([det[n] for n in names])
    combos = []
    for i in np.flatnonzero(~keep):
        order = np.argsort(-np.abs(vecs[:, i]))[:4]
        combos.append({"eigenvalue": float(w[i]), "components": {names[k]: float(vecs[k, i]) for k in order}})
    names_determined = [n for n, d in zip(names, determined) if d]
    return Identifiability(determined=names_determined,
            undetermined=[n for n, d in zip(names, determined) if not d],
            relative_se=dict(zip(names, se_total.tolist())),
            ci95={n: [values[k] * (1 - half_width[k]), values[k] * (1 + half_width[k])]
                     for k, n in enumerate(names) if determined[k]},
            model_error_bound_rel=dict(zip(names, bias.tolist())),
            free_combinations=combos, rank=int(keep.sum()), parameters=len(names), at_bound=at_bound,
            residual_rms_nm=residual_rms, noise_nm=noise, misfit_ratio=misfit_ratio,
            systematic_residual_nm=systematic,
            effective_samples=n_eff, samples=n_samples, not_determined_because=reasons,
            uncertainty="least-squares covariance with the residual's variance, inflated by n/n_eff "
                           "(integrated autocorrelation time of the residual), plus the largest bias a model error of "
                           f"{model_error_rms:.3g} N·m RMS can cause (the residual's systematic part, at least the "
                           f"physics' own {MODEL_PHYSICS_ERROR_NM:g} N·m)"
                           + (f"; the {extension.name} parameters fitted jointly as nuisances (profiled out)"
                              if extension is not None else "")
                           + (f", and {shape_cols.shape[1]} terms of how its shape may differ from its family "
                              "(free, profiled out: the extension's shape uncertainty)" if shape_cols is not None else "")
                           + measured_inputs_text(subject, set_angles_fitted),
            measurement_se_rel=dict(zip(names, np.sqrt(measurement_var).tolist())),
            measurement_nuisances=measured,
            extension=extension.name if extension is not None else None, model_misfit=model_misfit,
            thigh_would_determine=[n for n, d, w in zip(names, determined, with_thigh)
                                   if w and not d and not reasons and subject.thigh_length_m is None],
            extension_share=extension_share,
            shape_limited=[n for n in shape_limited if not reasons and n not in set(names_determined)])


def with_plausible_models(idf: Identifiability, result: PmpResult,
                          alternatives: list[tuple[str, PmpResult, Identifiability]],
                          rel_se_limit: float = 0.035) -> Identifiability:
    """``idf`` (of ``result``) with model uncertainty: each interval widened to the hull of its own and the
    parameter's intervals under ``alternatives`` (name, fit, identifiability: models the held-out test could not
    reject beside the fitted one, :attr:`analysis.pmp.model_diagnosis.ModelDiagnosis.plausible`).

    A parameter stays determined when every model determines it and the hull stays within ± ``rel_se_limit`` of its
    estimate: its value must not hang on a choice the data cannot make. Measured on an OpenSim-made subject with
    compliant knee tendons and a tone, where a tone was named and compliant tendons beside it predicted every
    held-out fold better by 7 % (the margin is 10 %): rectus femoris' slack length was 5.6 % off with an interval
    of ±3 % under the tone alone.
    """
    if not alternatives:
        return idf
    determined, ci95 = [], {}
    for n in idf.determined:
        value = result.parameters[n]
        lo, hi = idf.ci95[n]
        held = True
        for _, _alt_result, alt in alternatives:
            if n not in alt.determined:
                held = False
                break
            alt_lo, alt_hi = alt.ci95[n]
            lo, hi = min(lo, alt_lo), max(hi, alt_hi)
        if held and max(value - lo, hi - value) <= rel_se_limit * abs(value):
            determined.append(n)
            ci95[n] = [lo, hi]
    names = ", ".join(name for name, _, _ in alternatives)
    return dataclasses.replace(
        idf, determined=determined, undetermined=[n for n in idf.relative_se if n not in determined], ci95=ci95,
        model_alternatives=[name for name, _, _ in alternatives],
        uncertainty=idf.uncertainty + f"; model uncertainty: each interval is the hull of its own and the "
                                      f"parameter's interval under {names} (models the held-out test could not "
                                      "reject), and a parameter is determined only if every one of them determines it")


def measured_inputs_text(subject: Subject, set_angles_fitted: bool) -> str:
    """How the intervals carry the measured inputs (the end of ``Identifiability.uncertainty``)."""
    sd = f"SD {math.degrees(subject.set_angle_sd_rad):.1f}°"
    thigh = (f"the thigh's scale over the shank's (SD {100 * subject.thigh_over_shank_sd():.1f} %, "
             + ("from the thigh's tape measure)" if subject.thigh_length_m is not None else "the thigh not measured)"))
    delta = [f"the shank length (SD {1e3 * subject.shank_length_sd_m:.1f} mm)", thigh,
             f"the mass (SD {subject.mass_sd_kg:g} kg)"]
    fitted = f"; each set angle fitted with its prior ({sd}) and profiled out (joint covariance)" if set_angles_fitted else ""
    if not set_angles_fitted:
        delta.insert(2, f"each set angle ({sd})")
    return (f"{fitted}; {', '.join(delta[:-1])} and {delta[-1]} as measured inputs whose SDs are propagated to first "
            "order (delta method)")


def smoothed(angle_rad: np.ndarray) -> np.ndarray:
    """The sweep's angle with sensor noise averaged out (cubic Savitzky–Golay over ~1/20 of the trial)."""
    from scipy.signal import savgol_filter

    n = angle_rad.size
    window = min(n - (1 - n % 2), max(5, (n // 20) | 1))
    return savgol_filter(angle_rad, window, 3) if window > 3 else angle_rad


def autocorrelation_time(e: np.ndarray) -> float:
    """Integrated autocorrelation time of ``e`` (samples per independent sample, ≥ 1; Geyer's
    initial positive sequence)."""
    x = np.asarray(e, dtype=float) - float(np.mean(e))
    if x.size < 4 or not np.any(x):
        return 1.0
    spectrum = np.fft.rfft(x, 2 * x.size)
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[: x.size]
    acf = acf / acf[0]
    tau = 1.0
    for lag in range(1, x.size - 1, 2):
        pair = acf[lag] + acf[lag + 1]
        if pair <= 0:
            break
        tau += 2.0 * pair
    return float(min(max(tau, 1.0), x.size))

