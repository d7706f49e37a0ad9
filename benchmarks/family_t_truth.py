"""A twentieth generator family for the diagnosis, written after the nineteenth's run and before the next engine
change, to be run once on that change's frozen engine.

The second to nineteenth families (:mod:`benchmarks.family_b_truth` … ``family_s_truth``) became development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` before it was run; where an earlier family used a near relation it is said), and,
unlike the nineteenth, keeps every nuisance below what the diagnosis should name (the nineteenth's warming gain, up to
0.10–0.25 N·m on an orthosis against a noise SD of 0.05–0.08 N·m, was named a drift in 15 of 20 clean trials).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: a power law past an onset at each end of a joint's range, A·xⁿ with n 2.5–4 (no kink: slope and
  curvature start at zero), the steep end sized by its torque at the range's end, the onset toward a two-joint
  muscle moved by the other joint's angle. The AFO: a leaf spring in large deflection, k·(tan(θ + θ₀) − tan θ₀) with
  θ₀ 0–10° past an engagement of 0.5–3°.
- Motion: isokinetic strokes at a nominal 4–8 °/s with the drive's speed ripple (±3–8 % at 0.2–1 Hz), each stroke
  turning 0–10 % of the range short of its end, each reversal rounded by the drive's acceleration limit (a moving
  average over 0.3–0.6 s). The AFO: bends to 10–20°, each held 0.5–1.5 s at its top, up and down
  at unequal speeds (0.8–2.5 s each way).
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb friction with a rough spot, its level 30–100 % higher over a Gaussian stretch of 5–15° of the
    range (sign through a tanh of 0.3–1.5 °/s; the eleventh family's friction rose with angle monotonically);
    magnitude: its mean over the moving samples;
  * damping: viscous with a coefficient that changes along the range, b·(1 + c·(θ − θ_mid)/span), c ±0.3–0.6 (the
    tissue's thickness under the cuff); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a cubic contact, k·δ³ (a Hertzian law of a rubber bumper), anywhere in the last 5–25 % of either end of a
    joint's range (the AFO's at the top of its bend); named only;
  * delay: a buffer that resynchronises once: the latency steps from d₁ to d₂ (each 0.02–0.4 s) at 25–75 % of the
    trial; magnitude: the latency averaged over the trial's time;
  * activation: a clonus, 3–5 beats at 5–7 Hz under a raised-cosine envelope of 0.5–1.5 s, of either sign; magnitude:
    its peak;
  * limb-weight error: the limb resting on a support below an angle: the weight's moment wrong only beyond it (the
    error ∝ the weight's moment, zero on the support's side, switching on over 2–5°); magnitude: its peak;
  * drift: a temperature controller's sawtooth, slow ramps reset every 30–90 s; named only;
  * series compliance: a strap whose lever changes along the range, give = c·(1 + g·(θ − θ_mid)/span)·τ, g ±0.3–0.6;
    magnitude: the least-squares slope of the give on the torque;
  * inertia error: an attachment off the axis: I·θ̈ plus its centripetal moment m·e·r·θ̇²·sin(θ − φ) (the moment of
    the mass's eccentricity, 20–60 % of the inertia's torque at its largest); magnitude: the least-squares coefficient
    of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; white noise plus a flicker (an AR(1), ρ 0.9–0.99, at
  0.2–0.4 × the noise SD); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast or slow
  by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time
  included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
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


def power_toe(x_deg: np.ndarray, exponent: float) -> np.ndarray:
    """xⁿ past the onset (0 before it) for the angle ``x_deg`` past it."""
    return np.clip(np.asarray(x_deg, dtype=float), 0.0, None) ** exponent


def leaf_spring(deg: np.ndarray, engage_deg: float, preset_deg: float) -> np.ndarray:
    """A leaf spring in large deflection per unit stiffness: tan(θ' + θ₀) − tan θ₀ for θ' the bend past
    ``engage_deg`` (0 before it), θ₀ = ``preset_deg``."""
    bend = np.radians(np.clip(np.asarray(deg, dtype=float) - engage_deg, 0.0, None))
    preset = np.radians(preset_deg)
    return np.tan(bend + preset) - np.tan(preset)


def rippled_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 3–5 cycles of isokinetic strokes at a nominal 4–8 °/s with a speed ripple of ±3–8 % at
    0.2–1 Hz, each stroke turning 0–10 % of the range short of its end, 0.5 s still at the start, every reversal
    rounded by a moving average over 0.3–0.6 s (the drive's acceleration limit)."""
    nominal = float(rng.uniform(4.0, 8.0))
    depth, freq, phase = float(rng.uniform(0.03, 0.08)), float(rng.uniform(0.2, 1.0)), float(rng.uniform(0, 2 * np.pi))
    parts, here, clock = [np.full(int(0.5 * rate), lo)], lo, 0.0
    for i in range(2 * int(rng.integers(3, 6))):
        short = float(rng.uniform(0.0, 0.1)) * (hi - lo)
        end = hi - short if i % 2 == 0 else lo + short
        sign = 1.0 if end > here else -1.0
        path = [here]
        while (end - path[-1]) * sign > 0:
            clock += 1.0 / rate
            speed = nominal * (1.0 + depth * np.sin(2 * np.pi * freq * clock + phase))
            path.append(path[-1] + sign * speed / rate)
        path[-1] = end
        parts.append(np.array(path[1:]))
        here = end
    deg = np.concatenate(parts)
    # the drive's acceleration limit: a moving average over 0.3–0.6 s turns each reversal into a parabola (a
    # constant deceleration and acceleration of 2·speed / window)
    width = max(int(float(rng.uniform(0.3, 0.6)) * rate), 1)
    padded = np.concatenate([np.full(width, deg[0]), deg, np.full(width, deg[-1])])
    return np.convolve(padded, np.ones(width) / width, mode="same")[width:-width]


def held_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–8 bends from 0° to 10–20° and back, each way a raised cosine of 0.8–2.5 s, held 0.5–1.5 s at
    the top, 0.3 s at rest between."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(10.0, 20.0))
        up = np.linspace(0.0, 1.0, int(rng.uniform(0.8, 2.5) * rate))
        down = np.linspace(0.0, 1.0, int(rng.uniform(0.8, 2.5) * rate))
        parts += [peak * 0.5 * (1 - np.cos(np.pi * up)), np.full(int(rng.uniform(0.5, 1.5) * rate), peak),
                  peak * 0.5 * (1 + np.cos(np.pi * down)), np.zeros(int(0.3 * rate))]
    return np.concatenate(parts)


def rough_spot_friction(deg: np.ndarray, vel_deg_s: np.ndarray, spot_deg: float, width_deg: float, excess: float,
                        tanh_width: float) -> np.ndarray:
    """A friction per unit level (resisting the motion), (1 + excess·e^{−((θ − θ_r)/w)²})·tanh(θ̇ / width)."""
    return (1.0 + excess * np.exp(-(((deg - spot_deg) / width_deg) ** 2))) * np.tanh(vel_deg_s / tanh_width)


def graded_damping(deg: np.ndarray, vel: np.ndarray, middle_deg: float, span_deg: float, grade: float) -> np.ndarray:
    """A viscous damping per unit coefficient whose coefficient changes along the range: (1 + g·(θ − θ_mid)/span)·θ̇."""
    return (1.0 + grade * (deg - middle_deg) / span_deg) * vel


def cubic_stop(deg: np.ndarray, at_deg: float, high: bool) -> np.ndarray:
    """A stop per unit stiffness toward the range's inside (positive at the high end): δ³ past ``at_deg``."""
    sign = 1.0 if high else -1.0
    return sign * np.clip(sign * (deg - at_deg), 0.0, None) ** 3


def stepped_latency(torque: np.ndarray, t: np.ndarray, first_s: float, second_s: float, at_s: float
                    ) -> tuple[np.ndarray, np.ndarray]:
    """``torque`` read ``first_s`` late before ``at_s`` and ``second_s`` late after it (interpolated, held at the first
    sample before the trial); returns (the late torque, the latency at each sample in s)."""
    latency = np.where(t < at_s, first_s, second_s)
    return np.interp(t - latency, t, torque), latency


def clonus(t: np.ndarray, start_s: float, length_s: float, beat_hz: float) -> np.ndarray:
    """Beats at ``beat_hz`` (positive half-waves of a sine) under a raised-cosine envelope from ``start_s`` over
    ``length_s``; peak 1."""
    u = (t - start_s) / length_s
    envelope = np.where((u >= 0) & (u <= 1), 0.5 * (1 - np.cos(2 * np.pi * np.clip(u, 0, 1))), 0.0)
    beats = np.clip(np.sin(2 * np.pi * beat_hz * (t - start_s)), 0.0, None)
    y = envelope * beats
    return y / max(float(np.max(y)), 1e-12)


def off_support(deg: np.ndarray, support_deg: float, above: bool, switch_deg: float) -> np.ndarray:
    """The share (0 → 1) of the weight off a support: a logistic in angle past ``support_deg`` (above it or below
    it), 10–90 % over ``switch_deg``."""
    sign = 1.0 if above else -1.0
    return 1.0 / (1.0 + np.exp(-sign * (deg - support_deg) * 4.394 / switch_deg))


def sawtooth_drift(t: np.ndarray, period_s: float, phase: float) -> np.ndarray:
    """Slow ramps reset every ``period_s``: the fractional part of t/period + phase, minus its mean; largest
    excursion 1."""
    y = np.mod(t / period_s + phase, 1.0)
    y = y - np.mean(y)
    return y / max(float(np.max(np.abs(y))), 1e-12)


def eccentric_attachment(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, inertia: float, eccentric: float,
                         phase_rad: float) -> np.ndarray:
    """The torque (N·m) of an attachment of inertia ``inertia`` whose mass sits off the axis: I·θ̈ + ε·θ̇²·sin(θ − φ),
    ε = m·e·r (kg·m²)."""
    return inertia * acc + eccentric * vel**2 * np.sin(rad - phase_rad)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * leaf_spring(deg, c["engage"], c["preset"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * power_toe(on_low - deg, c["n_low"]) + c["a_high"] * power_toe(deg - on_high, c["n_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, preset = float(rng.uniform(0.5, 3.0)), float(rng.uniform(0.0, 10.0))
        k = float(rng.uniform(10.0, 25.0)) / float(leaf_spring(np.array(15.0), engage, preset))
        return {"engage": engage, "preset": preset, "k": k}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    n_low, n_high = float(rng.uniform(2.5, 4.0)), float(rng.uniform(2.5, 4.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / (on_low - lo) ** n_low, "a_high": t_high / (hi - on_high) ** n_high,
            "n_low": n_low, "n_high": n_high, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_t(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((20, 20, 20), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: rippled_strokes(r, a, b, rate),
                                         lambda r: held_bends(r, rate))
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
    if "series_compliance" in effects:  # a strap whose lever changes along the range
        c_give, grade = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.3, 0.6)) * float(rng.choice([-1.0, 1.0]))
        for _ in range(4):
            tau = _elastic(kind, joint_deg, fixed, coef)
            joint_deg = deg - c_give * (1.0 + grade * (deg - middle) / span) * tau
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, compliance_grade=grade)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # wrong only off a support
        above = bool(rng.random() < 0.5)
        support = low + float(rng.uniform(0.3, 0.7)) * span
        unit = off_support(deg, support, above, float(rng.uniform(2.0, 5.0))) * load.moment_nm / max(
            load.amplitude_nm, 1e-12)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12) * float(rng.choice([-1.0, 1.0]))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(support_deg=support, weight_off_above=above)
    if "coulomb_friction" in effects:
        spot = low + float(rng.uniform(0.2, 0.8)) * span
        unit = rough_spot_friction(deg, vel_deg, spot, float(rng.uniform(5.0, 15.0)), float(rng.uniform(0.3, 1.0)),
                                   float(rng.uniform(0.3, 1.5)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
        details.update(rough_spot_deg=spot)
    if "viscous_damping" in effects:
        grade = float(rng.uniform(0.3, 0.6)) * float(rng.choice([-1.0, 1.0]))
        unit = graded_damping(deg, vel, middle, span, grade)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
        details.update(damping_grade=grade)
    if "inertia" in effects:
        share, phase = float(rng.uniform(0.2, 0.6)), float(rng.uniform(0.0, 2 * np.pi))
        spin = vel**2 * np.sin(rad - phase)
        eccentric = share * float(np.max(np.abs(acc))) / max(float(np.max(np.abs(spin))), 1e-12)
        unit = eccentric_attachment(rad, vel, acc, 1.0, eccentric, phase)
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(eccentric_share=share)
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.25))
        top, bottom = (high, 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = cubic_stop(deg, at, high_end)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        beat = float(rng.uniform(5.0, 7.0))
        length = float(rng.integers(3, 6)) / beat + float(rng.uniform(0.0, 0.3))
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * clonus(t, start, length, beat)
        truth["activation_burst"] = peak
        details.update(clonus_start_s=start, clonus_hz=beat)
    if "sensor_drift" in effects:
        torque = torque + size() * sawtooth_drift(t, float(rng.uniform(30.0, 90.0)), float(rng.uniform(0.0, 1.0)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        first, second = float(rng.uniform(0.02, 0.4)), float(rng.uniform(0.02, 0.4))
        torque, latency = stepped_latency(torque, t, first, second, float(rng.uniform(0.25, 0.75)) * float(t[-1]))
        truth["time_delay"] = float(np.mean(latency))
        details.update(latencies_s=(first, second))
    noise = rng.normal(0.0, sd, t.size)
    flicker = lfilter([1.0], [1.0, -float(rng.uniform(0.9, 0.99))], rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.2, 0.4)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "clonus", "cubic_stop", "eccentric_attachment",
           "generate_t", "graded_damping", "held_bends", "leaf_spring", "off_support", "power_toe",
           "rippled_strokes", "rough_spot_friction", "sawtooth_drift", "stepped_latency"]
