"""A thirty-fourth generator family for the diagnosis, written (2026-12-08, forty-first stop) before that stop's second
frozen engine met the thirty-third family, nothing diagnosed on it; to be run once on the next change's frozen engine.

The second to thirty-third families (:mod:`benchmarks.family_b_truth` … ``family_ag_truth``) are development data once
run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: the tenth family's strokes were bang-bang with a
cruise, here a triangle in speed with none; the sixteenth's orthosis was a pneumatic strut, here a polytropic gas
spring with its preload; the twenty-seventh's bearing was worn along the range, here one running in over the trial.
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range Carroll's solid (W = a·I₁ + b·I₁⁴ + c·√I₂) in uniaxial tension, per
  unit a: 2(λ − λ⁻²)(1 + 4β·I₁³ + γ/(2λ√I₂)), I₁ = λ² + 2/λ, I₂ = 2λ + 1/λ² (β 10⁻⁴–10⁻³, γ 0.2–1), for the stretch
  λ = 1 + x̄/L (x̄ the softplus of the angle past an onset over 2–5°, L 0.5–1.5 × the end's reach); the steep end sized
  by its torque at the range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small
  linear term. The AFO: a polytropic gas spring, p₀·((1 − θ̄/θ_c)^(−γ) − 1) (γ 1.1–1.4, θ_c 40–80°, θ̄ the softplus of
  the bend past an engagement of 0.5–2°).
- Motion: 3–5 cycles between 85–100 % of the range's ends, each stroke a triangle in speed (accelerating uniformly to
  its middle, braking uniformly to its end; peak 6–12 °/s), held 0.5–2 s at each turn, a 0.5–1.5 s hold at the middle
  first. The AFO: 4–6 bends to 12–20°, each down and up along half-sines of 0.8–2 s, held 1.5–4 s at the bottom.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing running in, its level falling by 20–40 % over the trial along an exponential of 20–50 % of the
    trial, tanh(v/v₀) (v₀ 0.2–1 °/s); magnitude: its mean |F| over the moving samples;
  * damping: stiffness-proportional (Rayleigh's structural damping), β·K(θ)·θ̇ with K the passive curve's local
    stiffness (plus 10 % of its mean so the law does not vanish where the curve is flat); magnitude: the least-squares
    slope of its torque on θ̇;
  * stop: a spring-loaded end stop, a preload step of 30–60 % of its peak at contact (smoothed over 0.3°) and then
    linear, anywhere in the last 5–30 % of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a Thiran all-pass fractional delay (order 3–6, delay D in [N, N + 1] samples, flat group delay) behind a
    transport latency of 0–0.45 s; magnitude: the latency plus D samples;
  * activation: a Rayleigh pulse, ((t − t₀)/σ)·e^(−(t − t₀)²/2σ²) (σ 0.1–0.5 s), starting anywhere in 12–80 % of the
    trial, of either sign; magnitude: its peak;
  * limb-weight error: the segment's length mis-measured by 3–8 % (a tape measure), the weight's moment scaled by
    (1 + e); magnitude: its peak;
  * drift: an under-damped thermal controller settling, A·(1 − e^(−t/τ)·cos(2πt/P)) (τ 20–50 %, P 30–60 % of the
    trial), of either sign; named only;
  * series compliance: a cable with two slopes, c up to a knee torque of 20–50 % of the largest |τ|, c/(3–6) past it,
    c 0.03–0.15 °/N·m but at most 0.5 over the torque's stiffest rate; magnitude: the least-squares slope of the give
    on the torque;
  * inertia error: a mass mounted partway through (the inertia steps up at 30–70 % of the trial, smoothed over 1 s);
    magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise with a Brownian part (integrated white
  noise high-passed at 0.05 Hz, 10–20 % of the SD); the ADC's missing codes (every 32nd–64th code of the torque's
  quantum read as its neighbour); the torque channel clipping at 97–99.5 % of its largest |τ|; quantised torque and
  angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any
  column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from math import comb
from typing import Any

import numpy as np
from scipy.signal import butter, lfilter
from scipy.special import expit

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import (
    GRAVITY,
    behind_strap,
    coupled_onsets,
    damage_recording,
    draw_segments,
    draw_subject,
    kinematics,
    limb_load,
    protocol_set_up,
    softplus,
    trial_rng,
)

NOISE_SD_NM = {"afo": 0.07, "knee": 0.15, "ankle": 0.11}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def carroll_tension(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, quartic: float, root: float) -> np.ndarray:
    """An end per unit a: 2(λ − λ⁻²)(1 + 4β·I₁³ + γ/(2λ√I₂)), λ = 1 + x̄/L, x̄ the softplus of the angle ``x_deg``
    past the onset over ``smoothing_deg``, L = ``reach_deg``, β = ``quartic``, γ = ``root``."""
    lam = 1.0 + softplus(x_deg, smoothing_deg) / reach_deg
    i1 = lam * lam + 2.0 / lam
    i2 = 2.0 * lam + lam**-2
    return np.asarray(2.0 * (lam - lam**-2) * (1.0 + 4.0 * quartic * i1**3 + root / (2.0 * lam * np.sqrt(i2))), dtype=float)


def gas_spring(deg: np.ndarray, engage_deg: float, smoothing_deg: float, closing_deg: float, exponent: float) -> np.ndarray:
    """An orthosis per unit p₀: (1 − θ̄/θ_c)^(−γ) − 1, θ̄ the softplus (over ``smoothing_deg``) of the bend past
    ``engage_deg`` (zero at 0°), θ_c = ``closing_deg``, γ = ``exponent``."""
    d = np.asarray(deg, dtype=float)
    bend = softplus(d - engage_deg, smoothing_deg) - float(softplus(np.array(-engage_deg), smoothing_deg))
    share = np.clip(bend, 0.0, None) / closing_deg
    return np.asarray((1.0 - share) ** -exponent - 1.0, dtype=float)


def _triangle_speed(a: float, b: float, peak_deg_s: float, rate: float) -> np.ndarray:
    """From ``a`` to ``b`` (deg) accelerating uniformly to the middle and braking uniformly to the end, peak speed
    ``peak_deg_s``; samples after the start."""
    duration = 2.0 * abs(b - a) / peak_deg_s
    n = max(2, int(np.ceil(duration * rate)))
    u = np.arange(1, n + 1) / n
    share = np.where(u <= 0.5, 2.0 * u * u, 1.0 - 2.0 * (1.0 - u) ** 2)
    return np.asarray(a + (b - a) * share, dtype=float)


def triangle_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the middle, then 3–5 cycles between 85–100 % of the range's ends, each
    stroke a triangle in speed peaking at 6–12 °/s, held 0.5–2 s at each turn; back to the middle."""
    span, mid = hi - lo, 0.5 * (lo + hi)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    here = mid
    for _ in range(int(rng.integers(3, 6))):
        for side in (1.0, -1.0):
            target = mid + side * float(rng.uniform(0.85, 1.0)) * 0.5 * span
            parts.append(_triangle_speed(here, target, float(rng.uniform(6.0, 12.0)), rate))
            parts.append(np.full(int(rng.uniform(0.5, 2.0) * rate), target))
            here = target
    parts.append(_triangle_speed(here, mid, 8.0, rate))
    return np.concatenate(parts)


