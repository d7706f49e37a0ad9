"""Trials with hidden effects from a generator the diagnosis does not share.

Written apart from ``analysis.diagnosis`` (nothing is imported from it): its own baselines,
effect shapes, motions, anthropometrics and noise, so a test on these trials can see what the
diagnosis's own model gets wrong.

- Knee and ankle passive moments: Riener & Edrich (1999), J Biomech 32:539, eqs. for the knee
  (hip and ankle angles as parameters) and the ankle (knee angle as parameter), each exponential
  term's rate perturbed by up to ±10 % and its gain by up to ±25 % per subject. Their angle
  convention (knee flexion positive, ankle *plantar*flexion positive, moment positive in knee
  flexion and ankle plantarflexion) is converted to the trial CSV's (angle in flexion /
  dorsiflexion, torque = the specimen's resistance to that bending).
- Limb weight: de Leva (1996) segment fractions (shank 4.33 % of body mass, centre 43.95 % from
  the knee; foot 1.37 %, 44.15 % of its length), seated with the thigh horizontal.
- AFO: a spring engaging at 2–5° with a stiffening (or softening) of up to ±25 % over the range,
  bent by hand (bends of random peak, speed and skew).
- Effects, each sized so its largest contribution is ``noise_multiple`` × the noise's standard
  deviation: Coulomb friction (arctan-smoothed sign, width 0.3°/s), viscous damping, a hard stop
  (linear contact stiffness past the stop), a delay of the torque channel, an activation burst
  (a raised-cosine bump of 0.3–1.2 s), a limb-weight error and a torque drift.
- Nuisances: sampling at 100, 250 or 1000 Hz, AR(1) noise of random correlation, a torque
  offset, an angle offset, NaN cells, dropped rows, uneven speed and fast sweeps.

Angles in degrees at the edges (the motions), SI inside the returned arrays: ``angle_rad``,
``torque_nm``, ``time_s``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

G = 9.80665
SUBJECT = {"mass_kg": 72.0, "height_m": 1.76, "shank_length_m": 0.41, "foot_length_m": 0.265, "thigh_length_m": 0.42}
NOISE_SD_NM = {"afo": 0.08, "knee": 0.2, "ankle": 0.15}
#: the effects a kind can hide, with the diagnosis's name for each
EFFECTS: dict[str, tuple[str, ...]] = {
    "afo": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "sensor_drift"),
    "knee": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
             "sensor_drift"),
    "ankle": ("coulomb_friction", "viscous_damping", "hard_stop", "time_delay", "activation_burst", "gravity_error",
              "sensor_drift"),
}
#: the unit of each effect's reported magnitude (the diagnosis's magnitude key)
MAGNITUDE_KEY = {"coulomb_friction": "friction_Nm", "viscous_damping": "damping_Nm_s_per_rad",
                 "hard_stop": "stop_stiffness_Nm_per_deg", "time_delay": "delay_s",
                 "activation_burst": "burst_amplitude_Nm", "gravity_error": "gravity_moment_error_Nm",
                 "sensor_drift": "drift_Nm_per_s"}


@dataclass
class IndependentTrial:
    """A generated trial and what it hides."""

    kind: str
    time_s: np.ndarray
    angle_rad: np.ndarray
    torque_nm: np.ndarray
    fixed_deg: dict[str, float]
    subject: dict[str, float]
    effects: dict[str, float]          # cause → true magnitude (in MAGNITUDE_KEY units)
    details: dict[str, Any] = field(default_factory=dict)
    rate_hz: float = 100.0
    noise_sd_nm: float = 0.0


def riener_knee_nm(knee_flex_deg: np.ndarray, hip_flex_deg: float, ankle_df_deg: float, p: np.ndarray) -> np.ndarray:
    """Riener & Edrich's passive knee moment (N·m, positive = flexing), perturbed by ``p`` (gains, rates)."""
    phi_k, phi_h, phi_a = knee_flex_deg, hip_flex_deg, -ankle_df_deg
    return (p[0] * np.exp(1.800 - 0.0460 * phi_a - 0.0352 * p[3] * phi_k + 0.0217 * phi_h)
            - p[1] * np.exp(-3.971 - 0.0004 * phi_a + 0.0495 * p[4] * phi_k - 0.0128 * phi_h)
            - 4.820 + p[2] * np.exp(2.220 - 0.150 * p[5] * phi_k))


