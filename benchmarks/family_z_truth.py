"""A twenty-sixth generator family for the diagnosis, written (2026-12-07, thirty-fourth stop) after the twenty-fifth
family's run and before any further engine change, to be run once on the next change's frozen engine.

The second to twenty-fifth families (:mod:`benchmarks.family_b_truth` … ``family_y_truth``) are development data
once run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` at 058a0a2; where an earlier family used a near relation it is said) and keeps every
nuisance below what the diagnosis should name. Nothing is imported from ``analysis``, nor any physics from the other
generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a one-term Ogden solid in uniaxial tension, A·(λ^α − λ^{−α/2}) with
  the stretch λ = 1 + x̄/L (α 6–12, L 40–80°), x̄ the softplus of the angle past the onset over 1–3°; the steep end sized
  by its torque at the range's end, the onset toward a two-joint muscle moved by the other joint's angle; a small
  linear term. The AFO: a carbon leaf that softens as it bends, k·θ_s·tanh(θ/θ_s) (θ_s 25–40°).
- Motion: sinusoidal sweeps between the range's ends (no holds; the frequency set by a peak speed of 4–9 °/s), 2–3
  cycles after a 0.5–1.5 s hold at the low end. The AFO: 6–10 triangular bends to 10–20° at 8–20 °/s, back to 0–2°,
  through a 50 ms moving average.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Coulomb friction running in, its level F₀·(0.6 + 0.4·e^{−s/S}) with s the angle travelled so far and S
    30–100 % of the trial's travel, its sign v/(|v| + ε) (ε 0.2–0.8 °/s); magnitude: its mean |F| over the moving samples;
  * damping: a bushing squeezed as the joint turns, b₀·(1 + κ·u)·θ̇ with u the angle's position in the range from −1 to
    1 (κ ±0.3–0.6); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a Kelvin–Voigt contact, k·δ + c·δ̇ while δ > 0 (c such that the damping is 20–40 % of the contact's torque at
    its largest), anywhere in the last 5–30 % of either end of a joint's range (the AFO's at the top of its bend);
    named only;
  * delay: a transport delay of 0–0.45 s behind a running median of 5–21 samples; magnitude: the transport delay plus
    half the median's span;
  * activation: a rectangular excitation of 0.3–1 s through first-order activation dynamics, rising with 30–60 ms and
    falling with 150–400 ms (Zajac 1989), anywhere in 10–85 % of the trial, of either sign; magnitude: its peak;
  * limb-weight error: the segment's centre of mass entered 5–15° off its line, the weight's moment cos(ψ + φ) − cos ψ;
    magnitude: its peak;
  * drift: the room's air conditioning, a sinusoid of period 40–120 s; named only;
  * series compliance: a preloaded cable, giving only past its preload, c·sgn τ·max(|τ| − τ_p, 0) (τ_p 10–30 % of the
    largest torque); magnitude: the least-squares slope of the give on the torque;
  * inertia error: a flywheel through a viscous coupling, its torque J·ω̇_f with ω_f the angular velocity through a
    first-order lag of J/c = 20–100 ms; magnitude: the least-squares coefficient of its torque on θ̈ (sized to 3–5 × the
    noise in sweeps this slow and smooth, 10–30 kg·m² at the knee and ankle, as the twenty-third family's: an inertia
    error a slow sweep barely shows, kept to the family contract's size, not to a limb's).
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise whose SD grows with the torque's size (by
  30–60 % at its largest); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast or slow by up
  to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included);
  torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.ndimage import median_filter
from scipy.signal import lfilter

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import (
    GRAVITY,
    behind_strap,
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


def ogden_end(x_deg: np.ndarray, onset_smoothing_deg: float, scale_deg: float, alpha: float) -> np.ndarray:
    """A one-term Ogden solid in uniaxial tension per unit amplitude: λ^α − λ^{−α/2}, λ = 1 + x̄/L, x̄ = s·ln(1 + e^{x/s})
    the softplus of the angle ``x_deg`` past the onset over s = ``onset_smoothing_deg``, L = ``scale_deg``."""
    x = np.asarray(x_deg, dtype=float) / onset_smoothing_deg
    stretch = 1.0 + onset_smoothing_deg * np.logaddexp(0.0, x) / scale_deg
    return np.asarray(stretch**alpha - stretch ** (-0.5 * alpha), dtype=float)


def softening_leaf(deg: np.ndarray, softening_deg: float) -> np.ndarray:
    """An orthosis's carbon leaf per unit stiffness: θ_s·tanh(θ/θ_s) for θ ≥ 0 (deg), 0 below."""
    th = np.clip(np.asarray(deg, dtype=float), 0.0, None)
    return softening_deg * np.tanh(th / softening_deg)


