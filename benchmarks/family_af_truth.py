"""A thirty-second generator family for the diagnosis, written (2026-12-08, fortieth stop) before that stop's frozen
engine met the thirty-first family, nothing diagnosed on it; to be run once on the next change's frozen engine.

The second to thirty-first families (:mod:`benchmarks.family_b_truth` … ``family_ae_truth``) are development data once
run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: the eighteenth family's burst was a doublet of
twitches, here a triplet of alpha functions; the thirty-first's inertia came through a gear whose ratio varies with the
angle, here a counterweight sliding out along the arm (the inertia linear in the angle); limited-extensibility and
exponential ends were used often, here Knowles's power-law generalisation of the neo-Hookean solid and, on the orthosis,
Hart-Smith's exponential of the squared invariant. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a Knowles (generalised neo-Hookean) solid in uniaxial tension, per unit
  μ: (1 + (b/n)(I₁ − 3))^(n−1)·(λ − λ⁻²), I₁ = λ² + 2/λ (n 1.5–3, b 0.5–2), for the stretch λ = 1 + x̄/L (x̄ the softplus
  of the angle past an onset over 2–5°, L 0.5–1.5 × the end's reach); the steep end sized by its torque at the range's
  end, the onset toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a Hart-Smith
  band, exp(k(I₁ − 3)²)·(λ − λ⁻²) for λ = 1 + bend/L (L 40–80°), k set so the exponent at a 20° bend is 0.5–2, past an
  engagement of 0.5–2° (softplus).
- Motion: 3–5 cycles between 90–100 % of the range's ends, the strokes one way at 3–5 °/s and the other way at 5–8 °/s
  (which way is faster drawn per trial), each starting and stopping along a raised cosine over 0.2–0.6 s, held 1–3 s at
  one end and 0–0.5 s at the other, a 0.5–1.5 s hold at the middle first. The AFO: 6–9 bends whose depths rise from
  8–10° to 18–20° and fall back (a pyramid), each at 15–30 °/s with 0.2 s raised-cosine edges, held 0.3–1 s at the top.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a level that varies with the angle (a cam follower rubbing a track of uneven preload), F_c·(1 + a·sin(2π(θ
    − θ₀)/P))·tanh(v/v₀) (a 0.2–0.4, P 20–60°, v₀ 0.3–1 °/s); magnitude: its mean |F| over the moving samples;
  * damping: a damper thinning as it warms, b(t)·θ̇ with b falling as 1/(1 + β·W(t)/W(T)), W the work it has dissipated
    (∫θ̇² dt), β 0.25–0.65; magnitude: the least-squares slope of its torque on θ̇;
  * stop: Flores's dissipative contact, K·δ^1.5·(1 + 8(1 − e)/(5e)·δ̇/v_ref) while compressing (δ̇ > 0; the elastic
    part alone while released), e 0.5–0.9, v_ref 5 °/s, anywhere in the last 5–30 % of either end of a joint's range
    (the AFO's at the top of its bend); named only;
  * delay: a linear-phase low-pass, a Kaiser-windowed sinc (cut-off 2–8 Hz, β 4–8, its half-length 0.02–0.15 s),
    behind a transport delay of 0–0.35 s; magnitude: the transport delay plus the filter's half-length;
  * activation: a triplet of alpha functions, Σ aᵢ·u·e^(1−u), u = (t − tᵢ)/τ ≥ 0 (τ 0.04–0.12 s, 0.1–0.25 s apart,
    amplitudes 1, 0.6–0.9 and 0.3–0.7), starting anywhere in 12–80 % of the trial, of either sign; magnitude: the
    triplet's peak;
  * limb-weight error: the subject unloading (or pressing) the limb as they relax, the weight's moment scaled by
    s·(1 − e^(−t/τ)) (τ 20–60 % of the trial); magnitude: its peak;
  * drift: a warm-up along a Gompertz curve, A·exp(−b·e^(−ct)) (b 3–8, its inflection ln b / c at 20–60 % of the
    trial), of either sign; named only;
  * series compliance: a strap stiffening with the loading rate, a give c·τ·(1 − s·tanh(|τ̇|/r₀)) (s 0.2–0.4, r₀ the
    median |τ̇| over the moving samples), c 0.03–0.15 °/N·m but at most 0.5 over the torque's stiffest rate; magnitude:
    the least-squares slope of the give on the torque;
  * inertia error: a counterweight sliding out along the dynamometer's arm, J(θ) = J₀(1 + a(θ − θ_lo)/span) (a
    0.5–1.5): torque J(θ)·θ̈ + ½·J'(θ)·θ̇²; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Student-t noise (4–8 degrees of freedom) scaled to the SD;
  the torque ADC's integral nonlinearity (a cubic of 0.1–0.3 % of full scale); the encoder's interpolation error (a
  sinusoid in the angle of period 1–3° and 0.005–0.02°); a gain drifting by ±0.3–0.8 % over the trial (linearly);
  quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in
  runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import firwin

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
#: the contact's reference speed (deg/s) in Flores's dissipation term
FLORES_REFERENCE_DEG_S = 5.0


def knowles_tension(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, exponent: float, hardening: float
                    ) -> np.ndarray:
    """An end per unit μ: (1 + (b/n)(I₁ − 3))^(n−1)·(λ − λ⁻²), I₁ = λ² + 2/λ, λ = 1 + x̄/L with x̄ the softplus of the
    angle ``x_deg`` past the onset over ``smoothing_deg``, L = ``reach_deg``, n = ``exponent``, b = ``hardening``
    (n = 1: the neo-Hookean solid)."""
    lam = 1.0 + softplus(x_deg, smoothing_deg) / reach_deg
    invariant = lam * lam + 2.0 / lam
    return np.asarray((1.0 + hardening / exponent * (invariant - 3.0)) ** (exponent - 1.0) * (lam - lam**-2), dtype=float)


def hart_smith_band(deg: np.ndarray, engage_deg: float, smoothing_deg: float, length_deg: float, k: float) -> np.ndarray:
    """An orthosis's band per unit stiffness: exp(k(I₁ − 3)²)·(λ − λ⁻²) for λ = 1 + θ̄/L, θ̄ the softplus (over
    ``smoothing_deg``) of the bend past ``engage_deg`` (zero at 0°), L = ``length_deg``."""
    d = np.asarray(deg, dtype=float)
    bend = softplus(d - engage_deg, smoothing_deg) - float(softplus(np.array(-engage_deg), smoothing_deg))
    lam = 1.0 + np.clip(bend, 0.0, None) / length_deg
    invariant = lam * lam + 2.0 / lam
    return np.asarray(np.exp(k * (invariant - 3.0) ** 2) * (lam - lam**-2), dtype=float)


def _eased(a: float, b: float, speed: float, edge_s: float, rate: float) -> np.ndarray:
    """From ``a`` to ``b`` (deg) at ``speed`` °/s, the speed rising and falling along raised cosines over ``edge_s``
    (shortened on a short stroke); samples after the start."""
    distance = abs(b - a)
    edge = min(edge_s, distance / max(speed, 1e-9))
    duration = distance / max(speed, 1e-9) + edge
    n = max(2, int(np.ceil(duration * rate)))
    tt = np.arange(1, n + 1) / n * duration
    rise = 0.5 * (1.0 - np.cos(np.pi * np.clip(tt / max(edge, 1e-9), 0.0, 1.0)))
    fall = 0.5 * (1.0 - np.cos(np.pi * np.clip((duration - tt) / max(edge, 1e-9), 0.0, 1.0)))
    travelled = np.cumsum(np.minimum(rise, fall))
    return a + (b - a) * travelled / travelled[-1]


def two_speed_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the middle, then 3–5 cycles between 90–100 % of the range's ends, up at
    one speed (3–5 or 5–8 °/s) and down at the other, raised-cosine edges over 0.2–0.6 s, held 1–3 s at one end and
    0–0.5 s at the other; back to the middle."""
    span, mid = hi - lo, 0.5 * (lo + hi)
    slow, fast = float(rng.uniform(3.0, 5.0)), float(rng.uniform(5.0, 8.0))
    up, down = (slow, fast) if rng.random() < 0.5 else (fast, slow)
    long_hold_high = bool(rng.random() < 0.5)
    edge = float(rng.uniform(0.2, 0.6))
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    here = mid
    for _ in range(int(rng.integers(3, 6))):
        top = mid + float(rng.uniform(0.9, 1.0)) * 0.5 * span
        bottom = mid - float(rng.uniform(0.9, 1.0)) * 0.5 * span
        for target, speed, high in ((top, up, True), (bottom, down, False)):
            parts.append(_eased(here, target, speed, edge, rate))
            hold = rng.uniform(1.0, 3.0) if high == long_hold_high else rng.uniform(0.0, 0.5)
            parts.append(np.full(int(hold * rate), target))
            here = target
    parts.append(_eased(here, mid, down, edge, rate))
    return np.concatenate(parts)


