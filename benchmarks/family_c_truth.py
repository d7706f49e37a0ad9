"""A third generator family for the diagnosis, written after the engine froze (commit 98fd18d) and run once.

The second family (:mod:`benchmarks.family_b_truth`) became development data when its first run showed
where the engine failed; this one holds the engine to shapes neither earlier family has. Nothing is
imported from ``analysis`` or from the other generators.

- Passive moments from muscles, not from a joint-level formula: each joint is crossed by an agonist and
  an antagonist group whose passive force follows Thelen's (2003) exponential curve
  F = F₀ (e^{kε/ε₀} − 1)/(e^{k} − 1) past a slack length (zero before it), k = 4–6, ε₀ = 0.5–0.7, with a
  constant moment arm; two-joint groups change their slack angle with the fixed joint (hamstrings with
  the hip, gastrocnemius with the knee); a small linear ligament term. The onset at slack is a kink in
  the curvature, not a stop.
- The AFO's spring: a linear spring whose lever arm shortens with the bend (k·θ·cos(θ/2) past a slack of
  1–5°), plus strap compliance (a softening of 0–10 % over the bend).
- Limb: Winter (2009) segment fractions (shank 4.65 % of body mass, its centre 43.3 % of its length from
  the knee; foot 1.45 %, its centre 50 % of its length); the subject drawn per trial (mass 50–100 kg).
- Motions: knee and ankle isokinetic sweeps at 4–12 °/s with minimum-jerk turnarounds and dwells of
  0.3–1.2 s; the AFO bent by hand: raised-cosine bends to 12–20° with a 8–12 Hz physiological tremor.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay, a compliance by their ranges):
  * friction: Coulomb with a Stribeck peak of exponent 1 or 2 (Armstrong-Hélouvry 1994), the level in
    one direction 0.7–1.3 × the other; magnitude: the mean kinetic level;
  * damping: viscous with a quadratic part (b·v + b₂·v|v|, b₂ up to 30 % of b at the peak speed);
    magnitude: the effective linear coefficient (the least-squares slope of the damping torque on v);
  * stop: an exponential contact k(e^{δ/δ₀} − 1) (δ₀ 1–3°) or a preloaded linear one, anywhere in the
    last 40 % of the range at either end (the AFO's at its top); named only;
  * delay of the torque channel 0.02–0.6 s; magnitude the delay;
  * activation: a train of 2–3 gamma-shaped twitches (shape 2–4, 40–150 ms time-to-peak) within 1.5 s;
    magnitude: the train's peak;
  * limb-weight error: a mass error (70 %) or a centre of mass off the segment's axis (30 %, which moves
    the weight's phase); magnitude: the peak moment error;
  * drift: logarithmic settling a·ln(1 + t/τ) or a slow wander (a sinusoid of period 40–150 s); named only;
  * series compliance that stiffens with load (angle error c·τ/(1 + |τ|/τ₀)); magnitude: c at zero load;
  * inertia error ΔI·q̈; magnitude ΔI.
- Nuisances: 120–2000 Hz; noise white plus AR(2) (a resonance of the rig) plus 50 Hz mains hum; torque ADC
  quantisation (0.005–0.02 N·m) and encoder quantisation (0.005–0.02°); sample-time jitter; 0–2 %
  dropped rows; NaN cells in any column (0.1–0.3 %); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

GRAVITY = 9.81
NOISE_SD_NM = {"afo": 0.06, "knee": 0.2, "ankle": 0.12}
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
class FamilyCTrial:
    """A trial of the third family and what it hides (``effects``: cause → true magnitude, None if named only)."""

    kind: str
    time_s: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray
    fixed_deg: dict[str, float]
    subject: dict[str, float]
    effects: dict[str, float | None]
    details: dict[str, Any] = field(default_factory=dict)


def _min_jerk(n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n)
    return 10 * s**3 - 15 * s**4 + 6 * s**5


def _sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Isokinetic sweeps between ``lo`` and ``hi`` (deg) with minimum-jerk turnarounds and dwells."""
    speed = rng.uniform(4.0, 12.0)
    turn = rng.uniform(1.5, 4.0)  # degrees spent accelerating into and out of each end
    out = [np.full(int(rng.uniform(0.3, 1.2) * rate), lo)]
    a, b = lo, hi
    for _ in range(int(rng.integers(3, 5)) * 2):
        span = abs(b - a)
        cruise = max(span - 2 * turn, 1.0)
        dur = cruise / speed + 2 * (2 * turn / speed)
        x = _min_jerk(int(dur * rate)) if rng.random() < 0.3 else _trapezoid(int(dur * rate), turn / span)
        out.append(a + (b - a) * x)
        out.append(np.full(int(rng.uniform(0.3, 1.2) * rate), b))
        a, b = b, a
    return np.concatenate(out)


