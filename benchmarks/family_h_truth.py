"""An eighth generator family for the diagnosis, written after the seventh's run and run once when the engine froze.

The second to seventh families (:mod:`benchmarks.family_b_truth` … ``family_g_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses. Nothing is imported from
``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record).

- Passive moment: collagen's toe-then-linear response at each end of a joint's range, a softplus
  k·w·ln(1 + e^{(θ − θ_end)/w}) per end (linear far past the end, no exponential), plus a gentle linear term;
  the end toward which a two-joint muscle is stretched moved by the other joint's angle. The AFO: a spring
  engaging through a softplus of 0.5–2° with a moment arm growing 0–20 % over the bend.
- Motion: the dynamometer's trapezoidal velocity profile (an acceleration limit of 40–250 °/s², a speed of
  3–30 °/s chosen anew for each stroke), holds of 0–0.8 s at the ends. The AFO: bends by hand as half-cosine
  strokes (amplitude 10–20°, 0.6–2.5 s each way), held 0–0.5 s at the top.
- Limb: segment fractions 4.65 % (shank, centre 43 % down from the knee) and 1.45 % (foot, centre 44 % of its
  length) of the body mass.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing with a tight spot, its level varying with angle, F₀·(1 + a·sin(2π(θ − φ)/P)) (a 0.2–0.5,
    P 20–60°), times a saturated-linear law of the speed, clip(θ̇/v₀, −1, 1) (v₀ 0.2–1.5 °/s); magnitude: the
    level's mean over the moving samples;
  * damping: a Carreau viscosity, b·θ̇·(1 + (θ̇/v_c)²)^((n − 1)/2) (n 0.3–0.8, v_c 4–40 °/s); magnitude: b (its
    low-speed value);
  * stop: a two-stage pad, a soft pad 1–4° thick (k₁) backed by a hard stop (k₂ = 5–20·k₁), anywhere in the
    last third of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.5 s behind a second-order Butterworth low-pass (cut-off 2–15 Hz);
    magnitude: the transport delay plus the filter's group delay at low frequency;
  * activation: a stretch reflex, fired when the stretching speed first passes a threshold after a random time,
    an alpha-function twitch (t/τ)·e^{1 − t/τ} (τ 0.05–0.25 s) summed over 1–3 firings 0.1–0.3 s apart;
    magnitude: the torque's peak;
  * limb-weight error: a centre of mass off the segment's axis by an angle of 5–30° (either side) and a mass
    error, a moment ∝ cos(θ + φ); magnitude: its peak;
  * drift: a load cell's logarithmic creep, a·ln(1 + t/τ_c) (τ_c 1–20 s), on a slow thermal swing; named only;
  * series compliance: a strap whose slack is taken up, give g₀·tanh(τ/τ₀) (the give saturating at g₀ 0.5–3°);
    magnitude: its compliance at no load, g₀/τ₀ (°/N·m);
  * inertia error: a balanced attachment on the arm, ΔI·θ̈ (no weight moment); magnitude ΔI.
- Nuisances: 100–2000 Hz; AR(1) noise (ρ 0–0.9); single-sample electrical spikes (none to three of 4–8 × the
  noise SD) in half the trials; quantised torque and angle; the clock fast or slow by up to 0.03 % with jitter;
  dropped rows singly (0–1.5 %) and in runs; NaN cells in any column (≤ 0.4 %, time included); torque and angle
  offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial

GRAVITY = 9.81
NOISE_SD_NM = {"afo": 0.05, "knee": 0.18, "ankle": 0.1}


def _softplus(x: np.ndarray) -> np.ndarray:
    return np.logaddexp(0.0, x)


def _trapezoid_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Strokes (deg) between ``lo`` and ``hi`` at a trapezoidal velocity profile, and the angular acceleration
    (deg/s²) the profile commands (piecewise constant)."""
    accel = float(rng.uniform(40.0, 250.0))
    dt = 1.0 / rate
    hold0 = np.full(int(rng.uniform(0.2, 0.8) * rate), lo)
    angles, accs = [hold0], [np.zeros(hold0.size)]
    start = lo
    for stroke in range(2 * int(rng.integers(2, 5))):
        end = hi if stroke % 2 == 0 else lo
        speed = float(rng.uniform(3.0, 30.0))
        dist = abs(end - start)
        ramp = speed / accel
        if accel * ramp**2 > dist:  # a triangle: the stroke is too short to reach the speed
            ramp = float(np.sqrt(dist / accel))
            speed = accel * ramp
        cruise = max(dist - accel * ramp**2, 0.0) / speed
        total = 2.0 * ramp + cruise
        s = np.arange(0.0, total, dt)
        pos = np.where(s < ramp, 0.5 * accel * s**2,
                       np.where(s < ramp + cruise, 0.5 * accel * ramp**2 + speed * (s - ramp),
                                dist - 0.5 * accel * np.clip(total - s, 0.0, None) ** 2))
        acc = np.where(s < ramp, accel, np.where(s < ramp + cruise, 0.0, -accel))
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