def pyramid_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 6–9 bends whose depths rise from 8–10° to 18–20° and fall back, each at
    15–30 °/s with 0.2 s raised-cosine edges, held 0.3–1 s at the top, resting 0.2–0.5 s between."""
    count = int(rng.integers(6, 10))
    low, high = float(rng.uniform(8.0, 10.0)), float(rng.uniform(18.0, 20.0))
    apex = (count - 1) / 2.0
    depths = high - (high - low) * np.abs(np.arange(count) - apex) / max(apex, 1e-9)
    parts = [np.zeros(int(0.5 * rate))]
    for depth in depths:
        speed = float(rng.uniform(15.0, 30.0))
        parts += [_eased(0.0, float(depth), speed, 0.2, rate), np.full(int(rng.uniform(0.3, 1.0) * rate), float(depth)),
                  _eased(float(depth), 0.0, speed, 0.2, rate), np.zeros(int(rng.uniform(0.2, 0.5) * rate))]
    return np.concatenate(parts)


def cam_follower_friction(deg: np.ndarray, vel_deg_s: np.ndarray, depth: float, period_deg: float, phase_deg: float,
                          smoothing_deg_s: float) -> np.ndarray:
    """A friction per unit mean level whose level varies with the angle: (1 + a·sin(2π(θ − θ₀)/P))·tanh(v/v₀)."""
    level = 1.0 + depth * np.sin(2.0 * np.pi * (np.asarray(deg, dtype=float) - phase_deg) / period_deg)
    return np.asarray(level * np.tanh(np.asarray(vel_deg_s, dtype=float) / smoothing_deg_s), dtype=float)


def warming_damper(vel: np.ndarray, t: np.ndarray, thinning: float) -> np.ndarray:
    """A damper per unit initial coefficient whose coefficient falls as 1/(1 + β·W(t)/W(T)), W(t) = ∫θ̇² dt the work it
    has dissipated per unit coefficient: b(t)·θ̇."""
    v = np.asarray(vel, dtype=float)
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    work = np.cumsum(v * v * dt)
    share = work / max(float(work[-1]), 1e-300)
    return np.asarray(v / (1.0 + thinning * share), dtype=float)


def flores_contact(deg: np.ndarray, vel_deg_s: np.ndarray, at_deg: float, high: bool, restitution: float) -> np.ndarray:
    """A stop per unit contact stiffness (positive at the high end): δ^1.5·(1 + 8(1 − e)/(5e)·δ̇/v_ref) while compressing,
    δ^1.5 while released, δ (deg) the angle past ``at_deg`` toward the end, v_ref :data:`FLORES_REFERENCE_DEG_S`."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None)
    closing = np.clip(sign * np.asarray(vel_deg_s, dtype=float), 0.0, None)
    dissipation = 8.0 * (1.0 - restitution) / (5.0 * restitution) * closing / FLORES_REFERENCE_DEG_S
    return np.asarray(sign * depth**1.5 * (1.0 + dissipation), dtype=float)


