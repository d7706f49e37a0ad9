"""A twenty-fifth generator family for the diagnosis, written (2026-12-07, thirty-fourth stop) after the twenty-fourth
family's run and before any further engine change, to be run once on the next change's frozen engine.

The second to twenty-fourth families (:mod:`benchmarks.family_b_truth` … ``family_x_truth``) are development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at 5c4279e; where an earlier family used a near relation it is said) and keeps every
nuisance below what the diagnosis should name. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range Fung's exponential of a *quadratic* strain measure, A·(e^{(x̄/w)²} − 1)
  (the strain energy of soft tissue, Fung 1967; earlier families' exponentials were of the stretch itself), x̄ the
  softplus of the angle past the onset over 1–3°, w set so the range's end reaches e^{1.2…2.5}; the steep end sized by
  its torque at the range's end, the onset toward a two-joint muscle moved by the other joint's angle (the scaffold's
  coupling); a small linear term. The AFO: a torsion bar in a rubber bushing, k·(θ + θ³/(3θ_c²)) (θ_c 15–30°; the
  baseline's spring is quadratic).
- Motion: isokinetic strokes whose set speed alternates between a slow (2–4 °/s) and a fast (5–9 °/s) one, each with
  trapezoidal velocity ramps of 0.2–0.6 s, holds of 0.5–1.5 s at the ends, 2–4 cycles after a 0.5–1.5 s hold, the
  path through the drive's servo (two equal real poles at 8–15 Hz). The AFO: 5–10 bends to 10–20°, each a raised
  cosine up (0.8–2 s) and down (1–2.5 s), every other bend held 0.2–0.6 s at 40–70 % of the way up (a re-grip), the
  same servo.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing's Coulomb friction rising with the load it carries, F₀·(1 + μ·|τ_e|/max|τ_e|) (μ 0.3–0.8, τ_e
    the passive moment), its sign through erf(θ̇/ε) (ε 0.2–0.8 °/s; the thirteenth and eighteenth families' friction
    also grew with load, through other laws); magnitude: its mean |F| over the moving samples;
  * damping: an orifice, b₁θ̇ + b₂θ̇|θ̇|, the quadratic part 30–60 % of the torque at the trial's peak speed (the
    seventeenth family had an orifice with a bypass); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a cubic (Duffing) contact, k·δ³ for δ past the stop, anywhere in the last 5–30 % of either end of a joint's
    range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.45 s behind two equal first-order poles (τ 5–40 ms each); magnitude: the transport
    delay plus 2τ (the group delay at low frequency);
  * activation: an alpha-function twitch, (u/τ)·e^{1 − u/τ} for u ≥ 0 (τ 0.08–0.3 s), starting anywhere in 10–85 % of
    the trial, of either sign; magnitude: its peak;
  * limb-weight error: the segment's mass entered wrong by a constant factor (the weight's moment scaled); magnitude:
    its peak;
  * drift: the bridge's self-heating: the squared torque through a first-order lag of 20–60 s, from its start value;
    named only;
  * series compliance: a strap whose slack is taken up, give c·τ₀·ln(1 + |τ|/τ₀)·sgn τ (τ₀ 0.2–0.6 × the largest
    torque: its give per N·m falls with load; the twenty-fourth family's softened); magnitude: the least-squares slope
    of the give on the torque;
  * inertia error: a weight hung on a spring from the segment (natural frequency 2–5 Hz, damping ratio 0.1–0.3), its
    reaction torque J·ÿ with y the angle through that second-order system (the ninth family's pendulum swung under
    gravity); magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise plus a pink (1/f-like) component, the sum of
  three AR(1) processes at 0.1, 1 and 10 s, at 0.3–0.5 × the noise SD; a constant torque gain error of ±1 %; quantised
  torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN
  cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import bilinear, lfilter
from scipy.special import erf

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

NOISE_SD_NM = {"afo": 0.06, "knee": 0.16, "ankle": 0.12}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)
#: the drive servo's corner frequencies (Hz): the commanded path through two equal real poles at one of them
SERVO_HZ = (8.0, 15.0)


def fung_end(x_deg: np.ndarray, onset_smoothing_deg: float, width_deg: float) -> np.ndarray:
    """Fung's exponential of a quadratic strain per unit amplitude: e^{(x̄/w)²} − 1, x̄ = s·ln(1 + e^{x/s}) the
    softplus of the angle ``x_deg`` past the onset over ``onset_smoothing_deg`` s (deg), w = ``width_deg``."""
    x = np.asarray(x_deg, dtype=float) / onset_smoothing_deg
    smooth = onset_smoothing_deg * np.logaddexp(0.0, x)
    return np.expm1((smooth / width_deg) ** 2)


def torsion_bar(deg: np.ndarray, cubic_deg: float) -> np.ndarray:
    """An orthosis's torsion bar in a rubber bushing per unit stiffness: θ + θ³/(3θ_c²) for θ ≥ 0 (deg), 0 below."""
    th = np.clip(np.asarray(deg, dtype=float), 0.0, None)
    return th + th**3 / (3.0 * cubic_deg**2)


