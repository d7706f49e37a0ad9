"""A twenty-third generator family for the diagnosis, written (2026-11-29, thirty-first stop) before that stop's engine
change and held out from it, run once on its frozen engine (4f53208; benchmarks/results/diagnosis_family_w.json).

The second to twenty-second families (:mod:`benchmarks.family_b_truth` … ``family_v_truth``) are development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at c58563f; where an earlier family used a near relation it is said) and keeps every
nuisance below what the diagnosis should name. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range an entropic (worm-like chain) element, per unit stiffness
  L·(1/(4(1 − x/L)²) − 1/4 + x/L) for an angle x past the onset and a contour angle L (Marko & Siggia 1995, the law of
  titin's extensible segment), its stretch s = w·ln(1 + e^{x/w}) (the fibres' onsets spread over w 2–6°, so the
  stiffness rises smoothly from the onset: no kink; the thirteenth family's chain engaged at one angle), rising
  without bound toward L; L set so the range's end reaches 60–85 % of it; the steep end sized by its torque at the
  range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a
  gently progressive spring k·θⁿ (n 1.1–1.4).
- Motion: half-cosine strokes (the speed a sine over each stroke, peaking mid-range, a mean of 3–7 °/s drawn per
  stroke ±15 %), holds of 0–2 s at each end, 2–4 cycles after a 0.5–1.5 s hold (a continuous-passive-motion
  machine's profile). The AFO: 6–12 raised-cosine bends of 10–20° taking 1–3 s each way, returning to 0–3° between
  them (no rest), from 0° and back to 0° at the end.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb friction behind lost motion: after each reversal no friction until the joint has turned
    through a backlash of 0.5–2°, then its level engaged over 0.2°, its sign through tanh(v/ε) (ε 0.2–0.8 °/s; the
    fourteenth family's backlash was a damper's); magnitude: its mean over the moving samples;
  * damping: a rotary vane damper whose ports open and close with the angle, b(θ)·θ̇ with
    b(θ) = b₀·(1 + r·cos(2πθ/P + φ)) (r 0.2–0.5, P 10–30°; the thirteenth family rippled a friction that way);
    magnitude: the least-squares slope of its torque on θ̇;
  * stop: a pad that buckles: linear up to a peak at 0.5–1.5°, its torque dipping by 20–40 % over the next 0.5–1.5°
    as the pad gives way, then a seat 5–10 × stiffer, anywhere in the last 5–30 % of either end of a joint's range
    (the AFO's at the top of its bend; a pad reached by less than 4° shrunk by the reach over 4°); named only;
  * delay: a digital sensor's exponential moving average (a first-order low-pass, τ 0.05–0.5 s, no transport
    delay; the fourth family's was 5–30 ms in front of a pure delay, the thirteenth's two cascaded); magnitude: its
    group delay at low frequency, (1 − α)/α samples;
  * activation: a flexor spasm, a linear rise over 0.1–0.4 s and a hyperbolic release (1 + t/τ)⁻² (τ 0.1–0.4 s), of
    either sign; magnitude: its peak;
  * limb-weight error: the subject relaxing into a sleeve: a share of the limb's weight carried by it, growing as
    1 − e^{−t/τ} (τ 20–60 % of the trial; the seventeenth family's strap slipped once along a logistic);
    magnitude: its peak;
  * drift: a heater cycling once: the zero bowed as sin²(π·t/T) over the trial with a linear trend of up to half its
    size, minus its mean; named only;
  * series compliance: a strap with slack taken up: give c·τ up to a knee torque (20–50 % of the largest), a
    2.5–5 × stiffer give beyond it (the stiffening straps of earlier families were smooth); magnitude: the
    least-squares slope of the give on the torque;
  * inertia error: a fluid-filled boot, a solid share (40–70 %) of its inertia following the segment and the fluid's
    through a first-order lag of 0.05–0.2 s in acceleration; magnitude: the least-squares coefficient of its torque
    on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise plus a rig resonance (an AR(2) at 10–30 Hz,
  pole radius 0.9–0.97, at 0.2–0.4 × the noise SD) and mains hum (50 or 60 Hz, up to 0.3 × the noise SD, aliased
  where the rate is low); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast or slow by
  up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time
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

NOISE_SD_NM = {"afo": 0.06, "knee": 0.16, "ankle": 0.12}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def worm_like_chain(x_deg: np.ndarray, contour_deg: float, spread_deg: float | None = None) -> np.ndarray:
    """An entropic element per unit stiffness, x the angle (deg) past its onset: L·(1/(4(1 − s/L)²) − 1/4 + s/L),
    L = ``contour_deg``, its stretch s = x past the onset (0 before it) or, with ``spread_deg`` w, the fibres'
    onsets spread over a few degrees, s = w·ln(1 + e^{x/w}) (smooth at the onset; only s < L is meaningful)."""
    x = np.asarray(x_deg, dtype=float)
    stretch = np.clip(x, 0.0, None) if spread_deg is None else spread_deg * np.logaddexp(0.0, x / spread_deg)
    u = stretch / contour_deg
    return contour_deg * (0.25 / (1.0 - u) ** 2 - 0.25 + u)


def progressive_spring(deg: np.ndarray, exponent: float) -> np.ndarray:
    """An orthosis's spring per unit stiffness: θⁿ for θ ≥ 0 (deg), 0 below."""
    return np.clip(np.asarray(deg, dtype=float), 0.0, None) ** exponent


