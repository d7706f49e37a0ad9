"""A nineteenth generator family for the diagnosis, written after the eighteenth's run and before the next engine
change, to be run once on that change's frozen engine.

The second to eighteenth families (:mod:`benchmarks.family_b_truth` … ``family_r_truth``) became development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` before it was run; where an earlier family used a near relation it is said).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
segments' draw, the recording's damage, the protocol's set-up and the limb's load of :mod:`benchmarks.family_scaffold`).

- Passive moment: collagen fibres recruited one by one (the statistical recruitment model of tendon and ligament): at
  each end of a joint's range 12–30 linear fibres whose slack angles are drawn from a normal distribution about an
  onset (SD 3–8°), the steep end's fibres sized by their torque at the range's end. The AFO: a spring on a linkage
  (the AADS geometry), a linear spring between two pins at 4–7 cm and 8–12 cm from the hinge, preloaded to 1–4 mm:
  τ = k·(l − l₀)·dl/dθ.
- Motion: a dynamometer's strokes at a speed drawn per stroke (4–12 °/s), each with smooth starts and stops (a
  raised-cosine speed over 0.3–1 s), with the drive's cogging ripple in angle (0.05–0.2° over every 3–6° of travel).
  The AFO: 5–8 hand bends, each a sine in time with its own peak (10–20°) and unequal up and down times (0.6–2.5 s),
  with a physiological tremor (8–12 Hz, 0.03–0.15°).
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb friction that runs in, its level falling by 20–50 % with a time constant of 10–60 s (the
    sixth family's friction faded over the whole trial linearly); sign through a tanh of width 0.3–1.5 °/s;
    magnitude: its mean over the moving samples;
  * damping: a springpot (a fractional derivative of order α 0.5–0.9 of the angle, Grünwald–Letnikov), the
    viscoelastic element between a spring and a dashpot; magnitude: the least-squares coefficient on θ̇ of its torque
    regressed on θ̇ and a cubic in angle (the part a curve in angle does not hold);
  * stop: a bilinear stop, a soft pad of 1–3° and then a 3–10 × stiffer seat, anywhere in the last 3–25 % of either
    end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a torque sensor polled at 8–40 Hz and held between polls (a zero-order hold) after a transport delay of
    0–0.3 s; magnitude: the transport plus half the poll period;
  * activation: a stretch reflex's catch, a linear rise over 0.05–0.2 s and an exponential decay over 0.2–0.8 s, of
    either sign; magnitude: its peak;
  * limb-weight error: the segment's mass wrong, its soft tissue shifting with the segment's direction (a second
    harmonic of 10–30 %): ΔA·(cos ψ + h·sin 2ψ); magnitude: its peak;
  * drift: a cable knocked once (a step of either sign at 15–85 % of the trial, recovering over 20–60 s); named only;
  * series compliance: a strap with play, a linear give c·τ plus a backlash of 0.2–0.5° taken up at each reversal of
    the torque; magnitude: the least-squares slope of the give on the torque;
  * inertia error: an unmodelled mass seen through the coupling between the drive and the limb (a resonance of 5–10
    Hz, damping ratio 0.1–0.3): the mass's torque follows the limb's acceleration, which lags the drive's angle that
    is recorded; magnitude: the least-squares coefficient of its torque on the recorded angle's θ̈.
- Nuisances: 100–1000 Hz; white noise plus an amplifier's flicker (an AR(1), ρ 0.97–0.995, at 0.2–0.5 × the noise
  SD); the torque's gain drifting by up to ±1 % over the trial (the bridge warming); quantised torque and angle; the
  clock fast or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column
  (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import fftconvolve, lfilter

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

NOISE_SD_NM = {"afo": 0.065, "knee": 0.17, "ankle": 0.125}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def recruited_fibres(x_deg: np.ndarray, slack_deg: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """The torque of linear fibres each taut past its slack angle: Σ kᵢ·max(x − sᵢ, 0) (``x_deg`` toward the end)."""
    x = np.asarray(x_deg, dtype=float)[..., None]
    return np.sum(stiffness * np.maximum(x - slack_deg, 0.0), axis=-1)


def linkage_spring(deg: np.ndarray, pin_a_m: float, pin_b_m: float, preload_m: float, k_n_per_m: float) -> np.ndarray:
    """A linear spring between pins at ``pin_a_m`` and ``pin_b_m`` from the hinge (at right angles at 0°), resting
    ``preload_m`` shorter than its length at 0°: τ = k·(l − l₀)·dl/dθ (N·m for θ in degrees turned to rad)."""
    th = np.radians(deg) + np.pi / 2
    length = np.sqrt(pin_a_m**2 + pin_b_m**2 - 2 * pin_a_m * pin_b_m * np.cos(th))
    rest = float(np.sqrt(pin_a_m**2 + pin_b_m**2)) - preload_m
    dl = pin_a_m * pin_b_m * np.sin(th) / length
    return k_n_per_m * (length - rest) * dl


def paced_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg) of 3–5 cycles of strokes between ``lo`` and ``hi``, each at its own speed (4–12 °/s) reached and
    left along a raised-cosine speed over 0.3–1 s, 0.2–0.6 s still at each end, with the drive's cogging ripple
    (0.05–0.2° over every 3–6° of travel)."""
    parts = [np.full(int(0.5 * rate), lo)]
    ramp_s = float(rng.uniform(0.3, 1.0))
    for i in range(2 * int(rng.integers(3, 6))):
        start, end = (lo, hi) if i % 2 == 0 else (hi, lo)
        speed = float(rng.uniform(4.0, 12.0))
        cruise_s = max(abs(end - start) / speed - ramp_s, 0.0)
        t = np.arange(0.0, cruise_s + 2.0 * ramp_s, 1.0 / rate)
        v = np.where(t < ramp_s, 0.5 * (1 - np.cos(np.pi * t / ramp_s)),
                     np.where(t > cruise_s + ramp_s, 0.5 * (1 + np.cos(np.pi * (t - cruise_s - ramp_s) / ramp_s)), 1.0))
        path = np.cumsum(v) / max(float(np.sum(v)), 1e-12)
        parts.append(start + (end - start) * path)
        parts.append(np.full(int(float(rng.uniform(0.2, 0.6)) * rate), end))
    deg = np.concatenate(parts)
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(deg)))])
    ripple = float(rng.uniform(0.05, 0.2)) * np.sin(2 * np.pi * travel / float(rng.uniform(3.0, 6.0)))
    return np.clip(deg + ripple, lo, hi)