def sine_sweeps(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at ``lo``, then 2–3 cycles of lo + (hi − lo)(1 − cos 2πft)/2, f set by a peak
    speed of 4–9 °/s."""
    f = float(rng.uniform(4.0, 9.0)) / (np.pi * (hi - lo))
    cycles = int(rng.integers(2, 4))
    t = np.arange(int(np.ceil(cycles / f * rate)) + 1) / rate
    sweep = lo + (hi - lo) * 0.5 * (1.0 - np.cos(2.0 * np.pi * f * t))
    return np.concatenate([np.full(int(rng.uniform(0.5, 1.5) * rate), lo), sweep])


def triangle_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 6–10 linear bends to 10–20° at 8–20 °/s and back to 0–2° (0° after the last), through a 50 ms
    moving average (the ends held)."""
    parts = [np.zeros(int(0.4 * rate))]
    base = 0.0
    count = int(rng.integers(6, 11))
    for k in range(count):
        peak = float(rng.uniform(10.0, 20.0))
        back = 0.0 if k == count - 1 else float(rng.uniform(0.0, 2.0))
        for a, b in ((base, peak), (peak, back)):
            n = max(2, int(np.ceil(abs(b - a) / float(rng.uniform(8.0, 20.0)) * rate)))
            parts.append(a + (b - a) * np.arange(1, n + 1) / n)
        base = back
    parts.append(np.zeros(int(0.4 * rate)))
    deg = np.concatenate(parts)
    n = max(3, int(round(0.05 * rate)) | 1)
    padded = np.concatenate([np.full(n, deg[0]), deg, np.full(n, deg[-1])])
    return np.convolve(padded, np.ones(n) / n, mode="same")[n:-n]


def running_in_friction(deg: np.ndarray, vel_deg_s: np.ndarray, settle_fraction: float, epsilon_deg_s: float
                        ) -> np.ndarray:
    """A friction per unit initial level running in: (0.6 + 0.4·e^{−s/S})·v/(|v| + ε), s the angle travelled so far,
    S = ``settle_fraction`` × the whole travel."""
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(np.asarray(deg, dtype=float))))])
    level = 0.6 + 0.4 * np.exp(-travel / max(settle_fraction * float(travel[-1]), 1e-12))
    v = np.asarray(vel_deg_s, dtype=float)
    return level * v / (np.abs(v) + epsilon_deg_s)


def squeezed_bushing(vel: np.ndarray, deg: np.ndarray, lo: float, hi: float, slope: float) -> np.ndarray:
    """A damping per unit mid-range coefficient that varies along the range: (1 + κ·u)·θ̇, u = (2θ − lo − hi)/(hi − lo)
    from −1 to 1, κ = ``slope``."""
    u = (2.0 * np.asarray(deg, dtype=float) - lo - hi) / (hi - lo)
    return (1.0 + slope * u) * np.asarray(vel, dtype=float)


def kelvin_voigt_stop(deg: np.ndarray, vel_deg_s: np.ndarray, at_deg: float, high: bool, damping_s: float
                      ) -> np.ndarray:
    """A contact per unit stiffness toward the range's inside (positive at the high end): δ + c·δ̇ while δ > 0, δ the
    depth past ``at_deg`` (deg), c = ``damping_s`` (s), the damping never pulling (the sum kept ≥ 0)."""
    sign = 1.0 if high else -1.0
    depth = sign * (np.asarray(deg, dtype=float) - at_deg)
    inside = depth > 0.0
    force = np.where(inside, np.clip(depth + damping_s * sign * np.asarray(vel_deg_s, dtype=float), 0.0, None), 0.0)
    return sign * force


def median_delay(torque: np.ndarray, transport_s: float, span: int, rate: float) -> tuple[np.ndarray, float]:
    """(the torque delayed by ``transport_s`` (whole samples; the first value held before) and through a causal
    running median of ``span`` samples (odd); the delay in s: the shift plus (span − 1)/2 samples)."""
    shift = int(round(transport_s * rate))
    delayed = np.concatenate([np.full(shift, torque[0]), torque[:torque.size - shift]]) if shift else torque.copy()
    half = (span - 1) // 2
    centred = median_filter(delayed, size=span, mode="nearest")
    causal = np.concatenate([np.full(half, centred[0]), centred[:centred.size - half]])
    return causal, (shift + half) / rate


def activation_dynamics(t: np.ndarray, start_s: float, duration_s: float, rise_s: float, fall_s: float) -> np.ndarray:
    """A rectangular excitation from ``start_s`` for ``duration_s`` through first-order activation dynamics (rising
    with ``rise_s``, falling with ``fall_s``), its peak scaled to 1."""
    excitation = ((t >= start_s) & (t < start_s + duration_s)).astype(float)
    dt = np.diff(t, prepend=t[0])
    out = np.zeros(t.size)
    a = 0.0
    for i in range(t.size):
        tau = rise_s if excitation[i] > a else fall_s
        a += dt[i] * (excitation[i] - a) / tau
        out[i] = a
    return out / max(float(out.max()), 1e-12)