def _trapezoid(n: int, ramp_fraction: float) -> np.ndarray:
    """Position 0 → 1 over ``n`` samples with a constant speed between smooth (minimum-jerk velocity) ramps."""
    s = np.linspace(0.0, 1.0, n)
    r = float(np.clip(ramp_fraction, 0.02, 0.45))
    v = np.ones(n)
    up, down = s < r, s > 1 - r
    v[up] = _blend(s[up] / r)
    v[down] = _blend((1 - s[down]) / r)
    x = np.cumsum(v)
    return (x - x[0]) / (x[-1] - x[0])


def _blend(u: np.ndarray) -> np.ndarray:
    return 10 * u**3 - 15 * u**4 + 6 * u**5


def _bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """An operator's bends of an AFO (deg): raised-cosine bends with a physiological tremor."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak, dur = rng.uniform(12.0, 20.0), rng.uniform(1.5, 3.5)
        u = np.linspace(0.0, 1.0, int(dur * rate))
        parts.append(peak * 0.5 * (1 - np.cos(2 * np.pi * u)))
        parts.append(np.zeros(int(rng.uniform(0.2, 0.8) * rate)))
    deg = np.concatenate(parts)
    t = np.arange(deg.size) / rate
    tremor = rng.uniform(0.05, 0.15) * np.sin(2 * np.pi * rng.uniform(8.0, 12.0) * t + rng.uniform(0, 2 * np.pi))
    return deg + tremor * (deg > 1.0)


def _thelen(strain: np.ndarray, k: float, e0: float) -> np.ndarray:
    """Thelen (2003) passive force per maximal force at ``strain`` (zero below slack)."""
    e = np.clip(strain, 0.0, None)
    return (np.exp(k * e / e0) - 1.0) / (np.exp(k) - 1.0)


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], m: dict[str, float]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle from the muscle groups and ligaments crossing the joint."""
    if kind == "afo":
        bend = np.clip(deg - m["slack"], 0.0, None)
        return m["k"] * bend * np.cos(np.radians(bend) / 2) * (1 - m["soften"] * bend / 20.0)
    if kind == "knee":  # flexion positive: the quadriceps resist flexion, the hamstrings resist extension
        hip = fixed["hip_flexion_deg"]
        quad = _thelen((deg - m["quad_slack"]) * m["quad_strain_per_deg"], m["k1"], m["e1"]) * m["quad_f"]
        ham_slack = m["ham_slack"] - 0.6 * (hip - 55.0)  # a flexed hip stretches the hamstrings
        ham = _thelen((ham_slack - deg) * m["ham_strain_per_deg"], m["k2"], m["e2"]) * m["ham_f"]
        return quad - ham + m["lig"] * (deg - 45.0)
    knee = fixed["knee_flexion_deg"]  # ankle, dorsiflexion positive: the calf resists it, tibialis the other way
    calf_slack = m["calf_slack"] + 0.15 * knee  # a flexed knee slackens the gastrocnemius
    calf = _thelen((deg - calf_slack) * m["calf_strain_per_deg"], m["k1"], m["e1"]) * m["calf_f"]
    tib = _thelen((m["tib_slack"] - deg) * m["tib_strain_per_deg"], m["k2"], m["e2"]) * m["tib_f"]
    return calf - tib + m["lig"] * deg


