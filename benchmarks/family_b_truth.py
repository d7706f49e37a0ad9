"""A second generator family for the diagnosis: causes in shapes outside the engine's library.

Written apart from ``analysis.diagnosis`` and from the first generator (:mod:`benchmarks.diagnosis_truth`):
nothing is imported from either. It exists to be run once the engine is frozen (issue 31): the
engine was developed against the first family only.

- Passive baselines: a double exponential per joint (the form of Yoon & Mansour 1982 and Amankwah et
  al. 2004: one term resisting each end of the range), coefficients drawn per subject, the knee's
  flexion-end term scaled by the hip angle and the ankle's dorsiflexion-end term by the knee angle
  (two-joint muscles); an AFO's spring engaging at 2–6° with a ±20 % quadratic stiffening.
- Limb: Plagenhoef et al. (1983) segment fractions (shank 4.75 % of body mass, its centre 43.4 % from
  the knee; foot 1.43 %, 50 % of its length), seated, thigh horizontal; the limb's inertia is in the
  torque (the rig's arm is not: ``rig_inertia_kgm2`` = 0).
- Causes and their shapes:
  * friction: Stribeck (a static peak 1.3–1.8 × the kinetic level decaying over 1–4 °/s), different
    per direction by up to ±30 %; its magnitude is the mean kinetic level;
  * damping: viscous, b·q̇;
  * stop: Hunt–Crossley (k·δ^1.5·(1 + c·δ̇)) or quadratic (k·δ²), its angle anywhere in the last third
    of the range at either end (the AFO's at its high end); no linear stiffness to compare with: named only;
  * delay of the torque channel: 0.03–0.5 s;
  * activation burst: an EMG envelope, (t/τr)²·e^(−t/τd) normalised to its peak, rise 30–150 ms, decay
    0.1–0.6 s, at a random time; its magnitude is the peak;
  * limb-weight error: a fraction of the limb's weight (its peak moment error 3–5 × the noise);
  * drift: exponential settling (time constant 10–60 s) or a random walk: named only;
  * series compliance (the joint turns by the measured angle less c·τ): c in °/N·m;
  * inertia error: an unaccounted moving mass, ΔI·q̈;
  each sized so its largest contribution is 3–5 × the noise SD (the delay and compliance by their
  own ranges).
- Nuisances: 100–1000 Hz; AR(1) noise (ρ 0.3–0.9); torque and angle offsets; NaN cells in any column,
  time included (0.2 %); 1–3 % dropped rows; uneven speed (a ±10 % speed ripple).

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

G = 9.80665
SUBJECT = {"mass_kg": 68.0, "height_m": 1.72, "shank_length_m": 0.40, "foot_length_m": 0.255}
NOISE_SD_NM = {"afo": 0.07, "knee": 0.18, "ankle": 0.14}
EFFECTS: dict[str, tuple[str, ...]] = {
    "afo": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "sensor_drift", "series_compliance"),
    "knee": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
             "sensor_drift", "series_compliance", "inertia"),
    "ankle": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
              "sensor_drift", "series_compliance", "inertia"),
}
#: the engine's magnitude key per cause (None: the shape has no counterpart to compare with: named only)
MAGNITUDE_KEY: dict[str, str | None] = {
    "coulomb_friction": "friction_Nm", "viscous_damping": "damping_Nm_s_per_rad", "hard_stop": None,
    "time_delay": "delay_s", "activation_burst": "burst_amplitude_Nm", "gravity_error": "gravity_moment_error_Nm",
    "sensor_drift": None, "series_compliance": "compliance_deg_per_Nm", "inertia": "inertia_kgm2"}


@dataclass
class FamilyBTrial:
    """A trial of the second family and what it hides (``effects``: cause → true magnitude, None if named only)."""

    kind: str
    time_s: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray
    fixed_deg: dict[str, float]
    subject: dict[str, float]
    effects: dict[str, float | None]
    details: dict[str, Any] = field(default_factory=dict)


def _motion(rng: np.random.Generator, kind: str, rate: float, uneven: bool) -> np.ndarray:
    """Angle (deg) at ``rate``: isokinetic cycles (knee, ankle) or hand bends (AFO)."""
    if kind == "afo":
        parts = [np.zeros(int(0.4 * rate))]
        for _ in range(int(rng.integers(5, 8))):
            peak, dur = rng.uniform(12.0, 20.0), rng.uniform(1.2, 3.0)
            x = np.linspace(0.0, 1.0, int(dur * rate))
            skew = rng.uniform(0.7, 1.4)
            parts += [peak * 0.5 * (1 - np.cos(2 * np.pi * x**skew)), np.zeros(int(rng.uniform(0.2, 0.6) * rate))]
        return np.concatenate(parts)
    lo, hi = (5.0, rng.uniform(85.0, 100.0)) if kind == "knee" else (rng.uniform(-34.0, -28.0), 15.0)
    start, end = (lo, hi) if kind == "knee" else (hi, lo)
    speeds = rng.choice([5.0, 10.0, 15.0], 2, replace=False)
    accel = 60.0
    angle = [np.full(int(0.5 * rate), start)]
    for speed in speeds:
        for a, b in ((start, end), (end, start)):
            # a trapezoid in speed; the ripple (±10 % at 0.3 Hz) when the speed is uneven
            span = abs(b - a)
            t_ramp = speed / accel
            n = int((span / speed + t_ramp) * rate)
            t = np.arange(n) / rate
            v = np.minimum(1.0, np.minimum(t / t_ramp, (t[-1] - t) / t_ramp + 1e-9)).clip(0.0) * speed
            if uneven:
                v = v * (1.0 + 0.1 * np.sin(2 * np.pi * 0.3 * t + rng.uniform(0, 2 * np.pi)))
            pos = np.cumsum(v) / rate
            pos = pos / pos[-1] * span
            angle.append(a + np.sign(b - a) * pos)
            angle.append(np.full(int(0.3 * rate), b))
    return np.concatenate(angle)


def _passive_nm(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float]) -> np.ndarray:
    """Resistance toward positive angle (N·m) of the passive structures."""
    if kind == "knee":
        hip = fixed["hip_flexion_deg"]
        return (-c["a1"] * np.exp(-deg / c["w1"])
                + c["a2"] * np.exp(0.012 * (hip - 55.0)) * np.exp((deg - 90.0) / c["w2"]) + c["k0"] * deg)
    if kind == "ankle":
        knee = fixed["knee_flexion_deg"]
        return (-c["a1"] * np.exp(-(deg + 30.0) / c["w1"])
                + c["a2"] * np.exp(-0.01 * knee) * np.exp((deg - 15.0) / c["w2"]) + c["k0"] * deg)
    engaged = np.logaddexp(0.0, (deg - c["engage"]) / 0.5) * 0.5  # the spring's slack taken up over ~1°
    return c["k"] * engaged * (1.0 + c["stiffen"] * engaged / 20.0)


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float) -> tuple[np.ndarray, float]:
    """(the limb's weight as resistance toward positive angle, N·m; the limb's inertia about the joint, kg·m²)."""
    s, f = SUBJECT["shank_length_m"], SUBJECT["foot_length_m"]
    if kind == "knee":
        ms, mf = 0.0475 * mass, 0.0143 * mass
        weight = (ms * 0.434 * s + mf * s) * G
        inertia = ms * ((0.434 * s) ** 2 + (0.3 * s) ** 2) + mf * s**2
        return -weight * np.cos(rad), inertia
    if kind == "ankle":
        mf = 0.0143 * mass
        knee = np.radians(fixed["knee_flexion_deg"])
        return mf * 0.5 * f * G * np.cos(rad + np.pi / 2 - knee), mf * ((0.5 * f) ** 2 + (0.3 * f) ** 2)
    return np.zeros_like(rad), 0.0


def _ar1(rng: np.random.Generator, n: int, sd: float, rho: float) -> np.ndarray:
    e = rng.normal(0.0, sd * np.sqrt(1 - rho**2), n)
    out = np.empty(n)
    out[0] = rng.normal(0.0, sd)
    for i in range(1, n):
        out[i] = rho * out[i - 1] + e[i]
    return out


def generate_b(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials")
    rng = np.random.default_rng([31, list(EFFECTS).index(kind), seed, len(effects),
                                 *[EFFECTS[kind].index(e) for e in effects]])
    rate = float(rng.choice([100.0, 200.0, 500.0, 1000.0]))
    uneven = bool(rng.random() < 0.5)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.2)
    rho = float(rng.uniform(0.3, 0.9))
    deg = _motion(rng, kind, rate, uneven)
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    mass = SUBJECT["mass_kg"]
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        coef = {"a1": rng.uniform(2.0, 8.0), "w1": rng.uniform(6.0, 15.0), "a2": rng.uniform(5.0, 20.0),
                "w2": rng.uniform(15.0, 30.0), "k0": rng.uniform(0.0, 0.05)}
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        coef = {"a1": rng.uniform(3.0, 10.0), "w1": rng.uniform(5.0, 12.0), "a2": rng.uniform(3.0, 12.0),
                "w2": rng.uniform(6.0, 14.0), "k0": rng.uniform(0.0, 0.1)}
    else:
        coef = {"k": rng.uniform(0.3, 1.5), "engage": rng.uniform(2.0, 6.0), "stiffen": rng.uniform(-0.2, 0.2)}
    vel = np.gradient(rad, t)
    acc = np.gradient(vel, t)
    weight, inertia = _limb(kind, rad, fixed, mass)
    truth: dict[str, float | None] = {}
    details: dict[str, Any] = {"rate_hz": rate, "uneven": uneven, "noise_sd_Nm": sd, "rho": rho}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_rad = rad
    if "series_compliance" in effects:  # the joint turns by the measured angle less c·τ: τ = P(θ − c·τ)
        c_deg = float(rng.uniform(0.04, 0.15))
        tau = _passive_nm(kind, deg, fixed, coef)
        for _ in range(30):
            tau = _passive_nm(kind, deg - c_deg * tau, fixed, coef)
        joint_rad = np.radians(deg - c_deg * tau)
        truth["series_compliance"] = c_deg
    passive = _passive_nm(kind, np.degrees(joint_rad), fixed, coef)
    torque = passive + weight + inertia * acc
    if "coulomb_friction" in effects:
        fc = size() / 1.6
        asym, peak, vs = rng.uniform(-0.3, 0.3), rng.uniform(1.3, 1.8), np.radians(rng.uniform(1.0, 4.0))
        level = np.where(vel >= 0, fc * (1 + asym), fc * (1 - asym))
        torque = torque + np.tanh(vel / np.radians(0.2)) * level * (1 + (peak - 1) * np.exp(-(vel / vs) ** 2))
        truth["coulomb_friction"] = fc
    if "viscous_damping" in effects:
        b = size() / float(np.max(np.abs(vel)))
        torque = torque + b * vel
        truth["viscous_damping"] = b
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "gravity_error" in effects:
        frac = size() / float(np.max(np.abs(weight))) * float(rng.choice([-1.0, 1.0]))
        torque = torque + frac * weight
        truth["gravity_error"] = abs(frac) * float(np.max(np.abs(weight)))
        details["weight_error_fraction"] = frac
    if "hard_stop" in effects:
        lo, hi = float(deg.min()), float(deg.max())
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.0, 1.0 / 3.0)) * (hi - lo)
        at = hi - depth if high else lo + depth
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        rate_pen = np.gradient(pen, t)
        hunt = bool(rng.random() < 0.5)
        shape = pen**1.5 * (1 + 1.5 * 0.05 * rate_pen) if hunt else pen**2
        shape = np.clip(shape, 0.0, None)
        k = size() / max(float(shape.max()), 1e-9)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", stop_law="hunt-crossley" if hunt else "quadratic")
    if "activation_burst" in effects:
        rise, decay = rng.uniform(0.03, 0.15), rng.uniform(0.1, 0.6)
        start = float(rng.uniform(0.15, 0.8)) * t[-1]
        x = np.clip(t - start, 0.0, None)
        env = (x / rise) ** 2 * np.exp(-x / decay)
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * env / float(env.max())
        truth["activation_burst"] = amp
        details.update(burst_start_s=start, burst_rise_s=rise, burst_decay_s=decay)
    if "sensor_drift" in effects:
        if rng.random() < 0.5:
            tau_s = rng.uniform(10.0, 60.0)
            drift = size() * (1 - np.exp(-t / tau_s)) / (1 - np.exp(-t[-1] / tau_s))
            details["drift_law"] = "settling"
        else:
            walk = np.cumsum(rng.normal(0.0, 1.0, t.size))
            walk = np.convolve(walk, np.ones(int(rate)) / int(rate), mode="same")
            drift = size() * (walk - walk[0]) / max(float(np.max(np.abs(walk - walk[0]))), 1e-9)
            details["drift_law"] = "random walk"
        torque = torque + float(rng.choice([-1.0, 1.0])) * drift
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        d = float(rng.uniform(0.03, 0.5))
        torque = np.interp(t - d, t, torque)
        truth["time_delay"] = d
    torque = torque + _ar1(rng, t.size, sd, rho) + rng.uniform(-0.5, 0.5)
    angle = rad + np.radians(rng.uniform(-0.3, 0.3))
    keep = rng.random(t.size) > rng.uniform(0.01, 0.03)  # dropped rows
    t, angle, torque = t[keep], angle[keep], torque[keep]
    for col in (t, angle, torque):  # NaN cells in any column, time included
        col[rng.random(col.size) < 0.002] = np.nan
    return FamilyBTrial(kind, t, angle, torque, fixed, dict(SUBJECT), {e: truth[e] for e in effects}, details)
