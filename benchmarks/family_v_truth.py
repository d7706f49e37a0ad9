"""A twenty-second generator family for the diagnosis, written before the twenty-first's run and before the engine
change after the next, run once on that change's frozen engine (c3d0003; benchmarks/results/diagnosis_family_v.json).

The second to twenty-first families (:mod:`benchmarks.family_b_truth` … ``family_u_truth``) become development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at c7ed87c; where an earlier family used a near relation it is said) and keeps every
nuisance below what the diagnosis should name. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a ligament with a toe region (Blankevoort et al. 1991, J Biomech Eng
  113:263): per unit stiffness x²/(2·x_t) for an angle x past the onset up to the toe's end x_t (3–10°), x − x_t/2
  beyond; the steep end sized by its torque at the range's end, the onset toward a two-joint muscle moved by the other
  joint's angle; a small linear term. The AFO: a leaf spring that softens as it bends, S·tanh(θ'/S) past an
  engagement of 0.5–3° (S 15–40°).
- Motion: isokinetic strokes as a dynamometer's speed loop holds them, the nominal 4–6 °/s rippling by 5–15 % at
  0.5–2 Hz, each reversal a raised-cosine turn over 0.2–0.6 s, 2–4 cycles after a 0.5–1.5 s hold. The AFO: 6–12
  minimum-jerk bends of 12–20° (up and down each over 0.8–1.5 s), rests of 0–1 s between them.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a break-away friction, its level 1 + s·e^{−Δ/δ} for Δ the angle travelled since the last reversal
    (s 0.5–1.5, δ 0.5–2°), its sign through tanh(v/ε), ε 0.2–1 °/s (the seventh family's Dahl state rose to its
    level without overshoot); magnitude: its mean over the moving samples;
  * damping: a damper whose oil warms: its coefficient falls steadily by 20–40 % from the first sample to the last;
    magnitude: the least-squares slope of its torque on θ̇;
  * stop: a two-stage stop, a pad of 1–3° at stiffness k then a rigid stop at 5–10 k, anywhere in the last 5–30 % of
    either end of a joint's range (the AFO's at the top of its bend; a pad reached by less than 4° shrunk by the
    reach over 4°); named only;
  * delay: a transmitter's moving average (a boxcar of 0.1–0.9 s over the samples before); magnitude: its group
    delay, half the window less half a sample;
  * activation: a contraction with a physiological tremor, its envelope a smoothstep rise over 0.1–0.3 s, a plateau
    of 0.2–0.8 s and an exponential release (τ 0.15–0.5 s), times 1 + d·sin(2π·f·t) (f 8–12 Hz, d 0.15–0.3), of
    either sign; magnitude: the envelope's peak;
  * limb-weight error: a cushion under the limb carrying a share of its weight over the 20–40 % of the range
    nearest one end, its contact growing over 5–15° (a smoothstep); magnitude: its peak;
  * drift: a thermal drift following the room's air conditioning, a sinusoid of period 40–150 s plus a linear trend
    of up to half its size; named only;
  * series compliance: a strap that stiffens as it is loaded, its give c·τ/(1 + |τ|/τ₀), τ₀ 0.3–1 × the largest
    torque; magnitude: the least-squares slope of the give on the torque;
  * inertia error: a wobbling soft-tissue mass on the segment (natural frequency 4–8 Hz, damping ratio 0.2–0.5; the
    twelfth family's wobbling mass was undamped and on the arm), its torque I_w·a for a its angular acceleration;
    magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Laplace noise plus a flicker (an AR(1), ρ 0.9–0.99, at
  0.2–0.4 × the noise SD); single-sample spikes in up to 0.02 % of samples at 4–6 × the noise SD; a constant torque
  gain error of ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped
  singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import lfilter, lsim

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


def toe_region(x_deg: np.ndarray, toe_deg: float) -> np.ndarray:
    """A ligament per unit stiffness, x the angle (deg) past its onset: 0 before it, x²/(2·``toe_deg``) in the toe
    region, x − ``toe_deg``/2 beyond (continuous in value and slope)."""
    x = np.clip(np.asarray(x_deg, dtype=float), 0.0, None)
    return np.where(x <= toe_deg, x * x / (2.0 * toe_deg), x - 0.5 * toe_deg)


def softening_leaf_spring(deg: np.ndarray, engage_deg: float, saturation_deg: float) -> np.ndarray:
    """A leaf spring per unit stiffness: S·tanh(θ'/S) for θ' the bend past ``engage_deg`` (0 before it),
    S = ``saturation_deg``."""
    bend = np.clip(np.asarray(deg, dtype=float) - engage_deg, 0.0, None)
    return saturation_deg * np.tanh(bend / saturation_deg)


def rippled_isokinetic(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 2–4 cycles from ``lo`` to ``hi`` and back after a 0.5–1.5 s hold: in each stroke the speed
    is the nominal 4–6 °/s times 1 + r·sin(2π·f·t + φ) (r 0.05–0.15, f 0.5–2 Hz), brought up from and down to rest
    by raised-cosine turns of 0.2–0.6 s, the stroke's progress scaled to end exactly at its end."""
    nominal = float(rng.uniform(4.0, 6.0))
    ripple, ripple_hz, phase = float(rng.uniform(0.05, 0.15)), float(rng.uniform(0.5, 2.0)), float(rng.uniform(0, 2 * np.pi))
    turn_s = float(rng.uniform(0.2, 0.6))
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), lo)]
    elapsed = 0.0
    for i in range(2 * int(rng.integers(2, 5))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        total = abs(end - start) / nominal + turn_s
        tt = np.arange(1, int(np.ceil(total * rate)) + 1) / rate
        ramp = np.minimum(np.clip(tt / turn_s, 0.0, 1.0), np.clip((total - tt) / turn_s, 0.0, 1.0))
        speed = 0.5 * (1.0 - np.cos(np.pi * ramp)) * (1.0 + ripple * np.sin(2 * np.pi * ripple_hz * (elapsed + tt) + phase))
        progress = np.cumsum(speed) / float(np.sum(speed))
        parts.append(start + (end - start) * progress)
        elapsed += total
    return np.concatenate(parts)


def minimum_jerk_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 6–12 bends from 0° to 12–20° and back, up and down each a minimum-jerk profile
    (10u³ − 15u⁴ + 6u⁵) over 0.8–1.5 s, rests of 0–1 s at 0° between them."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(6, 13))):
        peak = float(rng.uniform(12.0, 20.0))
        for a, b in ((0.0, peak), (peak, 0.0)):
            n = max(2, int(rng.uniform(0.8, 1.5) * rate))
            u = np.arange(1, n + 1) / n
            parts.append(a + (b - a) * (10 * u**3 - 15 * u**4 + 6 * u**5))
        parts.append(np.zeros(int(rng.uniform(0.0, 1.0) * rate)))
    parts.append(np.zeros(int(0.4 * rate)))
    return np.concatenate(parts)


def travel_since_reversal(deg: np.ndarray, vel_deg_s: np.ndarray, still_deg_s: float = 0.1) -> np.ndarray:
    """The angle (deg) travelled since the motion last changed direction (0 at the first sample; a sample slower than
    ``still_deg_s`` keeps the direction it had)."""
    step = np.abs(np.diff(np.asarray(deg, dtype=float), prepend=float(deg[0])))
    out = np.zeros(step.size)
    direction, travelled = 0.0, 0.0
    for i, (v, s) in enumerate(zip(vel_deg_s, step, strict=True)):
        d = float(np.sign(v)) if abs(v) > still_deg_s else direction
        if d != direction and d != 0.0:
            direction, travelled = d, 0.0
        travelled += s
        out[i] = travelled
    return out


def breakaway_friction(deg: np.ndarray, vel_deg_s: np.ndarray, overshoot: float, travel_deg: float,
                       epsilon_deg_s: float) -> np.ndarray:
    """A friction per unit sliding level (resisting the motion): (1 + ``overshoot``·e^{−Δ/``travel_deg``})·tanh(v/ε),
    Δ the travel since the last reversal (:func:`travel_since_reversal`)."""
    level = 1.0 + overshoot * np.exp(-travel_since_reversal(deg, vel_deg_s) / travel_deg)
    return level * np.tanh(vel_deg_s / epsilon_deg_s)


def warming_damper(t: np.ndarray, vel: np.ndarray, fade: float) -> np.ndarray:
    """A damping per unit initial coefficient whose coefficient falls linearly by ``fade`` (a fraction) from the first
    sample to the last: (1 − fade·(t − t₀)/span)·θ̇."""
    span = max(float(t[-1] - t[0]), 1e-12)
    return (1.0 - fade * (t - t[0]) / span) * vel


def two_stage_stop(deg: np.ndarray, at_deg: float, high: bool, pad_deg: float, ratio: float) -> np.ndarray:
    """A stop per unit pad stiffness toward the range's inside (positive at the high end): the depth δ past
    ``at_deg`` at stiffness 1 up to ``pad_deg``, at ``ratio`` beyond it."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    return sign * (np.minimum(depth, pad_deg) + ratio * np.clip(depth - pad_deg, 0.0, None))


def boxcar_average(torque: np.ndarray, window: int) -> np.ndarray:
    """The mean of the ``window`` samples up to each one (the first sample repeated before the trial)."""
    padded = np.concatenate([np.full(window - 1, torque[0]), torque])
    c = np.concatenate([[0.0], np.cumsum(padded)])
    return (c[window:] - c[:-window]) / window


def tremulous_contraction(t: np.ndarray, start_s: float, rise_s: float, plateau_s: float, release_s: float,
                          tremor_hz: float, tremor_depth: float) -> tuple[np.ndarray, np.ndarray]:
    """(the contraction, its envelope), the envelope of peak 1: a smoothstep rise over ``rise_s`` from ``start_s``,
    held ``plateau_s``, released as e^{−t/``release_s``}; the contraction the envelope times
    1 + ``tremor_depth``·sin(2π·``tremor_hz``·(t − ``start_s``))."""
    u = t - start_s
    rise = np.clip(u / rise_s, 0.0, 1.0)
    envelope = np.where(u < 0.0, 0.0, rise * rise * (3.0 - 2.0 * rise))
    after = u - rise_s - plateau_s
    envelope = np.where(after > 0.0, np.exp(-np.clip(after, 0.0, None) / release_s), envelope)
    return envelope * (1.0 + tremor_depth * np.sin(2 * np.pi * tremor_hz * u)), envelope


def cushion_contact(deg: np.ndarray, edge_deg: float, ramp_deg: float, toward_high: bool) -> np.ndarray:
    """The share (0–1) of a cushion's contact: 0 before ``edge_deg``, a smoothstep over ``ramp_deg`` toward the range's
    high end (``toward_high``) or low end, 1 beyond."""
    x = (np.asarray(deg, dtype=float) - edge_deg) * (1.0 if toward_high else -1.0) / ramp_deg
    u = np.clip(x, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def air_conditioning_drift(t: np.ndarray, period_s: float, phase: float, trend: float) -> np.ndarray:
    """sin(2π·t/``period_s`` + ``phase``) plus a linear trend of ``trend`` (end to end, in units of the sinusoid's
    amplitude), minus its mean, largest excursion 1."""
    span = max(float(t[-1] - t[0]), 1e-12)
    y = np.sin(2 * np.pi * (t - t[0]) / period_s + phase) + trend * ((t - t[0]) / span - 0.5)
    y = y - y.mean()
    return y / max(float(np.max(np.abs(y))), 1e-12)


def stiffening_strap_give(torque: np.ndarray, compliance: float, saturation_nm: float) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ/(1 + |τ|/``saturation_nm``)."""
    return compliance * torque / (1.0 + np.abs(torque) / saturation_nm)


def wobbling_acceleration(t: np.ndarray, acc: np.ndarray, natural_hz: float, damping_ratio: float) -> np.ndarray:
    """The angular acceleration (rad/s²) of a mass joined to the segment by a spring and damper (natural frequency
    ``natural_hz``, damping ratio ``damping_ratio``) when the segment accelerates by ``acc``: the segment's
    acceleration through (2ζω·s + ω²)/(s² + 2ζω·s + ω²), from rest."""
    w = 2 * np.pi * natural_hz
    _, y, _ = lsim(([2 * damping_ratio * w, w * w], [1.0, 2 * damping_ratio * w, w * w]), acc, t - t[0])
    return np.asarray(y, dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * softening_leaf_spring(deg, c["engage"], c["saturation"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * toe_region(on_low - deg, c["toe_low"]) + c["a_high"] * toe_region(deg - on_high, c["toe_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, saturation = float(rng.uniform(0.5, 3.0)), float(rng.uniform(15.0, 40.0))
        k = float(rng.uniform(10.0, 25.0)) / float(softening_leaf_spring(np.array(15.0), engage, saturation))
        return {"engage": engage, "saturation": saturation, "k": k}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    toe_low, toe_high = float(rng.uniform(3.0, 10.0)), float(rng.uniform(3.0, 10.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(toe_region(np.array(on_low - lo), toe_low)),
            "a_high": t_high / float(toe_region(np.array(hi - on_high), toe_high)),
            "toe_low": toe_low, "toe_high": toe_high, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_v(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((22, 22, 22), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: rippled_isokinetic(r, a, b, rate),
                                         lambda r: minimum_jerk_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    low, high = float(deg.min()), float(deg.max())

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap that stiffens as it is loaded
        tau_max = float(np.max(np.abs(_elastic(kind, deg, fixed, coef))))
        c_give, saturation = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.3, 1.0)) * max(tau_max, 1e-9)
        for _ in range(4):
            joint_deg = deg - stiffening_strap_give(_elastic(kind, joint_deg, fixed, coef), c_give, saturation)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, saturation_Nm=saturation)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # a cushion carrying a share of the limb's weight near one end of the range
        toward_high = bool(rng.random() < 0.5)
        reach = float(rng.uniform(0.2, 0.4)) * (high - low)
        ramp = float(rng.uniform(5.0, 15.0))
        edge = high - reach if toward_high else low + reach
        unit = -load.moment_nm * cushion_contact(deg, edge, ramp, toward_high)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(cushion_edge_deg=edge, cushion_toward_high=toward_high)
    if "coulomb_friction" in effects:
        unit = breakaway_friction(deg, vel_deg, float(rng.uniform(0.5, 1.5)), float(rng.uniform(0.5, 2.0)),
                                  float(rng.uniform(0.2, 1.0)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        fade = float(rng.uniform(0.2, 0.4))
        unit = warming_damper(t, vel, fade)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
        details.update(damping_fade=fade)
    if "inertia" in effects:
        natural_hz, ratio = float(rng.uniform(4.0, 8.0)), float(rng.uniform(0.2, 0.5))
        unit = wobbling_acceleration(t, acc, natural_hz, ratio)
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(wobble_hz=natural_hz, wobble_damping_ratio=ratio)
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (high, 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        reach = float(np.max(np.clip((1.0 if high_end else -1.0) * (deg - at), 0.0, None)))
        unit = two_stage_stop(deg, at, high_end, float(rng.uniform(1.0, 3.0)) * min(1.0, reach / 4.0),
                              float(rng.uniform(5.0, 10.0)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape, _ = tremulous_contraction(t, start, float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.2, 0.8)),
                                         float(rng.uniform(0.15, 0.5)), float(rng.uniform(8.0, 12.0)),
                                         float(rng.uniform(0.15, 0.3)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(contraction_start_s=start)
    if "sensor_drift" in effects:
        torque = torque + size() * air_conditioning_drift(t, float(rng.uniform(40.0, 150.0)),
                                                          float(rng.uniform(0.0, 2 * np.pi)), float(rng.uniform(-0.5, 0.5)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        window = max(2, int(round(float(rng.uniform(0.1, 0.9)) * rate)))
        torque = boxcar_average(torque, window)
        truth["time_delay"] = 0.5 * (window - 1) / rate
    noise = rng.laplace(0.0, sd / np.sqrt(2.0), t.size)
    flicker = lfilter([1.0], [1.0, -float(rng.uniform(0.9, 0.99))], rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.2, 0.4)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    spikes = rng.random(t.size) < rng.uniform(0.0, 2e-4)
    noise[spikes] += rng.uniform(4.0, 6.0, int(spikes.sum())) * sd * rng.choice([-1.0, 1.0], int(spikes.sum()))
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "air_conditioning_drift", "boxcar_average",
           "breakaway_friction", "cushion_contact", "generate_v", "minimum_jerk_bends", "rippled_isokinetic",
           "softening_leaf_spring", "stiffening_strap_give", "toe_region", "travel_since_reversal", "tremulous_contraction",
           "two_stage_stop", "warming_damper", "wobbling_acceleration"]
