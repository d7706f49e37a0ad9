"""An eighteenth generator family for the diagnosis, written after the seventeenth's run and before the next engine
change, to be run once on that change's frozen engine.

The second to seventeenth families (:mod:`benchmarks.family_b_truth` … ``family_q_truth``) became development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` before it was run; where an earlier family used a near relation it is said).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
segments' draw, the recording's damage, the protocol's set-up and the limb's load of :mod:`benchmarks.family_scaffold`).

- Passive moment: a ligament-like toe region at each end of a joint's range, k·w·softplus((x − x₀)/w) for x the angle
  toward that end (a stiffness rising along a logistic of width w 2–8° to a constant: toe, then linear; the
  steep end's stiffness set by its torque at the range's end), the onset toward a two-joint muscle moved by the other
  joint's angle. The AFO: a leaf spring bent past an engagement of 0.5–3°, k·θ^p with p 1.15–1.5 (a tapered leaf
  stiffens as its contact point moves).
- Motion: a dynamometer's ramp-and-hold strokes: each stroke between the range's ends at its own speed (3–10 °/s),
  reached and left with a constant acceleration of 15–60 °/s², held 0–1.5 s at each end, 3–5 cycles; one stroke in
  three turns back early, 20–40 % of the range short of its end (nested loops). The AFO: 5–8 minimum-jerk bends to
  10–20° and back, one in three reversed early at 40–70 % of its peak and bent again to the peak.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: load-dependent (a hinge's bearing friction rises with the torque it carries): sign(θ̇)·(F₀ + μ·|τ_el|)
    through a tanh of width 0.3–1.5 °/s, μ such that the load's share is 30–70 % of the level at the largest
    elastic torque (the eleventh family's friction rose with angle, not with load); magnitude: its mean over the
    moving samples;
  * damping: a power law, b·sign(θ̇)·|θ̇/v₉₅|^p·v₉₅ with p 0.5–1.8 about the 95th-percentile speed (the fifteenth
    family's relief valve and the first's shear-thinning were saturating laws); magnitude: the least-squares slope
    of its torque on θ̇;
  * stop: a Hunt–Crossley contact, k·δⁿ·(1 + λ·δ̇) with n 1.2–2 and λ 0–0.1 s/° (Hunt & Crossley 1975:
    λ = 1.5(1 − e)/v_in, a restitution e of 0.5–0.9 at 10–20 °/s), δ the penetration past a contact angle that is
    re-seated on each stroke (±0.3–1.5° about its mean: a strap's buckle), the mean anywhere in the
    last 5–30 % of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.35 s through an amplifier's second-order Butterworth low-pass (cut-off 1.5–8 Hz,
    group delay √2/(2πf_c) at low frequency); magnitude: the total low-frequency group delay;
  * activation: a gamma-shaped twitch, (t/t_p)^k·e^{k(1 − t/t_p)} (time to peak t_p 0.1–0.5 s, k 2–6), two of them
    0.4–1.5 s apart with the second 40–90 % of the first (a doublet), either sign; magnitude: the larger peak;
  * limb-weight error: the segment's centre of mass off its long axis by 5–20° and its moment amplitude wrong,
    ΔA·cos(ψ + φ) (earlier families' errors followed the modelled segment's own direction); magnitude: its peak;
  * drift: a thermal drift, a linear ramp plus an air-conditioning cycle (a sinusoid of period 60–300 s), either
    share 30–70 %; named only;
  * series compliance: a strap that stiffens as it tightens, give = c·τ/(1 + |τ|/τ_s), τ_s 0.5–2 × the largest
    elastic torque; magnitude: the least-squares slope of the give on the torque;
  * inertia error: an attachment on a linkage whose reflected inertia changes with angle, I₀·(1 + 0.2–0.5·cos(θ − θ_m))
    (its torque I(θ)·θ̈ + ½·I′(θ)·θ̇²); magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances: 100–1000 Hz; white noise plus a 1/f-like flicker (two AR(1) processes, ρ 0.9 and 0.995, at 0.2–0.5 ×
  the noise SD); mains hum (50 or 60 Hz, 0.1–0.4 × the noise SD) at rates of 250 Hz and over (below, the
  amplifier's anti-alias filter takes it); rare electrical spikes (0–0.05 % of rows, 4–10 × the noise SD); a torque
  gain error of ±1.5 %; quantised torque and angle; the clock fast or slow by up to 0.03 % with jitter; rows
  dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import butter, lfilter, lfilter_zi

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import (
    GRAVITY,
    coupled_onsets,
    damage_recording,
    draw_segments,
    draw_subject,
    kinematics,
    limb_load,
    protocol_set_up,
    trial_rng,
)

NOISE_SD_NM = {"afo": 0.06, "knee": 0.16, "ankle": 0.12}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def toe_linear(x_deg: np.ndarray, onset_deg: float, width_deg: float) -> np.ndarray:
    """A toe region's torque per unit stiffness (deg): w·softplus((x − x₀)/w), whose slope rises along a logistic
    from 0 to 1 around the onset (toe, then linear)."""
    z = (np.asarray(x_deg, dtype=float) - onset_deg) / width_deg
    return width_deg * np.logaddexp(0.0, z)


def ramp_hold_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of a dynamometer's strokes: from ``lo``, each stroke at its own speed (3–10 °/s) reached and left
    at a constant acceleration (15–60 °/s²), held 0–1.5 s at its end; one stroke in three turns back 20–40 % of the
    range short of its end; 3–5 cycles."""
    accel = float(rng.uniform(15.0, 60.0))
    here, parts, strokes = lo, [np.full(int(0.5 * rate), lo)], 2 * int(rng.integers(3, 6))
    for i in range(strokes):
        going_up = i % 2 == 0
        end = hi if going_up else lo
        if rng.random() < 1.0 / 3.0:
            short = float(rng.uniform(0.2, 0.4)) * (hi - lo)
            end = end - short if going_up else end + short
        distance = abs(end - here)
        speed = min(float(rng.uniform(3.0, 10.0)), float(np.sqrt(accel * distance)))  # a short stroke may not reach it
        ramp_s = speed / accel
        cruise_s = max(distance / speed - ramp_s, 0.0)
        t = np.arange(0.0, 2.0 * ramp_s + cruise_s, 1.0 / rate)
        travelled = np.where(t < ramp_s, 0.5 * accel * t**2,
                             np.where(t < ramp_s + cruise_s, 0.5 * accel * ramp_s**2 + speed * (t - ramp_s),
                                      distance - 0.5 * accel * np.maximum(2.0 * ramp_s + cruise_s - t, 0.0) ** 2))
        travelled = np.clip(travelled, 0.0, distance)
        parts.append(here + (1.0 if end > here else -1.0) * travelled)
        here = end
        parts.append(np.full(int(float(rng.uniform(0.0, 1.5)) * rate) + 1, here))
    return np.concatenate(parts)


