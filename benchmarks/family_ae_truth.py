"""A thirty-first generator family for the diagnosis, written (2026-12-07, thirty-ninth stop) while the thirtieth family
waited for its one run on this stop's frozen engine, before any further engine change, nothing diagnosed on it; to be
run once on the next change's frozen engine.

The second to thirtieth families (:mod:`benchmarks.family_b_truth` … ``family_ad_truth``) are development data once
run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: limiting-extensibility ends were Gent's (fifth,
sixth and later families) and Arruda–Boyce's (twenty-third); here van der Waals's (Kilian's) form, its lock the
square root of the invariant's share. A triangle-wave drift is new (sawtooth, square and sinusoidal zeros were used).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a van der Waals (Kilian) network in uniaxial tension without its
  attraction term, per unit μ: (λ − λ⁻²)/(1 − η), η = √((I₁(λ) − 3)/(I₁(λ_m) − 3)), I₁ = λ² + 2/λ, for the stretch
  λ = 1 + x̄/L (x̄ the softplus of the angle past an onset over 2–5°, L 0.5–1.5 × the end's reach) with the locking
  stretch λ_m 1.3–1.6 × the stretch the range's end reaches; the steep end sized by its torque at the range's end, the
  onset toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: an elastic band over
  a cam whose radius changes with the bend, r(θ) = r₀(1 + e·θ/20°) (e −0.3…0.3): torque k·r(θ)·∫₀^θ̄ r dφ / r₀²
  past an engagement of 0.5–2° (softplus).
- Motion: 3–5 cycles between the range's ends (each end jittered by up to 3 % of the range), each stroke at its own
  speed drawn from 2–8 °/s with trapezoidal speed profiles (accelerating over 0.3–1 s), resting 0–2 s at each end, a
  0.5–1.5 s hold at the middle first. The AFO: 5–8 bends to 10–20°, each loaded quickly (a raised cosine over
  0.4–0.8 s) and released slowly (1–2 s), rested 0.3–1 s.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: Karnopp's stick band: within |v| < Δv (0.2–1 °/s) the friction rises linearly with the speed to a static
    level 1.2–1.6 × the sliding one, beyond it the sliding level, sign(v)·F_c (a drop at the band's edge); magnitude:
    its mean |F| over the moving samples;
  * damping: a Jeffreys body (a dashpot beside a Maxwell arm, Oldroyd-B at small strain): D + λ₁·Ḋ = b·(θ̇ + λ₂·θ̈)
    (λ₁ 0.05–0.4 s, λ₂ 0.2–0.6 × λ₁); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a magnetic catch: a linear contact past its angle, and within 0.5–2° before it an attraction pulling the
    joint in (its peak 10–25 % of the contact's peak, growing as the gap closes), anywhere in the last 5–30 % of
    either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.45 s behind a third-order elliptic (Cauer) low-pass (cut-off 3–15 Hz, 0.5–1 dB
    ripple, 40 dB stop band); magnitude: the transport delay plus the filter's group delay at 0.05 Hz;
  * activation: a Cauchy (Lorentzian) pulse, 1/(1 + ((t − t₀)/γ)²) (γ 0.08–0.3 s: heavy tails), its peak anywhere
    in 12–85 % of the trial, of either sign; magnitude: its peak;
  * limb-weight error: the segment's centre of mass off its axis: the weight's moment turned by a fixed angle, the
    error ∝ sin ψ beside the model's cos ψ; magnitude: its peak;
  * drift: a supply's ripple, a triangle wave of period 30–90 s, random phase; named only;
  * series compliance: a Burgers strap: an instant give c·τ, a delayed give (Kelvin–Voigt, 30–80 % of c, retardation
    0.2–1 s) and a slow flow (a dashpot whose give over the trial's mean |τ| and length is 10–30 % of c·|τ|max), c
    0.03–0.15 °/N·m but the instant and delayed gives at most 0.35 and the flow over the trial at most 0.15 over the
    torque's stiffest rate, so the joint's angle behind the strap is well defined; magnitude: the least-squares slope
    of the give on the torque;
  * inertia error: the dynamometer's motor seen through a non-circular gear, its ratio n(θ) = 1 + g·sin(2π(θ − θ₀)/P)
    (g 0.1–0.3, P 40–120°): torque J·n²·θ̈ + J·n·n'·θ̇²; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise with a pink part (1/f, 0.2–0.4 × the
  white SD); play of 0.02–0.06° in the encoder's coupling (the angle lags by it after each reversal); a constant torque
  gain error of ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped
  singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.signal import ellip, group_delay, lfilter

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


def van_der_waals_tension(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, locking_stretch: float
                          ) -> np.ndarray:
    """An end per unit μ: (λ − λ⁻²)/(1 − η), η = √((I₁(λ) − 3)/(I₁(λ_m) − 3)), I₁ = λ² + 2/λ, for λ = 1 + x̄/L with x̄
    the softplus of the angle ``x_deg`` past the onset over ``smoothing_deg``, L = ``reach_deg``, λ_m =
    ``locking_stretch`` (η held below 0.999)."""
    x = np.asarray(x_deg, dtype=float) / smoothing_deg
    lam = 1.0 + smoothing_deg * np.logaddexp(0.0, x) / reach_deg
    invariant = lam * lam + 2.0 / lam
    locked = locking_stretch**2 + 2.0 / locking_stretch  # I₁ where the network locks in uniaxial tension
    eta = np.minimum(np.sqrt(np.clip(invariant - 3.0, 0.0, None) / (locked - 3.0)), 0.999)
    return np.asarray((lam - lam**-2) / (1.0 - eta), dtype=float)


def band_over_cam(deg: np.ndarray, engage_deg: float, smoothing_deg: float, eccentricity: float) -> np.ndarray:
    """An orthosis's band over a cam per unit stiffness (N·m at r₀ = 1): r(θ̄)·∫₀^θ̄ r dφ with r = 1 + e·θ̄/20°, θ̄ the
    softplus (over ``smoothing_deg``) of the bend past ``engage_deg`` (deg, zero at 0°)."""
    d = np.asarray(deg, dtype=float)
    bend = smoothing_deg * (np.logaddexp(0.0, (d - engage_deg) / smoothing_deg)
                            - np.logaddexp(0.0, -engage_deg / smoothing_deg))
    radius = 1.0 + eccentricity * bend / 20.0
    stretch = bend + eccentricity * bend * bend / 40.0
    return np.asarray(radius * stretch, dtype=float)


def _trapezoid(a: float, b: float, speed: float, accel_s: float, rate: float) -> np.ndarray:
    """From ``a`` to ``b`` (deg) at ``speed`` °/s, the speed ramping up and down over ``accel_s`` (shortened on a
    short stroke); samples after the start."""
    distance = abs(b - a)
    ramp = min(accel_s, distance / max(speed, 1e-9))
    duration = distance / max(speed, 1e-9) + ramp
    n = max(2, int(np.ceil(duration * rate)))
    tt = np.arange(1, n + 1) / rate
    tt = tt * duration / tt[-1]
    # speed profile: a trapezoid (ramp, cruise, ramp), integrated and scaled to the distance exactly
    v = np.minimum.reduce([np.ones_like(tt), tt / max(ramp, 1e-9), (duration - tt) / max(ramp, 1e-9)])
    travelled = np.cumsum(np.clip(v, 0.0, None))
    return a + (b - a) * travelled / travelled[-1]


def varied_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the middle, then 3–5 cycles between the ends (each jittered by up to 3 % of
    the range, kept inside it), every stroke at its own speed of 2–8 °/s with trapezoidal profiles accelerating over
    0.3–1 s, resting 0–2 s at each end; back to the middle."""
    span, mid = hi - lo, 0.5 * (lo + hi)
    points = [mid]
    for _ in range(int(rng.integers(3, 6))):
        points += [hi - float(rng.uniform(0.0, 0.03)) * span, lo + float(rng.uniform(0.0, 0.03)) * span]
    points.append(mid)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    for a, b in zip(points[:-1], points[1:], strict=True):
        parts.append(_trapezoid(a, b, float(rng.uniform(2.0, 8.0)), float(rng.uniform(0.3, 1.0)), rate))
        parts.append(np.full(int(rng.uniform(0.0, 2.0) * rate), b))
    return np.concatenate(parts)