def _half_sine(a: float, b: float, duration_s: float, rate: float) -> np.ndarray:
    n = max(2, int(np.ceil(duration_s * rate)))
    u = np.arange(1, n + 1) / n
    return np.asarray(a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * u)), dtype=float)


def held_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 4–6 bends to 12–20°, down and up along half-sines of 0.8–2 s, held 1.5–4 s
    at the bottom of the bend, resting 0.3 s between."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(4, 7))):
        depth = float(rng.uniform(12.0, 20.0))
        parts += [_half_sine(0.0, depth, float(rng.uniform(0.8, 2.0)), rate), np.full(int(rng.uniform(1.5, 4.0) * rate), depth),
                  _half_sine(depth, 0.0, float(rng.uniform(0.8, 2.0)), rate), np.zeros(int(0.3 * rate))]
    return np.concatenate(parts)


def running_in_friction(t: np.ndarray, vel_deg_s: np.ndarray, fall: float, time_constant_s: float,
                        smoothing_deg_s: float) -> np.ndarray:
    """A friction per unit initial level falling by ``fall`` of it along e^(−t/τ): (1 − fall·(1 − e^(−t/τ)))·tanh(v/v₀)."""
    level = 1.0 - fall * (1.0 - np.exp(-np.asarray(t, dtype=float) / time_constant_s))
    return np.asarray(level * np.tanh(np.asarray(vel_deg_s, dtype=float) / smoothing_deg_s), dtype=float)


