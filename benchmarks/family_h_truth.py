"""An eighth generator family for the diagnosis, written after the seventh's run and run once when the engine froze.

The second to seventh families (:mod:`benchmarks.family_b_truth` … ``family_g_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses. Nothing is imported from
``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and the
recording's damage of :mod:`benchmarks.family_scaffold`).

- Passive moment: collagen's toe-then-linear response at each end of a joint's range, a softplus
  k·w·ln(1 + e^{(θ − θ_end)/w}) per end (linear far past the end: neither exponential nor the fifth family's
  squared softplus), plus a gentle linear term;
  the end toward which a two-joint muscle is stretched moved by the other joint's angle. The AFO: a spring
  engaging through a softplus of 0.5–2° with a moment arm growing 0–20 % over the bend.
- Motion: the dynamometer's jerk-limited (S-curve) velocity profile, its acceleration ramping at a jerk limit
  of 300–2000 °/s³ up to 40–250 °/s², a speed of 3–30 °/s chosen anew for each stroke, with a velocity-loop
  ripple of 0–8 % at 1–3 Hz while cruising; holds of 0–0.8 s at the ends. The AFO: bends by hand as half-cosine
  strokes (amplitude 10–20°, 0.6–2.5 s each way), held 0–0.5 s at the top.
- Limb: segment fractions 4.65 % (shank, centre 43 % down from the knee) and 1.45 % (foot, centre 44 % of its
  length) of the body mass.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: mixed lubrication, a level reached as the square root of the speed, F·sign(θ̇)·min(1, √(|θ̇|/v₀))
    (v₀ 0.5–4 °/s); magnitude: F;
  * damping: a Carreau viscosity, b·θ̇·(1 + (θ̇/v_c)²)^((n − 1)/2) (n 0.3–0.8, v_c 4–40 °/s); magnitude: b (its
    low-speed value);
  * stop: a hardening bumper with a linear onset, k·(δ + δ³/δ_c²) (δ_c 2–6°), anywhere in the last third of
    either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.5 s behind a zero-order hold (the torque amplifier updating at 10–40 Hz,
    read at the recording's rate); magnitude: the transport delay plus half the hold period;
  * activation: clonus, 3–8 beats at 5–8 Hz, each a rectified half-sine, under an envelope rising over one beat
    and decaying over 0.2–0.8 s; magnitude: the torque's peak;
  * limb-weight error: a cast or weight on the segment the sidecar does not know of (its moment ∝ the segment's
    orientation, its inertia m·r² in the torque too: a mass never comes without it); magnitude: the weight
    moment's peak;
  * drift: a strain-gauge zero creeping with the load it carries, 2–6 % of the torque through a first-order lag
    of 5–30 s, plus a linear creep; named only;
  * series compliance: a cuff over soft tissue, a standard linear solid: an instant give c_i·τ and a delayed one
    c_d·τ creeping in over 0.5–3 s (c_i 60–85 % of the total); magnitude: the total static compliance (°/N·m);
  * inertia error: the rig arm's inertia entered wrong in the sidecar, ΔI·θ̈; magnitude ΔI.
- Nuisances: 100–2000 Hz; AR(1) noise (ρ 0–0.9) plus 0–2 bursts of interference (20–100 ms of 8–30 Hz at
  2–3 × the noise SD); quantised torque and angle; the clock fast or slow by up to 0.03 % with jitter; dropped
  rows singly (0–1.5 %) and in runs; NaN cells in any column (≤ 0.4 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, damage_recording, draw_subject, trial_rng

NOISE_SD_NM = {"afo": 0.05, "knee": 0.18, "ankle": 0.1}


def _softplus(x: np.ndarray) -> np.ndarray:
    return np.logaddexp(0.0, x)


def _s_curve_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Strokes (deg) between ``lo`` and ``hi`` on a jerk-limited (S-curve) velocity profile with a velocity-loop
    ripple while cruising, and the angular acceleration (deg/s²) of the profile."""
    accel, jerk = float(rng.uniform(40.0, 250.0)), float(rng.uniform(300.0, 2000.0))
    ripple, ripple_hz = float(rng.uniform(0.0, 0.08)), float(rng.uniform(1.0, 3.0))
    dt = 1.0 / rate
    hold0 = np.full(int(rng.uniform(0.2, 0.8) * rate), lo)
    angles, accs = [hold0], [np.zeros(hold0.size)]
    start = lo
    for stroke in range(2 * int(rng.integers(2, 5))):
        end = hi if stroke % 2 == 0 else lo
        dist = abs(end - start)
        speed = float(rng.uniform(3.0, 30.0))
        # the acceleration command: ramp up at the jerk limit, hold, ramp down, cruise, and the mirror image; the
        # speed is lowered until the stroke fits
        for _ in range(60):
            a_peak = min(accel, float(np.sqrt(speed * jerk)))
            t_j = a_peak / jerk
            t_a = max(speed / a_peak - t_j, 0.0)
            ramp_dist = speed * (2.0 * t_j + t_a) / 2.0 * 2.0  # distance to reach the speed and to stop from it
            if ramp_dist <= dist:
                break
            speed *= 0.9
        s_acc = np.concatenate([np.linspace(0.0, a_peak, max(int(t_j * rate), 1)),
                                np.full(int(t_a * rate), a_peak),
                                np.linspace(a_peak, 0.0, max(int(t_j * rate), 1))])
        v_ramp = np.cumsum(s_acc) * dt
        d_ramp = float(np.sum(v_ramp) * dt)
        cruise_n = max(int((dist - 2.0 * d_ramp) / max(v_ramp[-1], 1e-9) * rate), 0)
        tt = np.arange(cruise_n) * dt
        # the ripple fades in and out over the cruise (the velocity stays continuous where the ramps join)
        fade = np.sin(np.pi * tt / max(cruise_n * dt, dt)) ** 2
        cruise_v = v_ramp[-1] * (1.0 + ripple * fade * np.sin(2 * np.pi * ripple_hz * tt))
        vel = np.concatenate([v_ramp, cruise_v, v_ramp[::-1]])
        pos = np.cumsum(vel) * dt
        pos = pos * dist / max(float(pos[-1]), 1e-9)  # land on the target (the ripple's and the grid's residue)
        acc = np.gradient(np.gradient(pos, dt), dt)
        sign = 1.0 if end > start else -1.0
        hold = int(rng.uniform(0.0, 0.8) * rate)
        angles += [start + sign * pos, np.full(hold, end)]
        accs += [sign * acc, np.zeros(hold)]
        start = end
    return np.concatenate(angles), np.concatenate(accs)


