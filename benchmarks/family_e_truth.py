"""A fifth generator family for the diagnosis, written after the engine of 193e037 froze and run once.

The second to fourth families (:mod:`benchmarks.family_b_truth`, ``family_c_truth``, ``family_d_truth``) became
development data once run; the round that froze 193e037 developed against the fourth (Dahl's friction law of the
path, a drift judged on interpolated blocks). This one draws every cause from a law none of the earlier families
or the engine's library uses. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record;
and the seeding of :mod:`benchmarks.family_scaffold`).

- Passive moment: quadratic-softplus stiffening at each end of the range, k·w²·softplus(x/w)² with x the
  angle past an onset and w 3–8° its smoothness (it grows quadratically, not exponentially, far past the
  onset), onsets shifted by the other joint's angle (two-joint muscles), plus a linear term; the AFO a
  spring engaging through a softplus of 1–3° with a quadratic term.
- Motion: minimum-jerk (quintic) sweeps between the range's ends, 2–5 cycles at 3–20 °/s mean speed with
  holds of 0–1 s; in a third of joint trials the operator pauses once mid-sweep for 0.5–2 s. The AFO: hand
  bends of minimum-jerk shape with physiological tremor (8–12 Hz, 0.03–0.15°).
- Limb: cadaver-study segment fractions (shank 4.57 % of body mass, centre 41 % down; foot 1.33 %, 44 % of
  its length), not de Leva's, Dempster's or Winter's.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Maxwell-slip (Iwan) model, 3–6 elasto-slide elements whose slip thresholds share the level
    and whose springs reach them over 0.1–2° (hysteresis with gradual corners), the level varying ±0–20 %
    with angle (a bearing's ripple) in half the trials; magnitude: the sliding level Σ Fᵢ;
  * damping: a Maxwell element (spring k in series with a dashpot, relaxation time τ 0.03–0.3 s), the
    standard linear solid of soft tissue; magnitude: its low-speed damping k·τ;
  * stop: an elastomer bumper, F = k·δ/(1 − δ/δ_max) (densifying foam), anywhere in the last 40 % of either
    end of a joint's range (the AFO's at its top), δ at the sweep's end 30–80 % of δ_max; named only;
  * delay: a transport delay of 0–0.4 s behind a moving-average (boxcar) filter of 10–200 ms; magnitude: the
    transport delay plus half the boxcar (its group delay);
  * activation: one EMG-driven burst: motor-unit spikes at 8–25 Hz per unit, 20–60 units recruited with a
    ramp over 0.3–1.8 s, each a critically damped twitch of 40–100 ms contraction time; magnitude: the
    torque's peak;
  * limb-weight error: the sidecar's body mass off (the limb's whole weight scales, and the inertia the
    engine subtracts with it) by the fraction that makes the weight's moment err by 3–5 × the noise;
    magnitude: the peak moment error;
  * drift: a thermal cycle (a sinusoid of period 1–4 times the trial, random phase) on a linear creep; named
    only;
  * series compliance: a strap stiffening with load, give c·τ/(1 + |τ|/τ_s), τ_s 5–30 N·m (knee, ankle) or
    2–8 N·m (AFO); magnitude: c, the compliance at low load (°/N·m);
  * inertia error: a counterweighted attachment ΔI·q̈ (no weight of its own); magnitude ΔI.
- Nuisances: 100–2000 Hz; white noise plus a lightly damped rig resonance (15–40 Hz) in the torque; 0–3
  single-sample spikes of 6–10 × the noise; timestamps with jitter up to 20 % of a period; torque and angle
  offsets; 0–3 % dropped rows; NaN cells in any column (≤ 0.5 %, time included).

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, trial_rng

NOISE_SD_NM = {"afo": 0.05, "knee": 0.18, "ankle": 0.1}


def _min_jerk(a: float, b: float, duration: float, rate: float) -> np.ndarray:
    u = np.linspace(0.0, 1.0, max(int(duration * rate), 2))
    return a + (b - a) * (10 * u**3 - 15 * u**4 + 6 * u**5)


def _joint_sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Minimum-jerk sweeps (deg) between ``lo`` and ``hi`` with holds, one mid-sweep pause in a third of trials."""
    speed = rng.uniform(3.0, 20.0)
    cycles = int(rng.integers(2, 6))
    pause_at = int(rng.integers(0, 2 * cycles)) if rng.random() < 1 / 3 else -1
    parts = [np.full(int(rng.uniform(0.3, 1.5) * rate), lo)]
    a, b = lo, hi
    for k in range(2 * cycles):
        duration = abs(b - a) / speed
        if k == pause_at:
            mid = a + rng.uniform(0.3, 0.7) * (b - a)
            parts += [_min_jerk(a, mid, duration * abs(mid - a) / abs(b - a), rate),
                      np.full(int(rng.uniform(0.5, 2.0) * rate), mid),
                      _min_jerk(mid, b, duration * abs(b - mid) / abs(b - a), rate)]
        else:
            parts.append(_min_jerk(a, b, duration, rate))
        parts.append(np.full(int(rng.uniform(0.0, 1.0) * rate), b))
        a, b = b, a
    return np.concatenate(parts)