def tremulous_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–8 bends from 0°, each a half-sine up and down in time with its own peak (10–20°) and unequal
    up and down times (0.6–2.5 s), 0.3 s at rest between, with a tremor (8–12 Hz, 0.03–0.15°) while bent."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(10.0, 20.0))
        up = np.linspace(0.0, 1.0, int(rng.uniform(0.6, 2.5) * rate))
        down = np.linspace(0.0, 1.0, int(rng.uniform(0.6, 2.5) * rate))
        parts += [peak * np.sin(0.5 * np.pi * up), peak * np.cos(0.5 * np.pi * down), np.zeros(int(0.3 * rate))]
    deg = np.concatenate(parts)
    t = np.arange(deg.size) / rate
    tremor = float(rng.uniform(0.03, 0.15)) * np.sin(2 * np.pi * float(rng.uniform(8.0, 12.0)) * t)
    return np.where(deg > 0.5, deg + tremor, deg)


def running_in_friction(vel: np.ndarray, t: np.ndarray, level: float, fall: float, tau_s: float,
                        width: float) -> np.ndarray:
    """A friction (resisting the motion) whose level runs in: level·(1 + fall·(e^{−t/τ} − 1))·tanh(θ̇/width)."""
    return level * (1.0 + fall * np.expm1(-t / tau_s)) * np.tanh(vel / width)


def springpot(rad: np.ndarray, rate: float, order: float, memory_s: float = 5.0) -> np.ndarray:
    """The Grünwald–Letnikov fractional derivative of order ``order`` of ``rad`` sampled at ``rate`` Hz (rad/s^α),
    over a memory of ``memory_s`` seconds (the weights fall as k^{−1−α})."""
    n = max(min(int(memory_s * rate), rad.size), 2)
    k = np.arange(1, n)
    w = np.concatenate([[1.0], np.cumprod(1.0 - (order + 1.0) / k)])
    x = rad - rad[0]
    return fftconvolve(x, w)[: x.size] * rate**order


