"""A seventeenth generator family for the diagnosis, written after the sixteenth's run and before the next engine
change, to be run once on that change's frozen engine.

The second to sixteenth families (:mod:`benchmarks.family_b_truth` … ``family_p_truth``) became development data once
run. This one draws every cause from a law the engine's library does not hold (checked against
:mod:`analysis.diagnosis.causes` before it was run; where an earlier family used a near relation it is said).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
segments' draw, the recording's damage, the protocol's set-up and the limb's load of :mod:`benchmarks.family_scaffold`).

- Passive moment: Veronda & Westmann's (1970) law of skin at each end of a joint's range, A·(e^{b·x} − b·x − 1) for x
  the angle past an onset (b 0.15–0.5 /°: it starts quadratically, with no kink, and becomes exponential), sized by
  its torque at the range's end, the onset toward a two-joint muscle moved by the other joint's angle, plus a small
  linear term. Elastic: no memory in the clean trials. The AFO: a spring whose lever arm grows with the bend (a cam),
  k·θ·(1 + a·θ/15°) (a 0.1–0.4) past an engagement of 0.5–3°.
- Motion: a sinusoidal angle whose frequency sweeps (a linear chirp) from f₀ to 2–3·f₀ over the trial, f₀ set by a
  mean speed of 3–8 °/s at the start, between the range's ends, 2.5–4 cycles (every earlier family's strokes kept one
  period or stepped between fixed speeds). The AFO: bends of 12–19° following a raised-cosine in time (0.8–2.5 s
  each way), every other bend paused 0.2–0.8 s at its top.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: elasto-plastic presliding (Dupont et al. 2002): after each reversal the friction follows the angle
    travelled linearly, reaching its level F after a presliding angle of 0.2–2° and holding it (the engine's Dahl law
    turns over exponentially; the fourth family's LuGre bristle too); magnitude: its mean over the moving samples;
  * damping: viscous beyond a dead band, b·sign(θ̇)·max(|θ̇| − v_d, 0), v_d 10–30 % of the trial's peak speed (a
    damper with a bypass orifice; the fifteenth family's relief valve cut in at high speed, this one at low);
    magnitude: b;
  * stop: a linear stop engaged through a smoothstep (3s² − 2s³ over an engagement of 0.5–3°, so its stiffness
    rises from zero over that angle), anywhere in the last third of either end of a joint's range (the AFO's at the
    top of its bend); named only;
  * delay: a wireless link's latency wandering over the trial, a mean of 0.03–0.45 s modulated by ±15–35 % along a
    sinusoid of period 20–80 s (the ninth family's clocks drifted linearly); magnitude: the mean latency;
  * activation: a hyperbolic-secant-squared pulse (half-width 0.15–0.6 s) followed by an undershoot of 10–30 % of
    its peak relaxing over 0.5–1.5 s (an after-relaxation), of either sign; magnitude: its peak;
  * limb-weight error: a support strap slipping once at a random time (20–80 % through the trial): the segment's
    weight moment carried wrongly by a share stepping from zero along a logistic over 1–3 s (every earlier error was
    the same all trial); magnitude: its peak;
  * drift: two settling events at random times (a cable nudged twice), each an offset of either sign settling in
    over 5–20 s (1 − e^{−t/τ}); named only;
  * series compliance: a cuff whose give creeps under load, c·τ plus a creep c_r·τ through a first-order lag of
    1–4 s (c_r 30–60 % of c; the eighth family's solid's delayed give was under 0.3 s); magnitude: the least-squares
    slope of the give on the torque;
  * inertia error: a mass on a spring (a loosely strapped bag of 0.5–2 kg·m² reflected, tuned to 1–3 Hz, damping
    ratio 0.05–0.2) whose reaction torque adds to the measured one; magnitude: the least-squares coefficient of its
    torque on θ̈.
- Nuisances: 100–1000 Hz; white noise plus a slow amplifier flicker (an AR(1) of ρ 0.95–0.99 at 0.3–0.6 × the noise
  SD); a torque gain error of ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter;
  dropped rows singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle
  offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import lfilter

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

NOISE_SD_NM = {"afo": 0.07, "knee": 0.17, "ankle": 0.13}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def veronda_westmann(x_deg: np.ndarray, rate_per_deg: float) -> np.ndarray:
    """Veronda & Westmann's stiffening per unit amplitude: e^{b·x} − b·x − 1 for the angle ``x_deg`` past an onset
    (0 before it): quadratic at the onset, exponential beyond."""
    z = rate_per_deg * np.clip(np.asarray(x_deg, dtype=float), 0.0, None)
    return np.expm1(z) - z


def chirp_sweep(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): lo + (hi − lo)·(1 − cos φ)/2 with φ the phase of a linear chirp whose frequency rises from f₀
    (a mean speed of 3–8 °/s over the stroke) to 2–3·f₀ over 2.5–4 cycles."""
    f0 = float(rng.uniform(3.0, 8.0)) / (2.0 * (hi - lo))  # one cycle covers the range twice
    ratio = float(rng.uniform(2.0, 3.0))
    cycles = float(rng.uniform(2.5, 4.0))
    # cycles = ∫ f dt = f₀·T·(1 + ratio)/2 for a linear rise from f₀ to ratio·f₀ over T
    duration = 2.0 * cycles / (f0 * (1.0 + ratio))
    t = np.arange(0.0, duration, 1.0 / rate)
    phase = 2.0 * np.pi * (f0 * t + 0.5 * (ratio - 1.0) * f0 * t**2 / duration)
    return lo + (hi - lo) * 0.5 * (1.0 - np.cos(phase))


