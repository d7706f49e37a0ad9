"""A seventh generator family for the diagnosis, written after the sixth's run and run once when the engine froze.

The second to sixth families (:mod:`benchmarks.family_b_truth` … ``family_f_truth``) became development data once run.
This one draws every cause from a law none of them or the engine's library uses. Nothing is imported from
``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and the
recording's damage of :mod:`benchmarks.family_scaffold`).

- Passive moment: smooth everywhere, a hyperbolic sine about a neutral angle plus a cubic,
  A·sinh((θ − θ₀)/w) + C·((θ − θ₀)/w)³ (stiffening toward both ends without an onset; w 15–35°), θ₀ moved by the
  other joint's angle; the AFO a spring engaging through a smoothstep ramp of 1–3° (linear beyond).
- Motion: the dynamometer's speed command steps between cycles (two or three speeds of 3–20 °/s, changing
  cycle to cycle) and the arm follows it through a first-order lag of 0.1–0.4 s, so every turnaround is an
  exponential approach, not a ramp; holds of 0–1 s. The AFO: loaded at a steady speed to 10–20°, released in an
  exponential spring-back (time constant 0.2–0.6 s).
- Limb: segment fractions of 4.4 % (shank, centre 40 % down from the knee) and 1.4 % (foot, centre 45 % of its
  length) of the body mass.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing whose friction grows with its load, (F₀ + μ·|τ_passive|)·erf(θ̇/v₀), v₀ 0.3–2 °/s, the
    load part 20–60 % of the level at the range's ends; magnitude: the level's mean over the moving samples;
  * damping: a saturating viscosity, b·θ̇ / (1 + |θ̇|/v_sat), v_sat 20–60 °/s; magnitude: b (its low-speed value);
  * stop: a cushion, k·(√(δ² + r²) − r) for δ past the stop (a hinge rounded over r = 0.2–1°), anywhere in the
    last third of either end of a joint's range (the AFO's at its top); named only;
  * delay: a transport delay of 0–0.5 s behind a fourth-order Bessel low-pass (cut-off 3–20 Hz); magnitude: the
    transport delay plus the filter's group delay at low frequency;
  * activation: a fused (tetanic) contraction, (1 − e^{−t/τᵣ})² rising over τᵣ 0.05–0.3 s, held 0.2–1 s, relaxing
    as e^{−t/τ_d} (τ_d 0.1–0.4 s); magnitude: the torque's peak;
  * limb-weight error: a mass the sidecar does not know of: a cuff at the knee trial's ankle, a brace at the
    ankle trial's heel (behind the joint), sized so its moment errs by 3–5 × the noise; magnitude: its peak;
  * drift: an offset step (a cable knocked, 0.3–2 s to settle) at a random time on a slow creep; named only;
  * series compliance: a Kelvin–Voigt strap, its give following c·τ through a retardation time of 0.05–0.3 s;
    magnitude: c (°/N·m);
  * inertia error: an unaccounted attachment ΔI·q̈; magnitude ΔI.
- Nuisances: 100–1500 Hz; white noise plus an interference line at 8–30 Hz (0–0.6 × the noise SD, the drive's
  commutation) and quantisation of the torque (0.005–0.02 N·m) and the angle (0.01–0.05°); the sample clock
  running fast or slow by up to 0.05 % with jitter; dropped rows singly (0–2 %) and in runs; NaN cells in any
  column (≤ 0.5 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, damage_recording, draw_subject, trial_rng

NOISE_SD_NM = {"afo": 0.06, "knee": 0.2, "ankle": 0.12}


def _lagged_speed_sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Sweeps (deg) between ``lo`` and ``hi``: a speed command stepping cycle to cycle, followed through a
    first-order lag; holds of 0–1 s at the ends."""
    speeds = rng.uniform(3.0, 20.0, int(rng.integers(2, 4)))
    lag = float(rng.uniform(0.1, 0.4))
    dt = 1.0 / rate
    angle, out = lo, [np.full(int(rng.uniform(0.3, 1.0) * rate), lo)]
    for cycle in range(int(rng.integers(2, 5))):
        speed = float(speeds[cycle % speeds.size])
        for target in (hi, lo):
            v, seg = 0.0, []
            direction = 1.0 if target > angle else -1.0
            while (target - angle) * direction > 0.0:
                # slow down over the last stretch as the drive's position loop would (never overshoots)
                command = speed * min(1.0, abs(target - angle) / max(speed * lag, 1e-9))
                v += (direction * max(command, 0.2) - v) * (1.0 - np.exp(-dt / lag))
                angle = float(np.clip(angle + v * dt, min(lo, hi), max(lo, hi)))
                seg.append(angle)
                if len(seg) > 600 * rate:
                    break
            out += [np.array(seg), np.full(int(rng.uniform(0.0, 1.0) * rate), angle)]
    return np.concatenate(out)