def _muscles(rng: np.random.Generator, kind: str) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.2), "slack": rng.uniform(1.0, 5.0), "soften": rng.uniform(0.0, 0.1)}
    common = {"k1": rng.uniform(4.0, 6.0), "e1": rng.uniform(0.5, 0.7), "k2": rng.uniform(4.0, 6.0),
              "e2": rng.uniform(0.5, 0.7)}
    if kind == "knee":
        return {**common, "quad_slack": rng.uniform(40.0, 70.0), "quad_strain_per_deg": rng.uniform(0.004, 0.008),
                "quad_f": rng.uniform(15.0, 40.0), "ham_slack": rng.uniform(35.0, 60.0),
                "ham_strain_per_deg": rng.uniform(0.006, 0.012), "ham_f": rng.uniform(20.0, 50.0),
                "lig": rng.uniform(0.0, 0.03)}
    return {**common, "calf_slack": rng.uniform(-20.0, -5.0), "calf_strain_per_deg": rng.uniform(0.006, 0.012),
            "calf_f": rng.uniform(20.0, 50.0), "tib_slack": rng.uniform(-20.0, -5.0),
            "tib_strain_per_deg": rng.uniform(0.004, 0.01), "tib_f": rng.uniform(5.0, 20.0),
            "lig": rng.uniform(0.0, 0.05)}


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], subject: dict[str, float]
          ) -> tuple[np.ndarray, float, np.ndarray]:
    """(weight moment against increasing angle, N·m; limb inertia about the joint, kg·m²; the weight moment
    of a centre of mass off the segment's axis per metre of offset, N·m/m)."""
    mass, shank, foot = subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"]
    if kind == "knee":  # thigh horizontal; knee flexion 0 = shank horizontal, 90° = hanging
        m_s, m_f = 0.0465 * mass, 0.0145 * mass
        arm = (m_s * 0.433 * shank + m_f * shank) / (m_s + m_f)
        w = (m_s + m_f) * GRAVITY
        inertia = m_s * (0.433 * shank) ** 2 + m_s * (0.302 * shank) ** 2 + m_f * shank**2
        return -w * arm * np.cos(rad), inertia, w * np.sin(rad)
    if kind == "ankle":  # the foot: dorsiflexion lifts it against gravity when the shank is vertical
        m_f = 0.0145 * mass
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        w = m_f * GRAVITY
        return w * 0.5 * foot * np.cos(phase), m_f * ((0.5 * foot) ** 2 + (0.475 * foot) ** 2), -w * np.sin(phase)
    return np.zeros_like(rad), 0.0, np.zeros_like(rad)


def _rig_noise(rng: np.random.Generator, t: np.ndarray, sd: float, rate: float) -> np.ndarray:
    """White noise plus a rig resonance (AR(2) at 3–15 Hz) plus 50 Hz mains hum, scaled to ``sd`` in all."""
    n = t.size
    f0 = min(rng.uniform(3.0, 15.0), 0.4 * rate)
    r = rng.uniform(0.85, 0.98)
    a1, a2 = 2 * r * np.cos(2 * np.pi * f0 / rate), -r * r
    e = rng.normal(0.0, 1.0, n)
    res = np.zeros(n)
    for i in range(2, n):
        res[i] = a1 * res[i - 1] + a2 * res[i - 2] + e[i]
    res /= max(float(np.std(res)), 1e-12)
    white = rng.normal(0.0, 1.0, n)
    hum = np.sqrt(2) * np.sin(2 * np.pi * 50.0 * t + rng.uniform(0, 2 * np.pi)) if rate > 110 else np.zeros(n)
    share = rng.dirichlet([2.0, 2.0, 0.5])
    return sd * (np.sqrt(share[0]) * white + np.sqrt(share[1]) * res + np.sqrt(share[2]) * hum)