def quick_slow_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 5–8 bends to 10–20°, each loaded along a raised cosine over 0.4–0.8 s and
    released along one over 1–2 s, rested 0.3–1 s."""
    parts = [np.zeros(int(0.5 * rate))]

    def ramp(a: float, b: float, seconds: float) -> np.ndarray:
        s = np.arange(1, int(seconds * rate) + 1) / int(seconds * rate)
        return a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * s))

    for _ in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(10.0, 20.0))
        parts += [ramp(0.0, peak, float(rng.uniform(0.4, 0.8))), ramp(peak, 0.0, float(rng.uniform(1.0, 2.0))),
                  np.zeros(int(rng.uniform(0.3, 1.0) * rate))]
    return np.concatenate(parts)


def karnopp_friction(vel_deg_s: np.ndarray, band_deg_s: float, static_ratio: float) -> np.ndarray:
    """Karnopp's friction per unit sliding level: static_ratio·v/Δv within |v| < Δv, sign(v) beyond."""
    v = np.asarray(vel_deg_s, dtype=float)
    return np.asarray(np.where(np.abs(v) < band_deg_s, static_ratio * v / band_deg_s, np.sign(v)), dtype=float)


def jeffreys_damping(vel: np.ndarray, acc: np.ndarray, t: np.ndarray, relaxation_s: float, retardation_s: float
                     ) -> np.ndarray:
    """A Jeffreys body per unit b: D + λ₁·Ḋ = θ̇ + λ₂·θ̈, by exact first-order steps of the forcing held per sample."""
    forcing = np.asarray(vel, dtype=float) + retardation_s * np.asarray(acc, dtype=float)
    out = np.empty(forcing.size)
    state = float(forcing[0])
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    for i in range(forcing.size):
        state += (forcing[i] - state) * (1.0 - np.exp(-dt[i] / relaxation_s))
        out[i] = state
    return out