def servo(deg: np.ndarray, rate: float, corner_hz: float) -> np.ndarray:
    """The commanded path (deg) through two equal real poles at ``corner_hz``, started at rest at the first value."""
    a = float(np.exp(-2.0 * np.pi * corner_hz / rate))
    out = np.asarray(deg, dtype=float)
    for _ in range(2):
        out = lfilter([1.0 - a], [1.0, -a], out, zi=[a * out[0]])[0]
    return np.asarray(out, dtype=float)


def _trapezoid_stroke(start: float, end: float, speed: float, ramp_s: float, rate: float) -> np.ndarray:
    """A stroke (deg) from ``start`` to ``end`` at ``speed`` °/s with linear velocity ramps of ``ramp_s`` (shortened
    when the stroke is too short for them), excluding its first sample, ending exactly at ``end``."""
    span = abs(end - start)
    ramp = min(ramp_s, span / speed)
    duration = span / speed + ramp  # the ramps each lose half a ramp's travel
    n = max(2, int(np.ceil(duration * rate)))
    u = np.arange(1, n + 1) / rate
    v = speed * np.clip(np.minimum(u, duration - u) / max(ramp, 1e-9), 0.0, 1.0)
    travel = np.cumsum(v) / rate
    travel *= span / travel[-1]
    return start + np.sign(end - start) * travel


def alternating_speed_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at ``lo``, then 2–4 cycles of strokes to ``hi`` and back, their set speed
    alternating between a slow (2–4 °/s) and a fast (5–9 °/s) one, trapezoidal velocity ramps of 0.2–0.6 s, holds of
    0.5–1.5 s at each end; the path through the drive's servo."""
    slow, fast = float(rng.uniform(2.0, 4.0)), float(rng.uniform(5.0, 9.0))
    ramp = float(rng.uniform(0.2, 0.6))
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), lo)]
    for i in range(2 * int(rng.integers(2, 5))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        parts.append(_trapezoid_stroke(start, end, slow if i % 2 == 0 else fast, ramp, rate))
        parts.append(np.full(int(rng.uniform(0.5, 1.5) * rate), end))
    return servo(np.concatenate(parts), rate, float(rng.uniform(*SERVO_HZ)))


def regrip_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–10 bends to 10–20°, each a raised cosine up over 0.8–2 s and down over 1–2.5 s, every other
    bend held 0.2–0.6 s at 40–70 % of the way up; 0.4 s at 0° before, between and after; the drive's servo."""
    parts = [np.zeros(int(0.4 * rate))]
    for k in range(int(rng.integers(5, 11))):
        peak = float(rng.uniform(10.0, 20.0))
        legs = [(0.0, peak, (0.8, 2.0))]
        if k % 2 == 1:
            mid = float(rng.uniform(0.4, 0.7)) * peak
            legs = [(0.0, mid, (0.4, 1.0)), (mid, peak, (0.4, 1.0))]
        for i, (a, b, span) in enumerate(legs):
            n = max(2, int(rng.uniform(*span) * rate))
            s = np.arange(1, n + 1) / n
            parts.append(a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * s)))
            if len(legs) == 2 and i == 0:
                parts.append(np.full(int(rng.uniform(0.2, 0.6) * rate), mid))
        n = max(2, int(rng.uniform(1.0, 2.5) * rate))
        s = np.arange(1, n + 1) / n
        parts.append(peak * 0.5 * (1.0 + np.cos(np.pi * s)))
        parts.append(np.zeros(int(0.4 * rate)))
    return servo(np.concatenate(parts), rate, float(rng.uniform(*SERVO_HZ)))


