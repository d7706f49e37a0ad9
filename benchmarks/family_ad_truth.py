"""A thirtieth generator family for the diagnosis, written (2026-12-07, thirty-eighth stop) while the twenty-ninth
family's one run was under way (its figures unread) and before any further engine change, nothing diagnosed on it; to
be run once on the next change's frozen engine.

The second to twenty-ninth families (:mod:`benchmarks.family_b_truth` … ``family_ac_truth``) are development data
once run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: the twenty-ninth family's stop was a Mooney–Rivlin
bumper in compression (here the same law in tension is the passive end); damping varying along the range was linear
or toward the ends before (here it peaks mid-range through a linkage); a weight error that follows the posture
through a lag is new, the twenty-seventh's pooling grew with time alone. Nothing is imported from ``analysis``, nor
any physics from the other generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the
scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a Mooney–Rivlin solid in uniaxial tension, per unit
  2(λ − λ⁻²)(1 + r/λ) (r = C₂/C₁ 0–1) for the stretch λ = 1 + x̄/L (x̄ the softplus of the angle past an onset over
  2–5°, L 0.5–1.5 × the end's reach) times a stiffening e^{κ(λ − 1)} (κ 0.5–2); the steep end sized by its torque
  at the range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small linear term. The
  AFO: a carbon leaf whose torque is k·θ̄·(1 + θ̄/θ_s)^{−1}·(1 + (θ̄/θ_h)²) (softening, then a hardening strap; θ_s
  20–40°, θ_h 15–25°) past an engagement of 0.5–2° (softplus).
- Motion: a triangle whose centre wanders: 3–5 cycles at a constant 3–7 °/s, each cycle's centre shifted by ±15 % of
  the range (its ends clipped to the range), turns rounded by a cubic blend over 0.2–0.5 s, a 0.5–1.5 s hold at the
  start. The AFO: 5–8 bends to 10–20° in two steps (loaded to 40–60 % of the peak, paused 0.2–0.6 s, loaded on),
  released along a raised cosine over 0.5–1 s, rested 0.3–1 s.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bushing whose drag grows with the square of the speed (hydrodynamic), tanh(v/ε)·(1 + q·(v/v_max)²)
    (ε 0.1–0.4 °/s, q 0.2–0.6); magnitude: its mean |F| over the moving samples;
  * damping: a dashpot behind a linkage whose lever peaks mid-range, b·(1 + a·sin(π·s))²·θ̇ (s from 0 to 1 along
    the range, a 0.3–0.8); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a pad whose seat creeps: a linear contact whose angle moves 1–3° deeper into the range over the trial
    (linearly in time), anywhere in the last 5–30 % of either end of a joint's range (the AFO's at the top of its
    bend); named only;
  * delay: a transport delay of 0.02–0.45 s behind an alpha–beta tracker (a constant-velocity Kalman filter in steady
    state, α 0.1–0.4, β = α²/(2 − α): no lag on a ramp, an overshoot at each turn); magnitude: the transport delay;
  * activation: a Gumbel (extreme-value) density pulse, e^{−(z + e^{−z})} for z = (t − t_m)/w (w 0.1–0.5 s: a steep
    rise and a long tail), its mode anywhere in 12–85 % of the trial, of either sign; magnitude: its peak;
  * limb-weight error: fluid shifting within the limb with its posture: a share of the segment's weight following
    sin ψ (how far the segment hangs) through a first-order lag of 10–30 s, acting at its centre of mass, moment
    error ∝ m(t)·cos ψ; magnitude: its peak;
  * drift: a cooling fan speeding up: the zero oscillating with a period falling from 60–120 s to 20–40 s over the
    trial (a linear chirp), random phase; named only;
  * series compliance: a cuff gripping the skin, elastic up to a slip torque (30–70 % of the largest) and sliding on
    beyond it with a hardening of 20–50 % of the elastic rate (a Prandtl element with kinematic hardening: reloading
    after each reversal is elastic again), c 0.03–0.15 °/N·m but at most half of h over the torque's stiffest rate so
    the joint's angle behind it is well defined; magnitude: the least-squares slope of the give on the torque;
  * inertia error: the dynamometer's inertia compensation applied to a low-passed acceleration (τ 20–80 ms) with a
    wrong inertia: the torque error J_e·LP(θ̈) + J_c·(θ̈ − LP(θ̈)) (J_c the compensated inertia, 1–3 × J_e);
    magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise; the amplifier's gain drifting by ±0.5–1.5 %
  over the trial (linearly); mains hum aliased by the sampling to a beat of 0.05–0.5 Hz at 0.2–0.4 × the noise SD;
  quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in
  runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import (
    GRAVITY,
    coupled_onsets,
    damage_recording,
    draw_segments,
    draw_subject,
    kinematics,
    limb_load,
    protocol_set_up,
    trial_rng,
)

NOISE_SD_NM = {"afo": 0.065, "knee": 0.16, "ankle": 0.12}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def mooney_rivlin_tension(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, c2_over_c1: float,
                          stiffening: float) -> np.ndarray:
    """An end per unit C₁: 2(λ − λ⁻²)(1 + r/λ)·e^{κ(λ − 1)} (zero at λ = 1), the stretch λ = 1 + x̄/L with
    x̄ = s·ln(1 + e^{x/s}) the softplus of the angle ``x_deg`` past the onset over s = ``smoothing_deg``, L =
    ``reach_deg``, r = ``c2_over_c1``, κ = ``stiffening``."""
    x = np.asarray(x_deg, dtype=float) / smoothing_deg
    lam = 1.0 + smoothing_deg * np.logaddexp(0.0, x) / reach_deg
    return np.asarray(2.0 * (lam - lam**-2) * (1.0 + c2_over_c1 / lam) * np.exp(stiffening * (lam - 1.0)), dtype=float)


def carbon_leaf(deg: np.ndarray, engage_deg: float, smoothing_deg: float, soften_deg: float, harden_deg: float
                ) -> np.ndarray:
    """An orthosis's leaf per unit stiffness: θ̄·(1 + θ̄/θ_s)⁻¹·(1 + (θ̄/θ_h)²) for θ̄ the softplus (over
    ``smoothing_deg``) of the bend past ``engage_deg`` (deg, zero at 0°)."""
    d = np.asarray(deg, dtype=float)
    bend = smoothing_deg * (np.logaddexp(0.0, (d - engage_deg) / smoothing_deg)
                            - np.logaddexp(0.0, -engage_deg / smoothing_deg))
    return np.asarray(bend / (1.0 + bend / soften_deg) * (1.0 + (bend / harden_deg) ** 2), dtype=float)


def _blend_turns(deg: np.ndarray, rate: float, blend_s: float) -> np.ndarray:
    """``deg`` with each corner rounded: a moving average over ``blend_s`` applied three times (a cubic B-spline
    kernel), the ends held."""
    n = max(1, int(blend_s * rate / 3.0))
    out = np.asarray(deg, dtype=float)
    for _ in range(3):
        padded = np.concatenate([np.full(n, out[0]), out, np.full(n, out[-1])])
        kernel = np.ones(2 * n + 1) / (2 * n + 1)
        out = np.convolve(padded, kernel, mode="valid")
    return out


def wandering_triangle(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the range's middle, then 3–5 triangle cycles at a constant 3–7 °/s,
    each cycle's centre shifted by ±15 % of the range and its ends clipped to the range; back to the middle; corners
    rounded over 0.2–0.5 s."""
    speed = float(rng.uniform(3.0, 7.0))
    span, mid = hi - lo, 0.5 * (lo + hi)
    points = [mid]
    for _ in range(int(rng.integers(3, 6))):
        centre = mid + float(rng.uniform(-0.15, 0.15)) * span
        points += [min(hi, centre + 0.5 * span), max(lo, centre - 0.5 * span)]
    points.append(mid)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    for a, b in zip(points[:-1], points[1:], strict=True):
        n = max(2, int(np.ceil(abs(b - a) / speed * rate)))
        parts.append(a + (b - a) * np.arange(1, n + 1) / n)
    parts.append(np.full(int(rate), mid))
    return _blend_turns(np.concatenate(parts), rate, float(rng.uniform(0.2, 0.5)))