def cosine_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–8 bends to 12–19° and back to 0°, each way a raised cosine in time of 0.8–2.5 s, every other
    bend paused 0.2–0.8 s at its top, 0.3 s at rest between bends."""
    parts = [np.zeros(int(0.4 * rate))]
    for i in range(int(rng.integers(5, 9))):
        peak = float(rng.uniform(12.0, 19.0))
        up = np.linspace(0.0, 1.0, int(rng.uniform(0.8, 2.5) * rate))
        down = np.linspace(0.0, 1.0, int(rng.uniform(0.8, 2.5) * rate))
        parts.append(peak * 0.5 * (1.0 - np.cos(np.pi * up)))
        if i % 2 == 1:
            parts.append(np.full(int(rng.uniform(0.2, 0.8) * rate), peak))
        parts.append(peak * 0.5 * (1.0 + np.cos(np.pi * down)))
        parts.append(np.zeros(int(0.3 * rate)))
    return np.concatenate(parts)


def elastoplastic_friction(deg: np.ndarray, presliding_deg: float) -> np.ndarray:
    """Dupont's elasto-plastic friction per unit level (resisting increasing angle): the bristle deflection z follows
    the angle's increments and is held within ±``presliding_deg`` (stick, then full sliding at the level); the torque
    z / presliding_deg. Starts relaxed (z = 0)."""
    z = np.empty_like(deg, dtype=float)
    level = 0.0
    z[0] = 0.0
    steps = np.diff(deg, prepend=deg[0])
    for i, step in enumerate(steps):
        level = min(max(level + step, -presliding_deg), presliding_deg)
        z[i] = level
    return z / presliding_deg


def dead_band_damping(vel: np.ndarray, dead_band: float) -> np.ndarray:
    """Viscous damping beyond a dead band per unit coefficient: sign(θ̇)·max(|θ̇| − v_d, 0) (same unit as ``vel``)."""
    return np.sign(vel) * np.maximum(np.abs(vel) - dead_band, 0.0)


def smoothstep_stop(deg: np.ndarray, at_deg: float, high: bool, engage_deg: float) -> np.ndarray:
    """A linear stop reached through a smoothstep, per unit stiffness (N·m per degree), toward the range's inside
    (positive at the high end): ∫ s(δ) dδ, s = 3u² − 2u³ for u = δ / ``engage_deg`` ≤ 1, then 1."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (deg - at_deg), 0.0, None)
    u = np.clip(depth / engage_deg, 0.0, 1.0)
    within = engage_deg * (u**3 - 0.5 * u**4)  # ∫₀^δ (3u² − 2u³) dδ
    beyond = 0.5 * engage_deg + np.maximum(depth - engage_deg, 0.0)
    return sign * np.where(depth <= engage_deg, within, beyond)


def wandering_latency(torque: np.ndarray, t: np.ndarray, mean_s: float, depth: float, period_s: float,
                      phase: float) -> tuple[np.ndarray, np.ndarray]:
    """``torque`` read late by a latency mean_s·(1 + depth·sin(2πt/period + phase)) at each sample (interpolated,
    held at the first sample before the trial); returns (the late torque, the latency at each sample in s)."""
    latency = mean_s * (1.0 + depth * np.sin(2.0 * np.pi * t / period_s + phase))
    return np.interp(t - latency, t, torque), latency