def load_dependent_friction(vel_deg_s: np.ndarray, load_nm: np.ndarray, rise: float, epsilon_deg_s: float
                            ) -> np.ndarray:
    """A bearing's friction per unit unloaded level: (1 + μ·|τ_e|/max|τ_e|)·erf(θ̇/ε), μ = ``rise``."""
    load = np.abs(np.asarray(load_nm, dtype=float))
    level = 1.0 + rise * load / max(float(load.max()), 1e-12)
    return level * erf(np.asarray(vel_deg_s, dtype=float) / epsilon_deg_s)


def orifice_damper(vel: np.ndarray, quadratic_share: float) -> np.ndarray:
    """An orifice's torque per unit linear coefficient: θ̇ + b₂θ̇|θ̇|, b₂ set so the quadratic part is
    ``quadratic_share`` of the torque at the peak speed (the 95th percentile of |θ̇|)."""
    peak = max(float(np.percentile(np.abs(vel), 95.0)), 1e-12)
    b2 = quadratic_share / (1.0 - quadratic_share) / peak
    return vel + b2 * vel * np.abs(vel)


def cubic_stop(deg: np.ndarray, at_deg: float, high: bool) -> np.ndarray:
    """A stop per unit stiffness toward the range's inside (positive at the high end): δ³, δ the depth past
    ``at_deg`` (deg)."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    return sign * depth**3


def two_pole_delay(torque: np.ndarray, transport_s: float, pole_s: float, rate: float) -> tuple[np.ndarray, float]:
    """(the torque delayed by ``transport_s`` (whole samples; the first value held before) and through two equal
    first-order poles of ``pole_s`` each, started at rest at its first value; the group delay at low frequency in s:
    the shift plus each pole's a/(1 − a) samples)."""
    shift = int(round(transport_s * rate))
    out = np.concatenate([np.full(shift, torque[0]), torque[:torque.size - shift]]) if shift else torque.copy()
    a = float(np.exp(-1.0 / (pole_s * rate)))
    for _ in range(2):
        out = np.asarray(lfilter([1.0 - a], [1.0, -a], out, zi=[a * out[0]])[0], dtype=float)
    return out, (shift + 2.0 * a / (1.0 - a)) / rate


def alpha_twitch(t: np.ndarray, start_s: float, tau_s: float) -> np.ndarray:
    """An alpha-function twitch of peak 1 at u = τ: (u/τ)·e^{1 − u/τ} for u = t − ``start_s`` ≥ 0, 0 before."""
    u = np.clip(t - start_s, 0.0, None) / tau_s
    return u * np.exp(1.0 - u)


def self_heating(torque: np.ndarray, t: np.ndarray, lag_s: float) -> np.ndarray:
    """The bridge's self-heating per unit: the squared torque through a first-order lag of ``lag_s`` (started at
    its first value), minus that start value, largest excursion 1."""
    dt = float(np.median(np.diff(t)))
    b = 1.0 - float(np.exp(-dt / lag_s))
    power = np.asarray(torque, dtype=float) ** 2
    heat = np.asarray(lfilter([b], [1.0, b - 1.0], power, zi=[(1.0 - b) * power[0]])[0], dtype=float)
    heat = heat - power[0]
    return heat / max(float(np.max(np.abs(heat))), 1e-12)


def slack_strap_give(torque: np.ndarray, compliance: float, slack_nm: float) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ₀·ln(1 + |τ|/τ₀)·sgn τ, τ₀ = ``slack_nm`` (slope c at zero load,
    falling with load)."""
    return np.sign(torque) * compliance * slack_nm * np.log1p(np.abs(torque) / slack_nm)


def hung_weight(rad: np.ndarray, rate: float, natural_hz: float, damping_ratio: float) -> np.ndarray:
    """The acceleration (rad/s²) of a weight hung on a spring from the segment, ÿ with y the angle ``rad`` through
    ÿ + 2ζω ẏ + ω² y = 2ζω θ̇ + ω² θ (a spring and a dashpot to the segment), by the bilinear transform; started at
    rest at the first angle."""
    w = 2.0 * np.pi * natural_hz
    b, a = bilinear([2.0 * damping_ratio * w, w * w], [1.0, 2.0 * damping_ratio * w, w * w], fs=rate)
    theta = np.asarray(rad, dtype=float)
    y = lfilter(b, a, theta - theta[0]) + theta[0]
    t = np.arange(theta.size) / rate
    return np.gradient(np.gradient(y, t), t)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * torsion_bar(deg, c["cubic"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * fung_end(on_low - deg, c["smooth"], c["w_low"])
            + c["a_high"] * fung_end(deg - on_high, c["smooth"], c["w_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        cubic = float(rng.uniform(15.0, 30.0))
        return {"cubic": cubic, "k": float(rng.uniform(10.0, 25.0)) / float(torsion_bar(np.array(15.0), cubic))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(1.0, 3.0))
    # the width: the range's end (with the coupling's largest shift, 0.2 × 45°) reaches an exponent of 1.2–2.5
    reach_low, reach_high = on_low - lo + 9.0, hi - on_high + 9.0
    w_low = reach_low / np.sqrt(rng.uniform(1.2, 2.5))
    w_high = reach_high / np.sqrt(rng.uniform(1.2, 2.5))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(fung_end(np.array(on_low - lo), smooth, w_low)),
            "a_high": t_high / float(fung_end(np.array(hi - on_high), smooth, w_high)),
            "w_low": float(w_low), "w_high": float(w_high), "smooth": smooth, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def _rig_noise(rng: np.random.Generator, t: np.ndarray, sd: float) -> np.ndarray:
    """Gaussian noise plus a pink-like component (three AR(1) processes of time constants 0.1, 1 and 10 s, equal
    variance) at 0.3–0.5 × ``sd``, N·m."""
    dt = float(np.median(np.diff(t)))
    pink = np.zeros(t.size)
    for tau in (0.1, 1.0, 10.0):
        a = float(np.exp(-dt / tau))
        pink += lfilter([np.sqrt(1.0 - a * a)], [1.0, -a], rng.normal(0.0, 1.0, t.size),
                        zi=[a * float(rng.normal())])[0]
    return rng.normal(0.0, sd, t.size) + float(rng.uniform(0.3, 0.5)) * sd * pink / max(float(np.std(pink)), 1e-12)


def generate_y(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((25, 25, 25), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: alternating_speed_strokes(r, a, b, rate),
                                         lambda r: regrip_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap whose slack is taken up
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, slack = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.2, 0.6)) * tau_max
        joint_deg = behind_strap(deg, lambda d: slack_strap_give(_elastic(kind, d, fixed, coef), c_give, slack))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, slack_Nm=slack)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    elastic = _elastic(kind, joint_deg, fixed, coef)
    torque = elastic + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the segment's mass entered wrong
        error = size() * load.moment_nm / max(float(np.max(np.abs(load.moment_nm))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = load_dependent_friction(np.degrees(vel), elastic, float(rng.uniform(0.3, 0.8)),
                                       float(rng.uniform(0.2, 0.8)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        unit = orifice_damper(vel, float(rng.uniform(0.3, 0.6)))
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        hung = hung_weight(rad, rate, float(rng.uniform(2.0, 5.0)), float(rng.uniform(0.1, 0.3)))
        pad = size() * hung / max(float(np.max(np.abs(hung))), 1e-12)
        torque = torque + pad
        truth["inertia"] = float(np.dot(acc, pad) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = cubic_stop(deg, at, high_end)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * alpha_twitch(t, start, float(rng.uniform(0.08, 0.3)))
        truth["activation_burst"] = peak
        details.update(twitch_start_s=start)
    if "sensor_drift" in effects:
        torque = torque + size() * self_heating(torque, t, float(rng.uniform(20.0, 60.0)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, group_delay = two_pole_delay(torque, float(rng.uniform(0.0, 0.45)), float(rng.uniform(0.005, 0.04)),
                                             rate)
        truth["time_delay"] = group_delay
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + _rig_noise(rng, t, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "alpha_twitch", "alternating_speed_strokes",
           "cubic_stop", "fung_end", "generate_y", "hung_weight", "load_dependent_friction", "orifice_damper",
           "regrip_bends", "self_heating", "servo", "slack_strap_give", "torsion_bar", "two_pole_delay"]