def minimum_jerk(start: float, end: float, samples: int) -> np.ndarray:
    """A minimum-jerk path from ``start`` to ``end`` over ``samples`` samples: start + (end − start)(10s³ − 15s⁴ + 6s⁵)."""
    s = np.linspace(0.0, 1.0, max(samples, 2))
    return start + (end - start) * (10 * s**3 - 15 * s**4 + 6 * s**5)


def minimum_jerk_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–8 bends from 0° to 10–20° and back, each way 0.8–2.5 s of minimum jerk; one in three turned
    back early at 40–70 % of its peak and bent again to the peak; 0.3 s at rest between bends."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(10.0, 20.0))
        if rng.random() < 1.0 / 3.0:
            turn = float(rng.uniform(0.4, 0.7)) * peak
            parts += [minimum_jerk(0.0, peak, int(rng.uniform(0.8, 2.5) * rate)),
                      minimum_jerk(peak, turn, int(rng.uniform(0.4, 1.2) * rate)),
                      minimum_jerk(turn, peak, int(rng.uniform(0.4, 1.2) * rate))]
        else:
            parts.append(minimum_jerk(0.0, peak, int(rng.uniform(0.8, 2.5) * rate)))
        parts.append(minimum_jerk(peak, 0.0, int(rng.uniform(0.8, 2.5) * rate)))
        parts.append(np.zeros(int(0.3 * rate)))
    return np.concatenate(parts)


def load_dependent_friction(vel: np.ndarray, elastic_nm: np.ndarray, base_nm: float, mu: float,
                            width: float) -> np.ndarray:
    """A bearing's friction (N·m, resisting the motion): (F₀ + μ·|τ_el|)·tanh(θ̇ / width) (``vel`` and ``width`` in
    one unit)."""
    return (base_nm + mu * np.abs(elastic_nm)) * np.tanh(vel / width)


def power_law_damping(vel: np.ndarray, reference: float, exponent: float) -> np.ndarray:
    """A damping per unit coefficient: sign(θ̇)·|θ̇/v_ref|^p·v_ref (the unit of ``vel``), equal to θ̇ at ±v_ref."""
    return np.sign(vel) * np.abs(vel / reference) ** exponent * reference