def _hand_bends(rng: np.random.Generator, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """AFO bends by hand (deg): half-cosine strokes up to 10–20° and back, and their acceleration (deg/s²)."""
    dt = 1.0 / rate
    angles, accs = [np.zeros(int(0.4 * rate))], [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(10.0, 20.0))
        for up in (True, False):
            dur = float(rng.uniform(0.6, 2.5))
            s = np.arange(0.0, dur, dt)
            u = 0.5 * (1.0 - np.cos(np.pi * s / dur))
            a = 0.5 * (np.pi / dur) ** 2 * np.cos(np.pi * s / dur)
            angles.append(peak * u if up else peak * (1.0 - u))
            accs.append(peak * a if up else -peak * a)
            hold = int(rng.uniform(0.0, 0.5) * rate) if up else int(rng.uniform(0.2, 0.7) * rate)
            angles.append(np.full(hold, peak if up else 0.0))
            accs.append(np.zeros(hold))
    return np.concatenate(angles), np.concatenate(accs)


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "engage": rng.uniform(1.0, 4.0), "soft": rng.uniform(0.5, 2.0),
                "arm": rng.uniform(0.0, 0.2)}
    span = hi - lo
    # torque reached at each end of the range (N·m), the toe width (deg) and where the toe sits
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = {"knee": (1.0, 4.0), "ankle": (1.0, 4.0)}[kind]
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "w_low": rng.uniform(4.0, 12.0), "w_high": rng.uniform(4.0, 12.0),
            "toe_low": lo + rng.uniform(0.1, 0.3) * span, "toe_high": hi - rng.uniform(0.1, 0.3) * span,
            "linear": rng.uniform(0.0, 0.02), "shift": rng.uniform(0.05, 0.2)}


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float], lo: float, hi: float
             ) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        b = c["k"] * c["soft"] * _softplus((deg - c["engage"]) / c["soft"])
        return b * (1.0 + c["arm"] * deg / 20.0)
    # the two-joint muscle's end: knee extension (hamstrings, with the hip), ankle dorsiflexion (gastrocnemius,
    # with the knee): its toe moves by shift × the other joint's angle from its middle setting
    other = fixed["hip_flexion_deg"] - 55.0 if kind == "knee" else -(fixed["knee_flexion_deg"] - 45.0)
    toe_low, toe_high = c["toe_low"], c["toe_high"]
    if kind == "knee":
        toe_low = toe_low + c["shift"] * other
    else:
        toe_high = toe_high + c["shift"] * other
    low = _softplus((toe_low - deg) / c["w_low"])
    high = _softplus((deg - toe_high) / c["w_high"])
    low_ref = float(_softplus(np.array((c["toe_low"] - lo) / c["w_low"])))
    high_ref = float(_softplus(np.array((hi - c["toe_high"]) / c["w_high"])))
    return (-c["t_low"] * low / low_ref + c["t_high"] * high / high_ref
            + c["linear"] * (deg - 0.5 * (lo + hi)))


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "knee":  # thigh horizontal: flexion 0 = shank horizontal
        m_s, m_f = 0.0465 * mass, 0.0145 * mass
        r_s = 0.43 * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(rad)
        return moment, m_s * r_s**2 + m_s * (0.30 * shank) ** 2 + m_f * shank**2
    if kind == "ankle":
        m_f = 0.0145 * mass
        r_f = 0.44 * foot
        phase = rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        return m_f * GRAVITY * r_f * np.cos(phase), m_f * (r_f**2 + (0.3 * foot) ** 2)
    return np.zeros_like(rad), 0.0


