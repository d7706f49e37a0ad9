"""Scaffolding the later generator families share (not their physics): a trial's random stream from its family,
kind, effects and seed (the fifth to thirteenth families), the subject drawn for a trial (the sixth to thirteenth), a lab
recording's damage (the seventh to thirteenth): quantised torque and angle (with an angle offset), a clock fast or
slow with jitter, rows dropped singly and in runs, NaN cells in any column; the protocol's set-up (the ninth to
thirteenth): the other joint's set angle, the swept range and the motion's kinematics; and the distal segment's
direction in the sagittal plane (the tenth, twelfth and thirteenth), the moving segments' load about the
joint (the thirteenth to sixteenth), the passive ends' onsets moved by the other joint's angle (the ninth, tenth and
thirteenth to sixteenth) and the value of gravity (the fifth to sixteenth; the third and fourth keep their own, as their
docstrings promise nothing imported).

Each family draws its own ranges; the draws are made in one fixed order, so a family's trials are the same as when
each wrote these out (checked on 450 trials of the five families, every array identical).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from .family_b_truth import EFFECTS

#: standard gravity (m/s²), the one value every family's limb weight uses
GRAVITY = 9.81


def trial_rng(family: tuple[int, ...], kind: str, effects: tuple[str, ...], seed: int) -> np.random.Generator:
    """The random stream of one trial: seeded by the family's own prefix, the kind, the seed and the hidden effects
    (in any order); raises ValueError for an effect the kind cannot hide (names as :data:`EFFECTS`)."""
    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials")
    return np.random.default_rng([*family, list(EFFECTS).index(kind), seed,
                                  *sorted(EFFECTS[kind].index(e) for e in effects)])


def draw_subject(rng: np.random.Generator) -> dict[str, float]:
    """A subject: mass 45–110 kg, height 1.50–2.00 m, shank 0.246 and foot 0.152 of the height (Winter's), each
    ±5 %."""
    subject = {"mass_kg": float(rng.uniform(45.0, 110.0)), "height_m": float(rng.uniform(1.50, 2.00))}
    subject["shank_length_m"] = 0.246 * subject["height_m"] * rng.uniform(0.95, 1.05)
    subject["foot_length_m"] = 0.152 * subject["height_m"] * rng.uniform(0.95, 1.05)
    return subject


def draw_segments(rng: np.random.Generator) -> dict[str, float]:
    """A trial's segment parameters within the published tables' spread (fractions): the shank 4.3–4.8 % of body
    mass, its centre 40–44 % down from the knee, radius of gyration 28–31 % of its length; the foot 1.2–1.5 %,
    42–48 %, 23–27 % (the thirteenth and fourteenth families)."""
    return {"shank_mass": float(rng.uniform(0.043, 0.048)), "shank_centre": float(rng.uniform(0.40, 0.44)),
            "shank_gyration": float(rng.uniform(0.28, 0.31)), "foot_mass": float(rng.uniform(0.012, 0.015)),
            "foot_centre": float(rng.uniform(0.42, 0.48)), "foot_gyration": float(rng.uniform(0.23, 0.27))}


def damage_recording(rng: np.random.Generator, t: np.ndarray, rad: np.ndarray, torque: np.ndarray, rate: float, *,
                     torque_quantum_nm: tuple[float, float], angle_quantum_deg: tuple[float, float],
                     clock_fraction: float, drop_fraction: float, run_s: float, nan_fraction: float
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time stamps s, angle rad, torque N·m) as recorded from the true ``t`` (s), ``rad`` and ``torque`` at
    ``rate`` (Hz): torque and angle quantised with steps drawn from the given ranges (N·m, degrees), the angle off
    by up to ±0.5°; the clock fast or slow by up to ``clock_fraction`` with up to a tenth of a period's jitter;
    up to ``drop_fraction`` of rows lost singly and 0–3 runs of 0.01–``run_s`` s lost; up to ``nan_fraction`` of
    each column's cells NaN."""
    quantum = float(rng.uniform(*torque_quantum_nm))
    torque = np.round(torque / quantum) * quantum
    angle_q = np.radians(float(rng.uniform(*angle_quantum_deg)))
    angle = np.round((rad + np.radians(rng.uniform(-0.5, 0.5))) / angle_q) * angle_q
    stamp = t * (1.0 + rng.uniform(-clock_fraction, clock_fraction)) + rng.uniform(0.0, 0.1) / rate * rng.random(t.size)
    keep = rng.random(t.size) > rng.uniform(0.0, drop_fraction)
    for _ in range(int(rng.integers(0, 4))):  # runs of rows lost
        start = int(rng.integers(0, t.size))
        keep[start:start + int(rng.uniform(0.01, run_s) * rate)] = False
    stamp, angle, torque = stamp[keep].copy(), angle[keep].copy(), torque[keep].copy()
    nan_rate = rng.uniform(0.0, nan_fraction)
    for col in (stamp, angle, torque):
        col[rng.random(col.size) < nan_rate] = np.nan
    return stamp, angle, torque


def protocol_set_up(rng: np.random.Generator, kind: str,
                    joint_motion: Callable[[np.random.Generator, float, float], np.ndarray],
                    afo_motion: Callable[[np.random.Generator], np.ndarray]
                    ) -> tuple[dict[str, float], float, float, np.ndarray]:
    """(the fixed joints' set angles in degrees, the range's low and high end in degrees, the angle in degrees) of one
    trial: a knee swept over 3–12° to 80–95° at a hip set to 90, 55 or 15°; an ankle over −32…−22° to 10–20° at a
    knee set to 0, 45 or 90°, the family's ``joint_motion(rng, lo, hi)`` between them; an orthosis bent by its
    ``afo_motion(rng)`` from 0° to its largest bend."""
    fixed: dict[str, float] = {}
    if kind == "knee":
        fixed = {"hip_flexion_deg": float(rng.choice([90.0, 55.0, 15.0])), "ankle_dorsiflexion_deg": 0.0}
        lo, hi = float(rng.uniform(3.0, 12.0)), float(rng.uniform(80.0, 95.0))
        return fixed, lo, hi, joint_motion(rng, lo, hi)
    if kind == "ankle":
        fixed = {"knee_flexion_deg": float(rng.choice([0.0, 45.0, 90.0])), "hip_flexion_deg": 90.0}
        lo, hi = float(rng.uniform(-32.0, -22.0)), float(rng.uniform(10.0, 20.0))
        return fixed, lo, hi, joint_motion(rng, lo, hi)
    deg = afo_motion(rng)
    return fixed, 0.0, float(deg.max()), deg


def coupled_onsets(kind: str, on_low: float, on_high: float, shift: float, fixed: dict[str, float]) -> tuple[float, float]:
    """(low, high) onsets (deg) of a joint's passive ends moved by the other joint's set angle, ``shift`` degrees per
    degree away from its middle setting: the knee's extension end (the hamstrings) engages earlier with the hip
    flexed past 55°, the ankle's dorsiflexion end (the gastrocnemius) earlier with the knee extended below 45°."""
    if kind == "knee":
        return on_low + shift * (fixed["hip_flexion_deg"] - 55.0), on_high
    return on_low, on_high - shift * (45.0 - fixed["knee_flexion_deg"])


def segment_direction(kind: str, rad: np.ndarray, fixed: dict[str, float]) -> np.ndarray:
    """The distal segment's direction (rad from the horizontal, sagittal plane): the knee's shank horizontal at 0°
    flexion (the thigh horizontal), the foot's from the ankle angle and the knee's flexion."""
    if kind == "knee":
        return -rad
    return rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])