def magnetic_catch(deg: np.ndarray, at_deg: float, high: bool, reach_deg: float, pull_share: float) -> np.ndarray:
    """A stop per unit contact stiffness (positive at the high end): linear past ``at_deg``; within ``reach_deg`` before
    it an attraction toward it growing as the gap closes, (1 − gap/reach)², its peak ``pull_share`` × the contact's
    torque at one reach of compression."""
    sign = 1.0 if high else -1.0
    past = sign * (np.asarray(deg, dtype=float) - at_deg)
    contact = np.clip(past, 0.0, None)
    gap = np.clip(-past, 0.0, None)
    pull = np.where((past < 0.0) & (gap < reach_deg), pull_share * reach_deg * (1.0 - gap / reach_deg) ** 2, 0.0)
    return np.asarray(sign * (contact - pull), dtype=float)


def elliptic_low_pass(values: np.ndarray, rate: float, cutoff_hz: float, ripple_db: float) -> tuple[np.ndarray, float]:
    """(``values`` through a causal third-order elliptic low-pass of ``cutoff_hz`` with ``ripple_db`` of pass-band
    ripple and 40 dB of stop band, started at rest on the first value; its group delay at 0.05 Hz in s)."""
    b, a = ellip(3, ripple_db, 40.0, cutoff_hz / (0.5 * rate))
    x = np.asarray(values, dtype=float)
    filtered = lfilter(b, a, x - x[0]) + x[0]
    _, gd = group_delay((b, a), w=np.array([2.0 * np.pi * 0.05 / rate]))
    return np.asarray(filtered, dtype=float), float(gd[0]) / rate


def cauchy_pulse(t: np.ndarray, peak_s: float, half_width_s: float) -> np.ndarray:
    """A Lorentzian pulse per unit peak: 1/(1 + ((t − t₀)/γ)²)."""
    z = (np.asarray(t, dtype=float) - peak_s) / half_width_s
    return np.asarray(1.0 / (1.0 + z * z), dtype=float)


def triangle_zero(t: np.ndarray, period_s: float, phase: float) -> np.ndarray:
    """A triangle wave of ``period_s`` between −1 and 1, ``phase`` a share of its period."""
    u = (np.asarray(t, dtype=float) / period_s + phase) % 1.0
    return np.asarray(4.0 * np.abs(u - 0.5) - 1.0, dtype=float)


def burgers_give(torque: np.ndarray, t: np.ndarray, compliance: float, delayed_share: float, retardation_s: float,
                 flow_deg_per_nm_s: float) -> np.ndarray:
    """A Burgers strap's give (deg) under the torque history (N·m): c·τ, plus a Kelvin–Voigt give tending to
    ``delayed_share``·c·τ through ``retardation_s``, plus a flow of ``flow_deg_per_nm_s``·∫τ dt."""
    tau = np.asarray(torque, dtype=float)
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    delayed = np.empty(tau.size)
    state = 0.0
    for i in range(tau.size):
        state += (delayed_share * compliance * tau[i] - state) * (1.0 - np.exp(-dt[i] / retardation_s))
        delayed[i] = state
    return np.asarray(compliance * tau + delayed + flow_deg_per_nm_s * np.cumsum(tau * dt), dtype=float)


