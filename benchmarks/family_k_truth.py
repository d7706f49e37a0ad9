"""An eleventh generator family for the diagnosis, written before the engine of its round froze and run once after.

The second to tenth families (:mod:`benchmarks.family_b_truth` … ``family_j_truth``) became development data once run.
This one draws every cause from a law none of them or the engine's library uses (checked against their docstrings
before it was run). Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring
contract of :mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and
the recording's damage and the protocol's set-up of
:mod:`benchmarks.family_scaffold`).

- Passive moment: Fung's exponential law of soft tissue at each end of a joint's range, k·x·e^{(x/w)²} for x the
  angle past an onset (it stiffens faster than any single exponential: the exponent grows with the square of the
  stretch), w 0.6–1.2 × the furthest x the range reaches; the onset toward a two-joint muscle moved by the other
  joint's angle; plus a small linear term. The AFO: the same law of the bend past an engagement of 1–4° reached
  through a softplus of 0.3–1°.
- Motion: a stretch-and-return protocol: a slow stroke toward the end that stretches the two-joint muscles (3–8 °/s)
  and a quick return (12–30 °/s), each stroke's speed reached and left through a logistic blend of 0.1–0.4 s, holds
  of 0.2–1 s, 2–3 cycles. The AFO: bends by hand along a logistic curve (loading 1–3 s to 10–20°, unloading
  0.4–1.5 s), 0.2–1 s apart.
- Limb: Clauser et al. (1969): shank 4.35 % of body mass, centre 37.1 % down from the knee; foot 1.47 %, centre
  44.9 % of its length; radii of gyration about the centre 28 % (shank) and 26 % (foot) of the length.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a lip seal whose interference grows along the range, its level F₀·(1 + g·u) (u 0 → 1 from one end of
    the range to the other, g 0.3–0.8, either way; the fifth family's bearing ripple varied its level periodically
    by ≤ 20 %), its sign a linear ramp through a stick band clip(θ̇/w, −1, 1) (w 0.3–1.5 °/s); magnitude: the
    level's mean over the moving samples;
  * damping: direction-dependent (eccentric against concentric), b·θ̇ moving toward increasing angle and r·b·θ̇ the
    other way (r 0.4–0.7 or 1.4–2.5); magnitude: the least-squares coefficient of its torque on θ̇ over the moving
    samples;
  * stop: a standard-linear-solid bumper, k∞·δ plus a Maxwell arm (stiffness 1–3 × k∞, relaxation 0.2–1 s) that
    relaxes while the contact is held, never pulling, anywhere in the last third of either end of a joint's range
    (the AFO's at its top); named only;
  * delay: a transport delay of 0–0.45 s behind the device's causal moving median of 30–150 ms (a spike filter);
    magnitude: the transport delay plus half the median's window;
  * activation: a ramp contraction, the torque rising linearly over 0.3–1.5 s and released within 30–80 ms, of
    either sign; magnitude: its peak;
  * limb-weight error: the chair reclined by an angle the sidecar does not know, so the limb's weight acts at
    another orientation than the one the engine computes (the error's shape, a phase of the weight's moment, is the
    third family's centre of mass off the segment's axis: the one overlap, found in the check, kept as a cause a lab
    meets); magnitude: the peak moment error;
  * drift: the motor warming with the work it does, the zero following the mechanical power |θ̇·τ| through a
    first-order thermal lag of 30–120 s; named only;
  * series compliance: a strap that gives only in tension, c·max(±τ, 0) (one side of the torque, drawn);
    magnitude: c (°/N·m);
  * inertia error: a loosely strapped mass that follows the segment through a first-order lag of 10–40 ms, its
    torque ΔI times its own acceleration; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances: 100–1000 Hz; white noise plus random telegraph noise (a bistable offset of 0.3–0.6 × the noise SD
  switching at 0.2–2 Hz); a torque gain error of ±1.5 %; quantised torque and angle; the clock fast or slow by up
  to 0.02 % with jitter; dropped rows singly (0–1.5 %) and in runs; NaN cells in any column (≤ 0.4 %, time
  included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, damage_recording, draw_subject, kinematics, protocol_set_up, trial_rng

NOISE_SD_NM = {"afo": 0.06, "knee": 0.19, "ankle": 0.12}
#: Clauser et al. (1969): mass fraction, centre from the proximal joint, radius of gyration about the centre
#: (fractions of the segment's length)
SHANK = (0.0435, 0.371, 0.28)
FOOT = (0.0147, 0.449, 0.26)
#: how much larger an end's moment grows per degree its onset moves into the range with the other joint (1/deg)
COUPLING_PER_DEG = 0.03


def fung_moment(x_deg: np.ndarray, width_deg: float) -> np.ndarray:
    """Fung's exponential law: x·e^{(x/w)²} for ``x_deg`` past the onset (degrees), zero before it."""
    x = np.clip(x_deg, 0.0, None)
    return x * np.exp((x / width_deg) ** 2)