def half_cosine_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 2–4 cycles from ``lo`` to ``hi`` and back after a 0.5–1.5 s hold: each stroke
    a + (b − a)·(1 − cos πs)/2 over a duration set by a mean speed of 3–7 °/s (drawn per trial, ±15 % per stroke), a
    hold of 0–2 s after each."""
    mean_speed = float(rng.uniform(3.0, 7.0))
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), lo)]
    for i in range(2 * int(rng.integers(2, 5))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        duration = abs(end - start) / (mean_speed * float(rng.uniform(0.85, 1.15)))
        s = np.arange(1, int(np.ceil(duration * rate)) + 1) / np.ceil(duration * rate)
        parts.append(start + (end - start) * 0.5 * (1.0 - np.cos(np.pi * s)))
        parts.append(np.full(int(rng.uniform(0.0, 2.0) * rate), end))
    return np.concatenate(parts)


def raised_cosine_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 6–12 bends to 10–20°, up and down each a raised cosine over 1–3 s, returning to 0–3° between
    them (0° before the first and after the last)."""
    count = int(rng.integers(6, 13))
    parts = [np.zeros(int(0.4 * rate))]
    base = 0.0
    for k in range(count):
        peak = float(rng.uniform(10.0, 20.0))
        back = 0.0 if k == count - 1 else float(rng.uniform(0.0, 3.0))
        for a, b in ((base, peak), (peak, back)):
            n = max(2, int(rng.uniform(1.0, 3.0) * rate))
            s = np.arange(1, n + 1) / n
            parts.append(a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * s)))
        base = back
    parts.append(np.zeros(int(0.4 * rate)))
    return np.concatenate(parts)


def travel_since_turn(deg: np.ndarray, vel_deg_s: np.ndarray, still_deg_s: float = 0.1) -> np.ndarray:
    """The angle (deg) turned since the motion last changed direction (0 at the first sample and at each turn; a
    sample slower than ``still_deg_s`` keeps the direction before it)."""
    direction = np.sign(np.where(np.abs(vel_deg_s) > still_deg_s, vel_deg_s, 0.0))
    idx = np.where(direction != 0.0, np.arange(direction.size), 0)
    direction = direction[np.maximum.accumulate(idx)]  # a still sample keeps the last moving direction
    turn = np.r_[True, direction[1:] != direction[:-1]]
    path = np.cumsum(np.abs(np.diff(np.asarray(deg, dtype=float), prepend=float(deg[0]))))
    last_turn = np.maximum.accumulate(np.where(turn, np.arange(path.size), 0))
    return path - path[last_turn]


def lost_motion_friction(deg: np.ndarray, vel_deg_s: np.ndarray, backlash_deg: float, epsilon_deg_s: float,
                         engage_deg: float = 0.2) -> np.ndarray:
    """A friction per unit level (resisting the motion): 0 until the joint has turned ``backlash_deg`` since the last
    reversal, engaged linearly over ``engage_deg`` beyond it, times tanh(v/ε)."""
    engaged = np.clip((travel_since_turn(deg, vel_deg_s) - backlash_deg) / engage_deg, 0.0, 1.0)
    return engaged * np.tanh(vel_deg_s / epsilon_deg_s)


