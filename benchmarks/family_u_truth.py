"""A twenty-first generator family for the diagnosis, written after the twentieth's run and before the next engine
change, run once on that change's frozen engine (f319385; benchmarks/results/diagnosis_family_u.json).

The second to twentieth families (:mod:`benchmarks.family_b_truth` … ``family_t_truth``) became development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at 9555647, which added a drift wandering slower than the movement; where an earlier
family used a near relation it is said) and keeps every nuisance below what the diagnosis should name. Nothing is
imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a smoothed hinge raised to the power 1.5,
  A·(w·ln(1 + e^{x/w}))^{1.5} for x the angle past an onset (rounding width w 2–6°), the steep end sized by its
  torque at the range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small linear
  term. The AFO: a torsion spring through a cam, k·(θ' + a·sin(π·θ'/25°)) past an engagement of 0.5–3° (a 1–3°).
- Motion: strokes with a trapezoidal speed profile (3–7 °/s, acceleration 2–10 °/s²), each end held 0.5–2 s, 3–5
  cycles. The AFO: bends of 10–20° whose tempo drifts (each bend 1.5–4 s, the tempo changing steadily over the
  trial by up to ±40 %), no rest between them.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a worn gear's friction, its level modulated along the angle with a period of 4–10° and a depth of
    20–50 %, the sign through v/√(v² + ε²), ε 0.2–1 °/s (the eleventh family's rose with angle monotonically, the
    twentieth's had one rough spot); magnitude: its mean over the moving samples;
  * damping: a hydraulic damper with a check valve, its coefficient in the direction of increasing angle 0.3–0.7 ×
    that of decreasing angle, or the reverse; magnitude: the least-squares slope of its torque on θ̇;
  * stop: a preloaded bumper, a step of 30–60 % of its peak at contact (rounded over 0.1–0.3°) then linear,
    anywhere in the last 5–25 % of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a latency that wanders (a link's buffer): the mean 0.05–0.45 s plus a smooth random wander of ±20–40 ms
    (Gaussian noise smoothed over 1–3 s; the twentieth family's stepped once, the eleventh's clocks drifted
    linearly); magnitude: the latency averaged over the trial's time;
  * activation: a voluntary contraction, a trapezoid rising over 0.2–0.6 s, held 0.3–1 s and released over
    0.3–0.8 s, of either sign; magnitude: its peak;
  * limb-weight error: a brace whose centre of mass sits 10–40° off the segment's line (the eighteenth family's
    off-axis centre of mass is a near relation): error ∝ cos(ψ + φ); magnitude: its peak;
  * drift: a strain gauge's creep released in slips: 2–5 steps a minute at random times (a Poisson process), each
    of a normal size and smoothed over 0.5–2 s (the nineteenth family knocked its cable once); named only;
  * series compliance: a cuff that slides more one way, its give c·τ in the direction of increasing angle 0.4–0.8 ×
    that of decreasing angle, or the reverse (the sign through a tanh of 1 °/s); magnitude: the least-squares slope
    of the give on the torque;
  * inertia error: a weight that slides along the segment with the angle, I(θ) = I₀·(1 + g·(θ − θ_mid)/span), g
    ±0.3–0.6, its torque I(θ)·θ̈ + ½·I'(θ)·θ̇²; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; white noise plus a flicker (an AR(1), ρ 0.9–0.99, at
  0.2–0.4 × the noise SD); mains hum (50 or 60 Hz) at 0.2–0.4 × the noise SD; a constant torque gain error of
  ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly
  (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.signal import lfilter

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

NOISE_SD_NM = {"afo": 0.07, "knee": 0.17, "ankle": 0.13}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)
#: the AFO cam's period (deg of bend)
CAM_SPAN_DEG = 25.0


def smooth_hinge_power(x_deg: np.ndarray, width_deg: float, exponent: float = 1.5) -> np.ndarray:
    """(w·ln(1 + e^{x/w}))^``exponent`` for the angle ``x_deg`` past the onset, w = ``width_deg``."""
    x = np.asarray(x_deg, dtype=float) / width_deg
    return (width_deg * np.logaddexp(0.0, x)) ** exponent


def cam_spring(deg: np.ndarray, engage_deg: float, cam_deg: float) -> np.ndarray:
    """A torsion spring through a cam per unit stiffness: θ' + a·sin(π·θ'/CAM_SPAN_DEG) for θ' the bend past
    ``engage_deg`` (0 before it), a = ``cam_deg``."""
    bend = np.clip(np.asarray(deg, dtype=float) - engage_deg, 0.0, None)
    return bend + cam_deg * np.sin(np.pi * bend / CAM_SPAN_DEG)


def trapezoid_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 3–5 cycles of strokes from ``lo`` to ``hi`` and back with a trapezoidal speed profile
    (cruise 3–7 °/s, acceleration 2–10 °/s²), each end held 0.5–2 s."""
    cruise, accel = float(rng.uniform(3.0, 7.0)), float(rng.uniform(2.0, 10.0))
    parts = [np.full(int(rng.uniform(0.5, 2.0) * rate), lo)]
    for i in range(2 * int(rng.integers(3, 6))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        distance = abs(end - start)
        ramp_s = cruise / accel
        if accel * ramp_s**2 > distance:  # never reaches the cruise speed: a triangle
            ramp_s = float(np.sqrt(distance / accel))
        peak = accel * ramp_s
        cruise_s = max((distance - accel * ramp_s**2) / peak, 0.0)
        total = 2 * ramp_s + cruise_s
        tt = np.arange(1, int(np.ceil(total * rate)) + 1) / rate
        tt = np.minimum(tt, total)
        up = np.minimum(tt, ramp_s)
        mid = np.clip(tt - ramp_s, 0.0, cruise_s)
        down = np.clip(tt - ramp_s - cruise_s, 0.0, ramp_s)
        covered = 0.5 * accel * up**2 + peak * mid + peak * down - 0.5 * accel * down**2
        parts.append(start + np.sign(end - start) * np.minimum(covered, distance))
        parts.append(np.full(int(rng.uniform(0.5, 2.0) * rate), end))
    return np.concatenate(parts)


def drifting_tempo_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 8–14 bends from 0° to 10–20° and back, each a raised-cosine cycle whose period starts at
    1.5–4 s and changes steadily to up to ±40 % by the last, no rest between them."""
    count = int(rng.integers(8, 15))
    first = float(rng.uniform(1.5, 4.0))
    last = first * (1.0 + float(rng.uniform(-0.4, 0.4)))
    parts = [np.zeros(int(0.4 * rate))]
    for period in np.linspace(first, last, count):
        u = np.arange(int(period * rate)) / (period * rate)
        parts.append(float(rng.uniform(10.0, 20.0)) * 0.5 * (1.0 - np.cos(2 * np.pi * u)))
    parts.append(np.zeros(int(0.4 * rate)))
    return np.concatenate(parts)


def worn_gear_friction(deg: np.ndarray, vel_deg_s: np.ndarray, period_deg: float, depth: float, phase: float,
                       epsilon_deg_s: float) -> np.ndarray:
    """A friction per unit level (resisting the motion): (1 + depth·sin(2π·θ/period + phase))·v/√(v² + ε²)."""
    level = 1.0 + depth * np.sin(2 * np.pi * deg / period_deg + phase)
    return level * vel_deg_s / np.sqrt(vel_deg_s**2 + epsilon_deg_s**2)


def check_valve_damping(vel: np.ndarray, ratio: float, weak_when_rising: bool) -> np.ndarray:
    """A damping per unit coefficient: θ̇ in one direction, ``ratio``·θ̇ in the other (the weaker one the direction of
    increasing angle when ``weak_when_rising``)."""
    weak = vel > 0 if weak_when_rising else vel < 0
    return np.where(weak, ratio * vel, vel)


def preloaded_bumper(deg: np.ndarray, at_deg: float, high: bool, preload: float, round_deg: float) -> np.ndarray:
    """A stop per unit stiffness toward the range's inside (positive at the high end): a step of ``preload`` at
    contact rounded over ``round_deg`` (a smoothstep), plus the depth δ past ``at_deg``."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    u = np.clip(depth / round_deg, 0.0, 1.0)
    return sign * (preload * u * u * (3.0 - 2.0 * u) + depth)


def wandering_latency(rng: np.random.Generator, t: np.ndarray, mean_s: float, wander_s: float, smooth_s: float
                      ) -> np.ndarray:
    """A latency (s) at each time: ``mean_s`` plus Gaussian noise smoothed over ``smooth_s`` (a Gaussian kernel of
    that SD), scaled so its largest departure is ``wander_s`` and its mean is ``mean_s``."""
    step = float(np.median(np.diff(t)))
    wander = gaussian_filter1d(rng.normal(0.0, 1.0, t.size), smooth_s / step, mode="reflect")
    wander = wander - wander.mean()
    return mean_s + wander_s * wander / max(float(np.max(np.abs(wander))), 1e-12)


def read_late(torque: np.ndarray, t: np.ndarray, latency_s: np.ndarray) -> np.ndarray:
    """``torque`` read ``latency_s`` late at each sample (interpolated, held at the first sample before the trial)."""
    return np.interp(t - latency_s, t, torque)


def voluntary_contraction(t: np.ndarray, start_s: float, rise_s: float, hold_s: float, fall_s: float) -> np.ndarray:
    """A trapezoid of peak 1: rising linearly over ``rise_s`` from ``start_s``, held ``hold_s``, released over
    ``fall_s``."""
    u = t - start_s
    up = np.clip(u / rise_s, 0.0, 1.0)
    down = np.clip((u - rise_s - hold_s) / fall_s, 0.0, 1.0)
    return np.where(u >= 0.0, up - down, 0.0)


def creep_slips(rng: np.random.Generator, t: np.ndarray, per_minute: float, smooth_s: float) -> np.ndarray:
    """A zero that slips: steps of normal size at Poisson times (``per_minute`` a minute), each smoothed over
    ``smooth_s`` (a logistic 10–90 % over it); minus its mean, largest excursion 1 (zero if no slip falls in the
    trial)."""
    span = float(t[-1] - t[0])
    count = int(rng.poisson(per_minute * span / 60.0))
    times = t[0] + rng.uniform(0.0, span, count)
    y = np.zeros(t.size)
    for at, size in zip(times, rng.normal(0.0, 1.0, count), strict=True):
        y += size * 0.5 * (1.0 + np.tanh(0.5 * (t - at) * 4.394 / smooth_s))  # the logistic, without overflow
    y = y - y.mean()
    return y / max(float(np.max(np.abs(y))), 1e-12)


def sliding_weight(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, inertia: float, grade_per_rad: float,
                   middle_rad: float) -> np.ndarray:
    """The torque (N·m) of an inertia I(θ) = I₀·(1 + g·(θ − θ_mid)) (g per radian): I(θ)·θ̈ + ½·I'(θ)·θ̇²."""
    return inertia * (1.0 + grade_per_rad * (rad - middle_rad)) * acc + 0.5 * inertia * grade_per_rad * vel**2


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * cam_spring(deg, c["engage"], c["cam"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * smooth_hinge_power(on_low - deg, c["w_low"])
            + c["a_high"] * smooth_hinge_power(deg - on_high, c["w_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, cam = float(rng.uniform(0.5, 3.0)), float(rng.uniform(1.0, 3.0))
        k = float(rng.uniform(10.0, 25.0)) / float(cam_spring(np.array(15.0), engage, cam))
        return {"engage": engage, "cam": cam, "k": k}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    w_low, w_high = float(rng.uniform(2.0, 6.0)), float(rng.uniform(2.0, 6.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(smooth_hinge_power(np.array(on_low - lo), w_low)),
            "a_high": t_high / float(smooth_hinge_power(np.array(hi - on_high), w_high)),
            "w_low": w_low, "w_high": w_high, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_u(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((21, 21, 21), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: trapezoid_strokes(r, a, b, rate),
                                         lambda r: drifting_tempo_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    low, high = float(deg.min()), float(deg.max())
    middle, span = 0.5 * (low + high), max(high - low, 1e-9)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a cuff that slides more one way
        c_give, ratio = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.4, 0.8))
        weak_sign = float(rng.choice([-1.0, 1.0]))  # +1: the cuff gives less while the angle rises
        share = 1.0 - (1.0 - ratio) * 0.5 * (1.0 + weak_sign * np.tanh(vel_deg / 1.0))
        for _ in range(4):
            tau = _elastic(kind, joint_deg, fixed, coef)
            joint_deg = deg - c_give * share * tau
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, compliance_ratio=ratio)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # a brace whose centre of mass sits off the segment's line
        off = np.radians(float(rng.uniform(10.0, 40.0)) * float(rng.choice([-1.0, 1.0])))
        unit = np.cos(load.direction_rad + off)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12) * float(rng.choice([-1.0, 1.0]))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(brace_off_line_deg=float(np.degrees(off)))
    if "coulomb_friction" in effects:
        unit = worn_gear_friction(deg, vel_deg, float(rng.uniform(4.0, 10.0)), float(rng.uniform(0.2, 0.5)),
                                  float(rng.uniform(0.0, 2 * np.pi)), float(rng.uniform(0.2, 1.0)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        ratio, weak_rising = float(rng.uniform(0.3, 0.7)), bool(rng.random() < 0.5)
        unit = check_valve_damping(vel, ratio, weak_rising)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
        details.update(damping_ratio=ratio, weak_when_rising=weak_rising)
    if "inertia" in effects:
        grade = float(rng.uniform(0.3, 0.6)) * float(rng.choice([-1.0, 1.0])) / max(float(np.radians(span)), 1e-9)
        unit = sliding_weight(rad, vel, acc, 1.0, grade, float(np.radians(middle)))
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(inertia_grade_per_rad=grade)
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.25))
        top, bottom = (high, 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        share = float(rng.uniform(0.3, 0.6))  # the preload's share of the stop's peak
        reach = float(np.max(np.clip((1.0 if high_end else -1.0) * (deg - at), 0.0, None)))
        unit = preloaded_bumper(deg, at, high_end, share / (1 - share) * reach, float(rng.uniform(0.1, 0.3)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = voluntary_contraction(t, start, float(rng.uniform(0.2, 0.6)), float(rng.uniform(0.3, 1.0)),
                                      float(rng.uniform(0.3, 0.8)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(contraction_start_s=start)
    if "sensor_drift" in effects:
        torque = torque + size() * creep_slips(rng, t, float(rng.uniform(2.0, 5.0)), float(rng.uniform(0.5, 2.0)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = wandering_latency(rng, t, float(rng.uniform(0.05, 0.45)), float(rng.uniform(0.02, 0.04)),
                                    float(rng.uniform(1.0, 3.0)))
        torque = read_late(torque, t, latency)
        truth["time_delay"] = float(np.mean(latency))
    noise = rng.normal(0.0, sd, t.size)
    flicker = lfilter([1.0], [1.0, -float(rng.uniform(0.9, 0.99))], rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.2, 0.4)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    hum_hz = float(rng.choice([50.0, 60.0]))
    noise += float(rng.uniform(0.2, 0.4)) * sd * np.sin(2 * np.pi * hum_hz * t + float(rng.uniform(0, 2 * np.pi)))
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "cam_spring", "check_valve_damping",
           "creep_slips", "drifting_tempo_bends", "generate_u", "preloaded_bumper", "read_late", "sliding_weight",
           "smooth_hinge_power", "trapezoid_strokes", "voluntary_contraction", "wandering_latency",
           "worn_gear_friction"]