def _logistic_ramp(n: int) -> np.ndarray:
    """A position profile 0 → 1 over ``n`` samples along a logistic curve (ends at exactly 0 and 1)."""
    u = np.linspace(-6.0, 6.0, max(n, 2))
    s = 1.0 / (1.0 + np.exp(-u))
    return (s - s[0]) / (s[-1] - s[0])


def _stroke(dist: float, speed: float, blend_s: float, rate: float) -> np.ndarray:
    """Displacement (deg, 0 → ``dist``) of one stroke at ``speed`` °/s, the speed reached and left through logistic
    blends of ``blend_s`` s (the velocity a product of two logistic edges), scaled to end exactly on ``dist``."""
    duration = dist / speed + 2.0 * blend_s
    t = np.arange(0.0, duration, 1.0 / rate)
    edge = blend_s / 8.0
    v = 1.0 / (1.0 + np.exp(-(t - blend_s) / edge)) / (1.0 + np.exp((t - duration + blend_s) / edge))
    s = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]))])
    return dist * s / s[-1]


def _stretch_and_return(rng: np.random.Generator, lo: float, hi: float, toward_hi_slow: bool, rate: float
                        ) -> np.ndarray:
    """Cycles (deg) between ``lo`` and ``hi``: slow toward the stretching end, quick back."""
    slow, quick = float(rng.uniform(3.0, 8.0)), float(rng.uniform(12.0, 30.0))
    blend = float(rng.uniform(0.1, 0.4))
    start, end = (lo, hi) if toward_hi_slow else (hi, lo)
    out = [np.full(int(rng.uniform(0.2, 1.0) * rate), start)]
    for _ in range(int(rng.integers(2, 4))):
        for a, b, speed in ((start, end, slow), (end, start, quick)):
            out += [a + np.sign(b - a) * _stroke(abs(b - a), speed, blend, rate),
                    np.full(int(rng.uniform(0.2, 1.0) * rate), b)]
    return np.concatenate(out)


def _logistic_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg) by hand along logistic curves: loading 1–3 s to 10–20°, unloading 0.4–1.5 s, 0.2–1 s apart."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(10.0, 20.0))
        parts += [peak * _logistic_ramp(int(rng.uniform(1.0, 3.0) * rate)),
                  peak * (1.0 - _logistic_ramp(int(rng.uniform(0.4, 1.5) * rate))),
                  np.zeros(int(rng.uniform(0.2, 1.0) * rate))]
    return np.concatenate(parts)


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        bend = c["soft"] * np.logaddexp(0.0, (deg - c["engage"]) / c["soft"])
        return c["k"] * fung_moment(bend, c["w"])
    on_low, on_high = c["on_low"], c["on_high"]
    # a tenth of the range inside its end at the latest (the one-joint muscles still engage there)
    if kind == "knee":  # the hamstrings (the extension end) engage earlier with the hip flexed
        on_low = max(on_low + c["shift"] * (fixed["hip_flexion_deg"] - 55.0), c["lo"] + 0.1 * (c["hi"] - c["lo"]))
    else:  # the gastrocnemius (the dorsiflexion end) earlier with the knee extended
        on_high = min(on_high - c["shift"] * (45.0 - fixed["knee_flexion_deg"]), c["hi"] - 0.1 * (c["hi"] - c["lo"]))
    # each end's moment at the range's end is its drawn size, 3 % larger per degree its onset moved into the range
    t_low = c["t_low"] * np.exp(COUPLING_PER_DEG * (on_low - c["on_low"]))
    t_high = c["t_high"] * np.exp(COUPLING_PER_DEG * (c["on_high"] - on_high))
    low = fung_moment(on_low - deg, c["w_low"]) / float(fung_moment(np.array([on_low - c["lo"]]), c["w_low"])[0])
    high = fung_moment(deg - on_high, c["w_high"]) / float(fung_moment(np.array([c["hi"] - on_high]), c["w_high"])[0])
    return -t_low * low + t_high * high + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"]))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its moment at a 15° bend, 10–25 N·m
        engage, soft, w = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.3, 1.0)), float(rng.uniform(15.0, 30.0))
        return {"k": float(rng.uniform(10.0, 25.0)) / float(fung_moment(np.array([15.0 - engage]), w)[0]),
                "engage": engage, "soft": soft, "w": w}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": on_low, "on_high": on_high,
            "w_low": float(rng.uniform(0.6, 1.2)) * (on_low - lo), "w_high": float(rng.uniform(0.6, 1.2)) * (hi - on_high),
            "shift": float(rng.uniform(0.05, 0.2)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def segment_direction(kind: str, rad: np.ndarray, fixed: dict[str, float], recline_rad: float = 0.0) -> np.ndarray:
    """The distal segment's direction (rad from the horizontal, sagittal plane) in a chair reclined by
    ``recline_rad``: the knee's shank horizontal at 0° flexion (the thigh horizontal), the foot's from the ankle
    angle and the knee's flexion."""
    if kind == "knee":
        return -rad + recline_rad
    return rad + np.pi / 2 - np.radians(fixed["knee_flexion_deg"]) + recline_rad


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float,
          recline_rad: float = 0.0) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "afo":
        return np.zeros_like(rad), 0.0
    psi = segment_direction(kind, rad, fixed, recline_rad)
    if kind == "knee":
        m_s, m_f = SHANK[0] * mass, FOOT[0] * mass
        r_s = SHANK[1] * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(psi)
        return moment, m_s * (r_s**2 + (SHANK[2] * shank) ** 2) + m_f * shank**2
    m_f = FOOT[0] * mass
    r_f = FOOT[1] * foot
    return m_f * GRAVITY * r_f * np.cos(psi), m_f * (r_f**2 + (FOOT[2] * foot) ** 2)


