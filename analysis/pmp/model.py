"""The passive muscle model the fit uses: the trials, the subject, the free parameters and the muscles' moment.

The moment of every muscle crossing the moving joint from the DeGroote–Fregly passive curves, its
path as a Taylor polynomial about the measured angle, the calf tendons' lengths eliminated by
Newton's method on the fibre–tendon equilibrium (eq 3.2). :mod:`analysis.pmp.problem` builds the
collocation problem on it; :mod:`analysis.pmp.identifiability` judges what the fit determined.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..constants import GRAVITY_M_S2
from .curves import active_fiber_force, passive_fiber_force, tendon_force
from .geometry import MUSCLES
from .muscles import COMPLIANT, LegMuscles, scale_for_subject, thigh_over_shank_for_subject
from .workers import mapped

G = GRAVITY_M_S2
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
MEASUREMENT_SD = {"shank_length_m": 0.0025, "thigh_length_m": 0.0025, "set_angle_rad": math.radians(1.5),
                  "mass_kg": 0.25}
#: one SD of the thigh's scale over the shank's when the thigh was not measured (an assumed 3 %: adults' thigh
#: and shank are not in one proportion, and the leg is then scaled by the shank alone)
THIGH_OVER_SHANK_SD_UNMEASURED = 0.03


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
    #: hip to knee joint centre (m), if measured: the thigh's muscles are then scaled by it
    thigh_length_m: float | None = None
    thigh_length_sd_m: float = MEASUREMENT_SD["thigh_length_m"]

    def leg(self) -> LegMuscles:
        """The eleven muscles scaled to this subject: by the shank, the thigh's muscles by the thigh if measured."""
        return LegMuscles(length_scale=scale_for_subject(self.shank_length_m),
                          thigh_over_shank=thigh_over_shank_for_subject(self.thigh_length_m, self.shank_length_m))

    def thigh_over_shank_sd(self) -> float:
        """One SD of the thigh's scale over the shank's beside the shank's own error: the thigh's tape (a shank
        error moves the ratio too, and is counted with the shank), or :data:`THIGH_OVER_SHANK_SD_UNMEASURED`
        without the thigh's."""
        if self.thigh_length_m is None:
            return THIGH_OVER_SHANK_SD_UNMEASURED
        return self.thigh_length_sd_m / self.thigh_length_m

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


#: order of the Taylor expansion of path length and moment arm about the measured angle inside the fit
PATH_TAYLOR_ORDER = 3
#: trials' path expansions a leg keeps (a model-level diagnosis revisits a dozen trials at one set of anchors,
#: each at its set angle and a step either side)
PATH_CACHE_SIZE = 192


def other_joint(trial: PmpTrial) -> str:
    """The fixed joint whose set angle changes between a moving joint's conditions (hip for the knee, knee
    for the ankle)."""
    return "hip" if trial.joint == "knee" else "knee"


def set_angle_condition(trial: PmpTrial) -> tuple[str, str, float]:
    """The set-angle condition ``trial`` belongs to: (moving joint, fixed joint, its set angle in rad rounded to
    1e-6). Trials of one condition share the chair's setting, so they share its error."""
    other = other_joint(trial)
    return trial.joint, other, round(trial.fixed_rad.get(other, 0.0), 6)


def set_angle_label(condition: tuple[str, str, float]) -> str:
    """``"hip_set_angle_55deg (knee trials)"``: a set-angle condition's name in reports and results."""
    joint, other, angle_rad = condition
    return f"{other}_set_angle_{math.degrees(angle_rad):.0f}deg ({joint} trials)"


def posed_at(trial: PmpTrial, offset_rad: Any) -> PmpTrial:
    """``trial`` with its fixed joint (:func:`other_joint`) turned by ``offset_rad`` from the entered set angle (a
    number or a CasADi symbol)."""
    other = other_joint(trial)
    fixed: dict[str, Any] = dict(trial.fixed_rad)
    fixed[other] = trial.fixed_rad.get(other, 0.0) + offset_rad
    return PmpTrial(trial.joint, fixed, trial.time_s, trial.angle_rad, trial.velocity_rad_s, trial.torque_nm,
                    trial.name)