def zero_order_hold(signal: np.ndarray, t: np.ndarray, update_hz: float, phase_s: float) -> np.ndarray:
    """``signal`` (sampled at ``t``, s) as a device updating at ``update_hz`` shows it: each value held until the
    next update (updates at phase_s + k / update_hz). Its low-frequency group delay is half the hold period."""
    updates = phase_s + np.arange(0.0, float(t[-1]) + 1.0 / update_hz, 1.0 / update_hz)
    held = np.interp(updates, t, signal)
    index = np.clip(np.searchsorted(updates, t, side="right") - 1, 0, updates.size - 1)
    return np.where(t >= updates[0], held[index], signal[0])


def _clonus(rng: np.random.Generator, t: np.ndarray) -> tuple[np.ndarray, dict[str, Any]]:
    """Clonus's unit torque (peak 1): 3–8 beats at 5–8 Hz, each a rectified half-sine, under an envelope rising
    over one beat and decaying over 0.2–0.8 s, at a random time."""
    beat_hz, beats, decay = float(rng.uniform(5.0, 8.0)), int(rng.integers(3, 9)), float(rng.uniform(0.2, 0.8))
    onset = float(rng.uniform(0.15, 0.8)) * float(t[-1])
    s = t - onset
    on = (s >= 0.0) & (s <= beats / beat_hz)
    envelope = np.clip(s * beat_hz, 0.0, 1.0) * np.exp(-np.clip(s - 1.0 / beat_hz, 0.0, None) / decay)
    shape = np.where(on, envelope * np.clip(np.sin(2 * np.pi * beat_hz * s), 0.0, None), 0.0)
    return shape / max(float(shape.max()), 1e-12), {"clonus_onset_s": onset, "clonus_hz": beat_hz, "beats": beats}