def behind_burgers_strap(deg: np.ndarray, t: np.ndarray, elastic: Callable[[np.ndarray], np.ndarray],
                         give: Callable[[np.ndarray], np.ndarray], tolerance_deg: float = 1e-7) -> np.ndarray:
    """The joint's angle j (deg) behind the strap: j = ``deg`` − give(τ(j)), τ = ``elastic`` (N·m), by fixed-point
    iteration to ``tolerance_deg`` (a contraction where the give's total rate times the torque's stiffest rate is below
    1, which the caller keeps ≤ 0.5); raises RuntimeError when it has not converged in 200 rounds."""
    joint = np.asarray(deg, dtype=float).copy()
    change = float("inf")
    for _ in range(200):
        following = deg - give(elastic(joint))
        change = float(np.max(np.abs(following - joint)))
        joint = following
        if change < tolerance_deg:
            return joint
    raise RuntimeError(f"the strap's fixed point did not converge (last change {change:.3g}°)")


def non_circular_gear(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, depth: float, period_rad: float,
                      phase_rad: float) -> np.ndarray:
    """A motor's inertia per unit J through a gear of ratio n(θ) = 1 + g·sin(2π(θ − θ₀)/P): n²·θ̈ + n·n'·θ̇²."""
    arg = 2.0 * np.pi * (np.asarray(rad, dtype=float) - phase_rad) / period_rad
    n = 1.0 + depth * np.sin(arg)
    dn = depth * 2.0 * np.pi / period_rad * np.cos(arg)
    return np.asarray(n * n * acc + n * dn * vel * vel, dtype=float)


def encoder_play(deg: np.ndarray, play_deg: float) -> np.ndarray:
    """The angle an encoder behind a coupling with ``play_deg`` of play reads: it follows only once the play is taken
    up after each reversal (a backlash element)."""
    d = np.asarray(deg, dtype=float)
    out = np.empty(d.size)
    reading = float(d[0])
    half = 0.5 * play_deg
    for i, value in enumerate(d):
        if value - reading > half:
            reading = value - half
        elif reading - value > half:
            reading = value + half
        out[i] = reading
    return out