def riener_ankle_nm(ankle_df_deg: np.ndarray, knee_flex_deg: float, p: np.ndarray) -> np.ndarray:
    """Riener & Edrich's passive ankle moment (N·m, positive = plantarflexing), perturbed by ``p``."""
    phi_a, phi_k = -ankle_df_deg, knee_flex_deg
    return (p[0] * np.exp(2.1016 - 0.0843 * p[3] * phi_a - 0.0176 * phi_k)
            - p[1] * np.exp(-7.9763 + 0.1949 * p[4] * phi_a + 0.0008 * phi_k) - 1.792)


def limb_weight_resistance_nm(kind: str, angle_deg: np.ndarray, fixed: dict[str, float], subject: dict[str, float]) -> np.ndarray:
    """The limb's weight as resistance to the bending (N·m), seated with the thigh horizontal (de Leva)."""
    m = subject["mass_kg"]
    if kind == "knee":
        shank_m, foot_m = 0.0433 * m, 0.0137 * m
        arm = shank_m * 0.4395 * subject["shank_length_m"] + foot_m * subject["shank_length_m"]
        return -arm * G * np.cos(np.deg2rad(angle_deg))  # the hanging shank helps flexion
    if kind == "ankle":
        foot_m = 0.0137 * m
        foot_angle = np.deg2rad(angle_deg + 90.0 - fixed["knee_flexion_deg"])  # toe above horizontal
        return foot_m * G * 0.4415 * subject["foot_length_m"] * np.cos(foot_angle)
    return np.zeros_like(angle_deg)


def _sweep(rng: np.random.Generator, rate: float, start: float, end: float, speeds: list[float],
           uneven: bool) -> np.ndarray:
    """Isokinetic there-and-back sweeps (deg) at each speed (deg/s), holds of 0.5–1.5 s between."""
    def hold() -> np.ndarray:
        return np.full(int(rng.uniform(0.5, 1.5) * rate), 0.0)
    parts = [hold() + start]
    for v in speeds:
        for a, b in ((start, end), (end, start)):
            n = max(int(abs(b - a) / v * rate), 10)
            u = np.linspace(0.0, 1.0, n)
            if uneven:  # the arm's speed wanders ±15 % (a cheap dynamometer or a hand-held sweep)
                wob = 0.15 * rng.uniform(0.5, 1.0) / (2 * np.pi * 2)
                u = u + wob * np.sin(2 * np.pi * 2 * u)
            parts += [a + (b - a) * u, hold() + b]
    return np.concatenate(parts)


def _bends(rng: np.random.Generator, rate: float, peak: tuple[float, float], n_bends: int) -> np.ndarray:
    """Hand bends from 4° to a random peak and back (deg)."""
    parts = [np.full(int(0.4 * rate), 4.0)]
    for _ in range(n_bends):
        top = rng.uniform(*peak)
        up, down = rng.uniform(0.6, 1.8), rng.uniform(0.6, 1.8)
        u1 = np.linspace(0, 1, int(up * rate), endpoint=False)
        u2 = np.linspace(0, 1, int(down * rate), endpoint=False)
        parts += [4.0 + (top - 4.0) * 0.5 * (1 - np.cos(np.pi * u1)),
                  top - (top - 4.0) * 0.5 * (1 - np.cos(np.pi * u2)), np.full(int(rng.uniform(0.1, 0.5) * rate), 4.0)]
    return np.concatenate(parts)


