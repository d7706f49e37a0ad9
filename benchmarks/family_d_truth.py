"""A fourth generator family for the diagnosis, written after the engine froze (this round) and run once.

The second and third families (:mod:`benchmarks.family_b_truth`, :mod:`benchmarks.family_c_truth`) became
development data once run. This one draws every cause from a dynamic or published law none of the earlier
families used. Nothing is imported from ``analysis`` or from the other generators.

- Passive moments: double-exponential joint moments whose terms depend on the neighbouring joint, the form
  of Yoon & Mansour (1982) and Riener & Edrich (1999) with coefficients drawn around theirs: knee
  M = e^{a₁ − a₂θ + a₃φ_hip} − e^{b₁ + b₂θ − b₃φ_hip} + c·(θ − θ₀) (θ knee flexion, rad); ankle the same
  in dorsiflexion with the knee angle. The AFO: a hardening spring k·θ + k₃·θ³ past a slack of 1–4°.
- Limb: Dempster's segment fractions (shank 4.65 %, foot 1.45 % of body mass; centres at 43.3 % of the shank
  and 42.9 % of the foot from their proximal joints); subject mass 45–110 kg, height 1.50–2.00 m.
- Motion: the dynamometer tracks a trapezoidal speed command through its own second-order position loop
  (natural frequency 4–10 Hz, damping ratio 0.5–0.9: overshoot at each turnaround), 3–15 °/s; the AFO is
  bent by hand in half-sine bends with a hold of 0.2–1 s at the peak (10–20°).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay, a compliance by their ranges):
  * friction: the LuGre model (Canudas de Wit et al. 1995), bristle state z, dz/dt = v − σ₀|v|z/g(v),
    g(v) = F_C + (F_S − F_C)e^{−(v/v_S)²}, F = σ₀z + σ₁ dz/dt; magnitude: F_C (the kinetic level);
  * damping: a power law b·sign(v)|v|ⁿ, n = 0.6–1.4; magnitude: the least-squares linear coefficient;
  * stop: Hunt & Crossley (1975) contact k·δⁿ(1 + 1.5·α·δ̇), n = 1–2.5, anywhere in the last 35 % of
    either end of the range (the AFO's at its top); named only;
  * delay: a pure delay 0.03–0.5 s of the torque channel behind a first-order amplifier (5–30 ms);
    magnitude: the delay plus the amplifier's time constant (its low-frequency group delay);
  * activation: Zajac's (1989) first-order activation dynamics (τ_act 10–20 ms, τ_deact 40–60 ms) driven by
    one rectangular excitation of 0.2–1.5 s; magnitude: the torque's peak;
  * limb-weight error: the shank's (knee) or foot's (ankle) centre of mass misplaced along the segment by
    10–25 %; magnitude: the peak moment error;
  * drift: two-time-constant thermal settling or a low-passed random walk; named only;
  * series compliance (linear, 0.03–0.2 °/N·m); magnitude: the compliance;
  * inertia error ΔI·q̈; magnitude ΔI.
- Nuisances: 100–1500 Hz; noise 1/f-shaped (a sum of AR(1) processes at octave-spaced time constants) plus
  white; torque and angle offsets; 0–3 % dropped rows; NaN cells in any column (≤ 0.4 %, time included).

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

GRAVITY = 9.81
NOISE_SD_NM = {"afo": 0.05, "knee": 0.18, "ankle": 0.1}
EFFECTS: dict[str, tuple[str, ...]] = {
    "afo": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "sensor_drift", "series_compliance"),
    "knee": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
             "sensor_drift", "series_compliance", "inertia"),
    "ankle": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
              "sensor_drift", "series_compliance", "inertia"),
}
#: the engine's magnitude key per cause (None: named only)
MAGNITUDE_KEY: dict[str, str | None] = {
    "coulomb_friction": "friction_Nm", "viscous_damping": "damping_Nm_s_per_rad", "hard_stop": None,
    "time_delay": "delay_s", "activation_burst": "burst_amplitude_Nm", "gravity_error": "gravity_moment_error_Nm",
    "sensor_drift": None, "series_compliance": "compliance_deg_per_Nm", "inertia": "inertia_kgm2"}


@dataclass
class FamilyDTrial:
    """A trial of the fourth family and what it hides (``effects``: cause → true magnitude, None if named only)."""

    kind: str
    time_s: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray
    fixed_deg: dict[str, float]
    subject: dict[str, float]
    effects: dict[str, float | None]
    details: dict[str, Any] = field(default_factory=dict)


def _tracked_sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The arm's angle (deg): a trapezoidal speed command between ``lo`` and ``hi`` followed by a second-order
    position loop (it overshoots each turnaround a little)."""
    speed = rng.uniform(3.0, 15.0)
    accel = rng.uniform(30.0, 120.0)  # °/s² of the command's ramps
    dt = 1.0 / rate
    cmd = [lo] * int(rng.uniform(0.5, 1.5) * rate)
    a, b = lo, hi
    for _ in range(int(rng.integers(2, 5)) * 2):
        x, v, direction = a, 0.0, np.sign(b - a)
        while (b - x) * direction > 0:
            stop_dist = v * v / (2 * accel)
            v = max(v - accel * dt, 0.0) if abs(b - x) <= stop_dist else min(v + accel * dt, speed)
            x = x + direction * max(v, 0.05) * dt
            cmd.append(x if (b - x) * direction > 0 else b)
        cmd += [b] * int(rng.uniform(0.2, 1.0) * rate)
        a, b = b, a
    command = np.array(cmd)
    wn, zeta = 2 * np.pi * rng.uniform(4.0, 10.0), rng.uniform(0.5, 0.9)
    q, dq = command[0], 0.0
    out = np.empty_like(command)
    for i, c in enumerate(command):  # semi-implicit Euler of q̈ = ωn²(c − q) − 2ζωn q̇
        dq += (wn * wn * (c - q) - 2 * zeta * wn * dq) * dt
        q += dq * dt
        out[i] = q
    return out