def pink_noise(rng: np.random.Generator, n: int) -> np.ndarray:
    """Unit-SD noise whose spectrum falls as 1/f (white noise shaped in the frequency domain, its mean removed)."""
    spectrum = np.fft.rfft(rng.normal(0.0, 1.0, n))
    f = np.fft.rfftfreq(n)
    spectrum[1:] /= np.sqrt(f[1:])
    spectrum[0] = 0.0
    x = np.fft.irfft(spectrum, n)
    return np.asarray(x / max(float(np.std(x)), 1e-12), dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return np.asarray(c["k"] * band_over_cam(deg, c["engage"], 0.5, c["eccentricity"]), dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * van_der_waals_tension(on_low - deg, c["smooth"], c["reach_low"], c["lock_low"])
            + c["a_high"] * van_der_waals_tension(deg - on_high, c["smooth"], c["reach_high"], c["lock_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, eccentricity = float(rng.uniform(0.5, 2.0)), float(rng.uniform(-0.3, 0.3))
        return {"engage": engage, "eccentricity": eccentricity,
                "k": float(rng.uniform(10.0, 25.0)) / float(band_over_cam(np.array(15.0), engage, 0.5, eccentricity))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(2.0, 5.0))
    reach_low = (on_low - lo) * float(rng.uniform(0.5, 1.5))
    reach_high = (hi - on_high) * float(rng.uniform(0.5, 1.5))
    # the locking stretch 1.3–1.6 × the stretch each end reaches at the range's end (the other joint's coupling moves the
    # onset by a few degrees at most; the lock is far enough that η stays below 1 there)
    lam_low = 1.0 + (on_low - lo + 3.0 * smooth) / reach_low
    lam_high = 1.0 + (hi - on_high + 3.0 * smooth) / reach_high
    lock_low, lock_high = lam_low * float(rng.uniform(1.3, 1.6)), lam_high * float(rng.uniform(1.3, 1.6))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(van_der_waals_tension(np.array(on_low - lo), smooth, reach_low, lock_low)),
            "a_high": t_high / float(van_der_waals_tension(np.array(hi - on_high), smooth, reach_high, lock_high)),
            "reach_low": reach_low, "reach_high": reach_high, "lock_low": lock_low, "lock_high": lock_high,
            "smooth": smooth, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ae(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((31, 31, 31), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: varied_strokes(r, a, b, rate),
                                         lambda r: quick_slow_bends(r, rate))
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
    if "series_compliance" in effects:  # a Burgers strap
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give = float(rng.uniform(0.03, 0.15))
        delayed, retardation = float(rng.uniform(0.3, 0.8)), float(rng.uniform(0.2, 1.0))
        grid = np.linspace(float(deg.min()) - 5.0, float(deg.max()) + 5.0, 2001)
        stiffest = float(np.max(np.abs(np.gradient(_elastic(kind, grid, fixed, coef), grid))))
        # the gives' total rate (instant, delayed and the flow over the whole trial) at most half over the joint's
        # stiffest rate, so the joint's angle behind the strap is a contraction's fixed point (behind_burgers_strap)
        c_give = min(c_give, 0.35 / ((1.0 + delayed) * max(stiffest, 1e-9)))
        mean_abs = max(float(np.mean(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        flow = float(rng.uniform(0.1, 0.3)) * c_give * tau_max / (mean_abs * max(float(t[-1]), 1e-9))
        flow = min(flow, 0.15 / (max(stiffest, 1e-9) * max(float(t[-1]), 1e-9)))
        joint_deg = behind_burgers_strap(deg, t, lambda d: _elastic(kind, d, fixed, coef),
                                         lambda tau: burgers_give(tau, t, c_give, delayed, retardation, flow))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, delayed_share=delayed, retardation_s=retardation,
                       flow_deg_per_Nm_s=flow)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the centre of mass off the segment's axis
        unit = np.sin(load.direction_rad)
        error = size() * float(rng.choice([-1.0, 1.0])) * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = karnopp_friction(np.degrees(vel), float(rng.uniform(0.2, 1.0)), float(rng.uniform(1.2, 1.6)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        relaxation = float(rng.uniform(0.05, 0.4))
        unit = jeffreys_damping(vel, acc, t, relaxation, float(rng.uniform(0.2, 0.6)) * relaxation)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        unit = non_circular_gear(rad, vel, acc, float(rng.uniform(0.1, 0.3)), np.radians(float(rng.uniform(40.0, 120.0))),
                                 float(rng.uniform(0.0, 2.0 * np.pi)))
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["inertia"] = float(np.dot(acc, error) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = magnetic_catch(deg, at, high_end, float(rng.uniform(0.5, 2.0)), float(rng.uniform(0.1, 0.25)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low")
    if "activation_burst" in effects:
        peak_s = float(rng.uniform(0.12, 0.85)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * cauchy_pulse(t, peak_s, float(rng.uniform(0.08, 0.3)))
        truth["activation_burst"] = peak
        details.update(burst_peak_s=peak_s)
    if "sensor_drift" in effects:
        zero = triangle_zero(t, float(rng.uniform(30.0, 90.0)), float(rng.uniform(0.0, 1.0)))
        torque = torque + size() * zero
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = float(rng.uniform(0.0, 0.45))
        filtered, filter_delay = elliptic_low_pass(torque, rate, float(rng.uniform(3.0, 15.0)), float(rng.uniform(0.5, 1.0)))
        torque = np.interp(t - latency, t, filtered, left=filtered[0])
        truth["time_delay"] = latency + filter_delay
    read_deg = encoder_play(np.degrees(rad), float(rng.uniform(0.02, 0.06)))
    torque = (torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + rng.normal(0.0, sd, t.size)
              + float(rng.uniform(0.2, 0.4)) * sd * pink_noise(rng, t.size) + rng.uniform(-1.0, 1.0))
    stamp, angle, torque = damage_recording(rng, t, np.radians(read_deg), torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "band_over_cam", "behind_burgers_strap",
           "burgers_give", "cauchy_pulse", "elliptic_low_pass", "encoder_play", "generate_ae", "jeffreys_damping",
           "karnopp_friction", "magnetic_catch", "non_circular_gear", "pink_noise", "quick_slow_bends", "triangle_zero",
           "van_der_waals_tension", "varied_strokes"]