def kaiser_low_pass(values: np.ndarray, rate: float, cutoff_hz: float, beta: float, half_length_s: float
                    ) -> tuple[np.ndarray, float]:
    """(``values`` through a causal linear-phase FIR low-pass, a Kaiser-windowed sinc of ``cutoff_hz`` and window
    ``beta`` with 2·m + 1 taps, m the half-length in samples; its delay m / rate in s). Started at rest on the first
    value."""
    m = max(1, int(round(half_length_s * rate)))
    cutoff = min(cutoff_hz, 0.45 * rate)
    taps = firwin(2 * m + 1, cutoff, window=("kaiser", beta), fs=rate)
    x = np.asarray(values, dtype=float)
    padded = np.concatenate([np.full(2 * m, x[0]), x])
    filtered = np.convolve(padded, taps, mode="valid")
    return np.asarray(filtered, dtype=float), m / rate


def alpha_triplet(t: np.ndarray, start_s: float, time_constant_s: float, spacing_s: tuple[float, float],
                  amplitudes: tuple[float, float, float]) -> np.ndarray:
    """Three alpha functions aᵢ·u·e^(1−u), u = (t − tᵢ)/τ ≥ 0 (each peaking at aᵢ one τ after its start), the second
    and third ``spacing_s`` after the one before."""
    starts = (start_s, start_s + spacing_s[0], start_s + spacing_s[0] + spacing_s[1])
    out = np.zeros(np.asarray(t).size)
    for onset, a in zip(starts, amplitudes, strict=True):
        u = np.clip((np.asarray(t, dtype=float) - onset) / time_constant_s, 0.0, None)
        out += a * u * np.exp(1.0 - u)
    return out


