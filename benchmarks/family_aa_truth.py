"""A twenty-seventh generator family for the diagnosis, written (2026-12-07, thirty-fifth stop) while that stop's change
was measured on development data and before the twenty-sixth family's run, nothing diagnosed on it; to be run once on
the next change's frozen engine.

The second to twenty-sixth families (:mod:`benchmarks.family_b_truth` … ``family_z_truth``) are development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at the thirty-fifth stop's change) and keeps every nuisance below what the diagnosis
should name. Revised at the thirty-sixth stop, still with nothing diagnosed on it, after a grep of every spent family's
laws: the power-law ends (the twelfth, twentieth and twenty-first families' form) became Yeoh's hyperelastic law; the
centre of mass sliding with the angle (the thirteenth's) became blood pooling over time; the knocked connector (the
seventh's and twenty-fifth's) a battery running down; the tremor on the orthosis's bends (the nineteenth's) was
dropped; the Laplace noise with hum and spikes (the tenth's and twenty-second's) became noise growing with the drive's
speed. Near relations kept: the clonus (the eighth family's beats under a rising envelope), the off-axis weight (the
twelfth's pad sliding along the segment, an inertia there). Nothing is imported from ``analysis``, nor any physics
from the other generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range Yeoh's (1993) hyperelastic law in uniaxial tension,
  C₁·2(λ² − 1/λ)(1 + 2c₂(I₁ − 3) + 3c₃(I₁ − 3)²), I₁ = λ² + 2/λ, the stretch λ = 1 + x̄/L (x̄ the softplus of the angle
  past an onset over 1–3°, L 0.5–1 × the end's reach, c₂ 0–0.5, c₃ 0.05–0.5); the steep end sized by its torque at the
  range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a
  spring joined by an elastic strap past 4–10° of bend, θ + r·w·ln(1 + e^{(θ − θ_j)/w}) (r 0.3–0.8, w 1–2°).
- Motion: constant-speed ramps of 3–7 °/s with a 2–4 % speed ripple at 1–3 Hz (a servo's cogging), pauses of 0.2–2 s
  at every turn, turns smoothed over 0.15 s; 3–4 cycles. The AFO: 5–9 half-cosine bends to 10–20° of 1–2.5 s each
  way.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a worn bearing, its level varying with the angle, (1 + d·sin(2πθ/P))·v/√(v² + ε²) (d 0.2–0.5, P 10–30°,
    ε 0.2–0.8 °/s); magnitude: its mean |F| over the moving samples;
  * damping: an eddy-current brake, b·v/(1 + (v/v_c)²) with v_c 1.5–3 × the trial's peak speed (linear at low speed,
    flattening toward v_c); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a two-stage bumper, a soft pad over its first 0.5–2° and a contact 4–10 × stiffer past it (joined over
    0.3°), anywhere in the last 5–30 % of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: the torque sampled and held at 20–50 Hz and delivered 0.03–0.4 s late with ±5–20 ms of jitter (a bus's
    latency); magnitude: the mean latency plus half the hold period;
  * activation: clonus, beats of 5–8 Hz riding on a tonic part, (0.6 + 0.4·sin 2πf(t − t₀)) under a sin² envelope of
    0.6–2 s (the library's Hann burst is that envelope without the beats), anywhere in 10–85 % of the trial, of either
    sign; magnitude: its peak;
  * limb-weight error: blood pooling in the hanging shank (knee) or foot (ankle), its weight growing over the trial as
    1 − e^{−t/τ} (τ 30–120 s), its moment that times the segment's weight moment's shape; magnitude: its peak;
  * drift: a bridge amplifier's battery running down, 1/(1 − κ·t/T) − 1 (κ 0.6–0.9, T the trial's length): flat for
    most of the trial, rising ever faster toward its end, of either sign; named only;
  * series compliance: a strap that locks, its give c·τ_s·tanh(τ/τ_s) (τ_s 0.5–1 × the largest torque; the twenty-
    fifth family's strap softened, this one stiffens); magnitude: the least-squares slope of the give on the torque;
  * inertia error: a weight strapped off the segment's axis, its inertia J(θ) = J₀(1 + κ·u), u from −1 to 1 over the
    range (κ ±0.2–0.4), torque J(θ)·θ̈ + ½·J′(θ)·θ̇²; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise growing with the drive's speed (its SD
  1.3–1.8 × the resting one at the peak speed: the drive's switching interference); a constant torque gain error of
  ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter;
  rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

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
    trial_rng,
)

NOISE_SD_NM = {"afo": 0.07, "knee": 0.17, "ankle": 0.13}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def yeoh_end(x_deg: np.ndarray, onset_smoothing_deg: float, reach_deg: float, c2: float, c3: float) -> np.ndarray:
    """An end per unit C₁ following Yeoh's (1993) hyperelastic law in uniaxial tension,
    2(λ² − 1/λ)·(1 + 2c₂(I₁ − 3) + 3c₃(I₁ − 3)²) − its value at λ = 1 (zero), I₁ = λ² + 2/λ, the stretch
    λ = 1 + x̄/L with x̄ = s·ln(1 + e^{x/s}) the softplus of the angle ``x_deg`` past the onset over s =
    ``onset_smoothing_deg`` and L = ``reach_deg``; c₂ = ``c2``, c₃ = ``c3`` (≥ 0: it stiffens as a polynomial in the
    stretch invariant, neither a power of the angle nor an exponential)."""
    x = np.asarray(x_deg, dtype=float) / onset_smoothing_deg
    stretch = 1.0 + onset_smoothing_deg * np.logaddexp(0.0, x) / reach_deg
    i1 = stretch**2 + 2.0 / stretch
    return np.asarray(2.0 * (stretch**2 - 1.0 / stretch) * (1.0 + 2.0 * c2 * (i1 - 3.0) + 3.0 * c3 * (i1 - 3.0) ** 2),
                      dtype=float)


def strap_joined_spring(deg: np.ndarray, join_deg: float, ratio: float, width_deg: float) -> np.ndarray:
    """An orthosis's spring per unit stiffness joined by a strap past ``join_deg``: θ + r·w·ln(1 + e^{(θ − θ_j)/w})
    (r = ``ratio``, w = ``width_deg``) for θ ≥ 0 (deg), 0 below."""
    th = np.clip(np.asarray(deg, dtype=float), 0.0, None)
    joined = ratio * width_deg * (np.logaddexp(0.0, (th - join_deg) / width_deg)
                                  - np.logaddexp(0.0, -join_deg / width_deg))
    return th + joined


def _smoothed(deg: np.ndarray, rate: float, window_s: float) -> np.ndarray:
    """``deg`` through a Hann window of ``window_s`` (the ends held)."""
    n = max(3, int(round(window_s * rate)) | 1)
    window = np.hanning(n + 2)[1:-1]
    padded = np.concatenate([np.full(n, deg[0]), deg, np.full(n, deg[-1])])
    return np.convolve(padded, window / window.sum(), mode="same")[n:-n]


def paused_ramps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): 3–4 cycles of constant-speed ramps (3–7 °/s, a 2–4 % ripple at 1–3 Hz) between ``lo`` and
    ``hi``, a pause of 0.2–2 s at every turn, the turns smoothed over 0.15 s."""
    speed = float(rng.uniform(3.0, 7.0))
    ripple, cog_hz = float(rng.uniform(0.02, 0.04)), float(rng.uniform(1.0, 3.0))
    parts = [np.full(int(rng.uniform(0.2, 2.0) * rate), lo)]
    for _ in range(int(rng.integers(3, 5))):
        for a, b in ((lo, hi), (hi, lo)):
            n = int(np.ceil(abs(b - a) / speed * rate))
            tt = np.arange(1, n + 1) / rate
            travel = speed * (tt + ripple * (1.0 - np.cos(2.0 * np.pi * cog_hz * tt)) / (2.0 * np.pi * cog_hz))
            parts.append(a + np.sign(b - a) * np.clip(travel, 0.0, abs(b - a)))
            parts.append(np.full(int(rng.uniform(0.2, 2.0) * rate), b))
    return _smoothed(np.concatenate(parts), rate, 0.15)


