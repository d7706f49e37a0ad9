"""A twelfth generator family for the diagnosis, written after the eleventh's run and run once on the engine as it stood.

The second to eleventh families (:mod:`benchmarks.family_b_truth` … ``family_k_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses (checked against their
docstrings and :mod:`analysis.diagnosis.causes` before it was run; the near relations are said at each cause).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and
the recording's damage and the protocol's set-up of
:mod:`benchmarks.family_scaffold`).

- Passive moment: a power law at each end of a joint's range, k·x^p for x the angle past an onset (p 2.5–4: it
  stiffens algebraically, neither exponentially nor with a limiting extension), the onset toward a two-joint muscle
  moved by the other joint's angle, plus a small linear term. The AFO: the same law with p 1.2–1.7 of the bend past
  an engagement reached through a softplus of 0.5–2°.
- Motion: isokinetic strokes at 3–15 °/s reached and left through cosine speed ramps of 0.2–0.5 s, in half of the
  strokes a "jog-back" (the operator reverses by 2–6° at a random point of the stroke and resumes), holds of 0.2–1 s,
  2–4 cycles. The AFO: double presses, each bend loaded to 55–80 % of its peak (10–20°), eased off by 2–5°, pressed
  to the peak and released, raised-cosine segments of 0.3–1.5 s.
- Limb: segment parameters drawn per trial within the published tables' spread (shank 4.3–4.9 % of body mass, its
  centre 38–45 % down from the knee, radius of gyration 27–30 % of its length; foot 1.3–1.5 %, 40–50 %, 24–28 %).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: velocity-strengthening boundary lubrication, F₀·(1 + a·ln(1 + |θ̇|/v₀)) with a 0.2–0.5, v₀ 1–4 °/s, its
    sign a smoothstep across ±w (w 0.2–1 °/s; the tenth family's rate-and-state friction had a small ln-speed term
    beside its state, 0.05–0.15); magnitude: the level's mean over the moving samples;
  * damping: Eyring's shear-thickening viscosity, b·v₀·sinh(θ̇/v₀), v₀ 0.6–1.5 × the trial's peak speed (it grows
    faster than linear, the opposite of the saturating and shear-thinning laws); magnitude: the least-squares
    coefficient of its torque on θ̇ over the moving samples;
  * stop: a conical rubber bumper, k·δⁿ with n 3–4 (the fourth family's Hunt–Crossley exponents ran to 2.5),
    anywhere in the last third of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a packetised link: the torque travels in packets of 10–50 ms, each late by its own latency drawn from a
    gamma distribution (shape 4–8) about a mean of 0.05–0.6 s, and the logger reads the newest packet's samples at
    each tick; magnitude: the mean lag of what it reads (shorter than the mean latency: the newest packet to have
    arrived is likelier a quick one);
  * activation: a single gamma-density pulse, (t/τ)^κ·e^{κ(1 − t/τ)} with κ 5–9 and its peak τ 0.3–1 s after onset,
    of either sign (the third family's were trains of 2–3 shorter twitches of shape 2–4); magnitude: its peak;
  * limb-weight error: a wobbling mass (the calf's or the foot's soft tissue, on a soft mount): its centre sags off
    the segment's axis by an angle growing with the weight across the segment, φ = φ_max·cos ψ (φ_max 15–40°), where
    the engine takes it as rigid; magnitude: the peak moment error;
  * drift: a strain gauge's hysteresis: after each stroke's load peak the zero steps by a share of that peak
    (toward its sign) and settles over 1–3 s, a staircase (the seventh family's one knocked-cable step and the
    eighth's zero following the load through a lag are its relatives); named only;
  * series compliance: a strap whose give depends on where the joint is, c(θ) = c̄·(1 + g·(2u − 1)), u 0 → 1 over the
    range, g 0.3–0.6 either way (its contact moving on the segment); magnitude: c̄ (°/N·m);
  * inertia error: a pad sliding along the segment as it turns, a point mass at r(θ) = r₀·(1 + s·(2u − 1)), s
    0.2–0.4: its torque d/dt(m·r²·θ̇) = m·r²·θ̈ + 2·m·r·r′·θ̇²; magnitude: the least-squares coefficient of its torque on
    θ̈.
- Nuisances: 100–1000 Hz; white noise plus a cross-talk periodic in *angle* (a gear's mesh or a cogging torque
  picked up by the sensor: a sinusoid of period 3–10° and 0.3–0.6 × the noise SD); a torque gain error of ±1.5 %;
  quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; dropped rows singly (0–1.5 %) and
  in runs; NaN cells in any column (≤ 0.4 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, damage_recording, draw_subject, kinematics, protocol_set_up, segment_direction, trial_rng

NOISE_SD_NM = {"afo": 0.06, "knee": 0.18, "ankle": 0.12}
#: how much larger an end's moment grows per degree its onset moves into the range with the other joint (1/deg)
COUPLING_PER_DEG = 0.025


def power_moment(x_deg: np.ndarray, power: float) -> np.ndarray:
    """x^p for ``x_deg`` past the onset (degrees), zero before it."""
    return np.clip(x_deg, 0.0, None) ** power


def _cosine_ramp(n: int) -> np.ndarray:
    """0 → 1 over ``n`` samples along a raised cosine (ends at exactly 0 and 1)."""
    return 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, max(n, 2)))


def _stroke(dist: float, speed: float, ramp_s: float, rate: float) -> np.ndarray:
    """Displacement (deg, 0 → ``dist``) at ``speed`` °/s with cosine speed ramps of ``ramp_s`` s at either end,
    scaled to end exactly on ``dist``."""
    duration = abs(dist) / speed + ramp_s
    t = np.arange(0.0, duration, 1.0 / rate)
    v = np.minimum(1.0, np.minimum(t, duration - t) / ramp_s)
    v = 0.5 - 0.5 * np.cos(np.pi * np.clip(v, 0.0, 1.0))
    s = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]))])
    return dist * s / s[-1] if s[-1] > 0 else np.zeros_like(s)


def jogged_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Cycles (deg) between ``lo`` and ``hi``; in half of the strokes the operator jogs back by 2–6° and resumes."""
    speed, ramp = float(rng.uniform(3.0, 15.0)), float(rng.uniform(0.2, 0.5))
    out = [np.full(int(rng.uniform(0.2, 1.0) * rate), lo)]
    for _ in range(int(rng.integers(2, 5))):
        for a, b in ((lo, hi), (hi, lo)):
            if rng.random() < 0.5:
                at = a + (b - a) * float(rng.uniform(0.25, 0.75))
                back = float(rng.uniform(2.0, 6.0)) * np.sign(b - a)
                legs = [(a, at), (at, at - back), (at - back, b)]
            else:
                legs = [(a, b)]
            for start, end in legs:
                out.append(start + _stroke(end - start, speed, ramp, rate))
            out.append(np.full(int(rng.uniform(0.2, 1.0) * rate), b))
    return np.concatenate(out)