def _hand_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """An AFO bent by hand (deg): half-sine bends to 10–20° with a hold at the peak."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak, rise = rng.uniform(10.0, 20.0), rng.uniform(0.6, 1.6)
        u = np.linspace(0.0, 1.0, int(rise * rate))
        up = peak * np.sin(0.5 * np.pi * u) ** 2
        parts += [up, np.full(int(rng.uniform(0.2, 1.0) * rate), peak), up[::-1],
                  np.zeros(int(rng.uniform(0.2, 0.6) * rate))]
    return np.concatenate(parts)


def _passive(kind: str, rad: np.ndarray, fixed: dict[str, float], c: dict[str, float]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle (knee flexion, ankle dorsiflexion, AFO bend)."""
    if kind == "afo":
        bend = np.clip(np.degrees(rad) - c["slack"], 0.0, None)
        return c["k"] * bend + c["k3"] * bend**3
    other = np.radians(fixed["hip_flexion_deg"] if kind == "knee" else fixed["knee_flexion_deg"])
    # knee: the first term resists extension (hamstrings, more with the hip flexed), the second flexion
    return (-np.exp(c["a1"] - c["a2"] * rad + c["a3"] * other) + np.exp(c["b1"] + c["b2"] * rad - c["b3"] * other)
            + c["lin"] * (rad - c["rest"]))