def butterworth_low_pass(cutoff_hz: float, rate: float) -> tuple[np.ndarray, np.ndarray, float]:
    """A second-order Butterworth low-pass (digital, at ``rate``): its coefficients and its group delay (s) at low
    frequency."""
    from scipy.signal import butter, group_delay

    b, a = butter(2, min(cutoff_hz / (0.5 * rate), 0.9))
    _, gd = group_delay((b, a), w=np.array([2 * np.pi * 0.05 / rate]))
    return b, a, float(gd[0]) / rate


def _reflex(rng: np.random.Generator, t: np.ndarray, stretch_speed: np.ndarray) -> tuple[np.ndarray, dict[str, Any]]:
    """A stretch reflex's unit torque: 1–3 alpha-function twitches from the first time after a random moment that
    the stretching speed passes a threshold (half the trial's top stretching speed)."""
    top = float(np.max(stretch_speed))
    after = float(rng.uniform(0.1, 0.6)) * float(t[-1])
    crossing = np.flatnonzero((t > after) & (stretch_speed > 0.5 * top))
    onset = float(t[crossing[0]]) if crossing.size else after
    tau = float(rng.uniform(0.05, 0.25))
    shape = np.zeros_like(t)
    for k in range(int(rng.integers(1, 4))):
        s = (t - onset - k * float(rng.uniform(0.1, 0.3))) / tau
        shape += np.where(s > 0.0, np.clip(s, 0.0, None) * np.exp(1.0 - np.clip(s, 0.0, None)), 0.0)
    return shape / max(float(shape.max()), 1e-12), {"reflex_onset_s": onset, "twitch_s": tau}


