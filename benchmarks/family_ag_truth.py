"""A thirty-third generator family for the diagnosis, written (2026-12-08, forty-first stop) before that stop's frozen
engine met the thirty-second family, nothing diagnosed on it; to be run once on the next change's frozen engine.

The second to thirty-second families (:mod:`benchmarks.family_b_truth` … ``family_af_truth``) are development data once
run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: the twenty-eighth family's weight error was the knee's
centre of rotation rolling with the angle, here the dynamometer's axis fixed beside the joint's; the thirty-second's stop
was Flores's contact and the second's Hunt–Crossley's, here Lankarani and Nikravesh's hysteresis factor with a contact
exponent drawn per trial; the fifteenth's delay held samples (a zero-order hold), here a running median. Nothing is
imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range Swanson's power-law solid in uniaxial tension, per unit modulus:
  (λ − λ⁻²)·(I₁/3)^α, I₁ = λ² + 2/λ (α 2–6), for the stretch λ = 1 + x̄/L (x̄ the softplus of the angle past an onset
  over 2–5°, L 0.3–1 × the end's reach); the steep end sized by its torque at the range's end, the onset toward a
  two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a cantilever whose free length
  shortens as its shell rolls onto the leg, stiffness k₀/(1 − θ/θ_m)³, so τ = k₀θ_m/2·((1 − θ̄/θ_m)⁻² − 1) (θ_m
  60–120°, θ̄ the softplus of the bend past an engagement of 0.5–2°).
- Motion: 3–5 cycles, each stroke between its own turning points (85–100 % of the range's ends), at its own speed of
  3–7 °/s along a cycloidal profile (the speed a raised cosine of the whole stroke's time, so its peak is twice its
  mean), held 0–1.5 s at each turn, a 0.5–1.5 s hold at the middle first. The AFO: 6–9 bends to depths drawn from
  10–20° in random order, each a cycloid of 0.6–1.5 s down and up, held 0.2–0.8 s at the bottom of the bend and
  resting 0.2–0.6 s between bends.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a grease-packed bearing after Herschel and Bulkley, a yield level plus a power-law part,
    sign(v)·(1 + h·(|v|/v_max)^p) smoothed by tanh(v/v₀) (h 0.1–0.3, p 0.3–0.6, v₀ 0.2–0.8 °/s); magnitude: its mean
    |F| over the moving samples;
  * damping: a dashpot with a check valve, its coefficient 1.3–2 × larger one way than the other (which way drawn);
    magnitude: the least-squares slope of its torque on θ̇;
  * stop: Lankarani and Nikravesh's contact, K·δⁿ·(1 + 3(1 − e²)/4·δ̇/v_ref) while compressing (the elastic part
    alone while released), n 1.0–2.2, e 0.4–0.9, v_ref 5 °/s, anywhere in the last 5–30 % of either end of a joint's
    range (the AFO's at the top of its bend); named only;
  * delay: a causal running median over 0.05–0.3 s (a spike filter in the logger) behind a transport delay of
    0–0.4 s; magnitude: the transport delay plus half the median's window;
  * activation: an ex-Gaussian burst (a Gaussian rise, σ 0.04–0.15 s, convolved with an exponential decay,
    0.1–0.6 s), starting anywhere in 12–80 % of the trial, of either sign; magnitude: its peak;
  * limb-weight error: the dynamometer's axis 1–3 cm from the joint's, in a direction drawn per trial: the weight's
    moment changes by m·g·d·cos(ψ − φ) (m the moving segments' mass, ψ the segment's direction); magnitude: its peak;
  * drift: a zero creeping as the square root of the time since an onset at 0–40 % of the trial (an adhesive or a
    gauge's diffusion-limited creep), of either sign; named only;
  * series compliance: a cuff on compacting soft tissue, a give c·τ_s·asinh(τ/τ_s) (linear at small torques,
    logarithmic at large; τ_s 20–60 % of the largest |τ|), c 0.03–0.15 °/N·m but at most 0.5 over the torque's
    stiffest rate; magnitude: the least-squares slope of the give on the torque;
  * inertia error: a mass coupled to the arm through a torsional spring (a two-mass system resonating at 6–15 Hz,
    damping ratio 0.1–0.3): its torque J·θ̈₂, θ₂ the arm's angle through that resonance; magnitude: the least-squares
    coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise whose SD grows with the torque's size
  (heteroscedastic: ∝ 1 + m·|τ|/max|τ|, m 0.3–1, scaled to the SD); the torque sampled 0.2–0.5 of a sample after the
  angle (the channels' skew); the encoder losing and regaining a count (1–5 single-sample glitches of one quantum);
  quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in
  runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.ndimage import median_filter
from scipy.signal import bilinear, lfilter
from scipy.stats import exponnorm

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
#: the contact's reference speed (deg/s) in Lankarani and Nikravesh's hysteresis factor
CONTACT_REFERENCE_DEG_S = 5.0


def swanson_tension(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, power: float) -> np.ndarray:
    """An end per unit modulus: (λ − λ⁻²)·(I₁/3)^α, I₁ = λ² + 2/λ, λ = 1 + x̄/L with x̄ the softplus of the angle
    ``x_deg`` past the onset over ``smoothing_deg``, L = ``reach_deg``, α = ``power``."""
    lam = 1.0 + softplus(x_deg, smoothing_deg) / reach_deg
    invariant = lam * lam + 2.0 / lam
    return np.asarray((lam - lam**-2) * (invariant / 3.0) ** power, dtype=float)


def rolling_cantilever(deg: np.ndarray, engage_deg: float, smoothing_deg: float, limit_deg: float) -> np.ndarray:
    """An orthosis per unit initial stiffness (N·m/deg): ½θ_m((1 − θ̄/θ_m)⁻² − 1), the integral of k₀/(1 − θ/θ_m)³,
    θ̄ the softplus (over ``smoothing_deg``) of the bend past ``engage_deg`` (zero at 0°), θ_m = ``limit_deg``."""
    d = np.asarray(deg, dtype=float)
    bend = softplus(d - engage_deg, smoothing_deg) - float(softplus(np.array(-engage_deg), smoothing_deg))
    share = np.clip(bend, 0.0, None) / limit_deg
    return np.asarray(0.5 * limit_deg * ((1.0 - share) ** -2 - 1.0), dtype=float)


def _cycloid(a: float, b: float, duration_s: float, rate: float) -> np.ndarray:
    """From ``a`` to ``b`` (deg) in ``duration_s`` along a cycloid (speed a raised cosine); samples after the start."""
    n = max(2, int(np.ceil(duration_s * rate)))
    u = np.arange(1, n + 1) / n
    return np.asarray(a + (b - a) * (u - np.sin(2.0 * np.pi * u) / (2.0 * np.pi)), dtype=float)


def cycloidal_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the middle, then 3–5 cycles, each stroke to its own turning point (85–100 %
    of the range's end) at its own mean speed of 3–7 °/s along a cycloid, held 0–1.5 s at each turn; back to the
    middle."""
    span, mid = hi - lo, 0.5 * (lo + hi)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    here = mid
    for _ in range(int(rng.integers(3, 6))):
        for side in (1.0, -1.0):
            target = mid + side * float(rng.uniform(0.85, 1.0)) * 0.5 * span
            speed = float(rng.uniform(3.0, 7.0))
            parts.append(_cycloid(here, target, abs(target - here) / speed, rate))
            parts.append(np.full(int(rng.uniform(0.0, 1.5) * rate), target))
            here = target
    parts.append(_cycloid(here, mid, abs(mid - here) / 5.0, rate))
    return np.concatenate(parts)


