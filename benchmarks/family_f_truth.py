"""A sixth generator family for the diagnosis, written during the round after the fifth's run, run once after it froze.

The second to fifth families (:mod:`benchmarks.family_b_truth` … ``family_e_truth``) became development data once run.
This one draws every cause from a law none of them or the engine's library uses. Nothing is imported from
``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw of
:mod:`benchmarks.family_scaffold`).

- Passive moment: limiting-extensibility (Gent-like) stiffening at each end, k·x/(1 − (x/x_max)²) for x the
  angle past an onset (x_max 1.3–2.5 × the furthest x the sweep reaches), the onsets shifted by the other
  joint's angle, plus a linear term; the AFO a spring k·b + k₃·b³ of the bend b past its engagement.
- Motion: sinusoidal sweeps (a cosine between the range's ends, period from a mean speed of 3–20 °/s), 2–5
  cycles, holds of 0–1.2 s at either end; the AFO bent by hand in raised-cosine bends with holds.
- Limb: segment fractions of Plagenhoef et al. (1983) (shank 4.75 % of body mass, centre 43.4 % down; foot
  1.43 %, 50 % of its length).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb level whose sign follows the direction of motion through a first-order lag of
    20–100 ms, the level falling by 10–30 % over the trial (grease warming); magnitude: its mean level;
  * damping: tissue viscosity growing with stretch, b(θ)·θ̇, b rising 1–3× from one end of the range to the
    other; magnitude: the least-squares linear coefficient;
  * stop: a bilinear pad (a soft first stage of 1–4°, then 3–8 × stiffer) anywhere in the last 40 % of either
    end of a joint's range (the AFO's at its top); named only;
  * delay: a pure delay of 0–0.4 s behind a second-order Butterworth low-pass (cut-off 2–15 Hz); magnitude:
    the pure delay plus the filter's low-frequency group delay √2/(2π f_c);
  * activation: a stretch reflex: a burst whose onset follows the joint's stretch speed crossing 80 % of its
    peak in one sweep, 40–150 ms later, an alpha-function shape (t/τ)·e^{1 − t/τ}, τ 0.1–0.5 s; magnitude:
    the torque's peak;
  * limb-weight error: the sidecar's shank length off (knee), or a shoe the sidecar does not know of at the
    foot's centre (ankle), sized so the weight's moment errs by 3–5 × the noise; magnitude: the peak moment
    error;
  * drift: piecewise-linear, 2–4 breakpoints at random times; named only;
  * series compliance: a linear strap (0.03–0.2 °/N·m) with a dead band (backlash) of ±0.05–0.2°;
    magnitude: the strap's compliance;
  * inertia error: an unaccounted attachment ΔI·q̈ (counterweighted); magnitude ΔI.
- Nuisances: 120–1000 Hz; heavy-tailed noise (Student t, 3–6 degrees of freedom) through an AR(1) of ρ 0–0.8,
  plus mains hum (50 or 60 Hz) of 0–0.5 × the noise SD; dropped rows in bursts (USB hiccups of 20–200 ms,
  0–4 of them) and singly (0–2 %); NaN cells in any column (≤ 0.4 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, draw_subject, trial_rng

NOISE_SD_NM = {"afo": 0.05, "knee": 0.18, "ankle": 0.1}


def _cosine_sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Half-cosine sweeps (deg) between ``lo`` and ``hi``, holds of 0–1.2 s at either end."""
    speed = rng.uniform(3.0, 20.0)
    half = abs(hi - lo) / speed  # s per sweep at that mean speed
    u = np.linspace(0.0, 1.0, max(int(half * rate), 2))
    up = lo + (hi - lo) * 0.5 * (1.0 - np.cos(np.pi * u))
    parts = [np.full(int(rng.uniform(0.3, 1.2) * rate), lo)]
    for _ in range(int(rng.integers(2, 6))):
        parts += [up, np.full(int(rng.uniform(0.0, 1.2) * rate), hi), up[::-1],
                  np.full(int(rng.uniform(0.0, 1.2) * rate), lo)]
    return np.concatenate(parts)


