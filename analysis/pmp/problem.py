"""The fit: build the collocation problem → solve it with IPOPT → a frozen :class:`PmpResult`.

build problem → solve → result, after bioptim. For every trial the states are the moving joint's
angle q and velocity v, the control is the dynamometer torque u, and the dynamics are

    I q̈ = u + M_muscles(q; p) + M_gravity(q)

(u is the torque the dynamometer applies toward positive angle once the arm's weight is
removed: exactly a trial CSV's ``torque_Nm``, whose sign :mod:`analysis.trial_csv` defines).
Hermite–Simpson collocation (states and controls at the nodes and interval midpoints) enforces
the dynamics; the calf muscles' tendon lengths are algebraic variables held by the fibre–tendon
equilibrium (eq 3.2) at every point. The cost is eq 3.8, Simpson-integrated over time:
(q − q_m)²/σ_q² + (v − v_m)²/σ_v² + (u − u_m)²/σ_u² with σ_q = 0.5°, σ_v = 2 °/s, σ_u = 0.5 N·m
(typical dynamometer noise), plus an explicit Gaussian prior about the (scaled) generic values
(:data:`PRIOR_RELATIVE_SD`: slack lengths 5 %, strains 25 %, weighted :data:`PRIOR_WEIGHT`) so
that directions the data do not determine stay near the generic model instead of wandering to
absorb model error; the identifiability report says which those are.

Parameters, shared by all trials given: tendon slack length of every muscle crossing a moving
joint (bounds 0.6–1.25 × generic, :data:`SLACK_BOUNDS`; a tendon longer than its path is simply
slack), passive fibre strain ε₀ of each of them (0.2–1.2) and tendon strain ε_T0 of the calf
muscles (0.02–0.12). All decision variables are scaled to order one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError
from ..fit import FitStatus
from .derivatives import PointCall, derivative_functions
from .model import (
    ParameterSet,
    PmpTrial,
    Subject,
    free_parameters,
    muscles_moment,
    path_taylor_rows,
    posed_at,
    set_angle_condition,
    set_angle_label,
)
from .muscles import LegMuscles

SIGMA_Q_RAD = np.deg2rad(0.5)
SIGMA_V_RAD_S = np.deg2rad(2.0)
SIGMA_U_NM = 0.5
#: the prior of every parameter: Gaussian about its (scaled) generic value with these relative
#: SDs — the spread between subjects the model assumes (slack lengths after scaling ±5 %, strains
#: ±25 %) — and as much weight as PRIOR_WEIGHT of one trial's mean squared normalised error
PRIOR_RELATIVE_SD = {"tendon_slack_length_m": 0.05, "passive_strain": 0.25, "tendon_strain": 0.25}
PRIOR_WEIGHT = 0.01
#: the fixed joints' set angles are fitted per condition about the entered value, with a Gaussian prior of
#: the subject's ``set_angle_sd_rad`` weighted as the muscles' prior (PRIOR_WEIGHT of one trial's mean squared
#: normalised error per SD²: the weight of one independent sample among a trial's ~100 effective ones)
SET_ANGLE_PRIOR_WEIGHT = PRIOR_WEIGHT
#: the fitted set-angle offsets stay within this many SDs of the entered angle
SET_ANGLE_MAX_SD = 4.0
#: where the calf tendons' normalised lengths start (a tendon just taut)
TENDON_START = 1.01


#: one trial's collocation variables (angle, velocity, scaled control, calf tendon lengths or None), as numpy arrays
CollocationState = tuple[np.ndarray, np.ndarray, np.ndarray, "np.ndarray | None"]


@dataclass(frozen=True)
class PmpResult:
    """Estimates, the fit per trial, and the solver's account of itself, in SciPy's ``OptimizeResult``
    names (:mod:`analysis.fit`): ``success``, ``status`` (a :class:`~analysis.fit.FitStatus`),
    ``message``, ``nit``, ``fun`` (the final cost) and ``x`` (the estimates in ``parameters``' order).
    A fit that did not converge is a result with ``success=False`` and the last iterate, never an
    exception. ``solver_status`` is IPOPT's own word for how it ended."""

    parameters: dict[str, float]
    generic: dict[str, float]
    lower: dict[str, float]
    upper: dict[str, float]
    fun: float
    nit: int
    solve_time_s: float
    success: bool
    status: FitStatus
    message: str
    solver_status: str
    trials: list[dict[str, np.ndarray]] = field(default_factory=list)
    extension_parameters: dict[str, float] = field(default_factory=dict)  # a model extension's estimates
    #: the fitted offset (rad) of each condition's fixed-joint set angle, keyed by ``set_angle_label``
    #: (e.g. ``"hip_set_angle_55deg (knee trials)"``); empty when the set angles were held as entered
    set_angle_offsets_rad: dict[str, float] = field(default_factory=dict)
    #: the priors' share of the minimised objective (``fun`` + ``regularisation`` is what IPOPT minimised): fits of
    #: one problem from different starts compare by that sum (:attr:`objective`)
    regularisation: float = 0.0
    #: per trial, the collocation variables where the solve ended, in the problem's own scaling (the angle, rad; the
    #: velocity, rad/s; the control over its scale; the calf tendons' normalised lengths, None without): a larger
    #: model's fit of the same trials starts there (:meth:`PmpProblem.start_at`)
    collocation_states: tuple[CollocationState, ...] = ()

    @property
    def objective(self) -> float:
        """What the solver minimised: the cost and the priors' regularisation."""
        return self.fun + self.regularisation

    @property
    def x(self) -> np.ndarray:
        """The estimates (SI) in the order of :attr:`parameters`."""
        return np.array(list(self.parameters.values()), dtype=float)


@dataclass
class PmpProblem:
    """A built collocation problem: the CasADi ``Opti`` with its decision variables, cost and what the
    result reads back (per trial: the times, the state and control variables, the measured signals)."""

    opti: Any
    parameters: ParameterSet
    p_scaled: Any
    e_scaled: Any
    cost: Any
    regularisation: Any
    outputs: list[tuple[Any, ...]]
    extension: Any
    n_ext: int
    intervals: int
    max_iter: int
    #: per trial, the torque term's Simpson weights: the Opti parameter, the points' times (s), the full weights
    torque_weights: list[tuple[Any, np.ndarray, np.ndarray]] = field(default_factory=list)
    #: trials whose paths' Taylor anchors follow the fitted joint angle (an extension turns the joint): the Opti
    #: parameter of the coefficients, the trial, the leg, its index in ``outputs``, the current anchors (rad)
    anchors: list[tuple[Any, PmpTrial, LegMuscles, int, np.ndarray]] = field(default_factory=list)
    #: the set-angle offsets' Opti variable (offset = SD · variable, one per condition) and the conditions' labels
    set_angles: Any = None
    set_angle_labels: list[str] = field(default_factory=list)
    set_angle_sd_rad: float = 0.0
    #: the parameters' bounds (SI, in ``parameters.names``' order; a held parameter has both at its value)
    lower: np.ndarray | None = None
    upper: np.ndarray | None = None
    #: each trial's point function as mapped over its points (:mod:`analysis.pmp.derivatives`)
    point_calls: list[PointCall] = field(default_factory=list)

    def start_at(self, parameters: dict[str, float] | None = None, extension_values: Sequence[float] | None = None,
                 set_angle_offsets_rad: dict[str, float] | None = None,
                 states: Sequence[CollocationState] | None = None) -> None:
        """Start the next solve from these values (SI: a fit's ``parameters``, its extension's values in the
        extension's order, its set-angle offsets by label; each clipped into its bounds; what is not given keeps
        its start). The states and controls start at the measured motion, as built, or at ``states`` (a fit's
        :attr:`PmpResult.collocation_states` on the same trials and intervals; a trial whose variables have other
        shapes keeps the measured motion).

        A larger model started from a smaller one's parameters but at the measured motion does not start at the
        smaller one's optimum: an OpenSim-made subject's end-range structures, compliant knee tendons and a tone,
        started so from the pair's fold fit (objective 0.578), converged at 0.982 with the activation at its bound and
        predicted the left-out blocks 0.590 N·m off; from the pair's states as well, at 0.189 and 0.230 N·m (the pair
        0.268)."""
        pset = self.parameters
        lower = pset.lower if self.lower is None else self.lower
        upper = pset.upper if self.upper is None else self.upper
        if parameters is not None:
            values = np.array([parameters.get(n, g) for n, g in zip(pset.names, pset.generic)])
            self.opti.set_initial(self.p_scaled, np.clip(values, lower, upper) / pset.generic)
        if extension_values is not None and self.n_ext:
            ext = self.extension
            size = np.asarray(ext.typical, dtype=float)
            values = np.clip(np.asarray(extension_values, dtype=float), np.asarray(ext.lower), np.asarray(ext.upper))
            self.opti.set_initial(self.e_scaled, values / size)
        if set_angle_offsets_rad is not None and self.set_angles is not None:
            offsets = np.array([set_angle_offsets_rad.get(lbl, 0.0) for lbl in self.set_angle_labels])
            self.opti.set_initial(self.set_angles, np.clip(offsets / self.set_angle_sd_rad, -SET_ANGLE_MAX_SD,
                                                           SET_ANGLE_MAX_SD))
        given = states if states is not None and len(states) == len(self.point_calls) else [None] * len(self.point_calls)
        for call, out, state in zip(self.point_calls, self.outputs, given, strict=True):
            _t, _tt, _q, _v, _u, u_scale, qm, vm, um = out
            measured = (qm[None, :], vm[None, :], (um / u_scale)[None, :], TENDON_START)
            for variable, value, built in zip(_state_variables(call), state or measured, measured, strict=True):
                if variable.numel() == 0:
                    continue
                ok = value is not None and variable.shape == np.shape(value)
                self.opti.set_initial(variable, value if ok else built)

    def leave_out(self, held_out_s: list[list[tuple[float, float]]] | None) -> None:
        """Leave the torque in these windows (per trial, (start, end) s) out of the cost of the next solve;
        None: every sample in. The built solver is kept (one build serves every held-out fold)."""
        for i_trial, (param, times_s, full) in enumerate(self.torque_weights):
            w = full.copy()
            for start_s, end_s in (held_out_s[i_trial] if held_out_s else []):
                w[(times_s >= start_s) & (times_s <= end_s)] = 0.0
            self.opti.set_value(param, w)


def estimate(trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None, intervals: int = 40,
             max_iter: int = 300, initial: dict[str, float] | None = None, parameters: ParameterSet | None = None,
             moment: Any = None, extension: Any = None,
             progress: Callable[[int, float], None] | None = None,
             held_out_s: list[list[tuple[float, float]]] | None = None, expand: bool = True,
             fit_set_angles: bool = True, fixed: dict[str, float] | None = None) -> PmpResult:
    """Fit the passive parameters shared by ``trials`` (all at once): :func:`build_problem`, then :func:`solve`.

    ``progress(iteration, objective)`` is called after every IPOPT iteration (a progress line for
    a fit that takes seconds).

    ``parameters`` and ``moment(trial, q, par) → (moment, equilibrium residuals, tendon symbols)``
    replace the eleven-muscle leg with another passive model (a test rig, or the single-muscle
    problem the Moco benchmark shares with OpenSim); by default the leg's muscles.

    ``extension`` (an :class:`analysis.pmp.model_diagnosis.Extension`) adds its terms to the
    dynamics and its parameters to the decision variables, fitted with the muscles' (the model-level
    diagnosis); its estimates are in ``PmpResult.extension_parameters``.

    ``held_out_s`` (per trial, a list of (start, end) time windows, s) leaves the torque in those
    windows out of the cost (the motion is still tracked): the model-level diagnosis's held-out blocks.

    ``fit_set_angles`` (the leg's own muscles only): each condition's fixed-joint set angle (the hip for knee
    trials, the knee for ankle trials) is fitted as a nuisance about the entered value with a Gaussian prior of
    ``subject.set_angle_sd_rad`` (:data:`SET_ANGLE_PRIOR_WEIGHT`); the offsets are in
    ``PmpResult.set_angle_offsets_rad``. A chair set 3° off otherwise moves the two-joint muscles' lengths by
    millimetres the slack lengths or an extension must absorb.

    :raises InputError: a trial is empty or moves another joint than knee/ankle.
    """
    problem = build_problem(trials, subject, leg=leg, intervals=intervals, max_iter=max_iter, initial=initial,
                            parameters=parameters, moment=moment, extension=extension, held_out_s=held_out_s, expand=expand,
                            fit_set_angles=fit_set_angles, fixed=fixed)
    return solve(problem, progress)


def build_problem(trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None, intervals: int = 40,
                  max_iter: int = 300, initial: dict[str, float] | None = None, parameters: ParameterSet | None = None,
                  moment: Any = None, extension: Any = None,
                  held_out_s: list[list[tuple[float, float]]] | None = None, expand: bool = True,
                  fit_set_angles: bool = True, fixed: dict[str, float] | None = None) -> PmpProblem:
    """The collocation problem of :func:`estimate` (its arguments), built and not solved; ``expand``: the
    problem's functions expanded into scalar operations for the solver (slower to make, faster per iteration:
    for a problem solved for several held-out folds, :meth:`PmpProblem.leave_out`).

    :raises InputError: a trial is empty or moves another joint than knee/ankle.
    """
    import casadi as ca

    if not trials:
        raise InputError("no trials to fit")
    leg = leg or LegMuscles()
    pset = parameters or free_parameters(leg, trials)
    n_par = len(pset.names)
    unknown = sorted(set(fixed or {}) - set(pset.names))
    if unknown:
        raise InputError(f"cannot hold {', '.join(unknown)} fixed: not a free parameter of these trials")
    lower, upper = pset.lower.copy(), pset.upper.copy()
    for name, value in (fixed or {}).items():  # held at a value (a profile's point): both bounds there
        lower[pset.names.index(name)] = upper[pset.names.index(name)] = value
    opti = ca.Opti()
    p_scaled = opti.variable(n_par)  # parameter = generic · p_scaled
    opti.subject_to(opti.bounded(lower / pset.generic, p_scaled, upper / pset.generic))
    start = np.clip(np.array([(initial or {}).get(n, g) for n, g in zip(pset.names, pset.generic)]), lower, upper) / pset.generic
    opti.set_initial(p_scaled, start)
    n_ext = len(extension.parameters) if extension is not None else 0
    e_scaled = opti.variable(max(n_ext, 1))  # extension parameter = its typical size · e_scaled
    if n_ext:
        e_size = np.asarray(extension.typical, dtype=float)
        opti.subject_to(opti.bounded(np.asarray(extension.lower) / e_size, e_scaled, np.asarray(extension.upper) / e_size))
        e_start = np.asarray(extension.start if extension.start is not None else np.zeros(n_ext), dtype=float)
        opti.set_initial(e_scaled, np.clip(e_start / e_size, np.asarray(extension.lower) / e_size,
                                           np.asarray(extension.upper) / e_size))
    else:
        opti.subject_to(e_scaled == 0)
    problem = PmpProblem(opti, pset, p_scaled, e_scaled, 0, 0, [], extension, n_ext, intervals, max_iter,
                         lower=lower, upper=upper)
    if fit_set_angles and moment is None and subject.set_angle_sd_rad > 0:
        conditions = sorted({set_angle_condition(t) for t in trials})
        problem.set_angle_labels = [set_angle_label(c) for c in conditions]
        problem.set_angle_sd_rad = float(subject.set_angle_sd_rad)
        problem.set_angles = opti.variable(len(conditions))  # offset = SD · variable
        opti.set_initial(problem.set_angles, 0.0)
        # ±4 SD (±6° by default): a chair is never set further off; the bound keeps the paths' expansion valid
        opti.subject_to(opti.bounded(-SET_ANGLE_MAX_SD, problem.set_angles, SET_ANGLE_MAX_SD))
    for t in trials:
        _add_trial(problem, t, subject, leg, moment)
    prior_sd = np.array([PRIOR_RELATIVE_SD[n.split(".")[1]] for n in pset.names]) if parameters is None \
        else np.full(n_par, 0.1)
    problem.regularisation = PRIOR_WEIGHT * ca.sumsqr((p_scaled - 1.0) / ca.DM(prior_sd))
    if n_ext:  # a vanishing pull toward no extension: a parameter no trial touches stays at 0
        problem.regularisation = problem.regularisation + 1e-6 * ca.sumsqr(e_scaled)
    if problem.set_angles is not None:
        problem.regularisation = problem.regularisation + SET_ANGLE_PRIOR_WEIGHT * ca.sumsqr(problem.set_angles)
    opti.minimize(problem.cost + problem.regularisation)
    # expanded into scalar operations once, when the solver is made (≈ 1–2 s), each IPOPT iteration is 6–8×
    # cheaper with an extension (end-range structures on six OpenSim trials, 12 intervals: 14.8 → 1.8 s per solve)
    # and 1.1–2× for the plain model, which since the vectorised constraints is never slower expanded (measured
    # 2026-11-27, same iterations and cost: six OpenSim trials, 16 intervals, 68 iterations 9.9 → 5.7 s, 29
    # iterations 7.7 → 4.2 s; the synthetic six trials 5.2 → 4.5 s, 30 intervals 8.3 → 7.3 s; one trial 1.4 → 1.5 s).
    # Only the paths' Taylor polynomials are expanded: with the B-spline tables (a moving joint axis, another
    # passive model) the axis fit went 43 → 40 s per solve and 2 → 14 s to build
    expand = expand and moment is None
    # the derivatives made per collocation point and assembled (:mod:`analysis.pmp.derivatives`): making CasADi's
    # own of the expanded problem was ≈ 3 s of a 3.4 s fit of six trials (measured 2026-11-29: the same iterations
    # and objective to 1e-13; a fit's first solve 3.39 → 0.86 s, each further solve 0.39 → 0.40 s)
    derivatives = (derivative_functions(opti, problem.point_calls) or {}) if expand else {}
    opti.solver("ipopt", {"print_time": False, "expand": expand, **derivatives},
                {"print_level": 0, "max_iter": max_iter, "tol": 1e-8, "sb": "yes"})
    problem.leave_out(held_out_s)
    return problem


def _add_trial(problem: PmpProblem, t: PmpTrial, subject: Subject, leg: LegMuscles, moment: Any) -> None:
    """One trial's states, controls, Hermite–Simpson dynamics and cost terms, added to ``problem``."""
    import casadi as ca

    if t.joint not in ("knee", "ankle"):
        raise InputError(f"{t.name}: the moving joint must be knee or ankle, not {t.joint!r}")
    if t.time_s.size < 10:
        raise InputError(f"{t.name}: {t.time_s.size} samples")
    opti, pset, extension, n_ext, intervals = problem.opti, problem.parameters, problem.extension, problem.n_ext, \
        problem.intervals
    n_par = len(pset.names)
    p_scaled, e_scaled = problem.p_scaled, problem.e_scaled
    own_leg = moment is None  # the leg's muscles (their paths are expanded about the measured angles)
    passive = moment or (lambda trial, q, par, local=None, **options: muscles_moment(leg, trial, q, par, local,
                                                                                        **options))
    n_pts = 2 * intervals + 1
    tt = np.linspace(t.time_s[0], t.time_s[-1], n_pts)
    dt = (tt[-1] - tt[0]) / intervals
    qm = np.interp(tt, t.time_s, t.angle_rad)
    vm = np.interp(tt, t.time_s, t.velocity_rad_s)
    um = np.interp(tt, t.time_s, t.torque_nm)
    u_scale = max(float(np.max(np.abs(um))), 1.0)
    q = opti.variable(n_pts)
    v = opti.variable(n_pts)
    u = opti.variable(n_pts)
    opti.set_initial(q, qm)
    opti.set_initial(v, vm)
    opti.set_initial(u, um / u_scale)
    inertia = subject.inertia_kgm2(t.joint)
    # the point dynamics as one SX function, mapped over every collocation point (a small MX graph)
    qs, vs, us, ps = ca.SX.sym("q"), ca.SX.sym("v"), ca.SX.sym("u"), ca.SX.sym("p", n_par)
    es = ca.SX.sym("e", max(n_ext, 1))
    par_s = {n: pset.generic[i] * ps[i] for i, n in enumerate(pset.names)}
    ext_par = [float(extension.typical[i]) * es[i] for i in range(n_ext)]
    # the condition's set-angle offset (rad), a symbol of the point function when the set angles are fitted; the
    # trial posed at it (its fixed joint a symbol) for the limb's weight and the extension's terms
    fitted_set_angle = own_leg and problem.set_angles is not None
    set_offset = ca.SX.sym("set_angle") if fitted_set_angle else 0.0
    posed = posed_at(t, set_offset) if fitted_set_angle else t
    q_joint = extension.joint_angle(posed, qs, ext_par) if n_ext else qs
    options = extension.muscle_options(posed, ext_par) if n_ext else {}  # what the extension changes in the muscles
    if options and not own_leg:
        raise InputError(f"{extension.name} changes the leg's muscles; it cannot extend another passive model")
    local_in: list[Any] = []
    # the leg's paths as Taylor polynomials about an anchor angle at each point: the measured angle; when an
    # extension turns the joint away from the arm's angle (an axis misalignment, by degrees) the anchors are
    # parameters that :func:`solve` moves to the fitted joint angle until they agree (:data:`REANCHOR_TOLERANCE_RAD`).
    # With the set angle fitted the coefficients at an offset δ are c + δ·c′ + δ²/2·c″ (:func:`path_taylor_rows`)
    if own_leg:
        coef = path_taylor_rows(leg, t, qm, fitted_set_angle)
        geo = ca.SX.sym("geo", coef.shape[0])
        if fitted_set_angle:
            k = (coef.shape[0] - 1) // 3
            paths = geo[1:1 + k] + set_offset * geo[1 + k:1 + 2 * k] + 0.5 * set_offset**2 * geo[1 + 2 * k:]
        else:
            paths = geo[1:]
        muscles, residuals, calf = passive(t, q_joint, par_s, (geo[0], paths), **options)
        local_in = [geo]
        if n_ext and extension.angle is not None:
            anchored = opti.parameter(*coef.shape)
            opti.set_value(anchored, coef)
            problem.anchors.append((anchored, t, leg, len(problem.outputs), coef[0].copy()))
            coef = anchored
    else:
        muscles, residuals, calf = passive(t, q_joint, par_s, **options)
    if n_ext and extension.angle is not None:  # the muscles' moment reaches the arm by virtual work
        muscles = muscles * ca.jacobian(q_joint, qs)
    gravity = subject.gravity_moment_nm(t.joint, qs, posed.fixed_rad, ca.cos)
    moment = gravity + muscles
    if n_ext:
        moment = moment + extension.moment(posed, qs, vs, ext_par, gravity)
    lts = ca.vertcat(*calf) if calf else ca.SX.sym("lt", 0)
    lt: Any = opti.variable(len(calf), n_pts) if calf else None
    if calf:
        opti.set_initial(lt, TENDON_START)
        opti.subject_to(opti.bounded(0.99, lt, 1.2))
    set_in = [set_offset] if fitted_set_angle else []
    point = ca.Function("point", [qs, vs, us, ps, es, lts, *set_in, *local_in],
                        [(us * u_scale + moment) / inertia, ca.vertcat(*residuals)])
    set_value = []
    if fitted_set_angle:
        index = problem.set_angle_labels.index(set_angle_label(set_angle_condition(t)))
        set_value = [ca.repmat(problem.set_angle_sd_rad * problem.set_angles[index], 1, n_pts)]
    point_inputs = (q.T, v.T, u.T, ca.repmat(p_scaled, 1, n_pts), ca.repmat(e_scaled, 1, n_pts),
                    lt if calf else ca.MX(0, n_pts), *set_value)
    path_inputs = (ca.MX(coef) if isinstance(coef, np.ndarray) else coef,) if local_in else ()
    acc_row, res_rows = point.map(n_pts)(*point_inputs, *path_inputs)
    problem.point_calls.append(PointCall(point, point_inputs, path_inputs, (acc_row, res_rows)))
    if calf:
        opti.subject_to(ca.vec(res_rows) == 0)
    acc = acc_row.T
    # Hermite–Simpson: points 0, 2, 4, … are nodes, odd points are interval midpoints; each condition as
    # one vector constraint over the intervals (a small MX graph: its derivatives evaluate fast)
    a, mid, b = slice(0, n_pts - 2, 2), slice(1, n_pts - 1, 2), slice(2, n_pts, 2)
    opti.subject_to(q[mid] == 0.5 * (q[a] + q[b]) + dt / 8 * (v[a] - v[b]))
    opti.subject_to(v[mid] == 0.5 * (v[a] + v[b]) + dt / 8 * (acc[a] - acc[b]))
    opti.subject_to(q[b] - q[a] == dt / 6 * (v[a] + 4 * v[mid] + v[b]))
    opti.subject_to(v[b] - v[a] == dt / 6 * (acc[a] + 4 * acc[mid] + acc[b]))
    w = np.full(n_pts, 2.0)
    w[1::2] = 4.0
    w[0] = w[-1] = 1.0
    w *= (dt / 2) / 3 / (tt[-1] - tt[0])  # Simpson weights, normalised to a mean
    w_u = opti.parameter(n_pts)  # the torque's weights: zero in a held-out window (PmpProblem.leave_out)
    problem.torque_weights.append((w_u, tt, w))
    err = ((q - qm) / SIGMA_Q_RAD) ** 2 + ((v - vm) / SIGMA_V_RAD_S) ** 2
    problem.cost = problem.cost + ca.dot(ca.DM(w), err) + ca.dot(w_u, ((u * u_scale - um) / SIGMA_U_NM) ** 2)
    problem.outputs.append((t, tt, q, v, u, u_scale, qm, vm, um))


#: the paths' Taylor anchors agree with the fitted joint angle when no point's differs by more than this
#: (rad): within 0.3° the polynomials are the tables to 1.3e-7 m of length and 5.8e-7 m of moment arm
REANCHOR_TOLERANCE_RAD = np.deg2rad(0.3)
#: at most this many solves, each from the same start with the anchors moved to the last solve's joint angles
REANCHOR_ROUNDS = 4


def _reanchor(problem: PmpProblem, sol: Any) -> float:
    """Move the Taylor anchors of the trials whose joint an extension turns to ``sol``'s joint angles; the
    largest move (rad), 0 when no trial has such anchors."""
    import casadi as ca

    if not problem.anchors:
        return 0.0
    ext = (np.atleast_1d(np.asarray(sol.value(problem.e_scaled)).ravel())
           * np.asarray(problem.extension.typical, dtype=float)).tolist()
    moved = 0.0
    for i, (param, trial, leg, output, anchors) in enumerate(problem.anchors):
        q_arm = np.asarray(sol.value(problem.outputs[output][2])).ravel()
        joint = np.asarray(ca.DM(problem.extension.joint_angle(trial, ca.DM(q_arm), ext))).ravel()
        moved = max(moved, float(np.max(np.abs(joint - anchors))))
        problem.opti.set_value(param, path_taylor_rows(leg, trial, joint, problem.set_angles is not None))
        problem.anchors[i] = (param, trial, leg, output, joint)
    return moved


def _state_variables(call: PointCall) -> tuple[Any, Any, Any, Any]:
    """A trial's collocation variables as its point function takes them (each ``n × points``): angle, velocity,
    scaled control, calf tendon lengths (empty without)."""
    return call.inputs[0], call.inputs[1], call.inputs[2], call.inputs[5]


def _state_values(sol: Any, call: PointCall) -> CollocationState:
    """A trial's collocation variables' values in a solution (each ``n × points``; no calf tendons: None)."""
    def value(x: Any) -> np.ndarray:
        return np.atleast_2d(np.asarray(sol.value(x), dtype=float))

    q, v, u, lt = _state_variables(call)
    return value(q), value(v), value(u), value(lt) if lt.numel() > 0 else None


def solve(problem: PmpProblem, progress: Callable[[int, float], None] | None = None) -> PmpResult:
    """Solve a built problem with IPOPT; a fit that does not converge is a result with ``success=False``."""
    import time

    opti, pset, cost, reg = problem.opti, problem.parameters, problem.cost, problem.regularisation
    p_scaled, e_scaled, extension, n_ext = problem.p_scaled, problem.e_scaled, problem.extension, problem.n_ext
    intervals, max_iter, outputs = problem.intervals, problem.max_iter, problem.outputs
    if progress is not None:
        opti.callback(lambda i: progress(int(i), float(opti.debug.value(cost + reg))))
    else:
        opti.callback()  # a problem solved again keeps no earlier solve's callback
    t0 = time.perf_counter()
    for _ in range(REANCHOR_ROUNDS):  # one round unless an extension turns the joint (:func:`_reanchor`)
        try:
            sol: Any = opti.solve()
            success, message = True, "IPOPT converged"
        except RuntimeError as err:  # the last iterate is still a result: success=False says so
            sol = opti.debug
            success, message = False, f"IPOPT did not converge ({str(err).splitlines()[-1][:160]}); tried " \
                                      f"{intervals} intervals per trial, max_iter {max_iter}, from the generic values"
        moved = _reanchor(problem, sol) if success else 0.0
        if moved <= REANCHOR_TOLERANCE_RAD:
            break
    else:
        message += (f"; the paths' Taylor anchors still moved {np.degrees(moved):.2f}° after {REANCHOR_ROUNDS} solves "
                    "(the muscles' paths are approximate where the joint turned that far)")
    solve_s = time.perf_counter() - t0
    est = np.asarray(sol.value(p_scaled)).ravel() * pset.generic
    stats = sol.stats()
    res_trials = []
    for t, tt, q, v, u, u_scale, qm, _vm, um in outputs:
        res_trials.append({"name": t.name, "time_s": tt, "angle_rad": sol.value(q), "velocity_rad_s": sol.value(v),
                           "torque_nm": sol.value(u) * u_scale, "measured_angle_rad": qm, "measured_torque_nm": um})
    ext_est = {}
    if n_ext:
        values = np.atleast_1d(np.asarray(sol.value(e_scaled)).ravel()) * np.asarray(extension.typical, dtype=float)
        ext_est = dict(zip(extension.parameters, values.tolist()))
    states = tuple(_state_values(sol, call) for call in problem.point_calls)
    set_offsets = {}
    if problem.set_angles is not None:
        values = np.atleast_1d(np.asarray(sol.value(problem.set_angles)).ravel()) * problem.set_angle_sd_rad
        set_offsets = dict(zip(problem.set_angle_labels, values.tolist()))
    return PmpResult(parameters=dict(zip(pset.names, est.tolist())), generic=dict(zip(pset.names, pset.generic.tolist())),
                     lower=dict(zip(pset.names, pset.lower.tolist())), upper=dict(zip(pset.names, pset.upper.tolist())),
                     fun=float(sol.value(cost)), nit=int(stats.get("iter_count", -1)), solve_time_s=solve_s,
                     success=success, status=FitStatus.CONVERGED if success else FitStatus.NOT_CONVERGED,
                     message=message, solver_status=str(stats.get("return_status", "unknown")), trials=res_trials,
                     extension_parameters=ext_est, set_angle_offsets_rad=set_offsets,
                     regularisation=float(sol.value(reg)), collocation_states=states)