def with_set_angles(trials: list[PmpTrial], offsets_rad: dict[str, float]) -> list[PmpTrial]:
    """``trials`` with each fixed joint at its set angle plus the fitted offset of its condition (rad, keyed by
    :func:`set_angle_label`; a condition without one keeps the entered angle)."""
    offsets = [float(offsets_rad.get(set_angle_label(set_angle_condition(t)), 0.0)) for t in trials]
    return [posed_at(t, d) if d else t for t, d in zip(trials, offsets, strict=True)]


#: step (rad) of the central differences of the paths' Taylor coefficients in the fixed joint's set angle
SET_ANGLE_STEP_RAD = 1e-3


def path_taylor_rows(leg: LegMuscles, trial: PmpTrial, anchors_rad: np.ndarray, set_angle: bool = False) -> np.ndarray:
    """The rows the fit evaluates a trial's paths from: the anchors (rad), then :func:`path_taylor`'s
    coefficients; with ``set_angle`` also their first and second derivatives in the fixed joint's set angle
    (central differences, :data:`SET_ANGLE_STEP_RAD`), so that the paths at a set angle off by δ are
    c + δ·c′ + δ²/2·c″ (second order: at δ = ±3° the lengths are within 0.02 mm of the paths at the shifted angle
    over the protocol's six sweeps)."""
    _, coef = path_taylor(leg, trial, anchors_rad)
    blocks = [anchors_rad.reshape(1, -1), coef]
    if set_angle:
        h = SET_ANGLE_STEP_RAD
        up, down = (path_taylor(leg, posed_at(trial, step), anchors_rad)[1] for step in (h, -h))
        blocks += [(up - down) / (2 * h), (up - 2 * coef + down) / h**2]
    return np.vstack(blocks)


def path_taylor(leg: LegMuscles, trial: PmpTrial, anchors_rad: np.ndarray) -> tuple[list[str], np.ndarray]:
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
    key = (trial.joint, tuple(sorted(trial.fixed_rad.items())), leg.length_scale, leg.thigh_over_shank,
           anchors_rad.tobytes())
    if key in leg.path_cache:  # the model-level diagnosis fits the same trials again and again
        return leg.path_cache[key]
    names, taylor = _taylor_function(leg, trial.joint)
    fixed = np.array([[trial.fixed_rad.get(j, 0.0)] for j in ("hip", "knee", "ankle")])
    values = mapped(taylor, anchors_rad.size)(anchors_rad.reshape(1, -1), np.repeat(fixed, anchors_rad.size, axis=1))
    _make_room(leg)
    leg.path_cache[key] = (names, np.asarray(values))
    return leg.path_cache[key]


def _make_room(leg: LegMuscles) -> None:
    """Empty ``leg``'s path cache when full, keeping the symbolic Taylor functions (a few per leg)."""
    if len(leg.path_cache) >= PATH_CACHE_SIZE:
        for k in [k for k in leg.path_cache if k[0] != "taylor function"]:
            del leg.path_cache[k]


def _taylor_function(leg: LegMuscles, joint: str) -> tuple[list[str], Any]:
    """The names of the muscles crossing ``joint`` and a CasADi function (angle of ``joint``, the three joints'
    angles as a column: hip, knee, ankle; rad) → :func:`path_taylor`'s coefficients, differentiated symbolically
    once per leg scale and joint (anchors and set angles change with every re-anchoring and set-angle step; the
    derivatives do not)."""
    import casadi as ca

    key = ("taylor function", joint, leg.length_scale, leg.thigh_over_shank)
    if key in leg.path_cache:
        return leg.path_cache[key]  # type: ignore[no-any-return]  # the cache holds this key's pair only
    names = [m for m in MUSCLES if joint in leg.paths[m].joints]
    x, fixed = ca.SX.sym("x"), ca.SX.sym("fixed", 3)
    angles = {"hip": fixed[0], "knee": fixed[1], "ankle": fixed[2], joint: x}
    rows = []
    for m in names:
        for expr in (leg.path_length_m(m, **angles), leg.moment_arm_m(m, joint, **angles)):
            d = expr
            for k in range(PATH_TAYLOR_ORDER + 1):
                rows.append(d / math.factorial(k))
                d = ca.jacobian(d, x)
    _make_room(leg)
    leg.path_cache[key] = (names, ca.Function("taylor", [x, fixed], [ca.vertcat(*rows)]))
    return leg.path_cache[key]  # type: ignore[no-any-return]  # the pair just stored