def two_step_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 5–8 bends to 10–20°, each loaded along a raised cosine to 40–60 % of its
    peak over 0.6–1.2 s, paused 0.2–0.6 s, loaded on to the peak over 0.6–1.2 s, released along a raised cosine over
    0.5–1 s to 0°, rested 0.3–1 s."""
    parts = [np.zeros(int(0.5 * rate))]

    def ramp(a: float, b: float, seconds: float) -> np.ndarray:
        s = np.arange(1, int(seconds * rate) + 1) / int(seconds * rate)
        return a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * s))

    for _ in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(10.0, 20.0))
        step = float(rng.uniform(0.4, 0.6)) * peak
        parts += [ramp(0.0, step, float(rng.uniform(0.6, 1.2))), np.full(int(rng.uniform(0.2, 0.6) * rate), step),
                  ramp(step, peak, float(rng.uniform(0.6, 1.2))), ramp(peak, 0.0, float(rng.uniform(0.5, 1.0))),
                  np.zeros(int(rng.uniform(0.3, 1.0) * rate))]
    return np.concatenate(parts)


def hydrodynamic_friction(vel_deg_s: np.ndarray, epsilon_deg_s: float, quadratic: float) -> np.ndarray:
    """A bushing's friction per unit level: tanh(v/ε)·(1 + q·(v/v_max)²), v_max the largest |v|."""
    v = np.asarray(vel_deg_s, dtype=float)
    ratio = v / max(float(np.max(np.abs(v))), 1e-12)
    return np.asarray(np.tanh(v / epsilon_deg_s) * (1.0 + quadratic * ratio * ratio), dtype=float)