def generate_c(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyCTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials")
    rng = np.random.default_rng([3, 1, 7, list(EFFECTS).index(kind), seed,
                                 *sorted(EFFECTS[kind].index(e) for e in effects)])
    rate = float(rng.choice([120.0, 250.0, 500.0, 1000.0, 2000.0]))
    subject = {"mass_kg": float(rng.uniform(50.0, 100.0)), "height_m": float(rng.uniform(1.55, 1.95))}
    subject["shank_length_m"] = 0.246 * subject["height_m"]
    subject["foot_length_m"] = 0.152 * subject["height_m"]
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        deg = _sweeps(rng, rng.uniform(3.0, 8.0), rng.uniform(85.0, 95.0), rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        deg = _sweeps(rng, rng.uniform(-32.0, -27.0), rng.uniform(12.0, 17.0), rate)
    else:
        deg = _bends(rng, rate)
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    vel = np.gradient(rad, t)
    acc = np.gradient(vel, t)
    muscles = _muscles(rng, kind)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # the joint turns less than measured by the compliance's give
        c0, tau0 = float(rng.uniform(0.04, 0.15)), float(rng.uniform(5.0, 30.0))
        tau = _passive(kind, deg, fixed, muscles)
        for _ in range(40):
            tau = _passive(kind, deg - c0 * tau / (1 + np.abs(tau) / tau0), fixed, muscles)
        joint_deg = deg - c0 * tau / (1 + np.abs(tau) / tau0)
        truth["series_compliance"] = c0
        details["compliance_tau0_Nm"] = tau0
    weight, inertia, off_axis = _limb(kind, np.radians(joint_deg), fixed, subject)
    torque = _passive(kind, joint_deg, fixed, muscles) + weight + inertia * acc
    if "coulomb_friction" in effects:
        level = size() / 1.5
        ratio, peak = rng.uniform(0.7, 1.3), rng.uniform(1.2, 1.7)
        vs, expo = np.radians(rng.uniform(0.5, 3.0)), float(rng.choice([1.0, 2.0]))
        up, down = 2 * level / (1 + ratio), 2 * level * ratio / (1 + ratio)  # mean of the two = level
        kinetic = np.where(vel >= 0, up, down)
        shape = np.tanh(vel / np.radians(0.1)) * (1 + (peak - 1) * np.exp(-(np.abs(vel) / vs) ** expo))
        torque = torque + kinetic * shape
        truth["coulomb_friction"] = level
        details.update(friction_ratio=ratio, stribeck_exponent=expo)
    if "viscous_damping" in effects:
        vmax = float(np.max(np.abs(vel)))
        quad = rng.uniform(0.0, 0.3)
        damp = vel + quad * vel * np.abs(vel) / vmax
        b = size() / float(np.max(np.abs(damp)))
        torque = torque + b * damp
        truth["viscous_damping"] = float(b * (damp @ vel) / (vel @ vel))
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "gravity_error" in effects:
        if rng.random() < 0.7:
            frac = float(rng.choice([-1.0, 1.0]))
            err = frac * weight
        else:
            err = off_axis * float(rng.choice([-1.0, 1.0]))
        err = err * size() / max(float(np.max(np.abs(err))), 1e-12)
        torque = torque + err
        truth["gravity_error"] = float(np.max(np.abs(err)))
    if "hard_stop" in effects:
        lo, hi = float(deg.min()), float(deg.max())
        high = kind == "afo" or bool(rng.random() < 0.5)
        at = hi - rng.uniform(0.05, 0.4) * (hi - lo) if high else lo + rng.uniform(0.05, 0.4) * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        if rng.random() < 0.5:
            shape = np.exp(pen / rng.uniform(1.0, 3.0)) - 1.0
            law = "exponential"
        else:
            shape = np.where(pen > 0, pen + rng.uniform(0.5, 2.0), 0.0)
            law = "preloaded linear"
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", stop_law=law)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.8)) * t[-1]
        train = np.zeros_like(t)
        for _ in range(int(rng.integers(2, 4))):
            onset = start + rng.uniform(0.0, 1.5)
            shape_k, peak_s = rng.uniform(2.0, 4.0), rng.uniform(0.04, 0.15)
            x = np.clip(t - onset, 0.0, None) / (peak_s / (shape_k - 1))
            twitch = x ** (shape_k - 1) * np.exp(-(x - (shape_k - 1)))
            train = train + rng.uniform(0.5, 1.0) * twitch / max(float(twitch.max()), 1e-12)
        amp = size()
        burst = float(rng.choice([-1.0, 1.0])) * amp * train / float(train.max())
        torque = torque + burst
        truth["activation_burst"] = amp
        details["burst_start_s"] = float(start)
    if "sensor_drift" in effects:
        if rng.random() < 0.5:
            drift = np.log1p(t / rng.uniform(2.0, 20.0))
            details["drift_law"] = "logarithmic settling"
        else:
            drift = np.sin(2 * np.pi * t / rng.uniform(40.0, 150.0) + rng.uniform(0, 2 * np.pi))
            drift = drift - drift[0]
            details["drift_law"] = "slow wander"
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        d = float(rng.uniform(0.02, 0.6))
        torque = np.interp(t - d, t, torque, left=torque[0])
        truth["time_delay"] = d
    torque = torque + _rig_noise(rng, t, sd, rate) + rng.uniform(-0.8, 0.8)
    lsb_nm, lsb_deg = rng.uniform(0.005, 0.02), rng.uniform(0.005, 0.02)
    torque = np.round(torque / lsb_nm) * lsb_nm
    angle_deg = np.round((deg + rng.uniform(-0.5, 0.5)) / lsb_deg) * lsb_deg
    stamp = t + rng.uniform(-0.1, 0.1, t.size) / rate  # sample-time jitter
    keep = rng.random(t.size) > rng.uniform(0.0, 0.02)
    stamp, angle, torque = stamp[keep], np.radians(angle_deg[keep]), torque[keep]
    nan_rate = rng.uniform(0.001, 0.003)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return FamilyCTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)
