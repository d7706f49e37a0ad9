"""A twenty-fourth generator family for the diagnosis, written (2026-11-30, thirty-second stop) before that stop's engine
change and held out from it, to be run once on its frozen engine.

The second to twenty-third families (:mod:`benchmarks.family_b_truth` … ``family_w_truth``) are development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at a4852f5; where an earlier family used a near relation it is said) and keeps every
nuisance below what the diagnosis should name. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range an eight-chain rubber network (Arruda & Boyce 1993), per unit
  stiffness L·ℒ⁻¹(s/L)/3 with the inverse Langevin function in Cohen's Padé form y(3 − y²)/(1 − y²), s the stretch
  past the onset and L the locking stretch; the fibres' onsets normally distributed (SD 1–4°), so the stretch is the
  expected one, s = σ·φ(x/σ) + x·Φ(x/σ) (smooth where it engages; the twenty-third family spread them along a softplus);
  L set so the range's end reaches 55–80 % of it; the steep end sized by its torque at the range's end, the onset
  toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a spring through a cam,
  k·θ·(1 + a·sin(πθ/θ_c)) (a 0.05–0.15, θ_c 1.1–1.5 × the largest bend).
- Motion: critically damped approach strokes (a position servo's step response, θ = b + (a − b)(1 + u/τ)e^{−u/τ},
  scaled to end at b, τ set by a mean speed of 3–8 °/s per stroke), holds of 0.3–2 s at each end, 2–4 cycles after a
  0.5–1.5 s hold, the whole path through the drive's bandwidth (a Hann window of 0.1 s). The AFO: 6–12 bends to
  10–20°, each loaded quickly (0.6–1.5 s) and released slowly (1.5–3.5 s) along a half-cosine, resting 0–0.5 s at
  0–2° between them, through the same window.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb friction along a rough track, its level F₀·(1 + r·ρ(θ)) with ρ a smooth random profile of the
    angle (Gaussian, correlation length 2–6°, unit RMS, r 0.2–0.4, the level kept ≥ 0.2·F₀), its sign through
    tanh(θ̇/ε) (ε 0.3–1 °/s; the thirteenth family's level rippled periodically with the angle, the twentieth's rose
    over one rough spot, the twenty-first's followed a worn gear's period); magnitude: its mean |F| over the moving
    samples;
  * damping: a dashpot thinned by its own heating: b(t) = b₀·(1 − h·E(t)), E the dissipated power b₀θ̇² through a
    first-order lag of 10–40 s normalised to its largest value, h 0.2–0.45 (the twenty-second family's oil warmed
    steadily with time); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a stop behind a soft liner, k·δ²/(δ + δ_l) (quadratic at first contact, linear past δ_l 0.5–2°), anywhere in
    the last 5–30 % of either end of a joint's range (the AFO's at the top of its bend; a stop reached by less than 4°
    has its liner shrunk by the reach over 4°); named only;
  * delay: a transport delay of 0–0.4 s behind a causal half-Gaussian smoother (its kernel e^{−k²/(2σ²)} over the
    samples before, σ 10–80 ms, cut at 4σ); magnitude: the transport delay plus the kernel's mean lag;
  * activation: a biexponential (Bateman) pulse e^{−u/τ₂} − e^{−u/τ₁} (τ₁ 0.03–0.15 s, τ₂ 0.2–0.8 s), of either sign;
    magnitude: its peak;
  * limb-weight error: a cold pack strapped to the segment melting and dripping away, its weight's moment (the
    segment's own moment's shape) decaying as e^{−t/τ} (τ 30–120 % of the trial; the twenty-third family's sleeve took
    a share growing as 1 − e^{−t/τ}); magnitude: its peak;
  * drift: the bridge following the room through two thermal masses: an Ornstein–Uhlenbeck wander (τ 15–60 s) through a
    first-order lag of 5–20 s, minus its mean; named only;
  * series compliance: a strap softening exponentially with load, give c·τ₀·(e^{|τ|/τ₀} − 1)·sgn τ (τ₀ 0.5–1.5 × the
    largest torque); magnitude: the least-squares slope of the give on the torque;
  * inertia error: a pad held to the segment by its grip, carried (J·θ̈) until its inertial torque reaches the grip
    (50–80 % of its largest J·θ̈), slipping at the grip beyond; magnitude: the least-squares coefficient of its
    torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise plus an AR(1) component (φ 0.5–0.9, at
  0.3–0.5 × the noise SD); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast or slow by
  up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time
  included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import lfilter
from scipy.special import ndtr

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
#: the drive's bandwidth: the commanded path through a Hann window of this length (s)
DRIVE_WINDOW_S = 0.1


def expected_stretch(x_deg: np.ndarray, spread_deg: float) -> np.ndarray:
    """The mean stretch (deg) of fibres whose onsets are normally distributed about 0 with SD ``spread_deg``, at an
    angle ``x_deg`` past the mean onset: σ·φ(x/σ) + x·Φ(x/σ) (→ max(x, 0) as σ → 0)."""
    x = np.asarray(x_deg, dtype=float)
    z = x / spread_deg
    return spread_deg * np.exp(-0.5 * z * z) / np.sqrt(2.0 * np.pi) + x * ndtr(z)


def eight_chain(stretch_deg: np.ndarray, locking_deg: float) -> np.ndarray:
    """An eight-chain network per unit stiffness: L·ℒ⁻¹(s/L)/3 with Cohen's Padé ℒ⁻¹(y) ≈ y(3 − y²)/(1 − y²), slope 1
    at s = 0 (only s < L is meaningful)."""
    y = np.asarray(stretch_deg, dtype=float) / locking_deg
    return locking_deg * y * (3.0 - y * y) / (1.0 - y * y) / 3.0


def cam_spring(deg: np.ndarray, ripple: float, cam_deg: float) -> np.ndarray:
    """An orthosis's spring through a cam per unit stiffness: θ·(1 + a·sin(πθ/θ_c)) for θ ≥ 0 (deg), 0 below."""
    th = np.clip(np.asarray(deg, dtype=float), 0.0, None)
    return th * (1.0 + ripple * np.sin(np.pi * th / cam_deg))