def sls_bumper(pen_deg: np.ndarray, t: np.ndarray, k_inf: float, k_arm: float, relax_s: float) -> np.ndarray:
    """A standard-linear-solid bumper's force for a penetration ``pen_deg`` (deg, ≥ 0) over ``t`` (s): k∞·δ plus a
    Maxwell arm, dm/dt = k_arm·δ̇ − m/τ (integrated exactly per sample for a piecewise-linear δ), the total never
    below zero (a bumper does not pull)."""
    m = np.zeros(t.size)
    for i in range(1, t.size):
        dt = t[i] - t[i - 1]
        decay = np.exp(-dt / relax_s)
        rate = k_arm * (pen_deg[i] - pen_deg[i - 1]) / dt if dt > 0 else 0.0
        m[i] = m[i - 1] * decay + rate * relax_s * (1.0 - decay)
    return np.clip(k_inf * pen_deg + m, 0.0, None)


def causal_median(x: np.ndarray, window: int) -> np.ndarray:
    """The median of the last ``window`` samples at each sample (the first ones over what there is)."""
    from numpy.lib.stride_tricks import sliding_window_view

    padded = np.concatenate([np.full(window - 1, x[0]), x])
    return np.median(sliding_window_view(padded, window), axis=1)


def ramp_contraction(t: np.ndarray, onset: float, rise_s: float, release_s: float) -> np.ndarray:
    """A contraction rising linearly from ``onset`` over ``rise_s`` s to 1, released linearly within ``release_s``."""
    s = t - onset
    return np.where(s < 0, 0.0, np.where(s < rise_s, s / rise_s, np.clip(1.0 - (s - rise_s) / release_s, 0.0, 1.0)))


def first_order_lag(x: np.ndarray, t: np.ndarray, tau_s: float) -> np.ndarray:
    """``x`` through a first-order lag of ``tau_s`` s (exact for a piecewise-constant input per sample)."""
    y = np.empty_like(x)
    y[0] = x[0]
    for i in range(1, x.size):
        a = np.exp(-(t[i] - t[i - 1]) / tau_s)
        y[i] = a * y[i - 1] + (1.0 - a) * x[i]
    return y


def telegraph(rng: np.random.Generator, n: int, rate: float, switch_hz: float) -> np.ndarray:
    """Random telegraph noise of unit amplitude (±1), switching as a Poisson process at ``switch_hz``."""
    flips = rng.random(n) < switch_hz / rate
    return np.where(np.cumsum(flips) % 2 == 0, 1.0, -1.0) * float(rng.choice([-1.0, 1.0]))