def _hand_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """An AFO bent by hand (deg): raised-cosine bends to 10–20° with holds."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = rng.uniform(10.0, 20.0)
        u = np.linspace(0.0, 1.0, int(rng.uniform(0.7, 2.0) * rate))
        up = peak * 0.5 * (1.0 - np.cos(np.pi * u))
        parts += [up, np.full(int(rng.uniform(0.1, 1.0) * rate), peak), up[::-1],
                  np.zeros(int(rng.uniform(0.2, 0.8) * rate))]
    return np.concatenate(parts)


def _gent(x: np.ndarray, k: float, x_max: float) -> np.ndarray:
    """Limiting-extensibility stiffening: k·x/(1 − (x/x_max)²) for x > 0, 0 below."""
    x = np.clip(x, 0.0, None)
    return k * x / (1.0 - (x / x_max) ** 2)


def _coefficients(rng: np.random.Generator, kind: str) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "k3": rng.uniform(0.0, 2e-4), "engage": rng.uniform(1.0, 4.0)}
    if kind == "knee":  # deg; extension end stiff, flexion end gentle
        return {"k_lo": rng.uniform(0.2, 0.6), "on_lo": rng.uniform(30.0, 50.0), "shift_lo": rng.uniform(0.1, 0.3),
                "k_hi": rng.uniform(0.02, 0.1), "on_hi": rng.uniform(50.0, 70.0), "lin": rng.uniform(0.0, 0.03),
                "margin_lo": rng.uniform(1.3, 2.5), "margin_hi": rng.uniform(1.3, 2.5)}
    return {"k_lo": rng.uniform(0.03, 0.1), "on_lo": rng.uniform(-20.0, -10.0), "shift_lo": rng.uniform(0.0, 0.05),
            "k_hi": rng.uniform(0.2, 0.6), "on_hi": rng.uniform(-5.0, 5.0), "lin": rng.uniform(0.0, 0.05),
            "margin_lo": rng.uniform(1.3, 2.5), "margin_hi": rng.uniform(1.3, 2.5)}


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float], reach: tuple[float, float]
             ) -> np.ndarray:
    """Resistance (N·m) toward increasing angle; ``reach`` (deg): the range's ends the sweep reaches, which set
    each end's limiting extension."""
    if kind == "afo":
        bend = np.clip(deg - c["engage"], 0.0, None)
        return c["k"] * bend + c["k3"] * bend**3
    other = fixed["hip_flexion_deg"] if kind == "knee" else fixed["knee_flexion_deg"]
    on_lo = c["on_lo"] + c["shift_lo"] * other if kind == "knee" else c["on_lo"]
    on_hi = c["on_hi"] if kind == "knee" else c["on_hi"] + c["shift_lo"] * (other - 45.0)
    x_lo_max = c["margin_lo"] * max(on_lo - reach[0], 1.0)
    x_hi_max = c["margin_hi"] * max(reach[1] - on_hi, 1.0)
    return (-_gent(on_lo - deg, c["k_lo"], x_lo_max) + _gent(deg - on_hi, c["k_hi"], x_hi_max)
            + c["lin"] * (deg - 0.5 * (on_lo + on_hi)))


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "knee":  # thigh horizontal: flexion 0 = shank horizontal
        m_s, m_f = 0.0475 * mass, 0.0143 * mass
        r_s = 0.434 * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(rad)
        return moment, m_s * r_s**2 + m_s * (0.3 * shank) ** 2 + m_f * shank**2
    if kind == "ankle":
        m_f = 0.0143 * mass
        r_f = 0.5 * foot
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        return m_f * GRAVITY * r_f * np.cos(phase), m_f * (r_f**2 + (0.47 * foot) ** 2)
    return np.zeros_like(rad), 0.0


def _first_order(t: np.ndarray, x: np.ndarray, tau: float) -> np.ndarray:
    out = np.empty_like(x)
    y = float(x[0])
    for i in range(x.size):
        dt = t[i] - t[i - 1] if i else 0.0
        y = x[i] + (y - x[i]) * np.exp(-dt / tau)
        out[i] = y
    return out