def shuffled_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 6–9 bends to depths drawn from 10–20° in random order, each a cycloid of
    0.6–1.5 s down and up, held 0.2–0.8 s at the bottom of the bend, resting 0.2–0.6 s between."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(6, 10))):
        depth = float(rng.uniform(10.0, 20.0))
        parts += [_cycloid(0.0, depth, float(rng.uniform(0.6, 1.5)), rate), np.full(int(rng.uniform(0.2, 0.8) * rate), depth),
                  _cycloid(depth, 0.0, float(rng.uniform(0.6, 1.5)), rate), np.zeros(int(rng.uniform(0.2, 0.6) * rate))]
    return np.concatenate(parts)


def herschel_bulkley_friction(vel_deg_s: np.ndarray, excess: float, power: float, smoothing_deg_s: float) -> np.ndarray:
    """A friction per unit yield level: tanh(v/v₀)·(1 + h·(|v|/v_max)^p), v_max the largest |v|."""
    v = np.asarray(vel_deg_s, dtype=float)
    top = max(float(np.max(np.abs(v))), 1e-12)
    return np.asarray(np.tanh(v / smoothing_deg_s) * (1.0 + excess * (np.abs(v) / top) ** power), dtype=float)


def check_valve_damper(vel: np.ndarray, ratio: float, stiffer_positive: bool) -> np.ndarray:
    """A dashpot per unit coefficient whose coefficient is ``ratio`` × larger when θ̇ is positive (``stiffer_positive``)
    or negative: b(sign θ̇)·θ̇."""
    v = np.asarray(vel, dtype=float)
    larger = v > 0.0 if stiffer_positive else v < 0.0
    return np.asarray(np.where(larger, ratio, 1.0) * v, dtype=float)