def generate_k(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((11, 11, 5), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    # slow toward the end that stretches the two-joint muscles (the knee's extension, the ankle's dorsiflexion)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: _stretch_and_return(r, a, b, kind == "ankle", rate),
                                         lambda r: _logistic_bends(r, rate))
    t, rad, vel, acc = kinematics(deg, rate)
    coef = _coefficients(rng, kind, lo, hi)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap that gives only in tension (one side of the torque)
        c0 = float(rng.uniform(0.03, 0.12))
        side = float(rng.choice([-1.0, 1.0]))
        # the give answers to the torque it lets through: the joint's angle j solves deg − j = c·side·max(side·P(j), 0),
        # whose left side falls and right side rises with j (a stiff end makes a fixed-point iteration diverge)
        low_j, high_j = deg - 30.0, deg + 30.0
        for _ in range(60):
            mid = 0.5 * (low_j + high_j)
            excess = deg - mid - c0 * side * np.clip(side * _passive(kind, mid, fixed, coef), 0.0, None)
            low_j, high_j = np.where(excess > 0.0, mid, low_j), np.where(excess > 0.0, high_j, mid)
        joint_deg = 0.5 * (low_j + high_j)
        truth["series_compliance"] = c0
        details.update(tension_side=side)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # the chair reclined by an angle the sidecar does not know: the weight acts at another orientation
        target = size()
        sign = float(rng.choice([-1.0, 1.0]))
        angles = np.radians(np.linspace(0.5, 45.0, 90))
        peaks = np.maximum.accumulate([float(np.max(np.abs(
            _limb(kind, joint, fixed, subject["mass_kg"], shank, foot, sign * a)[0] - weight))) for a in angles])
        recline = float(np.interp(target, peaks, angles)) if peaks[-1] >= target else float(angles[-1])
        reclined = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot, sign * recline)[0]
        torque = torque + reclined - weight
        truth["gravity_error"] = float(np.max(np.abs(reclined - weight)))
        details.update(recline_deg=float(np.degrees(sign * recline)))
    if "coulomb_friction" in effects:
        grow, band = float(rng.uniform(0.3, 0.8)), float(rng.uniform(0.3, 1.5))
        along = (deg - lo) / max(hi - lo, 1e-9)
        if rng.random() < 0.5:
            along = 1.0 - along
        level = 1.0 + grow * np.clip(along, 0.0, 1.0)
        unit = level * np.clip(np.degrees(vel) / band, -1.0, 1.0)
        f0 = size() / float(np.max(np.abs(unit)))
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(level[moving]))
        details.update(seal_growth=grow, stick_band_deg_s=band)
    if "viscous_damping" in effects:
        ratio = float(rng.uniform(0.4, 0.7)) if rng.random() < 0.5 else float(rng.uniform(1.4, 2.5))
        unit = np.where(vel > 0.0, vel, ratio * vel)
        b = size() / float(np.max(np.abs(unit)))
        torque = torque + b * unit
        v_m, u_m = vel[moving], b * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(direction_ratio=ratio)
    if "inertia" in effects:
        lag = float(rng.uniform(0.01, 0.04))
        follower = first_order_lag(rad, t, lag)
        unit = np.gradient(np.gradient(follower, t), t)
        d_inertia = size() / float(np.max(np.abs(unit)))
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(follower_lag_s=lag)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        arm, relax = float(rng.uniform(1.0, 3.0)), float(rng.uniform(0.2, 1.0))
        shape = sls_bumper(pen, t, 1.0, arm, relax)
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", maxwell_ratio=arm, relaxation_s=relax)
    if "activation_burst" in effects:
        rise, release = float(rng.uniform(0.3, 1.5)), float(rng.uniform(0.03, 0.08))
        onset = float(rng.uniform(0.15, 0.8)) * float(t[-1])
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * ramp_contraction(t, onset, rise, release)
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_rise_s=rise, burst_release_s=release)
    if "sensor_drift" in effects:
        heat = first_order_lag(np.abs(vel * passive), t, float(rng.uniform(30.0, 120.0)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * heat / max(float(np.max(heat)), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        lag, window_s = float(rng.uniform(0.0, 0.45)), float(rng.uniform(0.03, 0.15))
        window = max(1, int(round(window_s * rate)))
        filtered = causal_median(torque, window)
        torque = np.interp(t - lag, t, filtered, left=filtered[0])
        truth["time_delay"] = lag + 0.5 * (window - 1) / rate
        details.update(transport_delay_s=lag, median_window_s=window / rate)
    noise = rng.normal(0.0, sd, t.size) + float(rng.uniform(0.3, 0.6)) * sd * telegraph(
        rng, t.size, rate, float(rng.uniform(0.2, 2.0)))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.015),
                                            angle_quantum_deg=(0.005, 0.04), clock_fraction=2e-4, drop_fraction=0.015,
                                            run_s=0.1, nan_fraction=0.004)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "causal_median", "first_order_lag",
           "fung_moment", "generate_k", "ramp_contraction", "sls_bumper", "telegraph"]