def hunt_crossley_stop(deg: np.ndarray, vel_deg_s: np.ndarray, contact_deg: np.ndarray, high: bool, exponent: float,
                       dissipation_s_per_deg: float) -> np.ndarray:
    """A Hunt–Crossley contact per unit stiffness, toward the range's inside (positive at the high end):
    δⁿ·(1 + λ·δ̇), δ the penetration (deg) past ``contact_deg`` (one value per sample: re-seated per stroke), never
    pulling (clipped at zero)."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (deg - contact_deg), 0.0, None)
    rate = sign * vel_deg_s
    return sign * np.clip(depth**exponent * (1.0 + dissipation_s_per_deg * rate), 0.0, None)


def stroke_contacts(deg: np.ndarray, mean_deg: float, spread_deg: float, rng: np.random.Generator) -> np.ndarray:
    """The stop's contact angle (deg) at each sample: ``mean_deg`` moved by up to ±``spread_deg`` on each stroke (a
    stroke from one reversal of the angle to the next)."""
    direction = np.sign(np.diff(deg, prepend=deg[0]))
    # carry the last direction through holds (increasing before the first move)
    last_move = np.maximum.accumulate(np.where(direction != 0, np.arange(direction.size), -1))
    filled = np.where(last_move >= 0, direction[np.maximum(last_move, 0)], 1.0)
    stroke = np.concatenate([[0], np.cumsum(np.diff(filled) != 0)])
    offsets = rng.uniform(-spread_deg, spread_deg, int(stroke[-1]) + 1)
    return mean_deg + offsets[stroke]


def butterworth_lag(torque: np.ndarray, rate: float, cutoff_hz: float, transport_s: float, t: np.ndarray) -> np.ndarray:
    """``torque`` read ``transport_s`` late (interpolated, held at the first sample before the trial) through a
    second-order Butterworth low-pass at ``cutoff_hz`` (started at rest on the first sample)."""
    late = np.interp(t - transport_s, t, torque)
    b, a = butter(2, cutoff_hz, fs=rate)
    return lfilter(b, a, late, zi=lfilter_zi(b, a) * late[0])[0]


def gamma_doublet(t: np.ndarray, first_s: float, gap_s: float, time_to_peak_s: float, shape: float,
                  second_share: float) -> np.ndarray:
    """Two gamma-shaped twitches (t/t_p)^k·e^{k(1 − t/t_p)} (peak 1 at t_p after each start), the second ``gap_s``
    after the first at ``second_share`` of its size."""
    def twitch(start: float) -> np.ndarray:
        u = np.clip((t - start) / time_to_peak_s, 0.0, None)
        return np.where(u > 0.0, u**shape * np.exp(shape * (1.0 - u)), 0.0)

    return twitch(first_s) + second_share * twitch(first_s + gap_s)


def thermal_drift(t: np.ndarray, ramp_share: float, period_s: float, phase: float) -> np.ndarray:
    """A ramp plus a sinusoid (shares ``ramp_share`` and 1 − it of their sum's scale); largest excursion 1 about its
    mean."""
    span = max(float(t[-1] - t[0]), 1e-9)
    y = ramp_share * (t - t[0]) / span + (1.0 - ramp_share) * np.sin(2.0 * np.pi * t / period_s + phase)
    y = y - np.mean(y)
    return y / max(float(np.max(np.abs(y))), 1e-12)


def stiffening_give(torque: np.ndarray, saturation_nm: float) -> np.ndarray:
    """A strap's give per unit compliance (N·m): τ/(1 + |τ|/τ_s)."""
    return torque / (1.0 + np.abs(torque) / saturation_nm)


def linkage_inertia_torque(rad: np.ndarray, vel: np.ndarray, acc: np.ndarray, inertia: float, depth: float,
                           centre_rad: float) -> np.ndarray:
    """The torque (N·m) of an attachment whose reflected inertia I(θ) = I₀(1 + d·cos(θ − θ_m)): I(θ)·θ̈ + ½·I′(θ)·θ̇²."""
    i_theta = inertia * (1.0 + depth * np.cos(rad - centre_rad))
    d_i = -inertia * depth * np.sin(rad - centre_rad)
    return i_theta * acc + 0.5 * d_i * vel**2


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * np.maximum(deg - c["engage"], 0.0) ** c["power"]
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["k_low"] * toe_linear(-deg, -on_low, c["w_low"]) + c["k_high"] * toe_linear(deg, on_high, c["w_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, power = float(rng.uniform(0.5, 3.0)), float(rng.uniform(1.15, 1.5))
        return {"engage": engage, "power": power, "k": float(rng.uniform(10.0, 25.0)) / (15.0 - engage) ** power}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.15, 0.4) * span, hi - rng.uniform(0.15, 0.4) * span
    w_low, w_high = float(rng.uniform(2.0, 8.0)), float(rng.uniform(2.0, 8.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"k_low": t_low / float(toe_linear(np.array(-lo), -on_low, w_low)),
            "k_high": t_high / float(toe_linear(np.array(hi), on_high, w_high)),
            "on_low": on_low, "on_high": on_high, "w_low": w_low, "w_high": w_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_r(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((18, 18, 18), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: ramp_hold_strokes(r, a, b, rate),
                                         lambda r: minimum_jerk_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap stiffening as it tightens: give c·τ/(1 + |τ|/τ_s)
        c_give = float(rng.uniform(0.03, 0.15))
        saturation = float(rng.uniform(0.5, 2.0)) * max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1.0)
        for _ in range(4):  # the joint turns by the angle less the give, which depends on the torque it meets
            joint_deg = deg - c_give * stiffening_give(_elastic(kind, joint_deg, fixed, coef), saturation)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, saturation_Nm=saturation)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    elastic = _elastic(kind, joint_deg, fixed, coef)
    torque = elastic + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the centre of mass off the segment's axis and its moment amplitude wrong
        off = np.radians(float(rng.uniform(5.0, 20.0))) * float(rng.choice([-1.0, 1.0]))
        unit = np.cos(load.direction_rad + off) * (-1.0 if kind == "knee" else 1.0)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12) * float(rng.choice([-1.0, 1.0]))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(centre_off_axis_deg=float(np.degrees(off)), weight_moment_amplitude_Nm=load.amplitude_nm)
    if "coulomb_friction" in effects:
        width = float(rng.uniform(0.3, 1.5))
        load_share = float(rng.uniform(0.3, 0.7))
        level = size()
        base = (1.0 - load_share) * level
        mu = load_share * level / max(float(np.max(np.abs(elastic))), 1e-9)
        friction = load_dependent_friction(vel_deg, elastic, base, mu, width)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
        details.update(friction_width_deg_s=width, load_share=load_share)
    if "viscous_damping" in effects:
        reference = float(np.percentile(np.abs(vel), 95))
        exponent = float(rng.uniform(0.5, 1.8))
        unit = power_law_damping(vel, reference, exponent)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
        details.update(damping_exponent=exponent)
    if "inertia" in effects:
        depth, centre = float(rng.uniform(0.2, 0.5)), float(rng.uniform(rad.min(), rad.max()))
        unit = linkage_inertia_torque(rad, vel, acc, 1.0, depth, centre)
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(linkage_depth=depth)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high else bottom + depth * (top - bottom)
        contacts = stroke_contacts(deg, at, float(rng.uniform(0.3, 1.5)), rng)
        unit = hunt_crossley_stop(deg, vel_deg, contacts, high, float(rng.uniform(1.2, 2.0)),
                                  float(rng.uniform(0.0, 0.1)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low")
    if "activation_burst" in effects:
        first = float(rng.uniform(0.1, 0.8)) * float(t[-1])
        unit = gamma_doublet(t, first, float(rng.uniform(0.4, 1.5)), float(rng.uniform(0.1, 0.5)),
                             float(rng.uniform(2.0, 6.0)), float(rng.uniform(0.4, 0.9)))
        peak = size()
        burst = float(rng.choice([-1.0, 1.0])) * peak * unit / max(float(np.max(unit)), 1e-12)
        torque = torque + burst
        truth["activation_burst"] = peak
        details.update(burst_start_s=first)
    if "sensor_drift" in effects:
        torque = torque + size() * thermal_drift(t, float(rng.uniform(0.3, 0.7)), float(rng.uniform(60.0, 300.0)),
                                                 float(rng.uniform(0.0, 2.0 * np.pi)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        transport, cutoff = float(rng.uniform(0.0, 0.35)), float(rng.uniform(1.5, 8.0))
        torque = butterworth_lag(torque, rate, cutoff, transport, t)
        truth["time_delay"] = transport + float(np.sqrt(2.0) / (2.0 * np.pi * cutoff))
        details.update(transport_s=transport, cutoff_hz=cutoff)
    noise = rng.normal(0.0, sd, t.size)
    for rho in (0.9, 0.995):  # a 1/f-like flicker from two time scales
        flicker = lfilter([1.0], [1.0, -rho], rng.normal(0.0, 1.0, t.size))
        noise += float(rng.uniform(0.2, 0.5)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    if rate >= 250.0:
        mains = float(rng.choice([50.0, 60.0]))
        noise += float(rng.uniform(0.1, 0.4)) * sd * np.sin(2.0 * np.pi * mains * t + rng.uniform(0.0, 2.0 * np.pi))
    spikes = rng.random(t.size) < rng.uniform(0.0, 5e-4)
    noise[spikes] += rng.uniform(4.0, 10.0, int(spikes.sum())) * sd * rng.choice([-1.0, 1.0], int(spikes.sum()))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=3e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "butterworth_lag", "gamma_doublet",
           "generate_r", "hunt_crossley_stop", "linkage_inertia_torque", "load_dependent_friction", "minimum_jerk",
           "minimum_jerk_bends", "power_law_damping", "ramp_hold_strokes", "stiffening_give", "stroke_contacts",
           "thermal_drift", "toe_linear"]