def lankarani_contact(deg: np.ndarray, vel_deg_s: np.ndarray, at_deg: float, high: bool, exponent: float,
                      restitution: float) -> np.ndarray:
    """A stop per unit contact stiffness (positive at the high end): δⁿ·(1 + 3(1 − e²)/4·δ̇/v_ref) while compressing,
    δⁿ while released, δ (deg) the angle past ``at_deg`` toward the end, v_ref :data:`CONTACT_REFERENCE_DEG_S`."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    closing = np.clip(sign * np.asarray(vel_deg_s, dtype=float), 0.0, None)
    hysteresis = 0.75 * (1.0 - restitution**2) * closing / CONTACT_REFERENCE_DEG_S
    return np.asarray(sign * depth**exponent * (1.0 + hysteresis), dtype=float)


def running_median(values: np.ndarray, rate: float, window_s: float) -> tuple[np.ndarray, float]:
    """(``values`` through a causal running median of ``window_s`` (an odd number of samples, at least 3; the first
    samples see the first value repeated), its delay in s: half the window less half a sample)."""
    w = max(3, int(round(window_s * rate)) | 1)
    x = np.asarray(values, dtype=float)
    padded = np.concatenate([np.full(w - 1, x[0]), x])
    centred = median_filter(padded, size=w, mode="nearest")
    half = (w - 1) // 2
    return np.asarray(centred[half:half + x.size], dtype=float), half / rate


def ex_gaussian(t: np.ndarray, start_s: float, rise_sd_s: float, decay_s: float) -> np.ndarray:
    """An ex-Gaussian pulse of unit peak: a Gaussian (SD ``rise_sd_s``) centred ``2·rise_sd_s`` after ``start_s``,
    convolved with an exponential decay of ``decay_s``."""
    shape = exponnorm.pdf(np.asarray(t, dtype=float), decay_s / rise_sd_s, loc=start_s + 2.0 * rise_sd_s, scale=rise_sd_s)
    return np.asarray(shape / max(float(np.max(shape)), 1e-300), dtype=float)


def misaligned_axis(direction_rad: np.ndarray, offset_direction_rad: float) -> np.ndarray:
    """The weight's moment error per unit m·g·d of an axis a distance d from the joint's: cos(ψ − φ)."""
    return np.asarray(np.cos(np.asarray(direction_rad, dtype=float) - offset_direction_rad), dtype=float)


def square_root_creep(t: np.ndarray, onset_s: float) -> np.ndarray:
    """A zero creeping from 0 at ``onset_s`` to 1 at the trial's end as the square root of the time since the onset."""
    tt = np.asarray(t, dtype=float)
    return np.asarray(np.sqrt(np.clip(tt - onset_s, 0.0, None) / max(float(tt[-1]) - onset_s, 1e-12)), dtype=float)


def compacting_cuff(torque: np.ndarray, compliance: float, scale_nm: float) -> np.ndarray:
    """A cuff's give (deg): c·τ_s·asinh(τ/τ_s), ``compliance`` c in deg/N·m, τ_s = ``scale_nm``."""
    return np.asarray(compliance * scale_nm * np.arcsinh(np.asarray(torque, dtype=float) / scale_nm), dtype=float)


def two_mass_angle(rad: np.ndarray, rate: float, natural_hz: float, damping_ratio: float) -> np.ndarray:
    """The angle (rad) of a mass coupled to the arm through a torsional spring: ``rad`` through ω²/(s² + 2ζωs + ω²)
    (the bilinear transform at ``rate``), started at rest on the first value."""
    w = 2.0 * np.pi * natural_hz
    b, a = bilinear([w * w], [1.0, 2.0 * damping_ratio * w, w * w], fs=rate)
    x = np.asarray(rad, dtype=float)
    out = lfilter(b, a, x - x[0])
    return np.asarray(out + x[0], dtype=float)