def drive_bandwidth(deg: np.ndarray, rate: float) -> np.ndarray:
    """The commanded path (deg) through a Hann window of :data:`DRIVE_WINDOW_S` (the ends held, so the path starts
    and ends where it was commanded)."""
    n = max(3, int(round(DRIVE_WINDOW_S * rate)) | 1)
    window = np.hanning(n + 2)[1:-1]
    padded = np.concatenate([np.full(n, deg[0]), deg, np.full(n, deg[-1])])
    return np.convolve(padded, window / window.sum(), mode="same")[n:-n]


def critically_damped_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 2–4 cycles from ``lo`` to ``hi`` and back after a 0.5–1.5 s hold: each stroke a servo's
    critically damped approach a + (b − a)·(1 − (1 + x)e^{−x})/(1 − (1 + X)e^{−X}), x = u/τ up to X = 7 (the
    approach within 0.7 % of the span before it is scaled to end at b), τ set by a mean speed of 3–8 °/s drawn per
    stroke; a hold of 0.3–2 s after each; the path through the drive's bandwidth."""
    end_x = 7.0
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), lo)]
    for i in range(2 * int(rng.integers(2, 5))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        duration = abs(end - start) / float(rng.uniform(3.0, 8.0))
        n = int(np.ceil(duration * rate))
        x = end_x * np.arange(1, n + 1) / n
        shape = (1.0 - (1.0 + x) * np.exp(-x)) / (1.0 - (1.0 + end_x) * np.exp(-end_x))
        parts.append(start + (end - start) * shape)
        parts.append(np.full(int(rng.uniform(0.3, 2.0) * rate), end))
    return drive_bandwidth(np.concatenate(parts), rate)


def quick_load_slow_release_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 6–12 bends to 10–20°, each loaded along a half-cosine over 0.6–1.5 s and released over
    1.5–3.5 s, resting 0–0.5 s at 0–2° between them (0° before the first and after the last); through the drive's
    bandwidth."""
    count = int(rng.integers(6, 13))
    parts = [np.zeros(int(0.4 * rate))]
    base = 0.0
    for k in range(count):
        peak = float(rng.uniform(10.0, 20.0))
        back = 0.0 if k == count - 1 else float(rng.uniform(0.0, 2.0))
        for a, b, span in ((base, peak, (0.6, 1.5)), (peak, back, (1.5, 3.5))):
            n = max(2, int(rng.uniform(*span) * rate))
            s = np.arange(1, n + 1) / n
            parts.append(a + (b - a) * 0.5 * (1.0 - np.cos(np.pi * s)))
        parts.append(np.full(int(rng.uniform(0.0, 0.5) * rate), back))
        base = back
    parts.append(np.zeros(int(0.4 * rate)))
    return drive_bandwidth(np.concatenate(parts), rate)


def rough_track_friction(rng: np.random.Generator, deg: np.ndarray, vel_deg_s: np.ndarray, roughness: float,
                         correlation_deg: float, epsilon_deg_s: float) -> np.ndarray:
    """A friction per unit mean level along a rough track: (1 + r·ρ(θ))·tanh(θ̇/ε), ρ a Gaussian random profile of
    the angle with correlation length ``correlation_deg`` (white noise on a 0.1° grid smoothed by a Gaussian of SD
    ℓ/√2, so its autocorrelation is e^{−Δ²/(2ℓ²)}), scaled to unit RMS over the grid; the level kept ≥ 0.2."""
    deg = np.asarray(deg, dtype=float)
    step = 0.1
    grid = np.arange(float(deg.min()) - 5.0 * correlation_deg, float(deg.max()) + 5.0 * correlation_deg + step, step)
    sd = correlation_deg / np.sqrt(2.0) / step
    k = np.arange(-int(np.ceil(4.0 * sd)), int(np.ceil(4.0 * sd)) + 1)
    kernel = np.exp(-0.5 * (k / sd) ** 2)
    profile = np.convolve(rng.normal(0.0, 1.0, grid.size), kernel, mode="same")
    inner = slice(k.size, grid.size - k.size)
    profile = (profile - profile[inner].mean()) / max(float(profile[inner].std()), 1e-12)
    level = np.clip(1.0 + roughness * np.interp(deg, grid, profile), 0.2, None)
    return level * np.tanh(np.asarray(vel_deg_s, dtype=float) / epsilon_deg_s)


def heating_dashpot(vel: np.ndarray, rate: float, thinning: float, lag_s: float) -> np.ndarray:
    """A dashpot per unit cold coefficient thinned by its own heating: (1 − h·E)·θ̇, E the power θ̇² through a
    first-order lag of ``lag_s`` (from cold) over its largest value."""
    alpha = 1.0 - np.exp(-1.0 / (lag_s * rate))
    heat = np.asarray(lfilter([alpha], [1.0, alpha - 1.0], vel * vel), dtype=float)
    return (1.0 - thinning * heat / max(float(heat.max()), 1e-30)) * vel


def lined_stop(deg: np.ndarray, at_deg: float, high: bool, liner_deg: float) -> np.ndarray:
    """A stop per unit stiffness toward the range's inside (positive at the high end), δ its depth past ``at_deg``:
    δ²/(δ + δ_l), δ_l = ``liner_deg``."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    return sign * depth * depth / (depth + liner_deg)


def half_gaussian_smoother(torque: np.ndarray, transport_s: float, sigma_s: float, rate: float
                           ) -> tuple[np.ndarray, float]:
    """(the torque delayed by ``transport_s`` (whole samples; the first value held before) and smoothed by a causal
    half-Gaussian kernel of SD ``sigma_s`` cut at 4σ; the group delay at low frequency in s: the shift plus the
    kernel's mean lag)."""
    shift = int(round(transport_s * rate))
    delayed = np.concatenate([np.full(shift, torque[0]), torque[:torque.size - shift]]) if shift else torque.copy()
    k = np.arange(int(np.ceil(4.0 * sigma_s * rate)) + 1)
    kernel = np.exp(-0.5 * (k / (sigma_s * rate)) ** 2)
    kernel /= kernel.sum()
    padded = np.concatenate([np.full(k.size - 1, delayed[0]), delayed])
    out = np.convolve(padded, kernel, mode="valid")
    return out, (shift + float(np.dot(k, kernel))) / rate


def bateman_pulse(t: np.ndarray, start_s: float, rise_s: float, decay_s: float) -> np.ndarray:
    """A biexponential pulse of peak 1: e^{−u/τ₂} − e^{−u/τ₁} for u = t − ``start_s`` ≥ 0 (τ₁ = ``rise_s`` <
    τ₂ = ``decay_s``), 0 before."""
    u = np.clip(t - start_s, 0.0, None)
    shape = np.exp(-u / decay_s) - np.exp(-u / rise_s)
    u_peak = np.log(decay_s / rise_s) * rise_s * decay_s / (decay_s - rise_s)
    return shape / (np.exp(-u_peak / decay_s) - np.exp(-u_peak / rise_s))


def melting_share(t: np.ndarray, tau_s: float) -> np.ndarray:
    """The share (1 → 0) of a cold pack's weight left as it melts and drips: e^{−(t − t₀)/τ}."""
    return np.exp(-(t - t[0]) / tau_s)


def thermal_wander(rng: np.random.Generator, t: np.ndarray, wander_s: float, lag_s: float) -> np.ndarray:
    """An Ornstein–Uhlenbeck wander of time constant ``wander_s`` through a first-order lag of ``lag_s``, minus its
    mean, largest excursion 1."""
    dt = float(np.median(np.diff(t)))
    a = np.exp(-dt / wander_s)
    ou = lfilter([np.sqrt(1.0 - a * a)], [1.0, -a], rng.normal(0.0, 1.0, t.size), zi=[a * float(rng.normal())])[0]
    b = 1.0 - np.exp(-dt / lag_s)
    y = np.asarray(lfilter([b], [1.0, b - 1.0], ou, zi=[(1.0 - b) * float(ou[0])])[0], dtype=float)
    y = y - y.mean()
    return y / max(float(np.max(np.abs(y))), 1e-12)


def softening_strap_give(torque: np.ndarray, compliance: float, softening_nm: float) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ₀·(e^{|τ|/τ₀} − 1)·sgn τ, τ₀ = ``softening_nm`` (slope c at zero
    load)."""
    return np.sign(torque) * compliance * softening_nm * np.expm1(np.abs(torque) / softening_nm)


def gripped_pad(acc: np.ndarray, inertia: float, grip_nm: float) -> np.ndarray:
    """The pad's torque (N·m): J·θ̈ while it is carried, the grip once its inertial torque would pass it."""
    return np.clip(inertia * np.asarray(acc, dtype=float), -grip_nm, grip_nm)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * cam_spring(deg, c["ripple"], c["cam"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * eight_chain(expected_stretch(on_low - deg, c["spread"]), c["lock_low"])
            + c["a_high"] * eight_chain(expected_stretch(deg - on_high, c["spread"]), c["lock_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float, top: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        ripple, cam = float(rng.uniform(0.05, 0.15)), float(rng.uniform(1.1, 1.5)) * top
        return {"ripple": ripple, "cam": cam,
                "k": float(rng.uniform(10.0, 25.0)) / float(cam_spring(np.array(15.0), ripple, cam))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    spread = float(rng.uniform(1.0, 4.0))
    # the locking stretch: the range's end reaches 55–80 % of it (the onset may move by the coupling, up to 0.2 × 45°,
    # and the spread adds up to σ/√(2π) at the onset; measured from the farthest stretch so the chain never locks)
    reach_low, reach_high = on_low - lo + 9.0 + spread, hi - on_high + 9.0 + spread
    lock_low, lock_high = reach_low / rng.uniform(0.55, 0.8), reach_high / rng.uniform(0.55, 0.8)
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(eight_chain(expected_stretch(np.array(on_low - lo), spread), lock_low)),
            "a_high": t_high / float(eight_chain(expected_stretch(np.array(hi - on_high), spread), lock_high)),
            "lock_low": lock_low, "lock_high": lock_high, "spread": spread, "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def _rig_noise(rng: np.random.Generator, t: np.ndarray, sd: float) -> np.ndarray:
    """Gaussian noise plus an AR(1) component (φ 0.5–0.9) at 0.3–0.5 × ``sd``, N·m."""
    phi = float(rng.uniform(0.5, 0.9))
    coloured = lfilter([1.0], [1.0, -phi], rng.normal(0.0, 1.0, t.size))
    return rng.normal(0.0, sd, t.size) + float(rng.uniform(0.3, 0.5)) * sd * coloured / max(float(np.std(coloured)), 1e-12)


def generate_x(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((24, 24, 24), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: critically_damped_strokes(r, a, b, rate),
                                         lambda r: quick_load_slow_release_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi, float(deg.max()))
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap softening with load
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, softening = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.5, 1.5)) * tau_max
        joint_deg = behind_strap(deg, lambda d: softening_strap_give(_elastic(kind, d, fixed, coef), c_give, softening))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, softening_Nm=softening)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # a cold pack melting away
        unit = load.moment_nm * melting_share(t, float(rng.uniform(0.3, 1.2)) * float(t[-1]))
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        roughness, correlation = float(rng.uniform(0.2, 0.4)), float(rng.uniform(2.0, 6.0))
        unit = rough_track_friction(rng, deg, np.degrees(vel), roughness, correlation, float(rng.uniform(0.3, 1.0)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
        details.update(roughness=roughness, correlation_deg=correlation)
    if "viscous_damping" in effects:
        unit = heating_dashpot(vel, rate, float(rng.uniform(0.2, 0.45)), float(rng.uniform(10.0, 40.0)))
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        grip_share = float(rng.uniform(0.5, 0.8))
        grip = size()
        inertia = grip / (grip_share * max(float(np.max(np.abs(acc))), 1e-12))
        pad = gripped_pad(acc, inertia, grip)
        torque = torque + pad
        truth["inertia"] = float(np.dot(acc, pad) / np.dot(acc, acc))
        details.update(pad_inertia_kgm2=inertia, grip_Nm=grip)
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        reach = float(np.max(np.clip((1.0 if high_end else -1.0) * (deg - at), 0.0, None)))
        liner = float(rng.uniform(0.5, 2.0)) * min(1.0, reach / 4.0)
        unit = lined_stop(deg, at, high_end, liner)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", liner_deg=liner)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = bateman_pulse(t, start, float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.2, 0.8)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(pulse_start_s=start)
    if "sensor_drift" in effects:
        torque = torque + size() * thermal_wander(rng, t, float(rng.uniform(15.0, 60.0)), float(rng.uniform(5.0, 20.0)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, group_delay = half_gaussian_smoother(torque, float(rng.uniform(0.0, 0.4)),
                                                     float(rng.uniform(0.01, 0.08)), rate)
        truth["time_delay"] = group_delay
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + _rig_noise(rng, t, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "bateman_pulse", "cam_spring",
           "critically_damped_strokes", "drive_bandwidth", "eight_chain", "expected_stretch",
           "generate_x", "gripped_pad", "half_gaussian_smoother", "heating_dashpot", "lined_stop", "melting_share",
           "quick_load_slow_release_bends", "rough_track_friction", "softening_strap_give", "thermal_wander"]