def ported_damper(deg: np.ndarray, vel: np.ndarray, ripple: float, period_deg: float, phase: float) -> np.ndarray:
    """A damping per unit mean coefficient: (1 + ``ripple``·cos(2πθ/``period_deg`` + ``phase``))·θ̇."""
    return (1.0 + ripple * np.cos(2 * np.pi * np.asarray(deg, dtype=float) / period_deg + phase)) * vel


def buckling_pad(deg: np.ndarray, at_deg: float, high: bool, peak_deg: float, dip: float, give_deg: float,
                 ratio: float) -> np.ndarray:
    """A stop per unit pad stiffness toward the range's inside (positive at the high end), δ its depth past
    ``at_deg``: δ up to ``peak_deg``; then falling by the fraction ``dip`` as sin² over ``give_deg``; then rising
    at ``ratio`` from there."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    into = np.clip((depth - peak_deg) / give_deg, 0.0, 1.0)
    buckled = peak_deg * (1.0 - dip * np.sin(0.5 * np.pi * into) ** 2)
    seat = ratio * np.clip(depth - peak_deg - give_deg, 0.0, None)
    return sign * np.where(depth <= peak_deg, depth, buckled + seat)


def moving_average_filter(torque: np.ndarray, tau_s: float, rate: float) -> tuple[np.ndarray, float]:
    """(the torque through an exponential moving average of time constant ``tau_s`` at ``rate`` Hz, started at the
    first sample; its group delay at low frequency in s, (1 − α)/α samples)."""
    alpha = 1.0 - np.exp(-1.0 / (tau_s * rate))
    y, _ = lfilter([alpha], [1.0, alpha - 1.0], torque, zi=[(1.0 - alpha) * torque[0]])
    return np.asarray(y, dtype=float), (1.0 - alpha) / alpha / rate


def flexor_spasm(t: np.ndarray, start_s: float, rise_s: float, release_s: float) -> np.ndarray:
    """A spasm of peak 1: 0 before ``start_s``, rising linearly over ``rise_s``, released as
    (1 + t'/``release_s``)⁻² after its peak."""
    u = t - start_s
    after = np.clip(u - rise_s, 0.0, None)
    return np.where(u < 0.0, 0.0, np.where(u <= rise_s, u / rise_s, 1.0 / (1.0 + after / release_s) ** 2))


def relaxing_share(t: np.ndarray, tau_s: float) -> np.ndarray:
    """The share (0 → 1) of the weight a sleeve carries as the subject relaxes into it: 1 − e^{−(t − t₀)/τ}."""
    return 1.0 - np.exp(-(t - t[0]) / tau_s)


def heater_bow(t: np.ndarray, trend: float) -> np.ndarray:
    """sin²(π·(t − t₀)/T) plus a linear trend of ``trend`` (end to end, in units of the bow), minus its mean,
    largest excursion 1."""
    u = (t - t[0]) / max(float(t[-1] - t[0]), 1e-12)
    y = np.sin(np.pi * u) ** 2 + trend * (u - 0.5)
    y = y - y.mean()
    return y / max(float(np.max(np.abs(y))), 1e-12)


def slack_strap_give(torque: np.ndarray, compliance: float, knee_nm: float, stiffer: float) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ up to ``knee_nm``, ``compliance``/``stiffer`` per N·m beyond."""
    mag = np.abs(torque)
    return np.sign(torque) * compliance * (np.minimum(mag, knee_nm) + np.clip(mag - knee_nm, 0.0, None) / stiffer)


def sloshing_acceleration(acc: np.ndarray, solid_share: float, lag_s: float, rate: float) -> np.ndarray:
    """The boot's effective acceleration (rad/s²): ``solid_share`` of the segment's plus the rest through a
    first-order lag of ``lag_s`` (from rest)."""
    alpha = 1.0 - np.exp(-1.0 / (lag_s * rate))
    fluid = lfilter([alpha], [1.0, alpha - 1.0], acc)
    return solid_share * acc + (1.0 - solid_share) * np.asarray(fluid, dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * progressive_spring(deg, c["exponent"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * worm_like_chain(on_low - deg, c["contour_low"], c["spread"])
            + c["a_high"] * worm_like_chain(deg - on_high, c["contour_high"], c["spread"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        exponent = float(rng.uniform(1.1, 1.4))
        return {"exponent": exponent, "k": float(rng.uniform(10.0, 25.0)) / 15.0**exponent}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    spread = float(rng.uniform(2.0, 6.0))
    # the contour: the range's end reaches 60–85 % of it (the onset may move by the coupling, up to 0.2 × 45°, and the
    # spread adds up to w·ln 2; the contour is measured from the farthest stretch so the element never reaches it)
    reach_low, reach_high = on_low - lo + 9.0 + spread, hi - on_high + 9.0 + spread
    contour_low, contour_high = reach_low / rng.uniform(0.6, 0.85), reach_high / rng.uniform(0.6, 0.85)
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(worm_like_chain(np.array(on_low - lo), contour_low, spread)),
            "a_high": t_high / float(worm_like_chain(np.array(hi - on_high), contour_high, spread)),
            "contour_low": contour_low, "contour_high": contour_high, "spread": spread, "on_low": on_low,
            "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def _rig_noise(rng: np.random.Generator, t: np.ndarray, rate: float, sd: float) -> np.ndarray:
    """Gaussian noise, a rig resonance (AR(2) at 10–30 Hz) and mains hum, N·m."""
    noise = rng.normal(0.0, sd, t.size)
    hz, radius = float(rng.uniform(10.0, 30.0)), float(rng.uniform(0.9, 0.97))
    ring = lfilter([1.0], [1.0, -2.0 * radius * np.cos(2 * np.pi * min(hz, 0.45 * rate) / rate), radius * radius],
                   rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.2, 0.4)) * sd * ring / max(float(np.std(ring)), 1e-12)
    mains = float(rng.choice([50.0, 60.0]))
    noise += float(rng.uniform(0.0, 0.3)) * sd * np.sin(2 * np.pi * mains * t + float(rng.uniform(0, 2 * np.pi)))
    return noise


def generate_w(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((23, 23, 23), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: half_cosine_strokes(r, a, b, rate),
                                         lambda r: raised_cosine_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap whose slack is taken up
        tau_max = float(np.max(np.abs(_elastic(kind, deg, fixed, coef))))
        c_give, knee_nm = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.2, 0.5)) * max(tau_max, 1e-9)
        stiffer = float(rng.uniform(2.5, 5.0))
        for _ in range(4):
            joint_deg = deg - slack_strap_give(_elastic(kind, joint_deg, fixed, coef), c_give, knee_nm, stiffer)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, knee_Nm=knee_nm, stiffer=stiffer)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the subject relaxing into a sleeve that carries part of the weight
        unit = -load.moment_nm * relaxing_share(t, float(rng.uniform(0.2, 0.6)) * float(t[-1]))
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = lost_motion_friction(deg, vel_deg, float(rng.uniform(0.5, 2.0)), float(rng.uniform(0.2, 0.8)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        unit = ported_damper(deg, vel, float(rng.uniform(0.2, 0.5)), float(rng.uniform(10.0, 30.0)),
                             float(rng.uniform(0.0, 2 * np.pi)))
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        solid, lag = float(rng.uniform(0.4, 0.7)), float(rng.uniform(0.05, 0.2))
        unit = sloshing_acceleration(acc, solid, lag, rate)
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(solid_share=solid, fluid_lag_s=lag)
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        reach = float(np.max(np.clip((1.0 if high_end else -1.0) * (deg - at), 0.0, None)))
        shrink = min(1.0, reach / 4.0)
        unit = buckling_pad(deg, at, high_end, float(rng.uniform(0.5, 1.5)) * shrink, float(rng.uniform(0.2, 0.4)),
                            float(rng.uniform(0.5, 1.5)) * shrink, float(rng.uniform(5.0, 10.0)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = flexor_spasm(t, start, float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.1, 0.4)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(spasm_start_s=start)
    if "sensor_drift" in effects:
        torque = torque + size() * heater_bow(t, float(rng.uniform(-0.5, 0.5)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, group_delay = moving_average_filter(torque, float(rng.uniform(0.05, 0.5)), rate)
        truth["time_delay"] = group_delay
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + _rig_noise(rng, t, rate, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "buckling_pad", "flexor_spasm", "generate_w",
           "half_cosine_strokes", "heater_bow", "lost_motion_friction", "moving_average_filter", "ported_damper",
           "progressive_spring", "raised_cosine_bends", "relaxing_share", "slack_strap_give", "sloshing_acceleration",
           "travel_since_turn", "worm_like_chain"]