def gompertz_zero(t: np.ndarray, displacement: float, rate_per_s: float) -> np.ndarray:
    """A warm-up from 0 toward 1 along exp(−b·e^(−ct)), b = ``displacement``, c = ``rate_per_s``."""
    return np.asarray(np.exp(-displacement * np.exp(-rate_per_s * np.asarray(t, dtype=float))), dtype=float)


def rate_stiffening_compliance(torque_rate: np.ndarray, compliance: float, share: float, reference_rate: float
                               ) -> np.ndarray:
    """A strap's compliance (deg/N·m) at each sample: c·(1 − s·tanh(|τ̇|/r₀)), less give when loaded fast."""
    return np.asarray(compliance * (1.0 - share * np.tanh(np.abs(torque_rate) / max(reference_rate, 1e-12))), dtype=float)


def sliding_counterweight(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, low_rad: float, span_rad: float,
                          growth: float) -> np.ndarray:
    """Torque per unit J₀ of an inertia J(θ) = J₀(1 + a(θ − θ_lo)/span): J(θ)·θ̈ + ½·J'(θ)·θ̇²."""
    inertia = 1.0 + growth * (np.asarray(rad, dtype=float) - low_rad) / span_rad
    return np.asarray(inertia * acc + 0.5 * growth / span_rad * np.asarray(vel, dtype=float) ** 2, dtype=float)


def student_noise(rng: np.random.Generator, n: int, sd: float) -> np.ndarray:
    """Student-t noise of 4–8 degrees of freedom scaled to the SD ``sd``."""
    dof = float(rng.uniform(4.0, 8.0))
    return np.asarray(rng.standard_t(dof, n) * sd / np.sqrt(dof / (dof - 2.0)), dtype=float)