def _double_presses(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): loaded to 55–80 % of the peak, eased off by 2–5°, pressed to the peak (10–20°), released."""
    parts = [np.zeros(int(0.4 * rate))]

    def seg(a: float, b: float) -> np.ndarray:
        return a + (b - a) * _cosine_ramp(int(rng.uniform(0.3, 1.5) * rate))

    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(10.0, 20.0))
        first = peak * float(rng.uniform(0.55, 0.8))
        eased = first - float(rng.uniform(2.0, 5.0))
        parts += [seg(0.0, first), seg(first, eased), seg(eased, peak), seg(peak, 0.0),
                  np.zeros(int(rng.uniform(0.2, 1.0) * rate))]
    return np.concatenate(parts)


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        bend = c["soft"] * np.logaddexp(0.0, (deg - c["engage"]) / c["soft"])
        return c["k"] * bend ** c["p"]
    on_low, on_high = c["on_low"], c["on_high"]
    span = c["hi"] - c["lo"]
    if kind == "knee":  # the hamstrings (the extension end) engage earlier with the hip flexed
        on_low = max(on_low + c["shift"] * (fixed["hip_flexion_deg"] - 55.0), c["lo"] + 0.1 * span)
    else:  # the gastrocnemius (the dorsiflexion end) earlier with the knee extended
        on_high = min(on_high - c["shift"] * (45.0 - fixed["knee_flexion_deg"]), c["hi"] - 0.1 * span)
    t_low = c["t_low"] * np.exp(COUPLING_PER_DEG * (on_low - c["on_low"]))
    t_high = c["t_high"] * np.exp(COUPLING_PER_DEG * (c["on_high"] - on_high))
    low = power_moment(on_low - deg, c["p_low"]) / (on_low - c["lo"]) ** c["p_low"]
    high = power_moment(deg - on_high, c["p_high"]) / (c["hi"] - on_high) ** c["p_high"]
    return -t_low * low + t_high * high + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"]))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its moment at a 15° bend, 10–25 N·m
        engage, soft, p = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.5, 2.0)), float(rng.uniform(1.2, 1.7))
        bend15 = soft * np.logaddexp(0.0, (15.0 - engage) / soft)
        return {"k": float(rng.uniform(10.0, 25.0)) / bend15**p, "engage": engage, "soft": soft, "p": p}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": lo + rng.uniform(0.2, 0.45) * span, "on_high": hi - rng.uniform(0.2, 0.45) * span,
            "p_low": float(rng.uniform(2.5, 4.0)), "p_high": float(rng.uniform(2.5, 4.0)),
            "shift": float(rng.uniform(0.05, 0.2)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float,
          seg: dict[str, float]) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "afo":
        return np.zeros_like(rad), 0.0
    psi = segment_direction(kind, rad, fixed)
    if kind == "knee":
        m_s, m_f = seg["shank_mass"] * mass, seg["foot_mass"] * mass
        r_s = seg["shank_centre"] * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(psi)
        return moment, m_s * (r_s**2 + (seg["shank_gyration"] * shank) ** 2) + m_f * shank**2
    m_f = seg["foot_mass"] * mass
    r_f = seg["foot_centre"] * foot
    return m_f * GRAVITY * r_f * np.cos(psi), m_f * (r_f**2 + (seg["foot_gyration"] * foot) ** 2)


def eyring(vel: np.ndarray, v0: float) -> np.ndarray:
    """Eyring's viscosity per unit coefficient: v₀·sinh(θ̇/v₀) (same units as ``vel``; slope 1 at rest)."""
    return v0 * np.sinh(vel / v0)