def _hand_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """An AFO bent by hand (deg): minimum-jerk bends to 10–20° with holds, and the hand's tremor."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = rng.uniform(10.0, 20.0)
        parts += [_min_jerk(0.0, peak, rng.uniform(0.8, 2.0), rate), np.full(int(rng.uniform(0.1, 0.8) * rate), peak),
                  _min_jerk(peak, 0.0, rng.uniform(0.8, 2.0), rate), np.zeros(int(rng.uniform(0.2, 0.6) * rate))]
    deg = np.concatenate(parts)
    t = np.arange(deg.size) / rate
    tremor = rng.uniform(0.03, 0.15) * np.sin(2 * np.pi * rng.uniform(8.0, 12.0) * t + rng.uniform(0, 2 * np.pi))
    return np.clip(deg + tremor * (deg > 1.0), 0.0, None)


def _softplus(x: np.ndarray) -> np.ndarray:
    return np.logaddexp(0.0, x)


def _coefficients(rng: np.random.Generator, kind: str) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "k2": rng.uniform(0.0, 0.02), "engage": rng.uniform(1.0, 4.0),
                "smooth": rng.uniform(1.0, 3.0)}
    if kind == "knee":  # deg; extension end stiff (hamstrings, more with the hip flexed), flexion end gentle
        return {"k_lo": rng.uniform(0.02, 0.06), "w_lo": rng.uniform(3.0, 8.0), "on_lo": rng.uniform(25.0, 45.0),
                "shift_lo": rng.uniform(0.1, 0.3), "k_hi": rng.uniform(0.002, 0.01), "w_hi": rng.uniform(3.0, 8.0),
                "on_hi": rng.uniform(55.0, 75.0), "lin": rng.uniform(0.0, 0.03)}
    return {"k_lo": rng.uniform(0.005, 0.02), "w_lo": rng.uniform(3.0, 8.0), "on_lo": rng.uniform(-20.0, -10.0),
            "shift_lo": rng.uniform(0.0, 0.05), "k_hi": rng.uniform(0.03, 0.08), "w_hi": rng.uniform(3.0, 8.0),
            "on_hi": rng.uniform(-5.0, 5.0), "lin": rng.uniform(0.0, 0.05)}


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle (knee flexion, ankle dorsiflexion, AFO bend)."""
    if kind == "afo":
        bend = c["smooth"] * _softplus((deg - c["engage"]) / c["smooth"])
        return c["k"] * bend + c["k2"] * bend**2
    other = fixed["hip_flexion_deg"] if kind == "knee" else fixed["knee_flexion_deg"]
    # knee: the hamstrings' onset moves toward flexion with the hip flexed; ankle: the gastrocnemius' dorsiflexion
    # onset moves toward plantarflexion with the knee straight
    on_lo = c["on_lo"] + c["shift_lo"] * other if kind == "knee" else c["on_lo"]
    on_hi = c["on_hi"] if kind == "knee" else c["on_hi"] + c["shift_lo"] * (other - 45.0)
    low = c["k_lo"] * (c["w_lo"] * _softplus((on_lo - deg) / c["w_lo"])) ** 2
    high = c["k_hi"] * (c["w_hi"] * _softplus((deg - on_hi) / c["w_hi"])) ** 2
    return -low + high + c["lin"] * (deg - 0.5 * (on_lo + on_hi))


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], subject: dict[str, float], mass_kg: float
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²) of a body of
    ``mass_kg``."""
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    if kind == "knee":  # thigh horizontal: flexion 0 = shank horizontal
        m_s, m_f = 0.0457 * mass_kg, 0.0133 * mass_kg
        r_s = 0.41 * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(rad)
        return moment, m_s * r_s**2 + m_s * (0.28 * shank) ** 2 + m_f * shank**2
    if kind == "ankle":
        m_f = 0.0133 * mass_kg
        r_f = 0.44 * foot
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        return m_f * GRAVITY * r_f * np.cos(phase), m_f * (r_f**2 + (0.49 * foot) ** 2)
    return np.zeros_like(rad), 0.0


def _maxwell_slip(rng: np.random.Generator, deg: np.ndarray, level: float) -> np.ndarray:
    """Maxwell-slip (Iwan) friction (N·m) along the angle ``deg``: elements whose springs reach their slip
    threshold over 0.1–2°; the thresholds sum to ``level``."""
    count = int(rng.integers(3, 7))
    share = rng.dirichlet(np.ones(count)) * level
    reach = rng.uniform(0.1, 2.0, count)  # deg of travel that loads each element to its threshold
    stiff = share / reach
    ripple = 1.0 + (rng.uniform(0.0, 0.2) * np.sin(2 * np.pi * deg / rng.uniform(10.0, 40.0) + rng.uniform(0, 6.3))
                    if rng.random() < 0.5 else 0.0)
    force = np.zeros(count)
    out = np.empty_like(deg)
    step = np.diff(deg, prepend=deg[0])
    for i in range(deg.size):
        force = np.clip(force + stiff * step[i], -share, share)
        out[i] = force.sum()
    return out * ripple


def _maxwell_damping(t: np.ndarray, vel: np.ndarray, k: float, tau: float) -> np.ndarray:
    """A spring k (N·m/rad) in series with a dashpot k·τ: dF/dt = k·θ̇ − F/τ, integrated exactly per step."""
    out = np.empty_like(vel)
    f = 0.0
    for i in range(vel.size):
        dt = t[i] - t[i - 1] if i else 0.0
        a = np.exp(-dt / tau)
        f = f * a + k * tau * vel[i] * (1.0 - a)
        out[i] = f
    return out


def _emg_burst(rng: np.random.Generator, t: np.ndarray, onset: float, duration: float) -> np.ndarray:
    """An EMG-driven torque (unit peak): recruited motor units firing spikes, each a critically damped twitch."""
    spikes = np.zeros(t.size)
    dt = float(t[1] - t[0])
    for _ in range(int(rng.integers(20, 61))):
        start = onset + rng.uniform(0.0, 0.5) * duration  # recruitment ramps over the burst's first half
        stop = onset + duration * rng.uniform(0.6, 1.0)
        rate = rng.uniform(8.0, 25.0)
        times = np.arange(start, stop, 1.0 / rate)
        times = times + rng.normal(0.0, 0.1 / rate, times.size)
        idx = np.clip(np.round((times - t[0]) / dt).astype(int), 0, t.size - 1)
        np.add.at(spikes, idx, 1.0)
    contraction = rng.uniform(0.04, 0.1)
    kernel_t = np.arange(0.0, 8 * contraction, dt)
    twitch = (kernel_t / contraction) * np.exp(1.0 - kernel_t / contraction)  # peaks at the contraction time
    out = np.convolve(spikes, twitch)[: t.size]
    return out / max(float(out.max()), 1e-12)


def _resonant_noise(rng: np.random.Generator, n: int, rate: float, sd: float) -> np.ndarray:
    """White noise plus a lightly damped rig resonance (an AR(2) at 15–40 Hz, damping ratio 0.05–0.2), to ``sd``."""
    from scipy.signal import lfilter

    f0 = min(rng.uniform(15.0, 40.0), 0.4 * rate)
    zeta = rng.uniform(0.05, 0.2)
    r = np.exp(-zeta * 2 * np.pi * f0 / rate)
    theta = 2 * np.pi * f0 * np.sqrt(1 - zeta**2) / rate
    ring = lfilter([1.0], [1.0, -2 * r * np.cos(theta), r * r], rng.normal(0.0, 1.0, n))
    ring = ring / max(float(np.std(ring)), 1e-12)
    total = rng.normal(0.0, 1.0, n) + rng.uniform(0.3, 1.0) * ring
    return sd * total / float(np.std(total))


def generate_e(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((5, 5, 2), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0, 2000.0]))
    subject = {"mass_kg": float(rng.uniform(45.0, 110.0)), "height_m": float(rng.uniform(1.50, 2.00))}
    subject["shank_length_m"] = 0.25 * subject["height_m"] * rng.uniform(0.95, 1.05)
    subject["foot_length_m"] = 0.15 * subject["height_m"] * rng.uniform(0.95, 1.05)
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        deg = _joint_sweeps(rng, rng.uniform(3.0, 12.0), rng.uniform(80.0, 95.0), rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        deg = _joint_sweeps(rng, rng.uniform(-32.0, -22.0), rng.uniform(10.0, 20.0), rate)
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

    joint_deg = deg
    if "series_compliance" in effects:  # the joint turns less than the arm by the strap's give
        c_deg = float(rng.uniform(0.03, 0.2))
        tau_s = float(rng.uniform(2.0, 8.0) if kind == "afo" else rng.uniform(5.0, 30.0))
        tau = _passive(kind, deg, fixed, coef)
        for _ in range(60):
            tau = _passive(kind, deg - c_deg * tau / (1.0 + np.abs(tau) / tau_s), fixed, coef)
        joint_deg = deg - c_deg * tau / (1.0 + np.abs(tau) / tau_s)
        truth["series_compliance"] = c_deg
        details["strap_saturation_Nm"] = tau_s
    joint = np.radians(joint_deg)
    true_mass = subject["mass_kg"]
    weight, inertia = _limb(kind, joint, fixed, subject, true_mass)
    torque = _passive(kind, joint_deg, fixed, coef) + weight + inertia * acc
    if "gravity_error" in effects:  # the sidecar's body mass is off: the engine subtracts the wrong weight
        fraction = size() / max(float(np.max(np.abs(weight))), 1e-12)  # the weight moment is linear in the mass
        subject["mass_kg"] = true_mass * (1.0 + float(rng.choice([-1.0, 1.0])) * fraction)
        nominal, _ = _limb(kind, joint, fixed, subject, subject["mass_kg"])
        truth["gravity_error"] = float(np.max(np.abs(weight - nominal)))
        details["entered_mass_kg"] = subject["mass_kg"]
    if "coulomb_friction" in effects:
        level = size() / 1.2
        torque = torque + _maxwell_slip(rng, deg, level)
        truth["coulomb_friction"] = level
    if "viscous_damping" in effects:
        tau_r = float(rng.uniform(0.03, 0.3))
        unit = _maxwell_damping(t, vel, 1.0, tau_r)
        k = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + k * unit
        truth["viscous_damping"] = k * tau_r
        details["relaxation_s"] = tau_r
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "hard_stop" in effects:
        lo, hi = float(deg.min()), float(deg.max())
        high = kind == "afo" or bool(rng.random() < 0.5)
        at = hi - rng.uniform(0.05, 0.4) * (hi - lo) if high else lo + rng.uniform(0.05, 0.4) * (hi - lo)
        if kind == "afo":
            at = hi - rng.uniform(0.05, 0.3) * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        d_max = float(pen.max()) / rng.uniform(0.3, 0.8)
        shape = pen / (1.0 - pen / d_max)
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low")
    if "activation_burst" in effects:
        duration = float(rng.uniform(0.3, 1.8))
        onset = float(rng.uniform(0.1, 0.85)) * (t[-1] - duration)
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * _emg_burst(rng, t, onset, duration)
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_duration_s=duration)
    if "sensor_drift" in effects:
        period = rng.uniform(1.0, 4.0) * t[-1]
        drift = np.sin(2 * np.pi * t / period + rng.uniform(0, 2 * np.pi)) + rng.uniform(-1.0, 1.0) * t / t[-1]
        drift = drift - drift[0]
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
        details["drift_period_s"] = period
    if "time_delay" in effects:
        transport = float(rng.uniform(0.0, 0.4))
        box = max(int(rng.uniform(0.01, 0.2) * rate), 1)
        smoothed = np.convolve(np.concatenate([np.full(box - 1, torque[0]), torque]), np.ones(box) / box, mode="valid")
        torque = np.interp(t - transport, t, smoothed, left=smoothed[0])
        truth["time_delay"] = transport + 0.5 * (box - 1) / rate
        details.update(transport_s=transport, boxcar_s=box / rate)
    torque = torque + _resonant_noise(rng, t.size, rate, sd) + rng.uniform(-1.0, 1.0)
    for i in rng.integers(0, t.size, int(rng.integers(0, 4))):
        torque[i] += float(rng.choice([-1.0, 1.0])) * rng.uniform(6.0, 10.0) * sd
    angle = rad + np.radians(rng.uniform(-0.5, 0.5))
    stamp = t + rng.uniform(-0.2, 0.2, t.size) / rate  # the logger's clock jitters
    keep = rng.random(t.size) > rng.uniform(0.0, 0.03)
    stamp, angle, torque = stamp[keep].copy(), angle[keep].copy(), torque[keep].copy()
    nan_rate = rng.uniform(0.0, 0.005)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "generate_e"]
