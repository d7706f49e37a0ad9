"""Trials with one hidden effect, drawn from a seed: the ground truth the diagnosis is tested against.

A trial is a baseline (AFO: a spring with a moment-arm nonlinearity; knee and ankle: Riener &
Edrich's passive moments, each term scaled at random by ±20 %, plus the limb's weight; replica:
a stiffening spring), a realistic motion (the AADS operator's uneven bends at varying speed;
isokinetic flexion and return at 5 and 15 °/s; replica holds every 8°), AR(1) torque noise
(lag-1 correlation 0.6) and at most one effect with a magnitude drawn from a realistic range.
Angles in degrees at the edges only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .causes import CAUSES, FRICTION_SPEED_RAD_S
from .data import G_M_S2, DiagnosisTrial

RATE_HZ = 100.0
#: magnitude ranges of each effect per kind (units of the cause's magnitude key)
RANGES: dict[str, dict[str, tuple[float, float]]] = {
    "coulomb_friction": {"afo": (0.3, 1.0), "knee": (0.6, 2.0), "ankle": (0.4, 1.5)},
    "viscous_damping": {"afo": (0.8, 2.5), "knee": (3.0, 8.0), "ankle": (2.0, 6.0)},
    "series_compliance": {"afo": (0.04, 0.12), "knee": (0.06, 0.15), "ankle": (0.06, 0.15)},
    "hard_stop": {"afo": (1.5, 4.0), "knee": (1.0, 3.0), "ankle": (1.0, 3.0), "replica": (0.5, 1.5)},
    "activation_burst": {"knee": (3.0, 10.0), "ankle": (2.0, 6.0)},
    "gravity_error": {"knee": (1.5, 4.0), "ankle": (0.5, 1.2)},
    "time_delay": {"afo": (0.04, 0.12), "knee": (0.05, 0.15), "ankle": (0.05, 0.15)},
    "sensor_drift": {"afo": (0.02, 0.06), "knee": (0.02, 0.05), "ankle": (0.02, 0.05), "replica": (0.005, 0.02)},
}
NOISE_NM = {"afo": 0.08, "knee": 0.2, "ankle": 0.15, "replica": 0.05}
SUBJECT = {"mass_kg": 75.0, "height_m": 1.78, "shank_length_m": 0.42, "foot_length_m": 0.26, "thigh_length_m": 0.43}


@dataclass
class HiddenEffect:
    """What was hidden: the cause, its magnitude (in the cause's magnitude key) and any other parameters."""

    cause: str
    magnitude: float
    extra: dict[str, float]


def causes_for(kind: str) -> list[str]:
    return [c for c in CAUSES if c != "none" and kind in CAUSES[c].kinds and kind in RANGES.get(c, {})]


def _ar1(rng: np.random.Generator, n: int, sd: float, rho: float = 0.6) -> np.ndarray:
    e = rng.normal(0.0, sd * np.sqrt(1 - rho**2), n)
    out = np.empty(n)
    out[0] = rng.normal(0.0, sd)
    for i in range(1, n):
        out[i] = rho * out[i - 1] + e[i]
    return out


def _sweeps(start: float, end: float, speeds: tuple[float, ...], hold_s: float = 0.5) -> np.ndarray:
    """Angle (deg) at RATE_HZ: start→end→start at each speed (deg/s), with short holds."""
    parts = [np.full(int(hold_s * RATE_HZ), start)]
    for v in speeds:
        n = int(abs(end - start) / v * RATE_HZ)
        go = np.linspace(start, end, n)
        parts += [go, np.full(int(hold_s * RATE_HZ), end), go[::-1], np.full(int(hold_s * RATE_HZ), start)]
    return np.concatenate(parts)


def _bends(rng: np.random.Generator, peak: tuple[float, float], cycles: int = 6) -> np.ndarray:
    parts = [np.full(30, 6.0)]
    for _ in range(cycles):
        top = rng.uniform(*peak)
        dur = rng.uniform(1.2, 3.5)
        skew = rng.uniform(0.35, 0.65)
        n = int(dur * RATE_HZ)
        u = np.linspace(0, 1, n, endpoint=False)
        ph = np.where(u < skew, u / skew * 0.5, 0.5 + (u - skew) / (1 - skew) * 0.5)
        parts += [6.0 + (top - 6.0) * 0.5 * (1 - np.cos(2 * np.pi * ph)), np.full(int(rng.uniform(0.1, 0.4) * RATE_HZ), 6.0)]
    return np.concatenate(parts)


def make_trial(kind: str, cause: str = "none", seed: int = 0, magnitude: float | None = None) -> tuple[DiagnosisTrial,
                                                                                                       HiddenEffect]:
    """A trial of ``kind`` hiding ``cause`` (``"random"``: one of the kind's causes, or none, drawn from the seed)."""
    rng = np.random.default_rng(seed)
    if cause == "random":
        options = ["none"] + causes_for(kind)
        cause = options[int(rng.integers(len(options)))]
    if cause != "none" and cause not in causes_for(kind):
        raise ValueError(f"{cause!r} is not a hidden effect for {kind} trials; one of {causes_for(kind)}")
    mag = float(magnitude if magnitude is not None else (rng.uniform(*RANGES[cause][kind]) if cause != "none" else 0.0))
    extra: dict[str, float] = {}
    fixed: dict[str, float] = {}
    if kind == "afo":
        peak = (23.0, 27.0) if cause == "hard_stop" else (17.0, 22.0)
        deg = _bends(rng, peak)
        k = rng.uniform(0.6, 1.8)           # N·m/°
        curv = rng.uniform(-0.012, 0.006) * k  # N·m/°², the moment arm's nonlinearity
        def spring(d: np.ndarray) -> np.ndarray:
            x = d - 5.0
            return k * x + curv * x**2
        extra["spring_Nm_per_deg"] = k
    elif kind in ("knee", "ankle"):
        deg = _sweeps(0.0, 90.0, (5.0, 15.0)) if kind == "knee" else _sweeps(15.0, -30.0, (5.0, 15.0))
        s = rng.uniform(0.8, 1.2, 4)
        hip = 90.0
        fixed = {"hip_flexion_deg": hip, "ankle_dorsiflexion_deg": 0.0} if kind == "knee" else \
            {"hip_flexion_deg": hip, "knee_flexion_deg": 0.0}
        def spring(d: np.ndarray) -> np.ndarray:
            if kind == "knee":
                m = (s[0] * np.exp(1.800 - 0.0352 * d + 0.0217 * hip) - s[1] * np.exp(-3.971 + 0.0495 * d - 0.0128 * hip)
                     - 4.820 + s[2] * np.exp(2.220 - 0.150 * d))
            else:
                m = s[0] * np.exp(-7.9763 - 0.1949 * d) - s[1] * np.exp(2.1016 + 0.0843 * d) + 1.792
            return -m  # the specimen resists: torque against the bending
    else:
        targets = np.arange(0.0, 90.1, 8.0)
        parts = []
        for a, b in zip(targets[:-1], targets[1:]):
            parts += [np.full(int(2.0 * RATE_HZ), a), np.linspace(a, b, int(abs(b - a) / 30.0 * RATE_HZ))]
        parts.append(np.full(int(2.0 * RATE_HZ), targets[-1]))
        deg = np.concatenate(parts)
        k = rng.uniform(0.15, 0.4)
        def spring(d: np.ndarray) -> np.ndarray:
            return 0.5 + k * d + 0.0015 * k * d**2
    t = np.arange(deg.size) / RATE_HZ
    th = np.deg2rad(deg)
    omega = np.gradient(th, t)
    trial_angle = deg.copy()
    torque = spring(deg)
    if cause == "hard_stop":
        stop = {"afo": rng.uniform(19.0, 21.5), "knee": rng.uniform(78.0, 85.0), "ankle": rng.uniform(8.0, 12.0),
                "replica": rng.uniform(60.0, 75.0)}[kind]
        torque = torque + mag * np.maximum(deg - stop, 0.0)
        extra["stop_angle_deg"] = stop
    elif cause == "series_compliance":
        trial_angle = deg + mag * torque  # the markers (or the arm) turn further than the spring does
    elif cause == "time_delay":
        torque = np.interp(t - mag, t, torque)
    if kind in ("knee", "ankle"):
        probe = DiagnosisTrial(kind, t, np.deg2rad(trial_angle), np.zeros_like(t), fixed, dict(SUBJECT))
        torque = torque + probe.limb_gravity_nm()
        if cause == "gravity_error":
            sign = float(rng.choice([-1.0, 1.0]))
            torque = torque + sign * mag * probe.gravity_shape()
            extra["sign"] = sign
    if cause == "coulomb_friction":
        torque = torque + mag * np.tanh(omega / FRICTION_SPEED_RAD_S)
    elif cause == "viscous_damping":
        torque = torque + mag * omega
    elif cause == "activation_burst":
        start = rng.uniform(t[0] + 2.0, t[-1] - 3.0)
        dur = rng.uniform(0.3, 0.8)
        u = (t - start) / dur
        torque = torque + mag * np.where((u >= 0) & (u <= 1), np.sin(np.pi * np.clip(u, 0, 1)), 0.0)
        extra.update(start_s=start, duration_s=dur)
    elif cause == "sensor_drift":
        torque = torque + mag * (t - t[0])
    torque = torque + _ar1(rng, t.size, NOISE_NM[kind])
    trial = DiagnosisTrial(kind, t, np.deg2rad(trial_angle), torque, fixed, dict(SUBJECT), f"synthetic-{kind}-{cause}-{seed}")
    return trial, HiddenEffect(cause, mag, extra)


def truth_magnitude(effect: HiddenEffect) -> float:
    """The hidden magnitude in the units the diagnosis reports it (its cause's magnitude key)."""
    return abs(effect.magnitude) if effect.cause == "gravity_error" else effect.magnitude


__all__ = ["make_trial", "HiddenEffect", "causes_for", "RANGES", "truth_magnitude", "G_M_S2"]