def smoothstep_sign(vel_deg_s: np.ndarray, band_deg_s: float) -> np.ndarray:
    """A sign through a cubic smoothstep across ±``band_deg_s``: −1 below, +1 above."""
    u = np.clip((vel_deg_s / band_deg_s + 1.0) / 2.0, 0.0, 1.0)
    return 2.0 * u * u * (3.0 - 2.0 * u) - 1.0


def gamma_pulse(t: np.ndarray, onset: float, peak_after_s: float, shape: float) -> np.ndarray:
    """(s/τ)^κ·e^{κ(1 − s/τ)} for s = t − onset ≥ 0 (peak 1 at s = τ), zero before the onset."""
    s = np.clip((t - onset) / peak_after_s, 0.0, None)
    return np.where(t >= onset, s**shape * np.exp(shape * (1.0 - s)), 0.0)


def packet_latency(rng: np.random.Generator, t: np.ndarray, mean_s: float, shape: float, packet_s: float
                   ) -> np.ndarray:
    """The latency (s) of each sample's packet: packets of ``packet_s`` s, each late by a gamma-distributed latency
    (``shape``, mean ``mean_s``)."""
    packet = np.floor((t - t[0]) / packet_s).astype(int)
    lat = rng.gamma(shape, mean_s / shape, int(packet.max()) + 1)
    return lat[packet]


def read_newest(t: np.ndarray, x: np.ndarray, latency: np.ndarray) -> np.ndarray:
    """What a logger reads at each tick of ``t``: the newest sample of ``x`` that has arrived (a sample made at
    t_j arrives at t_j + latency_j); before anything arrived, the first sample. Reading ``t`` itself gives the
    time each read sample was made."""
    arrival = t + latency
    order = np.argsort(arrival, kind="stable")
    count = np.searchsorted(arrival[order], t, side="right")  # how many samples have arrived by each tick
    newest = np.maximum.accumulate(order)  # the latest-made sample among the first m arrivals
    idx = np.where(count > 0, newest[np.maximum(count - 1, 0)], 0)
    return x[idx]


def staircase_drift(t: np.ndarray, torque: np.ndarray, vel: np.ndarray, settle_s: float) -> np.ndarray:
    """A zero stepping after each stroke's load peak by that peak (toward its sign), each step settling through a
    first-order lag of ``settle_s`` s: the unit staircase (scaled by the caller)."""
    ends = np.flatnonzero(np.diff(np.sign(np.where(np.abs(vel) > np.radians(0.5), vel, 0.0))) != 0) + 1
    bounds = np.concatenate([[0], ends, [t.size]])
    target = np.zeros(t.size)
    level = 0.0
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        target[a:b] = level
        if b > a:
            seg = torque[a:b]
            level += float(seg[int(np.argmax(np.abs(seg)))])
    y = np.empty(t.size)
    y[0] = target[0]
    for i in range(1, t.size):
        a = np.exp(-(t[i] - t[i - 1]) / settle_s)
        y[i] = a * y[i - 1] + (1.0 - a) * target[i]
    return y