def bilinear_stop(deg: np.ndarray, at_deg: float, high: bool, pad_deg: float, seat_ratio: float) -> np.ndarray:
    """A stop per unit pad stiffness toward the range's inside (positive at the high end): δ over the pad
    (``pad_deg``), then ``seat_ratio`` × stiffer."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (deg - at_deg), 0.0, None)
    return sign * (np.minimum(depth, pad_deg) + seat_ratio * np.maximum(depth - pad_deg, 0.0))


def held_polls(torque: np.ndarray, t: np.ndarray, poll_hz: float, transport_s: float, phase: float) -> np.ndarray:
    """``torque`` read ``transport_s`` late (held at the first sample before the trial) and sampled at ``poll_hz``
    (a poll at t = (k + phase)/poll_hz), each poll held until the next."""
    late = np.interp(t - transport_s, t, torque)
    polls = np.floor(t * poll_hz - phase) + phase
    held_at = np.clip(polls / poll_hz, t[0], t[-1])
    return np.interp(held_at, t, late)


def catch(t: np.ndarray, start_s: float, rise_s: float, decay_s: float) -> np.ndarray:
    """A catch of peak 1: a linear rise over ``rise_s`` from ``start_s``, then an exponential decay over ``decay_s``."""
    u = t - start_s
    return np.where(u < 0.0, 0.0, np.where(u < rise_s, u / rise_s, np.exp(-(u - rise_s) / decay_s)))


def knocked_cable(t: np.ndarray, at_s: float, recovery_s: float) -> np.ndarray:
    """A step of 1 at ``at_s`` recovering toward zero over ``recovery_s``."""
    return np.where(t >= at_s, np.exp(-(t - at_s) / recovery_s), 0.0)


def give_with_play(torque: np.ndarray, play_deg: float) -> np.ndarray:
    """The play (deg) taken up in a strap: a backlash of width ``play_deg`` following the torque's sign: the give
    moves only once the play is taken up, so it holds at reversals (returned about zero, ±play/2)."""
    out = np.empty_like(torque, dtype=float)
    state = 0.0
    for i, tau in enumerate(torque):
        if tau != 0.0:  # the play is taken up on the side the torque pulls; at zero torque it stays where it was
            state = 0.5 * play_deg * float(np.sign(tau))
        out[i] = state
    return out


def coupled_limb_acceleration(drive_rad: np.ndarray, rate: float, natural_hz: float, damping_ratio: float
                              ) -> np.ndarray:
    """The limb's angular acceleration (rad/s²) when it follows the drive's angle through a second-order coupling
    (``natural_hz``, ``damping_ratio``), semi-implicit Euler from rest at the first angle."""
    w = 2 * np.pi * natural_hz
    dt = 1.0 / rate
    x, v = float(drive_rad[0]), 0.0
    acc = np.empty_like(drive_rad, dtype=float)
    for i, target in enumerate(drive_rad):
        a = w * w * (target - x) - 2 * damping_ratio * w * v
        v += a * dt
        x += v * dt
        acc[i] = a
    return acc


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return linkage_spring(deg, c["pin_a"], c["pin_b"], c["preload"], c["k"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    low = recruited_fibres(on_low - deg, c["slack_low"], c["k_low"])
    high = recruited_fibres(deg - on_high, c["slack_high"], c["k_high"])
    return -low + high + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"]))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        c = {"pin_a": float(rng.uniform(0.04, 0.07)), "pin_b": float(rng.uniform(0.08, 0.12)),
             "preload": float(rng.uniform(0.001, 0.004)), "k": 1.0}
        c["k"] = float(rng.uniform(10.0, 25.0)) / float(linkage_spring(np.array(15.0), c["pin_a"], c["pin_b"],
                                                                        c["preload"], 1.0))
        return c
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.15, 0.4) * span, hi - rng.uniform(0.15, 0.4) * span
    out: dict[str, Any] = {"on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
                           "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}
    for end, reach, size in (("low", on_low - lo, big if kind == "knee" else small),
                             ("high", hi - on_high, small if kind == "knee" else big)):
        count = int(rng.integers(12, 31))
        slack = rng.normal(0.0, float(rng.uniform(3.0, 8.0)), count) + 0.3 * reach
        k = rng.uniform(0.5, 1.5, count)
        k *= float(rng.uniform(*size)) / max(float(recruited_fibres(np.array(reach), slack, k)), 1e-9)
        out[f"slack_{end}"], out[f"k_{end}"] = slack, k
    return out


def generate_s(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((19, 19, 19), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: paced_strokes(r, a, b, rate),
                                         lambda r: tremulous_bends(r, rate))
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
    if "series_compliance" in effects:  # a strap with play: the joint turns by the angle less c·τ and the play
        c_give, play = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.2, 0.5))
        for _ in range(4):
            tau = _elastic(kind, joint_deg, fixed, coef)
            joint_deg = deg - c_give * tau - give_with_play(tau, play)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j - tau_j.mean(), deg - joint_deg)
                                           / np.dot(tau_j - tau_j.mean(), tau_j - tau_j.mean()))
        details.update(compliance_deg_per_Nm=c_give, play_deg=play)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the mass wrong, its soft tissue shifting with the segment's direction
        harmonic = float(rng.uniform(0.1, 0.3))
        unit = load.moment_nm / max(load.amplitude_nm, 1e-12) + harmonic * np.sin(2 * load.direction_rad)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12) * float(rng.choice([-1.0, 1.0]))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(tissue_harmonic=harmonic, weight_moment_amplitude_Nm=load.amplitude_nm)
    if "coulomb_friction" in effects:
        friction = running_in_friction(vel_deg, t, 1.0, float(rng.uniform(0.2, 0.5)), float(rng.uniform(10.0, 60.0)),
                                       float(rng.uniform(0.3, 1.5)))
        friction *= size() / max(float(np.max(np.abs(friction))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        order = float(rng.uniform(0.5, 0.9))
        unit = springpot(joint, rate, order)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        design = np.column_stack([vel, np.ones_like(rad), rad, rad**2, rad**3])
        truth["viscous_damping"] = float(np.linalg.lstsq(design, damping, rcond=None)[0][0])
        details.update(springpot_order=order)
    if "inertia" in effects:
        natural, ratio = float(rng.uniform(5.0, 10.0)), float(rng.uniform(0.1, 0.3))
        unit = coupled_limb_acceleration(rad, rate, natural, ratio)
        inertial = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + inertial
        truth["inertia"] = float(np.dot(acc, inertial) / np.dot(acc, acc))
        details.update(coupling_hz=natural, coupling_damping_ratio=ratio)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.03, 0.25))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high else bottom + depth * (top - bottom)
        unit = bilinear_stop(deg, at, high, float(rng.uniform(1.0, 3.0)), float(rng.uniform(3.0, 10.0)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low")
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * catch(t, start, float(rng.uniform(0.05, 0.2)),
                                                                         float(rng.uniform(0.2, 0.8)))
        truth["activation_burst"] = peak
        details.update(catch_start_s=start)
    if "sensor_drift" in effects:
        at = float(rng.uniform(0.15, 0.85)) * float(t[-1])
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * knocked_cable(t, at, float(rng.uniform(20.0, 60.0)))
        truth["sensor_drift"] = None
        details.update(knock_s=at)
    if "time_delay" in effects:
        transport, poll = float(rng.uniform(0.0, 0.3)), float(rng.uniform(8.0, 40.0))
        torque = held_polls(torque, t, poll, transport, float(rng.uniform(0.0, 1.0)))
        truth["time_delay"] = transport + 0.5 / poll
        details.update(transport_s=transport, poll_hz=poll)
    noise = rng.normal(0.0, sd, t.size)
    flicker = lfilter([1.0], [1.0, -float(rng.uniform(0.97, 0.995))], rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.2, 0.5)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    gain = 1.0 + float(rng.uniform(-0.01, 0.01)) * t / max(float(t[-1]), 1e-9)
    torque = torque * gain + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "bilinear_stop", "catch",
           "coupled_limb_acceleration", "generate_s", "give_with_play", "held_polls", "knocked_cable",
           "linkage_spring", "paced_strokes", "recruited_fibres", "running_in_friction", "springpot",
           "tremulous_bends"]