def hand_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–9 half-cosine bends to 10–20° of 1–2.5 s each way, back to 0–2° (0° after the last)."""
    parts = [np.zeros(int(0.5 * rate))]
    base = 0.0
    count = int(rng.integers(5, 10))
    for k in range(count):
        peak = float(rng.uniform(10.0, 20.0))
        back = 0.0 if k == count - 1 else float(rng.uniform(0.0, 2.0))
        for a, b in ((base, peak), (peak, back)):
            n = int(rng.uniform(1.0, 2.5) * rate)
            parts.append(a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * np.arange(1, n + 1) / n)))
        base = back
    parts.append(np.zeros(int(0.5 * rate)))
    return np.concatenate(parts)


def worn_bearing_friction(deg: np.ndarray, vel_deg_s: np.ndarray, depth: float, period_deg: float,
                          epsilon_deg_s: float) -> np.ndarray:
    """A friction per unit mean level varying with the angle: (1 + d·sin(2πθ/P))·v/√(v² + ε²)."""
    v = np.asarray(vel_deg_s, dtype=float)
    level = 1.0 + depth * np.sin(2.0 * np.pi * np.asarray(deg, dtype=float) / period_deg)
    return level * v / np.sqrt(v * v + epsilon_deg_s**2)


def eddy_current_brake(vel: np.ndarray, critical: float) -> np.ndarray:
    """An eddy-current brake's torque per unit low-speed coefficient: v/(1 + (v/v_c)²) (v_c = ``critical``, in the
    velocity's units), linear at low speed, peaking at v_c."""
    v = np.asarray(vel, dtype=float)
    return v / (1.0 + (v / critical) ** 2)