def sech2_with_undershoot(t: np.ndarray, centre_s: float, half_width_s: float, undershoot: float,
                          relax_s: float) -> np.ndarray:
    """A sech² pulse of peak 1 (its half-width at half maximum ``half_width_s``) at ``centre_s``, then an undershoot
    of ``undershoot`` × the peak rising in with the pulse's fall and relaxing over ``relax_s``."""
    a = half_width_s / np.arccosh(np.sqrt(2.0))  # sech²(x/a) = 1/2 at x = half-width
    pulse = 1.0 / np.cosh((t - centre_s) / a) ** 2
    after = t - centre_s
    tail = np.where(after > 0.0, (1.0 - 1.0 / np.cosh(after / a) ** 2) * np.exp(-after / relax_s), 0.0)
    tail = tail / max(float(np.max(tail)), 1e-12)
    lo, hi = 0.0, 10.0 * undershoot  # the tail's size whose trough beside the pulse's own fall is −undershoot
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if float(np.min(pulse - mid * tail)) > -undershoot else (lo, mid)
    return pulse - 0.5 * (lo + hi) * tail


def slipping_share(t: np.ndarray, at_s: float, width_s: float) -> np.ndarray:
    """The share (0 → 1) of a strap's slip: a logistic in time centred on ``at_s``, 10–90 % over ``width_s``."""
    return 1.0 / (1.0 + np.exp(-(t - at_s) * 4.394 / width_s))


def two_settles(t: np.ndarray, times_s: tuple[float, float], taus_s: tuple[float, float],
                signs: tuple[float, float]) -> np.ndarray:
    """Two offsets settling in, each (1 − e^{−(t − t_k)/τ_k}) after its time, signs ±1; largest excursion 1."""
    y = np.zeros_like(t)
    for at, tau, sign in zip(times_s, taus_s, signs, strict=True):
        y += sign * np.where(t > at, -np.expm1(-(t - at) / tau), 0.0)
    return y / max(float(np.max(np.abs(y - np.mean(y)))), 1e-12)


def creeping_give(torque: np.ndarray, t: np.ndarray, creep_share: float, creep_s: float) -> np.ndarray:
    """A cuff's give per unit compliance: τ plus ``creep_share``·τ through a first-order lag of ``creep_s``
    (started at rest on the first sample's torque)."""
    a = float(np.exp(-(t[1] - t[0]) / creep_s)) if t.size > 1 else 0.0
    lagged = lfilter([1.0 - a], [1.0, -a], torque, zi=[a * float(torque[0])])[0]
    return torque + creep_share * lagged