def preloaded_cable_give(torque: np.ndarray, compliance: float, preload_nm: float) -> np.ndarray:
    """The cable's give (deg): ``compliance``·sgn τ·max(|τ| − τ_p, 0), τ_p = ``preload_nm``."""
    return np.sign(torque) * compliance * np.clip(np.abs(torque) - preload_nm, 0.0, None)


def coupled_flywheel(vel: np.ndarray, t: np.ndarray, lag_s: float) -> np.ndarray:
    """The flywheel's torque per unit inertia (rad/s²): the derivative of the angular velocity through a first-order lag
    of ``lag_s`` (started at the first velocity)."""
    dt = float(np.median(np.diff(t)))
    b = 1.0 - float(np.exp(-dt / lag_s))
    omega = lfilter([b], [1.0, b - 1.0], vel, zi=[(1.0 - b) * float(vel[0])])[0]
    return np.gradient(np.asarray(omega, dtype=float), t)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * softening_leaf(deg, c["soft"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * ogden_end(on_low - deg, c["smooth"], c["scale_low"], c["alpha_low"])
            + c["a_high"] * ogden_end(deg - on_high, c["smooth"], c["scale_high"], c["alpha_high"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        soft = float(rng.uniform(25.0, 40.0))
        return {"soft": soft, "k": float(rng.uniform(10.0, 25.0)) / float(softening_leaf(np.array(15.0), soft))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(1.0, 3.0))
    scale_low, scale_high = float(rng.uniform(40.0, 80.0)), float(rng.uniform(40.0, 80.0))
    alpha_low, alpha_high = float(rng.uniform(6.0, 12.0)), float(rng.uniform(6.0, 12.0))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(ogden_end(np.array(on_low - lo), smooth, scale_low, alpha_low)),
            "a_high": t_high / float(ogden_end(np.array(hi - on_high), smooth, scale_high, alpha_high)),
            "scale_low": scale_low, "scale_high": scale_high, "alpha_low": alpha_low, "alpha_high": alpha_high,
            "smooth": smooth, "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_z(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((26, 26, 26), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: sine_sweeps(r, a, b, rate),
                                         lambda r: triangle_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a preloaded cable
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, preload = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.1, 0.3)) * tau_max
        joint_deg = behind_strap(deg, lambda d: preloaded_cable_give(_elastic(kind, d, fixed, coef), c_give, preload))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, preload_Nm=preload)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the centre of mass entered off its line
        phi = np.radians(float(rng.uniform(5.0, 15.0)) * float(rng.choice([-1.0, 1.0])))
        unit = np.cos(load.direction_rad + phi) - np.cos(load.direction_rad)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = running_in_friction(deg, np.degrees(vel), float(rng.uniform(0.3, 1.0)), float(rng.uniform(0.2, 0.8)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        kappa = float(rng.uniform(0.3, 0.6)) * float(rng.choice([-1.0, 1.0]))
        unit = squeezed_bushing(vel, deg, bottom, top, kappa)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        unit = coupled_flywheel(vel, t, float(rng.uniform(0.02, 0.1)))
        flywheel = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + flywheel
        truth["inertia"] = float(np.dot(acc, flywheel) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        vel_deg = np.degrees(vel)
        elastic_unit = kelvin_voigt_stop(deg, vel_deg, at, high_end, 0.0)
        entry = float(np.max(np.abs(vel_deg[np.abs(elastic_unit) > 0]))) if np.any(elastic_unit) else 1.0
        share = float(rng.uniform(0.2, 0.4))
        # the damping's share of the contact's largest torque: c·v_entry / (δ_max + c·v_entry) = share
        damping_s = share * float(np.max(np.abs(elastic_unit))) / ((1.0 - share) * max(entry, 1e-9))
        unit = kelvin_voigt_stop(deg, vel_deg, at, high_end, damping_s)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", stop_damping_s=damping_s)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = activation_dynamics(t, start, float(rng.uniform(0.3, 1.0)), float(rng.uniform(0.03, 0.06)),
                                    float(rng.uniform(0.15, 0.4)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(excitation_start_s=start)
    if "sensor_drift" in effects:
        period = float(rng.uniform(40.0, 120.0))
        torque = torque + size() * np.sin(2.0 * np.pi * t / period + float(rng.uniform(0.0, 2.0 * np.pi)))
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, delay = median_delay(torque, float(rng.uniform(0.0, 0.45)), 2 * int(rng.integers(2, 11)) + 1, rate)
        truth["time_delay"] = delay
    grow = float(rng.uniform(0.3, 0.6))
    scale = 1.0 + grow * np.abs(torque) / max(float(np.max(np.abs(torque))), 1e-12)
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + rng.normal(0.0, sd, t.size) * scale
    torque = torque + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "activation_dynamics", "coupled_flywheel",
           "generate_z", "kelvin_voigt_stop", "median_delay", "ogden_end", "preloaded_cable_give", "running_in_friction",
           "sine_sweeps", "softening_leaf", "squeezed_bushing", "triangle_bends"]