def _loaded_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """An AFO loaded by hand at a steady speed to 10–20°, released in an exponential spring-back (deg)."""
    parts = [np.zeros(int(0.5 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak, speed = rng.uniform(10.0, 20.0), rng.uniform(8.0, 25.0)
        up = np.linspace(0.0, peak, max(int(peak / speed * rate), 2))
        tau = rng.uniform(0.2, 0.6)
        down = peak * np.exp(-np.arange(int(5 * tau * rate)) / (tau * rate))
        parts += [up, np.full(int(rng.uniform(0.1, 0.6) * rate), peak), down, np.zeros(int(rng.uniform(0.2, 0.8) * rate))]
    return np.concatenate(parts)


def _coefficients(rng: np.random.Generator, kind: str) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "engage": rng.uniform(1.0, 4.0), "ramp": rng.uniform(1.0, 3.0)}
    if kind == "knee":  # N·m, deg; stiffer toward extension (θ small)
        return {"amp": rng.uniform(0.5, 2.0), "cubic": rng.uniform(0.0, 0.4), "neutral": rng.uniform(45.0, 65.0),
                "width": rng.uniform(15.0, 35.0), "shift": rng.uniform(0.1, 0.3), "tilt": rng.uniform(-0.6, -0.2)}
    return {"amp": rng.uniform(0.3, 1.2), "cubic": rng.uniform(0.0, 0.3), "neutral": rng.uniform(-15.0, -5.0),
            "width": rng.uniform(15.0, 30.0), "shift": rng.uniform(0.0, 0.08), "tilt": rng.uniform(0.1, 0.5)}


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        b = np.clip(deg - c["engage"], 0.0, None)
        s = np.clip(b / c["ramp"], 0.0, 1.0)
        # smoothstep engagement over the ramp, linear beyond: continuous in value and slope
        return c["k"] * np.where(b < c["ramp"], c["ramp"] * (s**3 - 0.5 * s**4), b - 0.5 * c["ramp"])
    other = fixed["hip_flexion_deg"] - 55.0 if kind == "knee" else fixed["knee_flexion_deg"] - 45.0
    u = (deg - c["neutral"] - c["shift"] * other) / c["width"]
    # asymmetric: the tilt makes one end stiffer than the other
    return c["amp"] * np.sinh(u) * (1.0 + c["tilt"] * np.tanh(u)) + c["cubic"] * u**3


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "knee":  # thigh horizontal: flexion 0 = shank horizontal
        m_s, m_f = 0.044 * mass, 0.014 * mass
        r_s = 0.40 * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(rad)
        return moment, m_s * r_s**2 + m_s * (0.28 * shank) ** 2 + m_f * shank**2
    if kind == "ankle":
        m_f = 0.014 * mass
        r_f = 0.45 * foot
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        return m_f * GRAVITY * r_f * np.cos(phase), m_f * (r_f**2 + (0.45 * foot) ** 2)
    return np.zeros_like(rad), 0.0


def _bessel_low_pass(cutoff_hz: float, rate: float) -> tuple[np.ndarray, np.ndarray, float]:
    """A fourth-order Bessel low-pass (digital, at ``rate``): its coefficients and its group delay (s) at low
    frequency."""
    from scipy.signal import bessel, group_delay

    b, a = bessel(4, min(cutoff_hz / (0.5 * rate), 0.9), norm="phase")
    w, gd = group_delay((b, a), w=np.array([2 * np.pi * 0.05 / rate]))
    return b, a, float(gd[0]) / rate


def generate_g(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    from scipy.special import erf

    rng = trial_rng((7, 7, 4), kind, effects, seed)
    rate = float(rng.choice([100.0, 200.0, 500.0, 1000.0, 1500.0]))
    subject = draw_subject(rng)
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        deg = _lagged_speed_sweeps(rng, rng.uniform(3.0, 12.0), rng.uniform(80.0, 95.0), rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        deg = _lagged_speed_sweeps(rng, rng.uniform(-32.0, -22.0), rng.uniform(10.0, 20.0), rate)
    else:
        deg = _loaded_bends(rng, rate)
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
    if "series_compliance" in effects:  # the joint turns less than the arm by the strap's give (Kelvin–Voigt)
        c_deg, retard = float(rng.uniform(0.03, 0.2)), float(rng.uniform(0.05, 0.3))
        from scipy.signal import lfilter

        a = float(np.exp(-1.0 / (rate * retard)))  # the give relaxes toward c·τ over the retardation time
        give = np.zeros_like(deg)
        for _ in range(40):  # the give answers to the torque it lets through: iterate to the fixed point
            target = c_deg * _passive(kind, deg - give, fixed, coef)
            give = lfilter([1.0 - a], [1.0, -a], target, zi=[a * target[0]])[0]
        joint_deg = deg - give
        truth["series_compliance"] = c_deg
        details["retardation_s"] = retard
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        if kind == "knee":  # a cuff at the ankle: its weight's moment about the knee
            shape = -np.cos(joint)
        else:  # a brace at the heel, behind the ankle
            shape = -np.cos(joint + np.pi / 2 - np.radians(fixed["knee_flexion_deg"]))
        moment = size()
        torque = torque + moment * shape / float(np.max(np.abs(shape)))
        truth["gravity_error"] = moment
        details["unknown_mass_moment_Nm"] = moment
    if "coulomb_friction" in effects:
        v0 = np.radians(float(rng.uniform(0.3, 2.0)))
        load_share = float(rng.uniform(0.2, 0.6))
        load = np.abs(passive) / max(float(np.max(np.abs(passive))), 1e-12)
        level_shape = (1.0 - load_share) + load_share * load
        level = size() / max(float(np.max(level_shape)), 1e-12)
        torque = torque + level * level_shape * erf(vel / v0)
        moving = np.abs(vel) > 3.0 * v0
        truth["coulomb_friction"] = float(level * np.mean(level_shape[moving])) if moving.any() else float(level)
        details.update(friction_v0_deg_s=float(np.degrees(v0)), load_share=load_share)
    if "viscous_damping" in effects:
        v_sat = np.radians(float(rng.uniform(20.0, 60.0)))
        shape = vel / (1.0 + np.abs(vel) / v_sat)
        b = size() / float(np.max(np.abs(shape)))
        torque = torque + b * shape
        truth["viscous_damping"] = b
        details["v_sat_deg_s"] = float(np.degrees(v_sat))
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "hard_stop" in effects:
        lo, hi = reach
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33)) if kind != "afo" else float(rng.uniform(0.05, 0.3))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        r = float(rng.uniform(0.2, 1.0))
        shape = np.sqrt(pen**2 + r**2) - r
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", cushion_deg=r)
    if "activation_burst" in effects:
        rise, hold, relax = float(rng.uniform(0.05, 0.3)), float(rng.uniform(0.2, 1.0)), float(rng.uniform(0.1, 0.4))
        onset = float(rng.uniform(0.15, 0.75)) * float(t[-1])
        s = t - onset
        up = np.where(s > 0.0, (1.0 - np.exp(-np.clip(s, 0.0, None) / rise)) ** 2, 0.0)
        end = hold + 3.0 * rise
        shape = np.where(s <= end, up, up[np.searchsorted(s, end) - 1] * np.exp(-np.clip(s - end, 0.0, None) / relax))
        shape = shape / max(float(shape.max()), 1e-12)
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * shape
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_rise_s=rise, burst_hold_s=hold, burst_relax_s=relax)
    if "sensor_drift" in effects:
        at, settle = float(rng.uniform(0.2, 0.8)) * float(t[-1]), float(rng.uniform(0.3, 2.0))
        step = np.where(t > at, 1.0 - np.exp(-np.clip(t - at, 0.0, None) / settle), 0.0)
        creep = t / t[-1]
        drift = float(rng.choice([-1.0, 1.0])) * step + float(rng.uniform(-0.5, 0.5)) * creep
        torque = torque + size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
        details.update(drift_step_s=at, drift_settle_s=settle)
    if "time_delay" in effects:
        from scipy.signal import lfilter, lfilter_zi

        transport, cutoff = float(rng.uniform(0.0, 0.5)), float(rng.uniform(3.0, 20.0))
        b_f, a_f, filter_delay = _bessel_low_pass(cutoff, rate)
        filtered = lfilter(b_f, a_f, torque, zi=lfilter_zi(b_f, a_f) * torque[0])[0]
        torque = np.interp(t - transport, t, filtered, left=filtered[0])
        truth["time_delay"] = transport + filter_delay
        details.update(transport_s=transport, cutoff_hz=cutoff, filter_delay_s=filter_delay)
    hum = rng.uniform(0.0, 0.6) * sd * np.sqrt(2.0) * np.sin(2 * np.pi * rng.uniform(8.0, 30.0) * t
                                                             + rng.uniform(0, 2 * np.pi))
    torque = torque + rng.normal(0.0, sd, t.size) + hum + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.005, 0.02),
                                            angle_quantum_deg=(0.01, 0.05), clock_fraction=5e-4, drop_fraction=0.02,
                                            run_s=0.15, nan_fraction=0.005)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "generate_g"]