def two_stage_stop(deg: np.ndarray, at_deg: float, high: bool, pad_deg: float, ratio: float) -> np.ndarray:
    """A bumper per unit pad stiffness toward the range's inside (positive at the high end): δ through the pad, and
    (1 + r)·δ − r·δ_p past it (r = ``ratio``, δ_p = ``pad_deg``), joined over 0.3°; δ the depth past ``at_deg``."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    join = 0.3
    contact = ratio * join * (np.logaddexp(0.0, (depth - pad_deg) / join) - np.logaddexp(0.0, -pad_deg / join))
    return sign * np.where(depth > 0.0, depth + contact, 0.0)


def held_late(torque: np.ndarray, t: np.ndarray, latency_s: float, jitter_s: float, hold_hz: float,
              rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """(the torque sampled at ``hold_hz``, each sample delivered ``latency_s`` ± ``jitter_s`` late (never before the one
    ahead of it) and held until the next arrives; the delay in s: the mean latency plus half the hold period)."""
    ticks = np.arange(float(t[0]), float(t[-1]), 1.0 / hold_hz)
    values = np.interp(ticks, t, torque)
    arrive = np.maximum.accumulate(ticks + latency_s + rng.uniform(-jitter_s, jitter_s, ticks.size))
    idx = np.searchsorted(arrive, t, side="right") - 1
    out = np.where(idx >= 0, values[np.clip(idx, 0, None)], values[0])
    return out, latency_s + 0.5 / hold_hz


def clonus(t: np.ndarray, start_s: float, envelope_s: float, beat_hz: float) -> np.ndarray:
    """Clonus per unit peak: (0.6 + 0.4·sin 2πf(t − t₀)) under sin²(π(t − t₀)/T) for t₀ ≤ t ≤ t₀ + T."""
    u = (np.asarray(t, dtype=float) - start_s) / envelope_s
    inside = (u >= 0.0) & (u <= 1.0)
    shape = np.where(inside, np.sin(np.pi * np.clip(u, 0.0, 1.0)) ** 2
                     * (0.6 + 0.4 * np.sin(2.0 * np.pi * beat_hz * (t - start_s))), 0.0)
    return shape / max(float(np.max(shape)), 1e-12)


def battery_sag(t: np.ndarray, end_s: float, knee: float) -> np.ndarray:
    """A bridge amplifier's offset per unit, its battery running down: 1/(1 − κ·t/T) − 1 normalised to 1 at T =
    ``end_s`` (κ = ``knee`` < 1): flat for most of the trial, rising ever faster toward its end."""
    u = np.clip(np.asarray(t, dtype=float) / end_s, 0.0, 1.0)
    return (1.0 / (1.0 - knee * u) - 1.0) / (1.0 / (1.0 - knee) - 1.0)


def venous_pooling(t: np.ndarray, time_constant_s: float) -> np.ndarray:
    """The segment's extra mass per unit of its final gain as blood pools in it while it hangs: 1 − e^{−t/τ}
    (τ = ``time_constant_s``); the weight's moment error is this times the segment's weight moment shape."""
    return 1.0 - np.exp(-np.asarray(t, dtype=float) / time_constant_s)


def locking_strap_give(torque: np.ndarray, compliance: float, lock_nm: float) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ_s·tanh(τ/τ_s), τ_s = ``lock_nm``."""
    return compliance * lock_nm * np.tanh(np.asarray(torque, dtype=float) / lock_nm)