def _coefficients(rng: np.random.Generator, kind: str) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "k3": rng.uniform(0.0, 3e-4), "slack": rng.uniform(1.0, 4.0)}
    if kind == "knee":  # rad; about Riener & Edrich's knee terms (1.8 e^{−6.6 θ}…, 8.6 /rad at extension)
        return {"a1": rng.uniform(1.2, 2.2), "a2": rng.uniform(5.0, 9.0), "a3": rng.uniform(0.5, 1.5),
                "b1": rng.uniform(-3.5, -2.0), "b2": rng.uniform(2.0, 3.5), "b3": rng.uniform(0.0, 0.8),
                "lin": rng.uniform(0.0, 2.0), "rest": np.radians(rng.uniform(30.0, 60.0))}
    return {"a1": rng.uniform(-2.5, -1.0), "a2": rng.uniform(3.0, 8.0), "a3": rng.uniform(0.0, 0.5),
            "b1": rng.uniform(0.0, 1.0), "b2": rng.uniform(6.0, 11.0), "b3": rng.uniform(0.5, 1.5),
            "lin": rng.uniform(0.0, 3.0), "rest": np.radians(rng.uniform(-15.0, 0.0))}


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], subject: dict[str, float], com_scale: float = 1.0
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²);
    ``com_scale`` moves the centre of mass along the segment (1: Dempster's)."""
    mass, shank, foot = subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"]
    if kind == "knee":  # thigh horizontal: flexion 0 = shank horizontal
        m_s, m_f = 0.0465 * mass, 0.0145 * mass
        r_s = 0.433 * shank * com_scale
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(rad)
        return moment, m_s * r_s**2 + m_s * (0.302 * shank) ** 2 + m_f * shank**2
    if kind == "ankle":
        m_f = 0.0145 * mass
        r_f = 0.429 * foot * com_scale
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        return m_f * GRAVITY * r_f * np.cos(phase), m_f * (r_f**2 + (0.475 * foot) ** 2)
    return np.zeros_like(rad), 0.0


def _lugre(rng: np.random.Generator, t: np.ndarray, v: np.ndarray, level: float) -> np.ndarray:
    """LuGre friction torque (N·m) along the velocity ``v`` (rad/s), kinetic level ``level``."""
    fs = level * rng.uniform(1.1, 1.6)
    vs = np.radians(rng.uniform(0.5, 4.0))
    sigma0 = level / np.radians(rng.uniform(0.05, 0.3))  # bristle stiffness: full level over 0.05–0.3°
    sigma1 = rng.uniform(0.0, 1.0) * np.sqrt(sigma0 * 0.05)
    z, out = 0.0, np.empty_like(v)
    for i in range(v.size):
        dt = t[i] - t[i - 1] if i else t[1] - t[0]
        g = level + (fs - level) * np.exp(-((v[i] / vs) ** 2))
        # the bristle's relaxation is fast: integrate it exactly over the step at this sample's speed
        rate_z = sigma0 * abs(v[i]) / g
        z_ss = v[i] / rate_z if rate_z > 0 else z
        z_new = z_ss + (z - z_ss) * np.exp(-rate_z * dt) if rate_z > 0 else z
        dz = (z_new - z) / dt
        z = z_new
        out[i] = sigma0 * z + sigma1 * dz
    return out


def _activation(t: np.ndarray, onset: float, duration: float, tau_act: float, tau_deact: float) -> np.ndarray:
    """Zajac's first-order activation (0–1) driven by an excitation of 1 from ``onset`` for ``duration`` s."""
    u = ((t >= onset) & (t < onset + duration)).astype(float)
    a, out = 0.0, np.empty_like(t)
    for i in range(t.size):
        dt = t[i] - t[i - 1] if i else t[1] - t[0]
        tau = tau_act if u[i] > a else tau_deact
        a = u[i] + (a - u[i]) * np.exp(-dt / tau)
        out[i] = a
    return out


def _pink_noise(rng: np.random.Generator, n: int, rate: float, sd: float) -> np.ndarray:
    """A 1/f-shaped noise: AR(1) processes at octave-spaced time constants (5 ms … 1.3 s) of equal variance,
    plus white noise; scaled to ``sd``."""
    from scipy.signal import lfilter

    total = rng.normal(0.0, 1.0, n)
    for k in range(9):
        rho = np.exp(-1.0 / (0.005 * 2**k * rate))
        e = rng.normal(0.0, np.sqrt(1 - rho * rho), n)
        x = lfilter([1.0], [1.0, -rho], e, zi=[rho * rng.normal()])[0]
        total = total + x * rng.uniform(0.3, 0.6)
    return sd * total / float(np.std(total))


def generate_d(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyDTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials")
    rng = np.random.default_rng([4, 4, 1, list(EFFECTS).index(kind), seed,
                                 *sorted(EFFECTS[kind].index(e) for e in effects)])
    rate = float(rng.choice([100.0, 200.0, 400.0, 800.0, 1500.0]))
    subject = {"mass_kg": float(rng.uniform(45.0, 110.0)), "height_m": float(rng.uniform(1.50, 2.00))}
    subject["shank_length_m"] = 0.246 * subject["height_m"]
    subject["foot_length_m"] = 0.152 * subject["height_m"]
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        deg = _tracked_sweeps(rng, rng.uniform(2.0, 10.0), rng.uniform(80.0, 95.0), rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        deg = _tracked_sweeps(rng, rng.uniform(-33.0, -25.0), rng.uniform(10.0, 18.0), rate)
    else:
        deg = _hand_bends(rng, rate)
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    vel = np.gradient(rad, t)
    acc = np.gradient(vel, t)
    coef = _coefficients(rng, kind)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint = rad
    if "series_compliance" in effects:  # the joint turns less than the arm by the compliance's give
        c_deg = float(rng.uniform(0.03, 0.2))
        tau = _passive(kind, rad, fixed, coef)
        for _ in range(50):
            tau = _passive(kind, rad - np.radians(c_deg) * tau, fixed, coef)
        joint = rad - np.radians(c_deg) * tau
        truth["series_compliance"] = c_deg
    com_scale = 1.0
    if "gravity_error" in effects:
        com_scale = 1.0 + float(rng.choice([-1.0, 1.0])) * rng.uniform(0.10, 0.25)
    weight, inertia = _limb(kind, joint, fixed, subject, com_scale)
    torque = _passive(kind, joint, fixed, coef) + weight + inertia * acc
    if "gravity_error" in effects:  # the trial's sidecar keeps Dempster's centre: what it gets wrong, sized
        nominal, _ = _limb(kind, joint, fixed, subject, 1.0)
        err = weight - nominal
        scale = size() / max(float(np.max(np.abs(err))), 1e-12)
        torque = torque - err + err * scale
        truth["gravity_error"] = float(np.max(np.abs(err * scale)))
        details["com_scale"] = com_scale
    if "coulomb_friction" in effects:
        level = size() / 1.4
        torque = torque + _lugre(rng, t, vel, level)
        truth["coulomb_friction"] = level
    if "viscous_damping" in effects:
        n = rng.uniform(0.6, 1.4)
        shape = np.sign(vel) * np.abs(vel) ** n
        b = size() / float(np.max(np.abs(shape)))
        torque = torque + b * shape
        truth["viscous_damping"] = float(b * (shape @ vel) / (vel @ vel))
        details["damping_exponent"] = n
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "hard_stop" in effects:
        lo, hi = float(deg.min()), float(deg.max())
        high = kind == "afo" or bool(rng.random() < 0.5)
        at = hi - rng.uniform(0.05, 0.35) * (hi - lo) if high else lo + rng.uniform(0.05, 0.35) * (hi - lo)
        pen = np.radians(np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None))
        rate_in = np.gradient(pen, t)
        n = rng.uniform(1.0, 2.5)
        shape = pen**n * np.clip(1.0 + 1.5 * rng.uniform(0.0, 0.5) * rate_in / np.radians(10.0), 0.0, None)
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", stop_exponent=n)
    if "activation_burst" in effects:
        onset, duration = float(rng.uniform(0.1, 0.8)) * t[-1], float(rng.uniform(0.2, 1.5))
        act = _activation(t, onset, duration, rng.uniform(0.01, 0.02), rng.uniform(0.04, 0.06))
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * act / max(float(act.max()), 1e-12)
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_duration_s=duration)
    if "sensor_drift" in effects:
        if rng.random() < 0.5:
            t1, t2 = rng.uniform(3.0, 15.0), rng.uniform(20.0, 120.0)
            drift = rng.uniform(0.3, 1.0) * (1 - np.exp(-t / t1)) + rng.uniform(-1.0, 1.0) * (1 - np.exp(-t / t2))
            details["drift_law"] = "two-time-constant settling"
        else:
            from scipy.ndimage import uniform_filter1d

            steps = np.cumsum(rng.normal(0.0, 1.0, t.size))
            drift = uniform_filter1d(steps, max(int(5.0 * rate), 1), mode="nearest")  # a 5 s moving mean
            drift = drift - drift[0]
            details["drift_law"] = "low-passed random walk"
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        d, tau = float(rng.uniform(0.03, 0.5)), float(rng.uniform(0.005, 0.03))
        from scipy.signal import lfilter

        a = np.exp(-1.0 / (rate * tau))  # the amplifier's first-order lag, sampled at the trial's rate
        lagged = lfilter([1.0 - a], [1.0, -a], torque, zi=[a * torque[0]])[0]
        torque = np.interp(t - d, t, lagged, left=lagged[0])
        truth["time_delay"] = d + tau
        details.update(pure_delay_s=d, amplifier_tau_s=tau)
    torque = torque + _pink_noise(rng, t.size, rate, sd) + rng.uniform(-1.0, 1.0)
    angle = rad + np.radians(rng.uniform(-0.5, 0.5))
    keep = rng.random(t.size) > rng.uniform(0.0, 0.03)
    stamp, angle, torque = t[keep].copy(), angle[keep].copy(), torque[keep].copy()
    nan_rate = rng.uniform(0.0, 0.004)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return FamilyDTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)