def heteroscedastic_noise(rng: np.random.Generator, torque: np.ndarray, sd: float) -> np.ndarray:
    """Gaussian noise whose SD grows with the torque's size, ∝ 1 + m·|τ|/max|τ| (m 0.3–1), scaled to RMS ``sd``."""
    size = np.abs(np.asarray(torque, dtype=float))
    scale = 1.0 + float(rng.uniform(0.3, 1.0)) * size / max(float(size.max()), 1e-12)
    scale = scale / np.sqrt(np.mean(scale**2))
    return np.asarray(rng.standard_normal(size.size) * scale * sd, dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return np.asarray(c["k"] * rolling_cantilever(deg, c["engage"], 0.5, c["limit"]), dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * swanson_tension(on_low - deg, c["smooth"], c["reach_low"], c["p_low"])
            + c["a_high"] * swanson_tension(deg - on_high, c["smooth"], c["reach_high"], c["p_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, limit = float(rng.uniform(0.5, 2.0)), float(rng.uniform(60.0, 120.0))
        unit = float(rolling_cantilever(np.array(15.0), engage, 0.5, limit))
        return {"engage": engage, "limit": limit, "k": float(rng.uniform(10.0, 25.0)) / unit}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(2.0, 5.0))
    c = {"reach_low": (on_low - lo) * float(rng.uniform(0.3, 1.0)), "reach_high": (hi - on_high) * float(rng.uniform(0.3, 1.0)),
         "p_low": float(rng.uniform(2.0, 6.0)), "p_high": float(rng.uniform(2.0, 6.0))}
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    c["a_low"] = t_low / float(swanson_tension(np.array(on_low - lo), smooth, c["reach_low"], c["p_low"]))
    c["a_high"] = t_high / float(swanson_tension(np.array(hi - on_high), smooth, c["reach_high"], c["p_high"]))
    return {**c, "smooth": smooth, "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ag(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((33, 33, 33), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: cycloidal_strokes(r, a, b, rate),
                                         lambda r: shuffled_bends(r, rate))
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
    if "series_compliance" in effects:  # a cuff on compacting soft tissue
        commanded = _elastic(kind, deg, fixed, coef)
        grid = np.linspace(float(deg.min()) - 5.0, float(deg.max()) + 5.0, 2001)
        stiffest = float(np.max(np.abs(np.gradient(_elastic(kind, grid, fixed, coef), grid))))
        c_give = min(float(rng.uniform(0.03, 0.15)), 0.5 / max(stiffest, 1e-9))
        scale = max(float(rng.uniform(0.2, 0.6)) * float(np.max(np.abs(commanded))), 1e-6)
        joint_deg = behind_strap(deg, lambda j: compacting_cuff(_elastic(kind, j, fixed, coef), c_give, scale))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, compaction_scale_Nm=scale)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the dynamometer's axis beside the joint's
        offset_direction = float(rng.uniform(-np.pi, np.pi))
        error = size() * float(rng.choice([-1.0, 1.0])) * unit_peak(misaligned_axis(load.direction_rad, offset_direction))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(axis_offset_direction_rad=offset_direction)
    if "coulomb_friction" in effects:
        unit = herschel_bulkley_friction(np.degrees(vel), float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.3, 0.6)),
                                         float(rng.uniform(0.2, 0.8)))
        friction = size() * unit_peak(unit)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        damping = size() * unit_peak(check_valve_damper(vel, float(rng.uniform(1.3, 2.0)), bool(rng.random() < 0.5)))
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        second = two_mass_angle(rad, rate, float(rng.uniform(6.0, 15.0)), float(rng.uniform(0.1, 0.3)))
        second_acc = np.gradient(np.gradient(second, t), t)
        error = size() * unit_peak(second_acc)  # a mass added: more inertia
        torque = torque + error
        truth["inertia"] = float(np.dot(acc, error) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = lankarani_contact(deg, np.degrees(vel), at, high_end, float(rng.uniform(1.0, 2.2)), float(rng.uniform(0.4, 0.9)))
        torque = torque + size() * unit_peak(unit)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", range_deg=(bottom, top))
    if "activation_burst" in effects:
        start = float(rng.uniform(0.12, 0.8)) * float(t[-1])
        shape = ex_gaussian(t, start, float(rng.uniform(0.04, 0.15)), float(rng.uniform(0.1, 0.6)))
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(burst_start_s=start)
    if "sensor_drift" in effects:
        onset = float(rng.uniform(0.0, 0.4)) * float(t[-1])
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * square_root_creep(t, onset)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = float(rng.uniform(0.0, 0.4))
        filtered, filter_delay = running_median(torque, rate, float(rng.uniform(0.05, 0.3)))
        torque = np.interp(t - latency, t, filtered, left=filtered[0])
        truth["time_delay"] = latency + filter_delay
    skew = float(rng.uniform(0.2, 0.5)) / rate  # the torque sampled after the angle
    torque = np.interp(t + skew, t, torque)
    read_rad = rad.copy()
    quantum = np.radians(float(rng.uniform(0.005, 0.03)))
    glitches = rng.integers(0, t.size, int(rng.integers(1, 6)))
    read_rad[glitches] += quantum * rng.choice([-1.0, 1.0], glitches.size)
    torque = torque + heteroscedastic_noise(rng, torque, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, read_rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "check_valve_damper", "compacting_cuff",
           "cycloidal_strokes", "ex_gaussian", "generate_ag", "herschel_bulkley_friction", "heteroscedastic_noise",
           "lankarani_contact", "misaligned_axis", "rolling_cantilever", "running_median", "shuffled_bends",
           "square_root_creep", "swanson_tension", "two_mass_angle"]