def linkage_dashpot(vel: np.ndarray, s: np.ndarray, lever: float) -> np.ndarray:
    """A dashpot behind a linkage per unit coefficient: (1 + a·sin(π·s))²·θ̇ (s from 0 to 1 along the range)."""
    return np.asarray((1.0 + lever * np.sin(np.pi * np.clip(np.asarray(s, dtype=float), 0.0, 1.0))) ** 2
                      * np.asarray(vel, dtype=float), dtype=float)


def creeping_stop(deg: np.ndarray, t: np.ndarray, at_deg: float, high: bool, creep_deg: float) -> np.ndarray:
    """A linear pad per unit stiffness (toward the range's inside, positive at the high end) whose seat starts at
    ``at_deg`` and creeps ``creep_deg`` deeper into the range, linearly over the trial."""
    sign = 1.0 if high else -1.0
    tt = np.asarray(t, dtype=float)
    seat = at_deg - sign * creep_deg * (tt - tt[0]) / max(float(tt[-1] - tt[0]), 1e-12)
    return np.asarray(sign * np.clip(sign * (np.asarray(deg, dtype=float) - seat), 0.0, None), dtype=float)


def alpha_beta_tracker(values: np.ndarray, t: np.ndarray, alpha: float) -> np.ndarray:
    """``values`` through a steady-state alpha–beta tracker (β = α²/(2 − α)): a constant-velocity prediction
    corrected by α of the innovation in level and β/Δt in rate."""
    x = np.asarray(values, dtype=float)
    beta = alpha * alpha / (2.0 - alpha)
    level, rate_ = float(x[0]), 0.0
    out = np.empty(x.size)
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    for i in range(x.size):
        step = max(float(dt[i]), 1e-9)
        predicted = level + rate_ * step
        innovation = x[i] - predicted
        level = predicted + alpha * innovation
        rate_ = rate_ + beta * innovation / step
        out[i] = level
    return out


def gumbel_pulse(t: np.ndarray, mode_s: float, width_s: float) -> np.ndarray:
    """A Gumbel density pulse per unit peak: e^{1 − (z + e^{−z})} for z = (t − t_m)/w (its peak 1 at the mode)."""
    z = (np.asarray(t, dtype=float) - mode_s) / width_s
    return np.asarray(np.exp(1.0 - (z + np.exp(-np.clip(z, -50.0, None)))), dtype=float)


def lagged_share(signal: np.ndarray, t: np.ndarray, time_constant_s: float) -> np.ndarray:
    """``signal`` through a first-order lag of ``time_constant_s`` from its first value (exact for held samples)."""
    x = np.asarray(signal, dtype=float)
    out = np.empty(x.size)
    state = float(x[0])
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    for i in range(x.size):
        state += (x[i] - state) * (1.0 - np.exp(-dt[i] / time_constant_s))
        out[i] = state
    return out


