"""Passive muscle-tendon parameters from isokinetic trials by direct collocation (CasADi, Hermite–Simpson).

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

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..constants import GRAVITY_M_S2
from ..errors import InputError
from ..fit import FitStatus
from .curves import passive_fiber_force, tendon_force
from .geometry import MUSCLES
from .muscles import COMPLIANT, LegMuscles

G = GRAVITY_M_S2
SIGMA_Q_RAD = np.deg2rad(0.5)
SIGMA_V_RAD_S = np.deg2rad(2.0)
SIGMA_U_NM = 0.5
#: the prior of every parameter: Gaussian about its (scaled) generic value with these relative
#: SDs — the spread between subjects the model assumes (slack lengths after scaling ±5 %, strains
#: ±25 %) — and as much weight as PRIOR_WEIGHT of one trial's mean squared normalised error
PRIOR_RELATIVE_SD = {"tendon_slack_length_m": 0.05, "passive_strain": 0.25, "tendon_strain": 0.25}
PRIOR_WEIGHT = 0.01
#: the residual may be at most this many times the measurement noise for anything to count as determined
MISFIT_LIMIT = 3.0
#: the model-error allowance added to every interval (N·m, RMS per sample; the bias it can cause,
#: bounded as below). The muscle model is now 0.021 N·m off OpenSim at worst; the allowance is for the
#: mismatch a fit can still pass the misfit test with. Measured on `python -m benchmarks pmp_opensim`
#: (10 OpenSim-made subjects, rigid and "realistic" variants): at 0.03 N·m, 36 parameters called
#: determined and 35 held the truth (the miss: a realistic-variant subject with unmodelled activation,
#: misfit 2.7×); at 0.25 N·m, 22 called and 22 held (max error 0.65 %). Before the calf fibres' ε₀ was
#: estimated, 0.03 N·m gave 18 of 24 (errors to 73 %): their ε₀ went into ε_T0
MODEL_ERROR_RMS_NM = 0.25
#: tendon slack length bounds, relative to the (scaled) generic value: subjects 20 % longer or
#: 40 % shorter than the generic model can be represented
SLACK_BOUNDS = (0.6, 1.25)


@dataclass
class PmpTrial:
    """One isokinetic trial (SI): the moving joint, the fixed angles (rad), and the measured signals."""

    joint: str                    # "knee" or "ankle"
    fixed_rad: dict[str, float]   # the other joints' angles, e.g. {"hip": 1.57, "ankle": 0.0}
    time_s: np.ndarray
    angle_rad: np.ndarray
    velocity_rad_s: np.ndarray
    torque_nm: np.ndarray         # u: dynamometer torque toward positive angle, arm weight removed
    name: str = ""


#: how well a lab measures what the model is scaled and posed by, one standard deviation: a tape on the
#: shank within ±5 mm, a goniometer or the chair's scale on a fixed joint within ±3°, a scale within ±0.5 kg,
#: each bound taken as two SD (95 %)
MEASUREMENT_SD = {"shank_length_m": 0.0025, "set_angle_rad": math.radians(1.5), "mass_kg": 0.25}


@dataclass
class Subject:
    """Anthropometrics for gravity, inertia and muscle scaling (Winter's segment fractions), and how well each
    was measured (one SD, :data:`MEASUREMENT_SD` by default): the intervals carry these uncertainties."""

    mass_kg: float = 75.0
    shank_length_m: float = 0.42
    foot_length_m: float = 0.26
    arm_inertia_kgm2: float = 0.0
    shank_length_sd_m: float = MEASUREMENT_SD["shank_length_m"]
    set_angle_sd_rad: float = MEASUREMENT_SD["set_angle_rad"]
    mass_sd_kg: float = MEASUREMENT_SD["mass_kg"]

    def inertia_kgm2(self, joint: str) -> float:
        m, ls, lf = self.mass_kg, self.shank_length_m, self.foot_length_m
        if joint == "knee":
            ms, mf = 0.0465 * m, 0.0145 * m
            return ms * (0.302 * ls) ** 2 + ms * (0.433 * ls) ** 2 + mf * ls**2 + self.arm_inertia_kgm2
        mf = 0.0145 * m
        return mf * (0.475 * lf) ** 2 + mf * (0.5 * lf) ** 2 + self.arm_inertia_kgm2

    def gravity_moment_nm(self, joint: str, q: Any, fixed: dict[str, float], cos: Any = np.cos) -> Any:
        """Limb weight toward positive angle (as the seated simulator: thigh horizontal)."""
        m = self.mass_kg
        if joint == "knee":
            return (0.0465 * m * 0.433 * self.shank_length_m + 0.0145 * m * self.shank_length_m) * G * cos(q)
        return -0.0145 * m * 0.5 * self.foot_length_m * G * cos(q + np.pi / 2 - fixed.get("knee", 0.0))


@dataclass
class ParameterSet:
    """Names, generic values, bounds and (after a fit) the estimates of the free parameters."""

    names: list[str]
    generic: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


def free_parameters(leg: LegMuscles, trials: list[PmpTrial]) -> ParameterSet:
    """Slack lengths of muscles crossing a moving joint, ε₀ of every one of them, and ε_T0 of the calf ones."""
    joints = {t.joint for t in trials}
    crossing = [m for m in MUSCLES if set(leg.paths[m].joints) & joints]
    names, gen, lo, hi = [], [], [], []
    for m in crossing:
        ls = leg.params[m].tendon_slack_length_m
        names.append(f"{m}.tendon_slack_length_m")
        gen.append(ls)
        lo.append(SLACK_BOUNDS[0] * ls)
        hi.append(SLACK_BOUNDS[1] * ls)  # a tendon longer than its path is slack: no force, no buckling
    for m in crossing:
        if m in COMPLIANT:
            names.append(f"{m}.tendon_strain")
            gen.append(leg.params[m].tendon_strain)
            lo.append(0.02)
            hi.append(0.12)
            # the calf fibres' ε₀ too: held at generic, a subject's 25 % different ε₀ went into ε_T0
            # (soleus ε_T0 +49 % on an OpenSim-made subject, with an interval of ±2 % that missed it)
            names.append(f"{m}.passive_strain")
            gen.append(leg.params[m].passive_strain)
            lo.append(0.2)
            hi.append(1.2)
        else:
            names.append(f"{m}.passive_strain")
            gen.append(leg.params[m].passive_strain)
            lo.append(0.2)
            hi.append(1.2)
    return ParameterSet(names, np.array(gen), np.array(lo), np.array(hi))


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

    @property
    def x(self) -> np.ndarray:
        """The estimates (SI) in the order of :attr:`parameters`."""
        return np.array(list(self.parameters.values()), dtype=float)


#: order of the Taylor expansion of path length and moment arm about the measured angle inside the fit
PATH_TAYLOR_ORDER = 3


def _path_taylor(leg: LegMuscles, trial: PmpTrial, anchors_rad: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Taylor coefficients (0 … :data:`PATH_TAYLOR_ORDER`) of the length and the moment arm about
    ``trial``'s joint of every muscle crossing it, at ``anchors_rad`` (the measured angles of the
    collocation points; the other joints at the trial's fixed angles): rows muscle by muscle, the
    length's coefficients then the moment arm's; columns the anchors. The fit evaluates the paths as
    these polynomials in (q − anchor), cheap for IPOPT (the B-spline tables called at every
    collocation point made a fit 14.9 s instead of 2.7 s). Measured against the tables over the
    protocol's sweeps: within 0.3° of the anchor ≤ 1.3e-7 m (length) and 5.8e-7 m (moment arm),
    within 1° 2.4e-5 / 8.1e-5 m, at 3° 0.9 / 2.9 mm. The fitted angle stays within the angle noise
    (0.1°) of the measured one; an extension that turns the joint by degrees (axis misalignment)
    uses the tables themselves."""
    import casadi as ca

    names = [m for m in MUSCLES if trial.joint in leg.paths[m].joints]
    x = ca.SX.sym("x")
    angles = {"hip": trial.fixed_rad.get("hip", 0.0), "knee": trial.fixed_rad.get("knee", 0.0),
              "ankle": trial.fixed_rad.get("ankle", 0.0), trial.joint: x}
    rows = []
    for m in names:
        for expr in (leg.path_length_m(m, **angles), leg.moment_arm_m(m, trial.joint, **angles)):
            d = expr
            for k in range(PATH_TAYLOR_ORDER + 1):
                rows.append(d / math.factorial(k))
                d = ca.jacobian(d, x)
    f = ca.Function("taylor", [x], [ca.vertcat(*rows)]).map(anchors_rad.size)
    return names, np.asarray(f(anchors_rad.reshape(1, -1)))


def _muscle_moment(leg: LegMuscles, m: str, joint: str, q: dict[str, Any], ls: Any, strain: Any, lt_norm: Any,
                   path: tuple[Any, Any] | None = None, fiber_strain: Any = None) -> tuple[Any, Any]:
    """(moment toward positive angle, equilibrium residual or None) of one muscle in CasADi;
    ``path`` (length, moment arm) replaces the leg's path evaluated at ``q``; ``strain`` is the
    tendon's ε_T0 for a compliant muscle (its fibre's ε₀ is ``fiber_strain``, default the leg's),
    the fibre's ε₀ otherwise."""
    import casadi as ca

    p = leg.paths[m]
    lo = leg.optimal_fiber_length_m(m)
    h = lo * np.sin(p.pennation_at_optimal_rad)
    lmt, r = path if path is not None else (leg.path_length_m(m, **q), leg.moment_arm_m(m, joint, **q))
    if m in COMPLIANT:
        lt = lt_norm * ls
        along = lmt - lt
        lm = ca.sqrt(along**2 + h**2)
        eps0 = leg.params[m].passive_strain if fiber_strain is None else fiber_strain
        res = passive_fiber_force(lm / lo, eps0) * along / lm - tendon_force(lt_norm, strain)
        return r * p.max_isometric_force_n * tendon_force(lt_norm, strain), res
    along = lmt - ls
    lm = ca.sqrt(along**2 + h**2)
    return r * p.max_isometric_force_n * passive_fiber_force(lm / lo, strain) * along / lm, None


def _muscles_moment(leg: LegMuscles, trial: PmpTrial, q: Any, par: dict[str, Any],
                    local: tuple[Any, Any] | None = None) -> tuple[Any, list[Any], list[Any]]:
    """Passive moment (CasADi) of the muscles crossing ``trial``'s joint at angle ``q``, the calf
    equilibrium residuals and their tendon-length symbols; ``par`` (numbers or symbols) overrides
    the leg's own parameters by name. ``local`` = (anchor angle, Taylor coefficients as
    :func:`_path_taylor` lays them out) evaluates the paths as polynomials about the anchor."""
    import casadi as ca

    paths: dict[str, tuple[Any, Any]] = {}
    if local is not None:
        anchor, coef = local
        delta = q - anchor
        n = PATH_TAYLOR_ORDER + 1
        names = [m for m in MUSCLES if trial.joint in leg.paths[m].joints]
        for i, m in enumerate(names):
            block = [coef[(2 * i + w) * n:(2 * i + w + 1) * n] for w in (0, 1)]
            paths[m] = tuple(sum(b[k] * delta**k for k in range(n)) for b in block)  # type: ignore[assignment]  # casadi expressions summed: casadi's stubs type the sum as float

    angles = {"hip": trial.fixed_rad.get("hip", 0.0), "knee": trial.fixed_rad.get("knee", 0.0),
              "ankle": trial.fixed_rad.get("ankle", 0.0), trial.joint: q}
    moment, residuals, lts = 0, [], []
    for m in MUSCLES:
        if trial.joint not in leg.paths[m].joints:
            continue
        base = leg.params[m]
        ls = par.get(f"{m}.tendon_slack_length_m", base.tendon_slack_length_m)
        strain = par.get(f"{m}.tendon_strain", base.tendon_strain) if m in COMPLIANT else \
            par.get(f"{m}.passive_strain", base.passive_strain)
        lt = ca.SX.sym(f"lt_{m}") if m in COMPLIANT else None
        fibre = par.get(f"{m}.passive_strain", base.passive_strain) if m in COMPLIANT else None
        mom, res = _muscle_moment(leg, m, trial.joint, angles, ls, strain, lt, paths.get(m), fibre)
        moment = moment + mom
        if res is not None:
            residuals.append(res)
            lts.append(lt)
    return moment, residuals, lts


#: largest calf-tendon equilibrium residual (normalised force) accepted as solved
EQUILIBRIUM_TOLERANCE = 1e-8


def _eliminate_tendons(moment: Any, residuals: list[Any], lts: list[Any], args: list[Any]) -> Any:
    """The moment with the calf tendon lengths solved from their equilibrium (Newton, implicit function)."""
    import casadi as ca

    if not lts:
        return moment
    z = ca.vertcat(*lts)
    # a state outside the calf equilibrium's domain gives NaN, which the caller reports (a forward
    # simulation that leaves it is NaN, not an exception). Newton does not raise on failure (CasADi
    # would print every enclosing function's inputs, pages of numbers, to stderr) and does not warn per
    # evaluation (thousands of lines); an unconverged solution is turned into NaN here instead
    g = ca.Function("g", [z, *args], [ca.vertcat(*residuals)])
    solve = ca.rootfinder("solve", "newton", g, {"show_eval_warnings": False, "error_on_fail": False})
    zsol = solve(ca.DM.ones(len(lts)) * 1.01, *args)
    solved = ca.norm_inf(g(zsol, *args)) < EQUILIBRIUM_TOLERANCE
    return ca.if_else(solved, ca.Function("m", [z, *args], [moment])(zsol, *args), np.nan)


def estimate(trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None, intervals: int = 40,
             max_iter: int = 300, initial: dict[str, float] | None = None, parameters: ParameterSet | None = None,
             moment: Any = None, extension: Any = None,
             progress: Callable[[int, float], None] | None = None,
             held_out_s: list[list[tuple[float, float]]] | None = None) -> PmpResult:
    """Fit the passive parameters shared by ``trials`` (all at once).

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

    :raises InputError: a trial is empty or moves another joint than knee/ankle.
    """
    import time

    import casadi as ca

    if not trials:
        raise InputError("no trials to fit")
    leg = leg or LegMuscles()
    pset = parameters or free_parameters(leg, trials)
    own_leg = moment is None  # the leg's muscles (their paths are expanded about the measured angles)
    passive = moment or (lambda trial, q, par, local=None: _muscles_moment(leg, trial, q, par, local))
    n_par = len(pset.names)
    opti = ca.Opti()
    p_scaled = opti.variable(n_par)  # parameter = generic · p_scaled
    opti.subject_to(opti.bounded(pset.lower / pset.generic, p_scaled, pset.upper / pset.generic))
    start = np.array([(initial or {}).get(n, g) for n, g in zip(pset.names, pset.generic)]) / pset.generic
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
    cost = 0
    outputs = []
    for i_trial, t in enumerate(trials):
        if t.joint not in ("knee", "ankle"):
            raise InputError(f"{t.name}: the moving joint must be knee or ankle, not {t.joint!r}")
        if t.time_s.size < 10:
            raise InputError(f"{t.name}: {t.time_s.size} samples")
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
        q_joint = extension.joint_angle(t, qs, ext_par) if n_ext else qs
        local_in: list[Any] = []
        # the leg's paths as Taylor polynomials about the measured angle of each point, unless an
        # extension turns the joint away from the arm's angle (by degrees: the expansion would be off)
        if own_leg and not (n_ext and extension.angle is not None):
            _, coef = _path_taylor(leg, t, qm)
            coef = np.vstack([qm.reshape(1, -1), coef])
            geo = ca.SX.sym("geo", coef.shape[0])
            muscles, residuals, calf = passive(t, q_joint, par_s, (geo[0], geo[1:]))
            local_in = [geo]
        else:
            muscles, residuals, calf = passive(t, q_joint, par_s)
        if n_ext and extension.angle is not None:  # the muscles' moment reaches the arm by virtual work
            muscles = muscles * ca.jacobian(q_joint, qs)
        gravity = subject.gravity_moment_nm(t.joint, qs, t.fixed_rad, ca.cos)
        moment = gravity + muscles
        if n_ext:
            moment = moment + extension.moment(t, qs, vs, ext_par, gravity)
        lts = ca.vertcat(*calf) if calf else ca.SX.sym("lt", 0)
        lt: Any = opti.variable(len(calf), n_pts) if calf else None
        if calf:
            opti.set_initial(lt, 1.01)
            opti.subject_to(opti.bounded(0.99, lt, 1.2))
        point = ca.Function("point", [qs, vs, us, ps, es, lts, *local_in],
                            [(us * u_scale + moment) / inertia, ca.vertcat(*residuals)])
        acc_row, res_rows = point.map(n_pts)(q.T, v.T, u.T, ca.repmat(p_scaled, 1, n_pts), ca.repmat(e_scaled, 1, n_pts),
                                              lt if calf else ca.DM.zeros(0, n_pts), *([coef] if local_in else []))
        if calf:
            opti.subject_to(ca.vec(res_rows) == 0)
        acc = [acc_row[k] for k in range(n_pts)]
        # Hermite–Simpson: points 0, 2, 4, … are nodes, odd points are interval midpoints
        for i in range(intervals):
            a, mid, b = 2 * i, 2 * i + 1, 2 * i + 2
            opti.subject_to(q[mid] == 0.5 * (q[a] + q[b]) + dt / 8 * (v[a] - v[b]))
            opti.subject_to(v[mid] == 0.5 * (v[a] + v[b]) + dt / 8 * (acc[a] - acc[b]))
            opti.subject_to(q[b] - q[a] == dt / 6 * (v[a] + 4 * v[mid] + v[b]))
            opti.subject_to(v[b] - v[a] == dt / 6 * (acc[a] + 4 * acc[mid] + acc[b]))
        w = np.full(n_pts, 2.0)
        w[1::2] = 4.0
        w[0] = w[-1] = 1.0
        w *= (dt / 2) / 3 / (tt[-1] - tt[0])  # Simpson weights, normalised to a mean
        w_u = w.copy()
        for start_s, end_s in (held_out_s[i_trial] if held_out_s else []):
            w_u[(tt >= start_s) & (tt <= end_s)] = 0.0
        err = ((q - qm) / SIGMA_Q_RAD) ** 2 + ((v - vm) / SIGMA_V_RAD_S) ** 2
        cost = cost + ca.dot(ca.DM(w), err) + ca.dot(ca.DM(w_u), ((u * u_scale - um) / SIGMA_U_NM) ** 2)
        outputs.append((t, tt, q, v, u, u_scale, qm, vm, um))
    prior_sd = np.array([PRIOR_RELATIVE_SD[n.split(".")[1]] for n in pset.names]) if parameters is None \
        else np.full(n_par, 0.1)
    reg = PRIOR_WEIGHT * ca.sumsqr((p_scaled - 1.0) / ca.DM(prior_sd))
    if n_ext:  # a vanishing pull toward no extension: a parameter no trial touches stays at 0
        reg = reg + 1e-6 * ca.sumsqr(e_scaled)
    opti.minimize(cost + reg)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "max_iter": max_iter, "tol": 1e-8,
                                                  "sb": "yes"})
    if progress is not None:
        opti.callback(lambda i: progress(int(i), float(opti.debug.value(cost + reg))))
    t0 = time.perf_counter()
    try:
        sol: Any = opti.solve()
        success, message = True, "IPOPT converged"
    except RuntimeError as err:  # the last iterate is still a result: success=False says so
        sol = opti.debug
        success, message = False, f"IPOPT did not converge ({str(err).splitlines()[-1][:160]}); tried " \
                                  f"{intervals} intervals per trial, max_iter {max_iter}, from the generic values"
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
    return PmpResult(parameters=dict(zip(pset.names, est.tolist())), generic=dict(zip(pset.names, pset.generic.tolist())),
                     lower=dict(zip(pset.names, pset.lower.tolist())), upper=dict(zip(pset.names, pset.upper.tolist())),
                     fun=float(sol.value(cost)), nit=int(stats.get("iter_count", -1)), solve_time_s=solve_s,
                     success=success, status=FitStatus.CONVERGED if success else FitStatus.NOT_CONVERGED,
                     message=message, solver_status=str(stats.get("return_status", "unknown")), trials=res_trials,
                     extension_parameters=ext_est)