def generate_l(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((12, 12, 7), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = {"shank_mass": float(rng.uniform(0.043, 0.049)), "shank_centre": float(rng.uniform(0.38, 0.45)),
           "shank_gyration": float(rng.uniform(0.27, 0.30)), "foot_mass": float(rng.uniform(0.013, 0.015)),
           "foot_centre": float(rng.uniform(0.40, 0.50)), "foot_gyration": float(rng.uniform(0.24, 0.28))}
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: jogged_strokes(r, a, b, rate),
                                         lambda r: _double_presses(r, rate))
    t, rad, vel, acc = kinematics(deg, rate)
    coef = _coefficients(rng, kind, lo, hi)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    along = np.clip((deg - lo) / max(hi - lo, 1e-9), 0.0, 1.0)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap whose give depends on where the joint is
        c_mean, grow = float(rng.uniform(0.03, 0.12)), float(rng.uniform(0.3, 0.6)) * float(rng.choice([-1.0, 1.0]))
        comp = c_mean * (1.0 + grow * (2.0 * along - 1.0))
        # the joint's angle j solves deg − j = c·P(j), whose left side falls and right side rises with j: bisection
        low_j, high_j = deg - 30.0, deg + 30.0
        for _ in range(60):
            mid = 0.5 * (low_j + high_j)
            excess = deg - mid - comp * _passive(kind, mid, fixed, coef)
            low_j, high_j = np.where(excess > 0.0, mid, low_j), np.where(excess > 0.0, high_j, mid)
        joint_deg = 0.5 * (low_j + high_j)
        truth["series_compliance"] = c_mean
        details.update(compliance_growth=grow)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot, seg)
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # a wobbling mass: its centre sags off the segment's axis by φ = φ_max·cos ψ, which the engine takes as rigid
        psi = segment_direction(kind, joint, fixed)
        sag = np.radians(float(rng.uniform(15.0, 40.0))) * np.cos(psi)
        unit = np.cos(psi + sag) - np.cos(psi)  # per unit m·g·r, toward the weight's moment sign
        sign = -1.0 if kind == "knee" else 1.0
        error = sign * size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(sag_max_deg=float(np.degrees(np.max(np.abs(sag)))))
    if "coulomb_friction" in effects:
        a, v0, band = float(rng.uniform(0.2, 0.5)), float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.2, 1.0))
        level = 1.0 + a * np.log1p(np.abs(np.degrees(vel)) / v0)
        unit = level * smoothstep_sign(np.degrees(vel), band)
        f0 = size() / float(np.max(np.abs(unit)))
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(level[moving]))
        details.update(strengthening=a, strengthening_speed_deg_s=v0, stick_band_deg_s=band)
    if "viscous_damping" in effects:
        v0 = float(rng.uniform(0.6, 1.5)) * float(np.max(np.abs(vel)))
        unit = eyring(vel, v0)
        b = size() / float(np.max(np.abs(unit)))
        torque = torque + b * unit
        v_m, u_m = vel[moving], b * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(eyring_speed_deg_s=float(np.degrees(v0)))
    if "inertia" in effects:
        spread = float(rng.uniform(0.2, 0.4)) * float(rng.choice([-1.0, 1.0]))
        r = 1.0 + spread * (2.0 * along - 1.0)           # r/r₀ along the range
        r_prime = 2.0 * spread / np.radians(max(hi - lo, 1e-9))  # d(r/r₀)/dθ (1/rad)
        unit = r**2 * acc + 2.0 * r * r_prime * vel**2   # per unit m·r₀²
        d_inertia = size() / float(np.max(np.abs(unit)))
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(pad_spread=spread)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        n = float(rng.uniform(3.0, 4.0))
        shape = pen**n
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", stop_exponent=n)
    if "activation_burst" in effects:
        shape_k, peak_after = float(rng.uniform(5.0, 9.0)), float(rng.uniform(0.3, 1.0))
        onset = float(rng.uniform(0.15, 0.75)) * float(t[-1])
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * gamma_pulse(t, onset, peak_after, shape_k)
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_peak_after_s=peak_after, burst_shape=shape_k)
    if "sensor_drift" in effects:
        stairs = staircase_drift(t, torque - float(np.median(torque)), vel, float(rng.uniform(1.0, 3.0)))
        torque = torque + size() * stairs / max(float(np.max(np.abs(stairs))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        mean_s, shape_g, packet_s = float(rng.uniform(0.05, 0.6)), float(rng.uniform(4.0, 8.0)), float(
            rng.uniform(0.01, 0.05))
        latency = packet_latency(rng, t, mean_s, shape_g, packet_s)
        torque = read_newest(t, torque, latency)
        lag = t - read_newest(t, t, latency)
        settled = t >= t[0] + float(latency.max())  # once every packet could have arrived
        truth["time_delay"] = float(np.mean(lag[settled]))
        details.update(mean_latency_s=mean_s, latency_shape=shape_g, packet_s=packet_s)
    period = float(rng.uniform(3.0, 10.0))
    noise = rng.normal(0.0, sd, t.size) + float(rng.uniform(0.3, 0.6)) * sd * np.sin(
        2.0 * np.pi * deg / period + float(rng.uniform(0.0, 2.0 * np.pi)))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.015),
                                            angle_quantum_deg=(0.005, 0.04), clock_fraction=2e-4, drop_fraction=0.015,
                                            run_s=0.1, nan_fraction=0.004)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "eyring", "gamma_pulse", "generate_l",
           "jogged_strokes", "packet_latency", "power_moment", "read_newest", "smoothstep_sign", "staircase_drift"]