def _ar1(rng: np.random.Generator, n: int, sd: float, rho: float) -> np.ndarray:
    from scipy.signal import lfilter
    e = rng.normal(0.0, sd * np.sqrt(1 - rho**2), n)
    e[0] = rng.normal(0.0, sd)
    return lfilter([1.0], [1.0, -rho], e)


def generate(kind: str, effects: tuple[str, ...] = (), seed: int = 0, *, noise_multiple: tuple[float, float] = (3.0, 5.0),
             rate_hz: float | None = None, nuisances: bool = False, fast: bool = False) -> IndependentTrial:
    """One trial of ``kind`` hiding ``effects`` (zero, one or two of :data:`EFFECTS`), drawn from ``seed``.

    Parameters
    ----------
    noise_multiple
        Range of each effect's peak contribution in multiples of the noise's standard deviation.
    rate_hz
        Sampling rate (Hz); drawn from 100/250/1000 Hz when ``nuisances`` and not given, else 100.
    nuisances
        Add offsets, NaN cells, dropped rows, uneven speed and random noise correlation.
    fast
        Isokinetic sweeps at 20 and 30 °/s instead of 5 and 10–15 °/s.
    """
    for e in effects:
        if e not in EFFECTS[kind]:
            raise ValueError(f"{e!r} is not an effect of {kind} trials: {EFFECTS[kind]}")
    rng = np.random.default_rng([seed, len(effects), *[EFFECTS[kind].index(e) for e in effects]])
    rate = float(rate_hz if rate_hz is not None else (rng.choice([100.0, 250.0, 1000.0]) if nuisances else 100.0))
    uneven = bool(nuisances and rng.random() < 0.5)
    sd = NOISE_SD_NM[kind] * (rng.uniform(0.7, 1.3) if nuisances else 1.0)
    rho = float(rng.uniform(0.3, 0.9) if nuisances else 0.6)
    fixed: dict[str, float] = {}
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "noise_rho": rho, "uneven": uneven}
    subj = dict(SUBJECT)
    if kind == "knee":
        hip = float(rng.choice([90.0, 55.0, 15.0]))
        fixed = {"hip_flexion_deg": hip, "ankle_dorsiflexion_deg": 0.0}
        top = 90.0 if "hard_stop" not in effects else rng.uniform(92.0, 98.0)
        speeds = [20.0, 30.0] if fast else [5.0, float(rng.choice([10.0, 15.0]))]
        deg = _sweep(rng, rate, 0.0, top, speeds, uneven)
        p = np.concatenate([rng.uniform(0.75, 1.25, 3), rng.uniform(0.9, 1.1, 3)])
        def passive(d: np.ndarray) -> np.ndarray:
            return -riener_knee_nm(d, hip, 0.0, p)
    elif kind == "ankle":
        knee = float(rng.choice([0.0, 45.0, 90.0]))
        fixed = {"knee_flexion_deg": knee, "hip_flexion_deg": 90.0}
        lo = -30.0 if "hard_stop" not in effects else rng.uniform(-34.0, -32.0)
        speeds = [20.0, 30.0] if fast else [5.0, float(rng.choice([10.0, 15.0]))]
        deg = _sweep(rng, rate, 15.0, lo, speeds, uneven)  # a plantarflexion sweep from 15° dorsiflexion
        p = np.concatenate([rng.uniform(0.75, 1.25, 2), [1.0], rng.uniform(0.9, 1.1, 2)])
        def passive(d: np.ndarray) -> np.ndarray:
            return riener_ankle_nm(d, knee, p)
    else:
        engage = rng.uniform(2.0, 5.0)
        k = rng.uniform(0.6, 1.8)
        bend = rng.uniform(-0.25, 0.25)
        peak = (17.0, 20.0) if "hard_stop" not in effects else (21.0, 23.0)
        deg = _bends(rng, rate, peak, int(rng.integers(6, 9)))
        def passive(d: np.ndarray) -> np.ndarray:
            x = np.maximum(d - engage, 0.0)
            return k * x * (1.0 + bend * x / 16.0)
        details.update(spring_Nm_per_deg=k, engage_deg=engage)
    t = np.arange(deg.size) / rate
    omega_deg = np.gradient(deg, t)
    torque = passive(deg) + limb_weight_resistance_nm(kind, deg, fixed, subj)
    truths: dict[str, float] = {}
    mult = {e: rng.uniform(*noise_multiple) for e in effects}
    for e in effects:  # the effects that change the angle–torque relation come first
        size = mult[e] * sd
        if e == "hard_stop":
            span = rng.uniform(4.0, 8.0)
            if kind == "ankle":  # the stop is at the plantarflexion end: stiffness resisting plantarflexion
                stop = deg.min() + span
                torque = torque - size / span * np.maximum(stop - deg, 0.0)
            else:
                stop = deg.max() - span
                torque = torque + size / span * np.maximum(deg - stop, 0.0)
            truths[e] = size / span
            details["stop_deg"] = stop
        elif e == "time_delay":
            rate_of_change = np.max(np.abs(np.gradient(torque, t)))
            d = float(np.clip(size / max(rate_of_change, 1e-9), 0.02, 0.3))
            torque = np.interp(t - d, t, torque)
            truths[e] = d
    if kind in ("knee", "ankle") and "gravity_error" in effects:
        wrong = dict(subj)
        sign = rng.choice([-1.0, 1.0])
        shape = limb_weight_resistance_nm(kind, deg, fixed, subj)
        scale = mult["gravity_error"] * sd / max(np.max(np.abs(shape)), 1e-9)
        torque = torque + sign * scale * shape
        truths["gravity_error"] = float(scale * np.max(np.abs(shape)) / np.max(np.abs(np.cos(np.deg2rad(
            deg + (90.0 - fixed["knee_flexion_deg"] if kind == "ankle" else 0.0))))))
        details["gravity_sign"] = sign
        del wrong
    for e in effects:
        size = mult[e] * sd
        if e == "coulomb_friction":
            torque = torque + size * (2 / np.pi) * np.arctan(omega_deg / 0.3)
            truths[e] = size
        elif e == "viscous_damping":
            b = size / np.max(np.abs(np.deg2rad(omega_deg)))
            torque = torque + b * np.deg2rad(omega_deg)
            truths[e] = b
        elif e == "activation_burst":
            dur = rng.uniform(0.3, 1.2)
            start = rng.uniform(t[0] + 2.0, t[-1] - 2.0 - dur)
            u = (t - start) / dur
            torque = torque + size * np.where((u >= 0) & (u <= 1), 0.5 * (1 - np.cos(2 * np.pi * np.clip(u, 0, 1))), 0.0)
            truths[e] = size
            details.update(burst_start_s=start, burst_duration_s=dur)
        elif e == "sensor_drift":
            truths[e] = size / (t[-1] - t[0])
            torque = torque + truths[e] * (t - t[0])
    torque = torque + _ar1(rng, t.size, sd, rho)
    angle = deg.copy()
    if nuisances:
        torque = torque + rng.uniform(-2.0, 2.0)
        angle = angle + rng.uniform(-1.5, 1.5)
        keep = rng.random(t.size) > 0.02
        t, angle, torque = t[keep], angle[keep], torque[keep]
        torque[rng.random(t.size) < 0.005] = np.nan
        angle[rng.random(t.size) < 0.005] = np.nan
    return IndependentTrial(kind, t, np.deg2rad(angle), torque, fixed, subj, truths, details, rate, sd)


__all__ = ["generate", "IndependentTrial", "EFFECTS", "MAGNITUDE_KEY", "riener_knee_nm", "riener_ankle_nm",
           "limb_weight_resistance_nm"]