def chirped_zero(t: np.ndarray, first_period_s: float, last_period_s: float, phase_rad: float) -> np.ndarray:
    """A zero oscillating with a period falling linearly in frequency from ``first_period_s`` to ``last_period_s``
    over the trial: sin(2π∫f dt + φ)."""
    tt = np.asarray(t, dtype=float) - float(t[0])
    total = max(float(tt[-1]), 1e-12)
    f0, f1 = 1.0 / first_period_s, 1.0 / last_period_s
    return np.asarray(np.sin(2.0 * np.pi * (f0 * tt + 0.5 * (f1 - f0) * tt * tt / total) + phase_rad), dtype=float)


def gripping_cuff(torque: np.ndarray, compliance: float, slip_nm: float, hardening: float) -> np.ndarray:
    """The cuff's give (deg) as the torque history (N·m) drives it: an elastic give c·τ in series with a slider of
    threshold ``slip_nm`` beside a hardening spring (a Prandtl element with kinematic hardening). The slider moves once
    |τ − k_h·s| reaches the threshold; past it the whole give grows at c/h (h = ``hardening``: the sliding stiffness
    over the elastic one); after a reversal it reloads elastically."""
    tau = np.asarray(torque, dtype=float)
    k_elastic = 1.0 / compliance
    k_hard = hardening * k_elastic / (1.0 - hardening)  # series: k_e·k_h/(k_e + k_h) = hardening·k_e
    slip = 0.0
    out = np.empty(tau.size)
    for i, value in enumerate(tau):
        back = k_hard * slip
        excess = value - back
        if excess > slip_nm:
            slip = (value - slip_nm) / k_hard
        elif excess < -slip_nm:
            slip = (value + slip_nm) / k_hard
        out[i] = value / k_elastic + slip
    return out


def behind_gripping_cuff(deg: np.ndarray, elastic: Callable[[np.ndarray], np.ndarray], compliance: float,
                         slip_nm: float, hardening: float, tolerance_deg: float = 1e-7) -> np.ndarray:
    """The joint's angle j (deg) behind the cuff of :func:`gripping_cuff`: j = ``deg`` − give(τ(j)) with τ = ``elastic``
    (N·m) and the give following the torque's history, by fixed-point iteration to ``tolerance_deg``. The give's rate
    is at most c/h per N·m (h = ``hardening``) and the slider is Lipschitz-1 in its input's history, so the iteration
    contracts (in the largest error over the trial) by c/h × the torque's stiffest rate, which the caller keeps ≤ 0.5;
    raises RuntimeError when it has not converged in 200 rounds."""
    joint = np.asarray(deg, dtype=float).copy()
    for _ in range(200):
        following = deg - gripping_cuff(elastic(joint), compliance, slip_nm, hardening)
        change = float(np.max(np.abs(following - joint)))
        joint = following
        if change < tolerance_deg:
            return joint
    raise RuntimeError(f"the cuff's fixed point did not converge (last change {change:.3g}°)")