def moment_function(leg: LegMuscles, trial: PmpTrial, parameters: dict[str, float]) -> Any:
    """CasADi function q ↦ passive muscle moment (N·m) about ``trial``'s joint with ``parameters``
    (generic values for any not given); the calf tendon lengths are solved by Newton inside it."""
    import casadi as ca

    q = ca.SX.sym("q")
    moment, residuals, lts = _muscles_moment(leg, trial, q, parameters)
    return ca.Function("moment", [q], [_eliminate_tendons(moment, residuals, lts, [q])])


def identifiability(result: PmpResult, trials: list[PmpTrial], subject: Subject, *, leg: LegMuscles | None = None,
                    rel_se_limit: float = 0.035, stride: int = 1, misfit_limit: float = MISFIT_LIMIT,
                    model_error_nm: float | None = None, extension: Any = None) -> dict[str, Any]:
    """Which parameters the trials determine, with honest 95 % intervals.

    Uncertainty: the torque residuals e = u_model(q) − u_measured at every measured sample
    (quasi-static model, as the sweeps are slow) are linearised in the relative parameters (J from
    CasADi's exact derivatives). The covariance is the least-squares one with the residual's own
    variance σ̂² (not an assumed sensor noise, so a model that misses the data gets wide
    intervals) inflated by n / n_eff, the residual's effective sample size from its integrated
    autocorrelation time (systematic misfit is correlated, and counts as few samples):
    C = σ̂² (JᵀJ)⁺ · n / n_eff, restricted to the directions the data constrain. The muscle
    model's own error (``model_error_nm``, RMS per sample; default :data:`MODEL_ERROR_RMS_NM`, as
    measured against OpenSim) can bias the estimate by at most |a_k|·|δ| for parameter k (a_k the
    row of the least-squares solution operator, |δ| = RMS·√n); the 95 % interval is
    ±(1.96·SE + that bound).

    A parameter is *determined* when (1) the fit converged; (2) the residual is consistent with
    the measurement noise or within the model error the intervals allow for: its RMS is at most
    ``misfit_limit`` × the noise seen in the torque's second differences, or its systematic part
    (√(RMS² − noise²)) at most ``model_error_nm`` (otherwise the report says the model does not fit
    well enough to determine anything, and by how much); (3) its interval's half-width is below 1.96 × ``rel_se_limit``
    (3.5 %, the dissertation's accuracy); (4) no parameter of its muscle is at a bound; and (5)
    every parameter of its synergists (other muscles crossing the same joints with the same
    moment-arm signs) is determined too — otherwise they can share the load in ways the local
    curvature does not see. The eigenvectors of the information with eigenvalues below
    1/limit² are the combinations the data leave free, listed with their largest components.

    With ``extension`` (the one ``result`` was fitted with), its terms are in the model and its
    parameters are nuisances fitted jointly: the muscles' information is the Schur complement
    I_mm − I_mn I_nn⁺ I_nm (the nuisances profiled out, to first order: a muscle parameter that
    trades against the extension gets the wider interval it deserves), and the least-squares
    solution operator is the one with the nuisances free.
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
    conditions = sorted({(t.joint, _other_joint(t), round(t.fixed_rad.get(_other_joint(t), 0.0), 6)) for t in trials})
    measured = (["shank_length_scale"] + [f"{o}_set_angle_{math.degrees(a):.0f}deg ({j} trials)" for j, o, a in conditions]
                + ["mass_kg"])
    prior_sd = np.array([subject.shank_length_sd_m / subject.shank_length_m]
                        + [subject.set_angle_sd_rad] * len(conditions) + [subject.mass_sd_kg])

    def model_u_of(t: PmpTrial, use_leg: LegMuscles, fixed: dict[str, float], mass_kg: float) -> Any:
        tt = PmpTrial(t.joint, fixed, t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm, t.name)
        q_joint = extension.joint_angle(tt, q, ext_par) if extension is not None else q
        moment = _eliminate_tendons(*_muscles_moment(use_leg, tt, q_joint, par), [q, prel, erel])
        if extension is not None and extension.angle is not None:  # virtual work, as in the fit
            moment = moment * ca.jacobian(q_joint, q)
        body = Subject(mass_kg, subject.shank_length_m, subject.foot_length_m, subject.arm_inertia_kgm2)
        gravity = body.gravity_moment_nm(t.joint, q, fixed, ca.cos)
        return -(moment + gravity + (extension.moment(tt, q, v, ext_par, gravity) if extension is not None else 0))

    step_scale, step_angle, step_mass = 1e-4, 1e-4, 1e-2
    scaled_leg = leg.rescaled(1.0 + step_scale)
    rows, residual_parts, noise_parts = [], [], []
    undefined = 0
    for t in trials:
        model_u = model_u_of(t, leg, t.fixed_rad, subject.mass_kg)
        angle = _smoothed(t.angle_rad)[::stride]  # angle noise must not pass for torque misfit on steep curves
        velocity = _smoothed(t.velocity_rad_s)[::stride]
        both = ca.vertcat(prel, erel)
        other = _other_joint(t)
        shifted = dict(t.fixed_rad)
        shifted[other] = t.fixed_rad.get(other, 0.0) + step_angle
        variants = [model_u_of(t, scaled_leg, t.fixed_rad, subject.mass_kg), model_u_of(t, leg, shifted, subject.mass_kg),
                    model_u_of(t, leg, t.fixed_rad, subject.mass_kg + step_mass)]
        f = ca.Function("u", [q, v, prel, erel], [model_u, ca.jacobian(model_u, both), *variants]).map(angle.size)
        out = f(angle.reshape(1, -1), velocity.reshape(1, -1), ca.repmat(ca.DM.ones(len(names)), 1, angle.size),
                ca.DM.zeros(len(ext_names), angle.size))
        u_pred = np.asarray(out[0]).ravel()
        rows.append(np.asarray(out[1]).reshape(-1, len(names) + len(ext_names)))  # the map lays the rows side by side
        cols = np.zeros((angle.size, len(measured)))
        cols[:, 0] = (np.asarray(out[2]).ravel() - u_pred) / step_scale
        key = (t.joint, other, round(t.fixed_rad.get(other, 0.0), 6))
        cols[:, 1 + conditions.index(key)] = (np.asarray(out[3]).ravel() - u_pred) / step_angle
        cols[:, -1] = (np.asarray(out[4]).ravel() - u_pred) / step_mass
        rows[-1] = np.hstack([rows[-1], cols])
        residual = u_pred - t.torque_nm[::stride]
        # where the fitted model has no value (the calf tendons without an equilibrium, an overflow) the sample
        # is left out and counted; any such sample makes nothing determined (below)
        defined = np.isfinite(residual) & np.isfinite(rows[-1]).all(axis=1)
        undefined += int((~defined).sum())
        rows[-1] = rows[-1][defined]
        residual_parts.append(residual[defined])
        # white noise from second differences (the smooth moment curve hardly has any): var(Δ²e) = 6σ²
        noise_parts.append(np.diff(t.torque_nm, 2) / np.sqrt(6.0))
    j_all = np.vstack(rows)
    j, j_nuis = j_all[:, :len(names)], j_all[:, len(names):]
    n_samples, k = j.shape
    residual_rms = float(np.sqrt(np.mean(np.concatenate(residual_parts) ** 2)))
    noise = float(1.4826 * np.median(np.abs(np.concatenate(noise_parts))))  # robust σ of white noise
    sigma2 = float(np.sum(np.concatenate(residual_parts) ** 2) / max(n_samples - k - len(ext_names), 1))
    n_eff = float(sum(e.size / _autocorrelation_time(e) for e in residual_parts))
    scale_c = sigma2 * n_samples / max(n_eff, 1.0)
    j_ext, j_meas = j_nuis[:, :len(ext_names)], j_nuis[:, len(ext_names):]
    if ext_names:
        # the extension's parameters profiled out (fitted jointly, first order): the muscles' columns made
        # orthogonal to the extension's
        j = j - j_ext @ (np.linalg.pinv(j_ext.T @ j_ext, rcond=1e-10) @ (j_ext.T @ j))
    info = j.T @ j / scale_c
    info_finite = n_samples > 0 and bool(np.all(np.isfinite(info)))
    if not info_finite:
        info = np.zeros_like(info)  # nothing is constrained: every parameter undetermined (the reasons say why)
    w, vecs = np.linalg.eigh(info)
    keep = w > 1.0 / rel_se_limit**2
    cov = (vecs[:, keep] / w[keep]) @ vecs[:, keep].T
    se = np.sqrt(np.maximum(np.diag(cov), 0.0))
    # the forward model's own error (against OpenSim, MODEL_ERROR_RMS_NM per sample) biases the fit
    # by at most |a_k|·|δ| for parameter k (a_k: row k of the least-squares solution operator,
    # restricted to the constrained directions; |δ| = RMS·√n): a bound added to the interval
    solve_rows = (vecs[:, keep] / w[keep]) @ vecs[:, keep].T @ j.T / scale_c
    bias = np.sqrt(np.sum(solve_rows**2, axis=1)) * model_error_nm * np.sqrt(n_samples)
    # a parameter is determined only if it has (almost) no part in the unconstrained directions
    free_part = np.sqrt(np.sum(vecs[:, ~keep] ** 2, axis=1)) if (~keep).any() else np.zeros(len(names))
    # the measured quantities (shank, set angles, mass) enter as they were entered; an error Δ in one shifts the
    # estimate by C·Jᵀ·J_Δ·Δ / c (the fit's response to the torque it causes): their SDs propagated to first
    # order (delta method) and added to the variance. Profiled into the information instead, the shank took
    # the slack lengths' information with it and the model-error bound (≈ 90 × the SE) made nothing determined
    sensitivity = cov @ j.T @ j_meas / scale_c
    measurement_var = np.sum((sensitivity * prior_sd[None, :]) ** 2, axis=1)
    se_total = np.sqrt(se**2 + measurement_var)
    half_width = 1.96 * se_total + bias
    determined = (half_width < 1.96 * rel_se_limit) & (free_part < 0.1)
    misfit_ratio = residual_rms / max(noise, 1e-12)
    # the residual's systematic part (beyond the white noise): the intervals' bias bound is built for a model
    # error up to model_error_nm RMS, so a residual whose systematic part stays within it is consistent with
    # them even when the noise is small (a 0.05 N·m sensor shows a 0.14 N·m model error as 3×)
    systematic = math.sqrt(max(residual_rms**2 - noise**2, 0.0))
    reasons = []
    if not info_finite:
        reasons.append("the fit's information is not finite: nothing can be determined from it")
    if not result.success:
        reasons.append(f"the fit did not converge ({result.message})")
    if undefined:
        reasons.append(f"the fitted model has no value at {undefined} of {n_samples + undefined} samples (the calf "
                       "tendons without an equilibrium there, or an overflow): its parameters are not trusted")
    if misfit_ratio > misfit_limit and systematic > model_error_nm:
        reasons.append(f"the model does not fit the data well enough to determine anything: residual RMS "
                       f"{residual_rms:.3g} N·m is {misfit_ratio:.1f}× the measurement noise ({noise:.3g} N·m; "
                       f"at most {misfit_limit:g}× allowed), its systematic part {systematic:.3g} N·m more than the "
                       f"{model_error_nm:g} N·m model error the intervals allow for")
    if reasons:
        determined[:] = False
    at_bound = [n for n in names if result.parameters[n] <= result.lower[n] * (1 + 1e-3)
                or result.parameters[n] >= result.upper[n] * (1 - 1e-3)]
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
    return {"determined": [n for n, d in zip(names, determined) if d],
            "undetermined": [n for n, d in zip(names, determined) if not d],
            "relative_se": dict(zip(names, se_total.tolist())),
            "ci95": {n: [values[k] * (1 - half_width[k]), values[k] * (1 + half_width[k])]
                     for k, n in enumerate(names) if determined[k]},
            "model_error_bound_rel": dict(zip(names, bias.tolist())),
            "free_combinations": combos, "rank": int(keep.sum()), "parameters": len(names), "at_bound": at_bound,
            "residual_rms_nm": residual_rms, "noise_nm": noise, "misfit_ratio": misfit_ratio,
            "systematic_residual_nm": systematic,
            "effective_samples": n_eff, "samples": n_samples, "not_determined_because": reasons,
            "uncertainty": "least-squares covariance with the residual's variance, inflated by n/n_eff "
                           "(integrated autocorrelation time of the residual)"
                           + (f"; the {extension.name} parameters fitted jointly as nuisances (profiled out)"
                              if extension is not None else "")
                           + f"; the shank length (SD {1e3 * subject.shank_length_sd_m:.1f} mm), each set angle "
                             f"(SD {math.degrees(subject.set_angle_sd_rad):.1f}°) and the mass (SD {subject.mass_sd_kg:g} kg) "
                             "as measured inputs whose SDs are propagated to first order (delta method)",
            "measurement_se_rel": dict(zip(names, np.sqrt(measurement_var).tolist())),
            "measurement_nuisances": measured,
            "extension": extension.name if extension is not None else None}


def _other_joint(trial: PmpTrial) -> str:
    """The fixed joint whose set angle changes between a moving joint's conditions (hip for the knee, knee
    for the ankle)."""
    return "hip" if trial.joint == "knee" else "knee"


def _smoothed(angle_rad: np.ndarray) -> np.ndarray:
    """The sweep's angle with sensor noise averaged out (cubic Savitzky–Golay over ~1/20 of the trial)."""
    from scipy.signal import savgol_filter

    n = angle_rad.size
    window = min(n - (1 - n % 2), max(5, (n // 20) | 1))
    return savgol_filter(angle_rad, window, 3) if window > 3 else angle_rad


def _autocorrelation_time(e: np.ndarray) -> float:
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