def generate_h(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    from scipy.signal import lfilter

    rng = trial_rng((8, 8, 1), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0, 2000.0]))
    subject = draw_subject(rng)
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        lo, hi = float(rng.uniform(3.0, 12.0)), float(rng.uniform(80.0, 95.0))
        deg, acc_deg = _s_curve_strokes(rng, lo, hi, rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        lo, hi = float(rng.uniform(-32.0, -22.0)), float(rng.uniform(10.0, 20.0))
        deg, acc_deg = _s_curve_strokes(rng, lo, hi, rate)
    else:
        deg, acc_deg = _hand_bends(rng, rate)
        lo, hi = 0.0, float(deg.max())
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    vel = np.gradient(rad, t)
    acc = np.radians(acc_deg)
    coef = _coefficients(rng, kind, lo, hi)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    rho = float(rng.uniform(0.0, 0.9))
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "rho": rho}
    truth: dict[str, float | None] = {}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # the joint turns less than the arm by the cuff's give
        total, instant = float(rng.uniform(0.03, 0.2)), float(rng.uniform(0.6, 0.85))
        creep_s = float(rng.uniform(0.5, 3.0))
        a_creep = float(np.exp(-1.0 / (rate * creep_s)))
        give = np.zeros_like(deg)
        for _ in range(40):  # the give answers to the torque it lets through: iterate to the fixed point
            load = _passive(kind, deg - give, fixed, coef, lo, hi)
            delayed = lfilter([1.0 - a_creep], [1.0, -a_creep], load, zi=[a_creep * load[0]])[0]
            give = total * (instant * load + (1.0 - instant) * delayed)
        joint_deg = deg - give
        truth["series_compliance"] = total
        details.update(instant_share=instant, creep_s=creep_s)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    passive = _passive(kind, joint_deg, fixed, coef, lo, hi)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # a cast (knee: on the shank, 60–90 % of its length down) or a weight on the foot (ankle, 30–70 % of its
        # length ahead of the joint, 0–3 cm above the sole line), its mass sized by the moment it makes
        if kind == "knee":
            r = float(rng.uniform(0.6, 0.9)) * shank
            shape = -np.cos(joint)
        else:
            along, up = float(rng.uniform(0.3, 0.7)) * foot, float(rng.uniform(0.0, 0.03))
            r = float(np.hypot(along, up))
            shape = np.cos(joint + np.pi / 2 - np.radians(fixed["knee_flexion_deg"]) + np.arctan2(up, along))
        moment = size()
        mass = moment / (GRAVITY * r * float(np.max(np.abs(shape))))
        torque = torque + mass * GRAVITY * r * shape + mass * r**2 * acc
        truth["gravity_error"] = moment
        details.update(unknown_mass_kg=mass, unknown_mass_at_m=r)
    if "coulomb_friction" in effects:
        v0 = np.radians(float(rng.uniform(0.5, 4.0)))
        level = size()
        torque = torque + level * np.sign(vel) * np.minimum(1.0, np.sqrt(np.abs(vel) / v0))
        truth["coulomb_friction"] = level
        details.update(friction_v0_deg_s=float(np.degrees(v0)))
    if "viscous_damping" in effects:
        n, v_c = float(rng.uniform(0.3, 0.8)), np.radians(float(rng.uniform(4.0, 40.0)))
        shape = vel * (1.0 + (vel / v_c) ** 2) ** ((n - 1.0) / 2.0)
        b = size() / float(np.max(np.abs(shape)))
        torque = torque + b * shape
        truth["viscous_damping"] = b
        details.update(carreau_n=n, carreau_speed_deg_s=float(np.degrees(v_c)))
    if "inertia" in effects:
        di = size() / float(np.max(np.abs(acc)))
        torque = torque + di * acc
        truth["inertia"] = di
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        hardening = float(rng.uniform(2.0, 6.0))
        shape = pen + pen**3 / hardening**2
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", hardening_deg=hardening)
    if "activation_burst" in effects:
        unit, info = _clonus(rng, t)
        amp = size()
        torque = torque + amp * unit
        truth["activation_burst"] = amp
        details.update(info)
    if "sensor_drift" in effects:
        share, lag_s = float(rng.uniform(0.02, 0.06)), float(rng.uniform(5.0, 30.0))
        a_lag = float(np.exp(-1.0 / (rate * lag_s)))
        zero = share * lfilter([1.0 - a_lag], [1.0, -a_lag], torque, zi=[0.0])[0]
        drift = zero + float(rng.uniform(-1.0, 1.0)) * float(np.max(np.abs(zero))) * t / t[-1]
        torque = torque + size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
        details.update(creep_share=share, creep_lag_s=lag_s)
    if "time_delay" in effects:
        transport, update_hz = float(rng.uniform(0.0, 0.5)), float(rng.uniform(10.0, 40.0))
        held = zero_order_hold(torque, t, update_hz, float(rng.uniform(0.0, 1.0 / update_hz)))
        torque = np.interp(t - transport, t, held, left=held[0])
        truth["time_delay"] = transport + 0.5 / update_hz
        details.update(transport_s=transport, update_hz=update_hz)
    white = rng.normal(0.0, sd * np.sqrt(1.0 - rho**2), t.size)
    noise = lfilter([1.0], [1.0, -rho], white, zi=[rho * rng.normal(0.0, sd)])[0]
    for _ in range(int(rng.integers(0, 3))):  # interference: a phone, a motor starting nearby
        at_s, dur, hz = float(rng.uniform(0.0, t[-1])), float(rng.uniform(0.02, 0.1)), float(rng.uniform(8.0, 30.0))
        on = (t >= at_s) & (t < at_s + dur)
        noise[on] += float(rng.uniform(2.0, 3.0)) * sd * np.sqrt(2.0) * np.sin(2 * np.pi * hz * (t[on] - at_s))
    torque = torque + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.015),
                                            angle_quantum_deg=(0.005, 0.04), clock_fraction=3e-4, drop_fraction=0.015,
                                            run_s=0.1, nan_fraction=0.004)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "generate_h", "zero_order_hold"]