def strapped_mass_torque(acc: np.ndarray, t: np.ndarray, inertia: float, natural_hz: float,
                         damping_ratio: float) -> np.ndarray:
    """The reaction torque (N·m) of an inertia ``inertia`` (kg·m²) on a spring–damper mount tuned to ``natural_hz``
    with ``damping_ratio``, its base driven with the joint's acceleration ``acc`` (rad/s²): the mass's own
    acceleration through the mount's second-order response, times its inertia (semi-implicit Euler)."""
    w = 2.0 * np.pi * natural_hz
    dt = float(t[1] - t[0]) if t.size > 1 else 1.0
    vel_base = np.concatenate([[0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * dt)])
    pos_base = np.concatenate([[0.0], np.cumsum(0.5 * (vel_base[1:] + vel_base[:-1]) * dt)])
    x, v = 0.0, 0.0  # the mass's angle and speed relative to the ground frame, minus the base's start
    out = np.empty_like(acc)
    for i in range(acc.size):
        a_mass = -w * w * (x - pos_base[i]) - 2.0 * damping_ratio * w * (v - vel_base[i])
        v += a_mass * dt
        x += v * dt
        out[i] = inertia * a_mass
    return out


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m, toward increasing angle's resistance)."""
    if kind == "afo":
        bend = np.maximum(deg - c["engage"], 0.0)
        return c["k"] * bend * (1.0 + c["cam"] * bend / 15.0)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    low_ref = float(veronda_westmann(np.array(c["on_low"] - c["lo"]), c["b_low"]))
    high_ref = float(veronda_westmann(np.array(c["hi"] - c["on_high"]), c["b_high"]))
    return (-c["t_low"] * veronda_westmann(on_low - deg, c["b_low"]) / low_ref
            + c["t_high"] * veronda_westmann(deg - on_high, c["b_high"]) / high_ref
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, cam = float(rng.uniform(0.5, 3.0)), float(rng.uniform(0.1, 0.4))
        tau15 = float(rng.uniform(10.0, 25.0))
        bend = 15.0 - engage
        return {"engage": engage, "cam": cam, "k": tau15 / (bend * (1.0 + cam * bend / 15.0))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
            "b_low": float(rng.uniform(0.15, 0.5)), "b_high": float(rng.uniform(0.15, 0.5)),
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_q(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((17, 17, 17), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: chirp_sweep(r, a, b, rate),
                                         lambda r: cosine_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a cuff whose give creeps: c·(τ + c_r·lag(τ))
        c_give, creep, creep_s = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.3, 0.6)), float(rng.uniform(1, 4))
        for _ in range(3):  # the joint turns by the angle less the give, which depends on the torque it meets
            joint_deg = deg - c_give * creeping_give(_elastic(kind, joint_deg, fixed, coef), t, creep, creep_s)
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, creep_share=creep, creep_s=creep_s)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # a support strap slipping once: the weight's moment carried wrongly from then on
        at = float(rng.uniform(0.2, 0.8)) * float(t[-1])
        unit = slipping_share(t, at, float(rng.uniform(1.0, 3.0))) * load.moment_nm / max(load.amplitude_nm, 1e-12)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12) * float(rng.choice([-1.0, 1.0]))
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(slip_s=at, weight_moment_amplitude_Nm=load.amplitude_nm)
    if "coulomb_friction" in effects:
        presliding = float(rng.uniform(0.2, 2.0))
        unit = elastoplastic_friction(deg, presliding)
        level = size()
        torque = torque + level * unit
        truth["coulomb_friction"] = float(level * np.mean(np.abs(unit[moving])))
        details.update(presliding_deg=presliding)
    if "viscous_damping" in effects:
        peak = float(np.percentile(np.abs(vel), 95))
        dead = float(rng.uniform(0.1, 0.3)) * peak
        unit = dead_band_damping(vel, dead)
        b = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + b * unit
        truth["viscous_damping"] = b
        details.update(dead_band_rad_s=dead)
    if "inertia" in effects:
        natural, ratio = float(rng.uniform(1.0, 3.0)), float(rng.uniform(0.05, 0.2))
        unit = strapped_mass_torque(acc, t, 1.0, natural, ratio)
        scale = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + scale * unit
        truth["inertia"] = float(np.dot(acc, scale * unit) / np.dot(acc, acc))
        details.update(mount_hz=natural, mount_damping_ratio=ratio, strapped_inertia_kgm2=scale)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        engage = float(rng.uniform(0.5, 3.0))
        unit = smoothstep_stop(deg, at, high, engage)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", engage_deg=engage)
    if "activation_burst" in effects:
        half = float(rng.uniform(0.15, 0.6))
        centre = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        unit = sech2_with_undershoot(t, centre, half, float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.5, 1.5)))
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * unit
        truth["activation_burst"] = peak
        details.update(pulse_centre_s=centre, pulse_half_width_s=half)
    if "sensor_drift" in effects:
        times = (float(rng.uniform(0.05, 0.5)) * float(t[-1]), float(rng.uniform(0.5, 0.9)) * float(t[-1]))
        taus = (float(rng.uniform(5.0, 20.0)), float(rng.uniform(5.0, 20.0)))
        signs = (float(rng.choice([-1.0, 1.0])), float(rng.choice([-1.0, 1.0])))
        torque = torque + size() * two_settles(t, times, taus, signs)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        mean = float(rng.uniform(0.03, 0.45))
        torque, latency = wandering_latency(torque, t, mean, float(rng.uniform(0.15, 0.35)),
                                            float(rng.uniform(20.0, 80.0)), float(rng.uniform(0.0, 2.0 * np.pi)))
        truth["time_delay"] = float(np.mean(latency))
        details.update(mean_latency_s=mean)
    noise = rng.normal(0.0, sd, t.size)
    rho = float(rng.uniform(0.95, 0.99))
    flicker = lfilter([1.0], [1.0, -rho], rng.normal(0.0, 1.0, t.size))
    noise += float(rng.uniform(0.3, 0.6)) * sd * flicker / max(float(np.std(flicker)), 1e-12)
    torque = torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "chirp_sweep", "cosine_bends",
           "creeping_give", "dead_band_damping", "elastoplastic_friction", "generate_q", "sech2_with_undershoot",
           "slipping_share", "smoothstep_stop", "strapped_mass_torque", "two_settles", "veronda_westmann",
           "wandering_latency"]