def generate_h(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    from scipy.signal import lfilter, lfilter_zi

    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials")
    rng = np.random.default_rng([8, 8, 1, list(EFFECTS).index(kind), seed,
                                 *sorted(EFFECTS[kind].index(e) for e in effects)])
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0, 2000.0]))
    subject = {"mass_kg": float(rng.uniform(45.0, 110.0)), "height_m": float(rng.uniform(1.50, 2.00))}
    subject["shank_length_m"] = 0.246 * subject["height_m"] * rng.uniform(0.95, 1.05)
    subject["foot_length_m"] = 0.152 * subject["height_m"] * rng.uniform(0.95, 1.05)
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        lo, hi = float(rng.uniform(3.0, 12.0)), float(rng.uniform(80.0, 95.0))
        deg, acc_deg = _trapezoid_strokes(rng, lo, hi, rate)
    elif kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        lo, hi = float(rng.uniform(-32.0, -22.0)), float(rng.uniform(10.0, 20.0))
        deg, acc_deg = _trapezoid_strokes(rng, lo, hi, rate)
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
    if "series_compliance" in effects:  # the joint turns less than the arm by the strap's give
        give_max, compliance = float(rng.uniform(0.5, 3.0)), float(rng.uniform(0.03, 0.2))
        load_scale = give_max / compliance  # N·m: the give is compliance × torque at small loads
        give = np.zeros_like(deg)
        for _ in range(40):  # the give answers to the torque it lets through: iterate to the fixed point
            give = give_max * np.tanh(_passive(kind, deg - give, fixed, coef, lo, hi) / load_scale)
        joint_deg = deg - give
        truth["series_compliance"] = compliance
        details.update(give_max_deg=give_max)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    passive = _passive(kind, joint_deg, fixed, coef, lo, hi)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        phi = float(rng.choice([-1.0, 1.0]) * rng.uniform(5.0, 30.0))
        base = joint if kind == "knee" else joint + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])
        shape = -np.cos(base + np.radians(phi))
        moment = size()
        torque = torque + moment * shape / float(np.max(np.abs(shape)))
        truth["gravity_error"] = moment
        details.update(com_offset_deg=phi)
    if "coulomb_friction" in effects:
        v0 = np.radians(float(rng.uniform(0.2, 1.5)))
        wobble, period, phase = float(rng.uniform(0.2, 0.5)), float(rng.uniform(20.0, 60.0)), float(rng.uniform(0, 360))
        level_shape = 1.0 + wobble * np.sin(2.0 * np.pi * (deg - phase) / period)
        level = size() / float(np.max(level_shape))
        torque = torque + level * level_shape * np.clip(vel / v0, -1.0, 1.0)
        moving = np.abs(vel) > v0
        truth["coulomb_friction"] = float(level * np.mean(level_shape[moving])) if moving.any() else float(level)
        details.update(friction_v0_deg_s=float(np.degrees(v0)), wobble=wobble, wobble_period_deg=period)
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
        pad, hard = float(rng.uniform(1.0, 4.0)), float(rng.uniform(5.0, 20.0))
        shape = np.where(pen < pad, pen, pad + hard * (pen - pad))
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", pad_deg=pad, hard_over_soft=hard)
    if "activation_burst" in effects:
        # the stretched muscle: knee flexion stretches the quadriceps, ankle dorsiflexion the calf (both positive)
        unit, info = _reflex(rng, t, np.clip(vel, 0.0, None))
        amp = size()
        torque = torque + amp * unit
        truth["activation_burst"] = amp
        details.update(info)
    if "sensor_drift" in effects:
        tau_c = float(rng.uniform(1.0, 20.0))
        creep = np.log1p(t / tau_c)
        swing = float(rng.uniform(-0.4, 0.4)) * np.sin(np.pi * t / t[-1] * float(rng.uniform(0.5, 1.0)))
        drift = float(rng.choice([-1.0, 1.0])) * creep / float(creep.max()) + swing
        torque = torque + size() * drift / max(float(np.max(np.abs(drift))), 1e-12)
        truth["sensor_drift"] = None
        details.update(creep_s=tau_c)
    if "time_delay" in effects:
        transport, cutoff = float(rng.uniform(0.0, 0.5)), float(rng.uniform(2.0, 15.0))
        b_f, a_f, filter_delay = butterworth_low_pass(cutoff, rate)
        filtered = lfilter(b_f, a_f, torque, zi=lfilter_zi(b_f, a_f) * torque[0])[0]
        torque = np.interp(t - transport, t, filtered, left=filtered[0])
        truth["time_delay"] = transport + filter_delay
        details.update(transport_s=transport, cutoff_hz=cutoff, filter_delay_s=filter_delay)
    white = rng.normal(0.0, sd * np.sqrt(1.0 - rho**2), t.size)
    noise = lfilter([1.0], [1.0, -rho], white, zi=[rho * rng.normal(0.0, sd)])[0]
    torque = torque + noise + rng.uniform(-1.0, 1.0)
    if rng.random() < 0.5:
        for _ in range(int(rng.integers(0, 4))):
            torque[int(rng.integers(0, t.size))] += float(rng.choice([-1.0, 1.0]) * rng.uniform(4.0, 8.0)) * sd
    quantum = float(rng.uniform(0.002, 0.015))
    torque = np.round(torque / quantum) * quantum
    angle_q = np.radians(float(rng.uniform(0.005, 0.04)))
    angle = np.round((rad + np.radians(rng.uniform(-0.5, 0.5))) / angle_q) * angle_q
    stamp = t * (1.0 + rng.uniform(-3e-4, 3e-4)) + rng.uniform(0.0, 0.1) / rate * rng.random(t.size)
    keep = rng.random(t.size) > rng.uniform(0.0, 0.015)
    for _ in range(int(rng.integers(0, 4))):  # runs of rows lost
        start = int(rng.integers(0, t.size))
        keep[start:start + int(rng.uniform(0.01, 0.1) * rate)] = False
    stamp, angle, torque = stamp[keep].copy(), angle[keep].copy(), torque[keep].copy()
    nan_rate = rng.uniform(0.0, 0.004)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "butterworth_low_pass", "generate_h"]