class LimbLoad(NamedTuple):
    """The moving segments' load about the joint (the thirteenth to fifteenth families, from :func:`limb_load`)."""

    moment_nm: np.ndarray      # the weight's moment against increasing angle, N·m
    inertia_kgm2: float        # the moving segments' moment of inertia about the joint, kg·m²
    amplitude_nm: float        # the weight's moment amplitude m·g·r, N·m
    direction_rad: np.ndarray  # the distal segment's direction ψ (:func:`segment_direction`), rad
    shank_kg: float            # the moving shank's mass (0 at the ankle and on an orthosis), kg
    foot_kg: float             # the moving foot's mass (0 on an orthosis), kg


def limb_load(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float,
              seg: dict[str, float], gravity: float) -> LimbLoad:
    """The load of the segments moved at ``kind``'s joint (none on an orthosis): the knee moves the shank and foot
    (the foot a point mass at the shank's end), the ankle the foot. ``mass`` kg, ``shank`` and ``foot`` lengths m,
    ``seg`` the segment fractions of :func:`draw_segments`, ``gravity`` m/s²."""
    if kind == "afo":
        return LimbLoad(np.zeros_like(rad), 0.0, 0.0, np.zeros_like(rad), 0.0, 0.0)
    psi = segment_direction(kind, rad, fixed)
    if kind == "knee":
        m_s, m_f = seg["shank_mass"] * mass, seg["foot_mass"] * mass
        r_s = seg["shank_centre"] * shank
        amplitude = (m_s * r_s + m_f * shank) * gravity
        inertia = m_s * (r_s**2 + (seg["shank_gyration"] * shank) ** 2) + m_f * shank**2
        return LimbLoad(-amplitude * np.cos(psi), inertia, amplitude, psi, m_s, m_f)
    m_f = seg["foot_mass"] * mass
    r_f = seg["foot_centre"] * foot
    amplitude = m_f * gravity * r_f
    return LimbLoad(amplitude * np.cos(psi), m_f * (r_f**2 + (seg["foot_gyration"] * foot) ** 2), amplitude, psi, 0.0, m_f)


def behind_strap(deg: np.ndarray, give: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """The joint's angle j (deg) behind a strap or cable: j + give(j) = ``deg`` at each sample, by bisection (the give
    grows with the joint's torque, which grows with its angle, so the left side rises with j; the twenty-fourth and
    twenty-fifth families)."""
    low, high = deg - 60.0, deg + 60.0
    for _ in range(60):
        mid = 0.5 * (low + high)
        above = mid + give(mid) > deg
        high, low = np.where(above, mid, high), np.where(above, low, mid)
    return 0.5 * (low + high)


def softplus(x_deg: np.ndarray, smoothing_deg: float) -> np.ndarray:
    """A smooth ramp (deg): ``smoothing_deg``·ln(1 + e^(x/smoothing_deg)), zero far below 0 and ``x_deg`` far above it
    (the passive ends' and orthoses' engagement, the thirty-second to thirty-fourth families)."""
    return np.asarray(smoothing_deg * np.logaddexp(0.0, np.asarray(x_deg, dtype=float) / smoothing_deg), dtype=float)


def kinematics(deg: np.ndarray, rate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(time s, angle rad, angular velocity rad/s, angular acceleration rad/s²) of an angle (degrees) sampled at
    ``rate`` Hz (central differences)."""
    t = np.arange(deg.size) / rate
    rad = np.radians(deg)
    vel = np.gradient(rad, t)
    return t, rad, vel, np.gradient(vel, t)


__all__ = ["GRAVITY", "LimbLoad", "behind_strap", "coupled_onsets", "damage_recording", "draw_segments", "draw_subject",
           "kinematics", "limb_load", "protocol_set_up", "segment_direction", "softplus", "trial_rng"]