def compensation_error(acc: np.ndarray, t: np.ndarray, lag_s: float, wrong_kgm2: float, compensated_kgm2: float
                       ) -> np.ndarray:
    """The torque error (N·m) of an inertia compensation applied to the acceleration through a first-order lag of
    ``lag_s``: J_e·LP(θ̈) + J_c·(θ̈ − LP(θ̈))."""
    a = np.asarray(acc, dtype=float)
    low = lagged_share(a, t, lag_s)
    return np.asarray(wrong_kgm2 * low + compensated_kgm2 * (a - low), dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return np.asarray(c["k"] * carbon_leaf(deg, c["engage"], 0.5, c["soften"], c["harden"]), dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * mooney_rivlin_tension(on_low - deg, c["smooth"], c["reach_low"], c["r"], c["kappa"])
            + c["a_high"] * mooney_rivlin_tension(deg - on_high, c["smooth"], c["reach_high"], c["r"], c["kappa"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, soften, harden = float(rng.uniform(0.5, 2.0)), float(rng.uniform(20.0, 40.0)), float(rng.uniform(15.0, 25.0))
        return {"engage": engage, "soften": soften, "harden": harden,
                "k": float(rng.uniform(10.0, 25.0)) / float(carbon_leaf(np.array(15.0), engage, 0.5, soften, harden))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(2.0, 5.0))
    reach_low = (on_low - lo) * float(rng.uniform(0.5, 1.5))
    reach_high = (hi - on_high) * float(rng.uniform(0.5, 1.5))
    r, kappa = float(rng.uniform(0.0, 1.0)), float(rng.uniform(0.5, 2.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(mooney_rivlin_tension(np.array(on_low - lo), smooth, reach_low, r, kappa)),
            "a_high": t_high / float(mooney_rivlin_tension(np.array(hi - on_high), smooth, reach_high, r, kappa)),
            "reach_low": reach_low, "reach_high": reach_high, "r": r, "kappa": kappa, "smooth": smooth,
            "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ad(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((30, 30, 30), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: wandering_triangle(r, a, b, rate),
                                         lambda r: two_step_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
    along = (deg - bottom) / (top - bottom)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a cuff gripping the skin, then sliding
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, slip_nm = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.3, 0.7)) * tau_max
        hardening = float(rng.uniform(0.2, 0.5))
        # the cuff's give at most half the joint's stiffest rate (a contraction: see behind_gripping_cuff)
        grid = np.linspace(float(deg.min()) - 5.0, float(deg.max()) + 5.0, 2001)
        stiffest = float(np.max(np.abs(np.gradient(_elastic(kind, grid, fixed, coef), grid))))
        c_give = min(c_give, 0.5 * hardening / max(stiffest, 1e-9))
        joint_deg = behind_gripping_cuff(deg, lambda d: _elastic(kind, d, fixed, coef), c_give, slip_nm, hardening)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, slip_Nm=slip_nm, hardening=hardening)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # fluid shifting with the posture through a lag
        share = lagged_share(np.sin(load.direction_rad), t, float(rng.uniform(10.0, 30.0)))
        unit = share * np.cos(load.direction_rad)
        error = size() * float(rng.choice([-1.0, 1.0])) * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = hydrodynamic_friction(np.degrees(vel), float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.2, 0.6)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        unit = linkage_dashpot(vel, along, float(rng.uniform(0.3, 0.8)))
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        unit = compensation_error(acc, t, float(rng.uniform(0.02, 0.08)), 1.0, float(rng.uniform(1.0, 3.0)))
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["inertia"] = float(np.dot(acc, error) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        creep = float(rng.uniform(1.0, 3.0))
        unit = creeping_stop(deg, t, at, high_end, creep)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", creep_deg=creep)
    if "activation_burst" in effects:
        mode = float(rng.uniform(0.12, 0.85)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * gumbel_pulse(t, mode, float(rng.uniform(0.1, 0.5)))
        truth["activation_burst"] = peak
        details.update(burst_mode_s=mode)
    if "sensor_drift" in effects:
        zero = chirped_zero(t, float(rng.uniform(60.0, 120.0)), float(rng.uniform(20.0, 40.0)),
                            float(rng.uniform(0.0, 2.0 * np.pi)))
        torque = torque + size() * zero / max(float(np.max(np.abs(zero))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = float(rng.uniform(0.02, 0.45))
        tracked = alpha_beta_tracker(torque, t, float(rng.uniform(0.1, 0.4)))
        torque = np.interp(t - latency, t, tracked, left=tracked[0])
        truth["time_delay"] = latency
    gain = 1.0 + float(rng.choice([-1.0, 1.0])) * float(rng.uniform(0.005, 0.015)) * t / max(float(t[-1]), 1e-12)
    hum = float(rng.uniform(0.2, 0.4)) * sd * np.sin(2.0 * np.pi * float(rng.uniform(0.05, 0.5)) * t
                                                      + float(rng.uniform(0.0, 2.0 * np.pi)))
    torque = torque * gain + rng.normal(0.0, sd, t.size) + hum + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "alpha_beta_tracker", "behind_gripping_cuff", "carbon_leaf",
           "chirped_zero", "compensation_error", "creeping_stop", "generate_ad", "gripping_cuff", "gumbel_pulse",
           "hydrodynamic_friction", "lagged_share", "linkage_dashpot", "mooney_rivlin_tension", "two_step_bends",
           "wandering_triangle"]