def stiffness_proportional_damping(stiffness: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """Rayleigh's structural damping per unit β: (K + 0.1·mean|K|)·θ̇, K the local stiffness."""
    k = np.abs(np.asarray(stiffness, dtype=float))
    return np.asarray((k + 0.1 * float(np.mean(k))) * np.asarray(vel, dtype=float), dtype=float)


def preloaded_stop(deg: np.ndarray, at_deg: float, high: bool, preload_share: float) -> np.ndarray:
    """A spring-loaded stop per unit stiffness (positive at the high end): a preload step of ``preload_share`` of the
    torque at 10° past contact, smoothed over 0.3° (a logistic), plus δ (deg past ``at_deg`` toward the end)."""
    sign = 1.0 if high else -1.0
    past = sign * (np.asarray(deg, dtype=float) - at_deg)
    step = preload_share / (1.0 - preload_share) * 10.0 * expit(past / 0.3 * 4.0)  # a logistic, without overflow
    return np.asarray(sign * (np.clip(past, 0.0, None) + step * (past > -3.0)), dtype=float)


def thiran_allpass(values: np.ndarray, order: int, delay_samples: float) -> np.ndarray:
    """``values`` through Thiran's all-pass fractional delay of ``order`` N and ``delay_samples`` D (N ≤ D ≤ N + 1:
    stable, maximally flat group delay D at low frequency), started at rest on the first value."""
    a = np.array([(-1.0) ** k * comb(order, k) * np.prod([(delay_samples - order + n) / (delay_samples - order + k + n)
                                                          for n in range(order + 1)]) for k in range(order + 1)])
    x = np.asarray(values, dtype=float)
    return np.asarray(lfilter(a[::-1], a, x - x[0]) + x[0], dtype=float)


def rayleigh_pulse(t: np.ndarray, start_s: float, width_s: float) -> np.ndarray:
    """A Rayleigh pulse of unit peak: u·e^((1 − u²)/2), u = (t − t₀)/σ ≥ 0 (peak 1 at u = 1)."""
    u = np.clip((np.asarray(t, dtype=float) - start_s) / width_s, 0.0, None)
    return np.asarray(u * np.exp(0.5 * (1.0 - u * u)), dtype=float)


def underdamped_settling(t: np.ndarray, time_constant_s: float, period_s: float) -> np.ndarray:
    """A zero settling toward 1 with an overshoot: 1 − e^(−t/τ)·cos(2πt/P)."""
    tt = np.asarray(t, dtype=float)
    return np.asarray(1.0 - np.exp(-tt / time_constant_s) * np.cos(2.0 * np.pi * tt / period_s), dtype=float)


def two_slope_cable(torque: np.ndarray, compliance: float, knee_nm: float, ratio: float) -> np.ndarray:
    """A cable's give (deg): c·τ up to ``knee_nm``, c/``ratio`` per N·m past it (odd in τ)."""
    tau = np.asarray(torque, dtype=float)
    size = np.abs(tau)
    give = np.where(size <= knee_nm, compliance * size, compliance * knee_nm + compliance / ratio * (size - knee_nm))
    return np.asarray(np.sign(tau) * give, dtype=float)


def mounted_mass(t: np.ndarray, at_s: float) -> np.ndarray:
    """The share of an added inertia present at each time: a logistic step at ``at_s`` over about 1 s."""
    return np.asarray(expit((np.asarray(t, dtype=float) - at_s) / 0.25), dtype=float)


def brownian_part(rng: np.random.Generator, n: int, rate: float, sd: float) -> np.ndarray:
    """Integrated white noise high-passed at 0.05 Hz (a second-order Butterworth), scaled to RMS ``sd``."""
    walk = np.cumsum(rng.standard_normal(n))
    b, a = butter(2, 0.05, btype="highpass", fs=rate)
    part = lfilter(b, a, walk - walk[0])
    rms = float(np.sqrt(np.mean(part**2)))
    return np.asarray(part / max(rms, 1e-12) * sd, dtype=float)


def missing_codes(torque: np.ndarray, quantum: float, every: int) -> np.ndarray:
    """``torque`` read by an ADC whose every ``every``-th code (of ``quantum`` N·m) is missing: read as the code below."""
    codes = np.round(np.asarray(torque, dtype=float) / quantum)
    codes = np.where(np.mod(codes, every) == 0, codes - 1.0, codes)
    return np.asarray(codes * quantum, dtype=float)


def clipped(torque: np.ndarray, share: float) -> np.ndarray:
    """``torque`` clipped at ``share`` of its largest |τ| (the channel saturating)."""
    top = share * float(np.max(np.abs(torque)))
    return np.asarray(np.clip(torque, -top, top), dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return np.asarray(c["k"] * gas_spring(deg, c["engage"], 0.5, c["closing"], c["gamma"]), dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * carroll_tension(on_low - deg, c["smooth"], c["reach_low"], c["q_low"], c["r_low"])
            + c["a_high"] * carroll_tension(deg - on_high, c["smooth"], c["reach_high"], c["q_high"], c["r_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, closing, gamma = float(rng.uniform(0.5, 2.0)), float(rng.uniform(40.0, 80.0)), float(rng.uniform(1.1, 1.4))
        unit = float(gas_spring(np.array(15.0), engage, 0.5, closing, gamma))
        return {"engage": engage, "closing": closing, "gamma": gamma, "k": float(rng.uniform(10.0, 25.0)) / unit}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(2.0, 5.0))
    c = {"reach_low": (on_low - lo) * float(rng.uniform(0.5, 1.5)), "reach_high": (hi - on_high) * float(rng.uniform(0.5, 1.5)),
         "q_low": float(10 ** rng.uniform(-4.0, -3.0)), "q_high": float(10 ** rng.uniform(-4.0, -3.0)),
         "r_low": float(rng.uniform(0.2, 1.0)), "r_high": float(rng.uniform(0.2, 1.0))}
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    c["a_low"] = t_low / float(carroll_tension(np.array(on_low - lo), smooth, c["reach_low"], c["q_low"], c["r_low"]))
    c["a_high"] = t_high / float(carroll_tension(np.array(hi - on_high), smooth, c["reach_high"], c["q_high"], c["r_high"]))
    return {**c, "smooth": smooth, "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ah(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((34, 34, 34), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: triangle_strokes(r, a, b, rate),
                                         lambda r: held_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    def unit_peak(x: np.ndarray) -> np.ndarray:
        return np.asarray(x / max(float(np.max(np.abs(x))), 1e-12), dtype=float)

    joint_deg = deg
    if "series_compliance" in effects:  # a cable with two slopes
        commanded = _elastic(kind, deg, fixed, coef)
        grid = np.linspace(float(deg.min()) - 5.0, float(deg.max()) + 5.0, 2001)
        stiffest = float(np.max(np.abs(np.gradient(_elastic(kind, grid, fixed, coef), grid))))
        c_give = min(float(rng.uniform(0.03, 0.15)), 0.5 / max(stiffest, 1e-9))
        knee_nm = float(rng.uniform(0.2, 0.5)) * max(float(np.max(np.abs(commanded))), 1e-6)
        ratio = float(rng.uniform(3.0, 6.0))
        joint_deg = behind_strap(deg, lambda j: two_slope_cable(_elastic(kind, j, fixed, coef), c_give, knee_nm, ratio))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, cable_knee_Nm=knee_nm, cable_ratio=ratio)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the segment's length mis-measured
        error = size() * float(rng.choice([-1.0, 1.0])) * unit_peak(load.moment_nm)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = running_in_friction(t, np.degrees(vel), float(rng.uniform(0.2, 0.4)), float(rng.uniform(0.2, 0.5)) * float(t[-1]),
                                   float(rng.uniform(0.2, 1.0)))
        friction = size() * unit_peak(unit)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        grid = np.linspace(float(deg.min()) - 1.0, float(deg.max()) + 1.0, 2001)
        local = np.interp(joint_deg, grid, np.gradient(_elastic(kind, grid, fixed, coef), grid))
        damping = size() * unit_peak(stiffness_proportional_damping(local, vel))
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        share = mounted_mass(t, float(rng.uniform(0.3, 0.7)) * float(t[-1]))
        error = size() * unit_peak(share * acc)
        torque = torque + error
        truth["inertia"] = float(np.dot(acc, error) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = preloaded_stop(deg, at, high_end, float(rng.uniform(0.3, 0.6)))
        torque = torque + size() * unit_peak(unit)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", range_deg=(bottom, top))
    if "activation_burst" in effects:
        start = float(rng.uniform(0.12, 0.8)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * rayleigh_pulse(t, start, float(rng.uniform(0.1, 0.5)))
        truth["activation_burst"] = peak
        details.update(burst_start_s=start)
    if "sensor_drift" in effects:
        zero = underdamped_settling(t, float(rng.uniform(0.2, 0.5)) * float(t[-1]), float(rng.uniform(0.3, 0.6)) * float(t[-1]))
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * unit_peak(zero)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = float(rng.uniform(0.0, 0.45))
        order = int(rng.integers(3, 7))
        samples = order + float(rng.uniform(0.0, 1.0))
        filtered = thiran_allpass(torque, order, samples)
        torque = np.interp(t - latency, t, filtered, left=filtered[0])
        truth["time_delay"] = latency + samples / rate
    torque = clipped(torque, float(rng.uniform(0.97, 0.995)))
    torque = torque + rng.standard_normal(t.size) * sd * np.sqrt(1.0 - 0.15**2) + brownian_part(rng, t.size, rate, 0.15 * sd)
    quantum = float(rng.uniform(0.002, 0.012))
    torque = missing_codes(torque, quantum, int(rng.integers(32, 65))) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "brownian_part", "carroll_tension",
           "clipped", "gas_spring", "generate_ah", "held_bends", "missing_codes", "mounted_mass", "preloaded_stop",
           "rayleigh_pulse", "running_in_friction", "stiffness_proportional_damping", "thiran_allpass", "triangle_strokes",
           "two_slope_cable", "underdamped_settling"]