def off_axis_weight(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, lo_rad: float, hi_rad: float, slope: float
                    ) -> np.ndarray:
    """The torque per unit mid-range inertia of a weight whose inertia varies along the range: J(θ)·θ̈ + ½·J′(θ)·θ̇²,
    J = 1 + κ·u, u = (2θ − lo − hi)/(hi − lo), κ = ``slope``."""
    u = (2.0 * np.asarray(rad, dtype=float) - lo_rad - hi_rad) / (hi_rad - lo_rad)
    return (1.0 + slope * u) * acc + 0.5 * (2.0 * slope / (hi_rad - lo_rad)) * vel * vel


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * strap_joined_spring(deg, c["join"], c["ratio"], c["width"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * yeoh_end(on_low - deg, c["smooth"], c["reach_low"], c["c2"], c["c3"])
            + c["a_high"] * yeoh_end(deg - on_high, c["smooth"], c["reach_high"], c["c2"], c["c3"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        join, ratio, width = float(rng.uniform(4.0, 10.0)), float(rng.uniform(0.3, 0.8)), float(rng.uniform(1.0, 2.0))
        return {"join": join, "ratio": ratio, "width": width,
                "k": float(rng.uniform(10.0, 25.0)) / float(strap_joined_spring(np.array(15.0), join, ratio, width))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(1.0, 3.0))
    # the contour L: the end's reach over 0.5–1 (a stretch of 2–3 at the range's end); Yeoh's c₂, c₃ per subject
    reach_low = (on_low - lo) * float(rng.uniform(0.5, 1.0))
    reach_high = (hi - on_high) * float(rng.uniform(0.5, 1.0))
    c2, c3 = float(rng.uniform(0.0, 0.5)), float(rng.uniform(0.05, 0.5))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(yeoh_end(np.array(on_low - lo), smooth, reach_low, c2, c3)),
            "a_high": t_high / float(yeoh_end(np.array(hi - on_high), smooth, reach_high, c2, c3)),
            "reach_low": reach_low, "reach_high": reach_high, "c2": c2, "c3": c3, "smooth": smooth,
            "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def drive_noise(rng: np.random.Generator, vel: np.ndarray, sd: float) -> np.ndarray:
    """Gaussian noise (N·m) whose SD is ``sd`` at rest and 1.3–1.8 × it at the trial's peak speed, in proportion to
    the speed between (the motor drive's interference grows with its current's switching)."""
    speed = np.abs(np.asarray(vel, dtype=float)) / max(float(np.max(np.abs(vel))), 1e-12)
    return rng.normal(0.0, 1.0, speed.size) * sd * (1.0 + float(rng.uniform(0.3, 0.8)) * speed)


def generate_aa(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((27, 27, 27), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: paused_ramps(r, a, b, rate),
                                         lambda r: hand_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap that locks
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, lock = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.5, 1.0)) * tau_max
        joint_deg = behind_strap(deg, lambda d: locking_strap_give(_elastic(kind, d, fixed, coef), c_give, lock))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, lock_Nm=lock)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # blood pooling in the hanging segment: its weight growing over the trial
        unit = venous_pooling(t, float(rng.uniform(30.0, 120.0))) * np.cos(load.direction_rad)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = worn_bearing_friction(deg, np.degrees(vel), float(rng.uniform(0.2, 0.5)), float(rng.uniform(10.0, 30.0)),
                                     float(rng.uniform(0.2, 0.8)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:  # an eddy-current brake, its critical speed 1.5–3 × the trial's peak speed
        critical = float(rng.uniform(1.5, 3.0)) * max(float(np.max(np.abs(vel))), 1e-9)
        unit = eddy_current_brake(vel, critical)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
        details.update(critical_speed_rad_s=critical)
    if "inertia" in effects:
        unit = off_axis_weight(rad, vel, acc, np.radians(bottom), np.radians(top),
                               float(rng.uniform(0.2, 0.4)) * float(rng.choice([-1.0, 1.0])))
        weight = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + weight
        truth["inertia"] = float(np.dot(acc, weight) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        pad = float(rng.uniform(0.5, 2.0))
        unit = two_stage_stop(deg, at, high_end, pad, float(rng.uniform(4.0, 10.0)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", pad_deg=pad)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = clonus(t, start, float(rng.uniform(0.6, 2.0)), float(rng.uniform(5.0, 8.0)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(clonus_start_s=start)
    if "sensor_drift" in effects:
        sag = battery_sag(t, float(t[-1]), float(rng.uniform(0.6, 0.9)))
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * sag / max(float(np.max(sag)), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, delay = held_late(torque, t, float(rng.uniform(0.03, 0.4)), float(rng.uniform(0.005, 0.02)),
                                  float(rng.uniform(20.0, 50.0)), rng)
        truth["time_delay"] = delay
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + drive_noise(rng, vel, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "battery_sag", "clonus", "drive_noise",
           "eddy_current_brake", "generate_aa", "hand_bends", "held_late", "locking_strap_give", "off_axis_weight",
           "paused_ramps", "strap_joined_spring", "two_stage_stop", "venous_pooling", "worn_bearing_friction", "yeoh_end"]