def adc_nonlinearity(torque: np.ndarray, full_scale: float, share: float) -> np.ndarray:
    """The torque an ADC with an integral nonlinearity of ``share`` of ``full_scale`` reads: a cubic bow, zero at 0 and
    at ± full scale, its largest error ``share``·full scale."""
    u = np.clip(np.asarray(torque, dtype=float) / full_scale, -1.0, 1.0)
    bow = (u**3 - u) / (2.0 / (3.0 * np.sqrt(3.0)))  # u³ − u peaks at 2/(3√3) in magnitude
    return np.asarray(torque + share * full_scale * bow, dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return np.asarray(c["k"] * hart_smith_band(deg, c["engage"], 0.5, c["length"], c["exponent"]), dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * knowles_tension(on_low - deg, c["smooth"], c["reach_low"], c["n_low"], c["b_low"])
            + c["a_high"] * knowles_tension(deg - on_high, c["smooth"], c["reach_high"], c["n_high"], c["b_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, length = float(rng.uniform(0.5, 2.0)), float(rng.uniform(40.0, 80.0))
        lam = 1.0 + 20.0 / length
        exponent = float(rng.uniform(0.5, 2.0)) / (lam * lam + 2.0 / lam - 3.0) ** 2
        unit = float(hart_smith_band(np.array(15.0), engage, 0.5, length, exponent))
        return {"engage": engage, "length": length, "exponent": exponent, "k": float(rng.uniform(10.0, 25.0)) / unit}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(2.0, 5.0))
    c = {"reach_low": (on_low - lo) * float(rng.uniform(0.5, 1.5)), "reach_high": (hi - on_high) * float(rng.uniform(0.5, 1.5)),
         "n_low": float(rng.uniform(1.5, 3.0)), "n_high": float(rng.uniform(1.5, 3.0)),
         "b_low": float(rng.uniform(0.5, 2.0)), "b_high": float(rng.uniform(0.5, 2.0))}
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    c["a_low"] = t_low / float(knowles_tension(np.array(on_low - lo), smooth, c["reach_low"], c["n_low"], c["b_low"]))
    c["a_high"] = t_high / float(knowles_tension(np.array(hi - on_high), smooth, c["reach_high"], c["n_high"], c["b_high"]))
    return {**c, "smooth": smooth, "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_af(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((32, 32, 32), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: two_speed_strokes(r, a, b, rate),
                                         lambda r: pyramid_bends(r, rate))
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
    if "series_compliance" in effects:  # a strap stiffening with the loading rate
        commanded = _elastic(kind, deg, fixed, coef)
        torque_rate = np.gradient(commanded, t)
        grid = np.linspace(float(deg.min()) - 5.0, float(deg.max()) + 5.0, 2001)
        stiffest = float(np.max(np.abs(np.gradient(_elastic(kind, grid, fixed, coef), grid))))
        c_give = min(float(rng.uniform(0.03, 0.15)), 0.5 / max(stiffest, 1e-9))
        share = float(rng.uniform(0.2, 0.4))
        reference = max(float(np.median(np.abs(torque_rate[moving]))) if moving.any() else 1.0, 1e-9)
        compliance = rate_stiffening_compliance(torque_rate, c_give, share, reference)
        joint_deg = behind_strap(deg, lambda j: compliance * _elastic(kind, j, fixed, coef))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, rate_share=share, reference_rate_Nm_s=reference)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the subject unloading (or pressing) the limb as they relax
        settle = float(rng.uniform(0.2, 0.6)) * float(t[-1])
        error = size() * float(rng.choice([-1.0, 1.0])) * unit_peak((1.0 - np.exp(-t / settle)) * load.moment_nm)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(unloading_time_constant_s=settle)
    if "coulomb_friction" in effects:
        unit = cam_follower_friction(np.degrees(rad), np.degrees(vel), float(rng.uniform(0.2, 0.4)),
                                     float(rng.uniform(20.0, 60.0)), float(rng.uniform(0.0, 60.0)), float(rng.uniform(0.3, 1.0)))
        friction = size() * unit_peak(unit)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        damping = size() * unit_peak(warming_damper(vel, t, float(rng.uniform(0.25, 0.65))))
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        unit = sliding_counterweight(rad, vel, acc, np.radians(bottom), np.radians(max(top - bottom, 1.0)),
                                     float(rng.uniform(0.5, 1.5)))
        error = size() * unit_peak(unit)
        torque = torque + error
        truth["inertia"] = float(np.dot(acc, error) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit = flores_contact(deg, np.degrees(vel), at, high_end, float(rng.uniform(0.5, 0.9)))
        torque = torque + size() * unit_peak(unit)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", range_deg=(bottom, top))
    if "activation_burst" in effects:
        start = float(rng.uniform(0.12, 0.8)) * float(t[-1])
        shape = alpha_triplet(t, start, float(rng.uniform(0.04, 0.12)),
                              (float(rng.uniform(0.1, 0.25)), float(rng.uniform(0.1, 0.25))),
                              (1.0, float(rng.uniform(0.6, 0.9)), float(rng.uniform(0.3, 0.7))))
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * unit_peak(shape)
        truth["activation_burst"] = peak
        details.update(burst_start_s=start)
    if "sensor_drift" in effects:
        displacement = float(rng.uniform(3.0, 8.0))
        inflection = float(rng.uniform(0.2, 0.6)) * float(t[-1])
        zero = gompertz_zero(t, displacement, np.log(displacement) / inflection)
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * (zero - zero[0])
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        latency = float(rng.uniform(0.0, 0.35))
        filtered, filter_delay = kaiser_low_pass(torque, rate, float(rng.uniform(2.0, 8.0)), float(rng.uniform(4.0, 8.0)),
                                                 float(rng.uniform(0.02, 0.15)))
        torque = np.interp(t - latency, t, filtered, left=filtered[0])
        truth["time_delay"] = latency + filter_delay
    period = float(rng.uniform(1.0, 3.0))
    read_deg = np.degrees(rad) + float(rng.uniform(0.005, 0.02)) * np.sin(2.0 * np.pi * np.degrees(rad) / period)
    gain = 1.0 + float(rng.choice([-1.0, 1.0])) * float(rng.uniform(0.003, 0.008)) * t / max(float(t[-1]), 1e-12)
    read = adc_nonlinearity(torque * gain, 1.2 * max(float(np.max(np.abs(torque))), 1e-9), float(rng.uniform(0.001, 0.003)))
    torque = read + student_noise(rng, t.size, sd) + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, np.radians(read_deg), torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "adc_nonlinearity", "alpha_triplet",
           "cam_follower_friction", "flores_contact", "generate_af", "gompertz_zero", "hart_smith_band", "kaiser_low_pass",
           "knowles_tension", "pyramid_bends", "rate_stiffening_compliance", "sliding_counterweight", "student_noise",
           "two_speed_strokes", "warming_damper"]