def generate_f(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((6, 6, 3), kind, effects, seed)
    rate = float(rng.choice([120.0, 240.0, 480.0, 1000.0]))
    subject = draw_subject(rng)
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        deg = _cosine_sweeps(rng, rng.uniform(3.0, 12.0), rng.uniform(80.0, 95.0), rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        deg = _cosine_sweeps(rng, rng.uniform(-32.0, -22.0), rng.uniform(10.0, 20.0), rate)
    else:
        deg = _hand_bends(rng, rate)
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    vel = np.gradient(rad, t)
    acc = np.gradient(vel, t)
    coef = _coefficients(rng, kind)
    reach = (float(deg.min()), float(deg.max()))
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # the joint turns less than the arm by the strap's give and its play
        c_deg, play = float(rng.uniform(0.03, 0.2)), float(rng.uniform(0.05, 0.2))
        tau = _passive(kind, deg, fixed, coef, reach)
        for _ in range(60):
            tau = _passive(kind, deg - c_deg * tau - play * np.tanh(tau / 0.2), fixed, coef, reach)
        joint_deg = deg - c_deg * tau - play * np.tanh(tau / 0.2)
        truth["series_compliance"] = c_deg
        details["play_deg"] = play
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    torque = _passive(kind, joint_deg, fixed, coef, reach) + weight + inertia * acc
    if "gravity_error" in effects and kind == "knee":  # the sidecar's shank length is off: the engine subtracts the
        sign = float(rng.choice([-1.0, 1.0]))           # wrong weight
        target = size()
        lo_f, hi_f = 0.0, 0.9
        for _ in range(60):  # the length error whose weight moment errs by the target (bisection)
            mid = 0.5 * (lo_f + hi_f)
            nominal, _ = _limb(kind, joint, fixed, subject["mass_kg"], shank * (1.0 + sign * mid), foot)
            lo_f, hi_f = (mid, hi_f) if float(np.max(np.abs(weight - nominal))) < target else (lo_f, mid)
        subject["shank_length_m"] = shank * (1.0 + sign * mid)
        truth["gravity_error"] = float(np.max(np.abs(weight - nominal)))
        details["entered_shank_length_m"] = subject["shank_length_m"]
    elif "gravity_error" in effects:  # a shoe on the foot the sidecar does not know of, at the foot's centre
        phase = joint + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        shoe = np.cos(phase)
        moment = size()
        torque = torque + moment * shoe / float(np.max(np.abs(shoe)))
        truth["gravity_error"] = moment
        details["shoe_kg"] = moment / float(np.max(np.abs(shoe))) / (GRAVITY * 0.5 * foot)
    if "coulomb_friction" in effects:
        level = size() / 1.2
        lag = float(rng.uniform(0.02, 0.1))
        fade = 1.0 - rng.uniform(0.1, 0.3) * t / t[-1]
        direction = _first_order(t, np.sign(vel) * (np.abs(vel) > np.radians(0.05)), lag)
        torque = torque + level * fade * direction
        truth["coulomb_friction"] = float(level * fade.mean())
        details["friction_lag_s"] = lag
    if "viscous_damping" in effects:
        growth = rng.uniform(1.0, 3.0)
        b_shape = 1.0 + (growth - 1.0) * (deg - reach[0]) / max(reach[1] - reach[0], 1e-9)
        shape = b_shape * vel
        b = size() / float(np.max(np.abs(shape)))
        torque = torque + b * shape
        truth["viscous_damping"] = float(b * (shape @ vel) / (vel @ vel))
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "hard_stop" in effects:
        lo, hi = reach
        high = kind == "afo" or bool(rng.random() < 0.5)
        at = hi - rng.uniform(0.05, 0.4) * (hi - lo) if high else lo + rng.uniform(0.05, 0.4) * (hi - lo)
        if kind == "afo":
            at = hi - rng.uniform(0.05, 0.3) * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        soft, ratio = float(rng.uniform(1.0, 4.0)), float(rng.uniform(3.0, 8.0))
        shape = np.minimum(pen, soft) + ratio * np.clip(pen - soft, 0.0, None)
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", soft_stage_deg=soft)
    if "activation_burst" in effects:
        stretch = -vel if kind == "knee" else vel  # knee: the hamstrings stretch on extension; ankle: the calf on dorsiflexion
        sweeps = np.flatnonzero((stretch[1:] >= 0.8 * stretch.max()) & (stretch[:-1] < 0.8 * stretch.max()))
        trigger = float(t[sweeps[int(rng.integers(0, sweeps.size))]]) if sweeps.size else 0.3 * float(t[-1])
        onset, tau_b = trigger + float(rng.uniform(0.04, 0.15)), float(rng.uniform(0.1, 0.5))
        u = np.clip(t - onset, 0.0, None) / tau_b
        shape = u * np.exp(1.0 - u)
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * shape
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_tau_s=tau_b)
    if "sensor_drift" in effects:
        knots_t = np.concatenate([[0.0], np.sort(rng.uniform(0.1, 0.9, int(rng.integers(2, 5)))) * t[-1], [t[-1]]])
        knots_v = np.concatenate([[0.0], rng.normal(0.0, 1.0, knots_t.size - 1)])
        drift = np.interp(t, knots_t, knots_v)
        torque = torque + size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        from scipy.signal import butter, lfilter, lfilter_zi

        pure, cutoff = float(rng.uniform(0.0, 0.4)), float(rng.uniform(2.0, 15.0))
        b_f, a_f = butter(2, min(cutoff / (0.5 * rate), 0.9))
        filtered = lfilter(b_f, a_f, torque, zi=lfilter_zi(b_f, a_f) * torque[0])[0]
        torque = np.interp(t - pure, t, filtered, left=filtered[0])
        truth["time_delay"] = pure + np.sqrt(2.0) / (2.0 * np.pi * cutoff)
        details.update(pure_delay_s=pure, cutoff_hz=cutoff)
    from scipy.signal import lfilter as _lfilter

    rho = float(rng.uniform(0.0, 0.8))
    shocks = rng.standard_t(float(rng.uniform(3.0, 6.0)), t.size)
    noise = _lfilter([1.0], [1.0, -rho], shocks)
    noise = sd * noise / float(np.std(noise))
    hum = rng.uniform(0.0, 0.5) * sd * np.sqrt(2.0) * np.sin(2 * np.pi * float(rng.choice([50.0, 60.0])) * t
                                                             + rng.uniform(0, 2 * np.pi))
    torque = torque + noise + hum + rng.uniform(-1.0, 1.0)
    angle = rad + np.radians(rng.uniform(-0.5, 0.5))
    keep = rng.random(t.size) > rng.uniform(0.0, 0.02)
    for _ in range(int(rng.integers(0, 5))):  # USB hiccups: a run of rows lost
        start = int(rng.integers(0, t.size))
        keep[start:start + int(rng.uniform(0.02, 0.2) * rate)] = False
    stamp, angle, torque = t[keep].copy(), angle[keep].copy(), torque[keep].copy()
    nan_rate = rng.uniform(0.0, 0.004)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "generate_f"]