def muscle_moment(leg: LegMuscles, m: str, joint: str, q: dict[str, Any], ls: Any, strain: Any, lt_norm: Any,
                   path: tuple[Any, Any] | None = None, fiber_strain: Any = None, activation: Any = 0.0) -> tuple[Any, Any]:
    """(moment toward positive angle, equilibrium residual or None) of one muscle in CasADi;
    ``path`` (length, moment arm) replaces the leg's path evaluated at ``q``. With a tendon length
    ``lt_norm`` (a symbol: the tendon is compliant) ``strain`` is the tendon's ε_T0 and the fibre's ε₀ is
    ``fiber_strain`` (default the leg's); with ``lt_norm`` None the tendon is rigid and ``strain`` is the
    fibre's ε₀. ``activation`` (0–1) adds the isometric active force a·f_L(l̃_M) to the fibre's passive force."""
    import casadi as ca

    p = leg.paths[m]
    lo = leg.optimal_fiber_length_m(m)
    h = lo * np.sin(p.pennation_at_optimal_rad)
    lmt, r = path if path is not None else (leg.path_length_m(m, **q), leg.moment_arm_m(m, joint, **q))
    if lt_norm is not None:
        lt = lt_norm * ls
        along = lmt - lt
        lm = ca.sqrt(along**2 + h**2)
        eps0 = leg.params[m].passive_strain if fiber_strain is None else fiber_strain
        fibre = passive_fiber_force(lm / lo, eps0) + activation * active_fiber_force(lm / lo)
        res = fibre * along / lm - tendon_force(lt_norm, strain)
        return r * p.max_isometric_force_n * tendon_force(lt_norm, strain), res
    along = lmt - ls
    lm = ca.sqrt(along**2 + h**2)
    fibre = passive_fiber_force(lm / lo, strain) + activation * active_fiber_force(lm / lo)
    return r * p.max_isometric_force_n * fibre * along / lm, None


def muscles_moment(leg: LegMuscles, trial: PmpTrial, q: Any, par: dict[str, Any],
                    local: tuple[Any, Any] | None = None, activation: Any = 0.0,
                    tendon_strain: dict[str, Any] | None = None) -> tuple[Any, list[Any], list[Any]]:
    """Passive moment (CasADi) of the muscles crossing ``trial``'s joint at angle ``q``, the
    equilibrium residuals of the compliant tendons and their tendon-length symbols; ``par`` (numbers
    or symbols) overrides the leg's own parameters by name. ``local`` = (anchor angle, Taylor
    coefficients as :func:`path_taylor` lays them out) evaluates the paths as polynomials about the
    anchor. A model extension may add a tonic ``activation`` (0–1, every muscle crossing the joint)
    and make more tendons compliant: ``tendon_strain`` maps a rigid-tendoned muscle to its ε_T0."""
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
        compliant = m in COMPLIANT or m in (tendon_strain or {})
        if m in COMPLIANT:
            strain = par.get(f"{m}.tendon_strain", base.tendon_strain)
        elif compliant:
            strain = (tendon_strain or {})[m]
        else:
            strain = par.get(f"{m}.passive_strain", base.passive_strain)
        lt = ca.SX.sym(f"lt_{m}") if compliant else None
        fibre = par.get(f"{m}.passive_strain", base.passive_strain) if compliant else None
        mom, res = muscle_moment(leg, m, trial.joint, angles, ls, strain, lt, paths.get(m), fibre, activation)
        moment = moment + mom
        if res is not None:
            residuals.append(res)
            lts.append(lt)
    return moment, residuals, lts


#: largest calf-tendon equilibrium residual (normalised force) accepted as solved
EQUILIBRIUM_TOLERANCE = 1e-8


def eliminate_tendons(moment: Any, residuals: list[Any], lts: list[Any], args: list[Any]) -> Any:
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


def moment_function(leg: LegMuscles, trial: PmpTrial, parameters: dict[str, float], **options: Any) -> Any:
    """CasADi function q ↦ passive muscle moment (N·m) about ``trial``'s joint with ``parameters``
    (generic values for any not given); the compliant tendons' lengths are solved by Newton inside it.
    ``options``: a model extension's ``activation`` and ``tendon_strain`` (:func:`muscles_moment`)."""
    import casadi as ca

    q = ca.SX.sym("q")
    moment, residuals, lts = muscles_moment(leg, trial, q, parameters, **options)
    return ca.Function("moment", [q], [eliminate_tendons(moment, residuals, lts, [q])])

