"""A ninth generator family for the diagnosis, written after the eighth's run and run once when the engine froze.

The second to eighth families (:mod:`benchmarks.family_b_truth` … ``family_h_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses. Nothing is imported from
``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and the
recording's damage and the protocol's set-up of
:mod:`benchmarks.family_scaffold`).

- Passive moment: collagen fibres recruited one by one (a structural model of ligament and tendon, after Shah,
  Hurschler et al.): the fibres' slack angles Weibull-distributed past an onset at each end of the range, each
  linear once taut, so the moment is the integral of the recruited fraction (a toe region whose shape is the
  distribution's, then linear); the onset toward a two-joint muscle moved by the other joint's angle.
  The AFO: a spring whose fibres (the strap and shell) recruit the same way over 2–6° from its engagement.
- Motion: an operator's speed knob: within each stroke the speed wanders smoothly between 2 and 25 °/s (a
  low-passed random walk), slowing to a stop at each end; holds of 0–0.8 s. The AFO: slow bends (1.5–4 s) to
  10–20° and quick releases (0.15–0.5 s, the hand letting the spring return, as in the seventh family's
  spring-back but as a raised cosine), 0.2–1 s apart.
- Limb: segment fractions 4.65 % (shank, centre 43 % down from the knee) and 1.45 % (foot, centre 44 % of its
  length) of the body mass.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a Bouc–Wen hysteresis, ż = (A·θ̇ − β|θ̇||z|^{n−1}z − γθ̇|z|^n) with n 2–4 (sharper corners than
    Dahl's), the torque F·z/z_max; magnitude: F, its sliding level;
  * damping: thixotropic tissue, b falling with the distance moved, b₀·(r + (1 − r)·e^{−travel/Θ}) (r 0.5–0.8,
    Θ 100–400°); magnitude: b's mean over the moving samples;
  * stop: a Kelvin–Voigt contact, k·δ + c·δ̇ while in contact (its damping 30–60 % of the elastic peak at
    entry), anywhere in the last third of either end of a joint's range (the AFO's at the top); named only;
  * delay: two devices' clocks: the torque recorded 0.05–0.45 s late at the start and the lag drifting by
    100–400 ppm of the elapsed time; magnitude: the mean lag;
  * activation: a biphasic (agonist then antagonist) burst, two smooth lobes of opposite sign, the second 40–80
    % of the first, 0.1–0.3 s each; magnitude: the larger lobe's peak;
  * limb-weight error: a cable bundle hanging from the distal segment, its weight borne only once the segment
    lifts it off the floor (a smoothstep over 20–40° past a lift-off angle); magnitude: its moment's peak;
  * drift: an amplifier's auto-zero, a slow ramp reset to zero every 8–30 s (a sawtooth); named only;
  * series compliance: a strap loosening over the trial, its compliance growing linearly by 50–150 %;
    magnitude: its mean compliance;
  * inertia error: an attachment on a compliant mount (a tuned mass, 3–8 Hz, damping ratio 0.1–0.4); its
    torque the second-order response to ΔI·θ̈; magnitude ΔI.
- Nuisances: 100–1000 Hz; white noise whose SD grows with the torque carried (a strain gauge: 60 % at no load
  to 140 % at the largest); quantised torque and angle; the clock fast or slow by up to 0.03 % with jitter;
  dropped rows singly (0–1.5 %) and in runs; NaN cells in any column (≤ 0.4 %, time included); offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# the scoring contract every family shares with the harness (benchmarks.diagnosis_family_b): the effects each kind
# may hide, the engine's magnitude key per cause, the trial record; the physics below is this family's own
from .family_b_truth import EFFECTS, MAGNITUDE_KEY, FamilyBTrial
from .family_scaffold import GRAVITY, coupled_onsets, damage_recording, draw_subject, kinematics, protocol_set_up, trial_rng

NOISE_SD_NM = {"afo": 0.05, "knee": 0.2, "ankle": 0.11}


def recruited(x: np.ndarray, scale: float, shape: float) -> np.ndarray:
    """The moment (in units of the full stiffness × degrees) of fibres whose slack angles past an onset are
    Weibull(scale, shape)-distributed, each linear once taut, at ``x`` degrees past the onset: ∫₀ˣ F(s) ds for F
    the distribution's CDF (0 before the onset)."""
    grid = np.linspace(0.0, max(float(np.max(x)), 1e-9), 4001)
    cdf = 1.0 - np.exp(-((grid / scale) ** shape))
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (cdf[1:] + cdf[:-1]) * np.diff(grid))])
    return np.interp(np.clip(x, 0.0, None), grid, integral)


def _knob_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Strokes (deg) between ``lo`` and ``hi`` at an operator's wandering speed (2–25 °/s): the knob an
    Ornstein–Uhlenbeck wander (SD 6 °/s over 1.5 s) about a level, the drive following it through a 0.3 s lag with
    its acceleration held to 60 °/s², slowing to a stop at each end."""
    dt, accel = 1.0 / rate, 60.0
    out = [np.full(int(rng.uniform(0.2, 0.8) * rate), lo)]
    angle = lo
    for stroke in range(2 * int(rng.integers(2, 4))):
        target = hi if stroke % 2 == 0 else lo
        direction = 1.0 if target > angle else -1.0
        level, knob, speed, seg = float(rng.uniform(5.0, 20.0)), 0.0, 0.0, []
        while (target - angle) * direction > 1e-6 and len(seg) < 600 * rate:
            knob += -knob * dt / 1.5 + 6.0 * np.sqrt(2.0 * dt / 1.5) * float(rng.normal())
            remaining = abs(target - angle)
            wanted = float(np.clip(level + knob, 2.0, 25.0))
            change = (wanted - speed) * (1.0 - np.exp(-dt / 0.3))
            speed = speed + float(np.clip(change, -accel * dt, accel * dt))
            # braking at the acceleration limit to stop on the target (the speed's cap falls as √(2·a·remaining))
            speed = max(min(speed, float(np.sqrt(2.0 * accel * remaining))), 0.05)
            angle = angle + direction * min(speed * dt, remaining)
            seg.append(angle)
        out += [np.array(seg), np.full(int(rng.uniform(0.0, 0.8) * rate), angle)]
    return np.concatenate(out)


def _bend_and_release(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): slow raised-cosine loading to 10–20° over 1.5–4 s, a quick release over 0.15–0.5 s."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(10.0, 20.0))
        up = np.arange(0.0, float(rng.uniform(1.5, 4.0)), 1.0 / rate)
        down = np.arange(0.0, float(rng.uniform(0.15, 0.5)), 1.0 / rate)
        parts += [peak * 0.5 * (1.0 - np.cos(np.pi * up / up[-1])),
                  peak * 0.5 * (1.0 + np.cos(np.pi * down / down[-1])),
                  np.zeros(int(rng.uniform(0.2, 1.0) * rate))]
    return np.concatenate(parts)


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, float], lo: float, hi: float
             ) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        return c["k"] * recruited(deg - c["engage"], c["scale"], c["shape"])
    # a two-joint muscle stretched by the other joint engages earlier: the hamstrings (knee extension, the low end)
    # with hip flexion, the gastrocnemius (ankle dorsiflexion, the high end) with knee extension
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    low = recruited(on_low - deg, c["scale_low"], c["shape_low"])
    high = recruited(deg - on_high, c["scale_high"], c["shape_high"])
    low_ref = float(recruited(np.array([c["on_low"] - lo]), c["scale_low"], c["shape_low"])[0])
    high_ref = float(recruited(np.array([hi - c["on_high"]]), c["scale_high"], c["shape_high"])[0])
    return -c["t_low"] * low / max(low_ref, 1e-9) + c["t_high"] * high / max(high_ref, 1e-9)


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, float]:
    if kind == "afo":
        return {"k": rng.uniform(0.3, 1.0), "engage": rng.uniform(1.0, 4.0), "scale": rng.uniform(2.0, 6.0),
                "shape": rng.uniform(1.5, 4.0)}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": lo + rng.uniform(0.25, 0.45) * span, "on_high": hi - rng.uniform(0.25, 0.45) * span,
            "scale_low": rng.uniform(5.0, 15.0), "scale_high": rng.uniform(5.0, 15.0),
            "shape_low": rng.uniform(1.5, 4.0), "shape_high": rng.uniform(1.5, 4.0), "shift": rng.uniform(0.05, 0.2)}


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


def bouc_wen(theta_deg: np.ndarray, n: float, beta_share: float) -> np.ndarray:
    """The Bouc–Wen state z/z_max along an angle path (deg): dz = (A − |z|ⁿ·(β·sgn(dθ·z) + γ))·dθ with A = 1, β + γ
    = 1 (so |z| → 1 while sliding), β = ``beta_share``; integrated per sample (substeps keep it stable)."""
    z = np.zeros(theta_deg.size)
    step = np.diff(theta_deg, prepend=theta_deg[0])
    beta, gamma = beta_share, 1.0 - beta_share
    width = 0.3  # deg: the presliding scale (z reaches its level over about this angle)
    zi = 0.0
    for i, d in enumerate(step):
        sub = max(1, int(abs(d) / (0.05 * width)) + 1)
        h = d / width / sub
        for _ in range(sub):
            zi += h * (1.0 - abs(zi) ** n * (beta * np.sign(h * zi) + gamma))
        z[i] = zi
    return np.clip(z, -1.0, 1.0)


def _biphasic(rng: np.random.Generator, t: np.ndarray) -> tuple[np.ndarray, dict[str, Any]]:
    """A biphasic burst's unit torque (the larger lobe's peak 1): a raised-cosine lobe, then one of opposite sign
    40–80 % as large."""
    d1, d2, ratio = float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.4, 0.8))
    onset = float(rng.uniform(0.15, 0.8)) * float(t[-1])
    s = t - onset
    lobe1 = np.where((s >= 0) & (s <= d1), np.sin(np.pi * np.clip(s / d1, 0, 1)) ** 2, 0.0)
    s2 = s - d1
    lobe2 = np.where((s2 >= 0) & (s2 <= d2), np.sin(np.pi * np.clip(s2 / d2, 0, 1)) ** 2, 0.0)
    return lobe1 - ratio * lobe2, {"burst_onset_s": onset, "lobes_s": (d1, d2), "second_over_first": ratio}


def generate_i(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    from scipy.signal import lfilter

    rng = trial_rng((9, 9, 2), kind, effects, seed)
    rate = float(rng.choice([100.0, 200.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: _knob_strokes(r, a, b, rate),
                                         lambda r: _bend_and_release(r, rate))
    t, rad, vel, acc = kinematics(deg, rate)
    coef = _coefficients(rng, kind, lo, hi)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # the strap loosens: its compliance grows over the trial
        c0, growth = float(rng.uniform(0.03, 0.12)), float(rng.uniform(0.5, 1.5))
        compliance = c0 * (1.0 + growth * t / t[-1])
        give = np.zeros_like(deg)
        for _ in range(40):  # the give answers to the torque it lets through: iterate to the fixed point
            give = compliance * _passive(kind, deg - give, fixed, coef, lo, hi)
        joint_deg = deg - give
        truth["series_compliance"] = float(np.mean(compliance))
        details.update(compliance_growth=growth)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    torque = _passive(kind, joint_deg, fixed, coef, lo, hi) + weight + inertia * acc
    if "gravity_error" in effects:
        # a cable bundle hanging from the distal segment: its weight is borne by the limb only once the segment has
        # lifted it off the floor (a smoothstep over 20–40° past a lift-off angle in the range's middle half)
        lift = lo + float(rng.uniform(0.25, 0.75)) * (hi - lo)
        width = float(rng.uniform(20.0, 40.0))
        raised = (lift - joint_deg) / width if kind == "knee" else (joint_deg - lift) / width  # knee: extension
        u = np.clip(raised, 0.0, 1.0)
        borne = u * u * (3.0 - 2.0 * u)
        if kind == "knee":
            shape = -np.cos(joint) * borne
        else:
            shape = np.cos(joint + np.pi / 2 - np.radians(fixed["knee_flexion_deg"])) * borne
        moment = size()
        torque = torque + moment * shape / max(float(np.max(np.abs(shape))), 1e-12)
        truth["gravity_error"] = moment
        details.update(lift_off_deg=lift, lift_width_deg=width)
    if "coulomb_friction" in effects:
        n, beta = float(rng.uniform(2.0, 4.0)), float(rng.uniform(0.3, 0.7))
        level = size()
        torque = torque + level * bouc_wen(deg, n, beta)
        truth["coulomb_friction"] = level
        details.update(bouc_wen_n=n, bouc_wen_beta=beta)
    if "viscous_damping" in effects:
        keep, fade = float(rng.uniform(0.5, 0.8)), float(rng.uniform(100.0, 400.0))
        travel = np.cumsum(np.abs(np.diff(deg, prepend=deg[0])))
        b_t = keep + (1.0 - keep) * np.exp(-travel / fade)
        b0 = size() / float(np.max(np.abs(b_t * vel)))
        torque = torque + b0 * b_t * vel
        moving = np.abs(vel) > np.radians(0.5)
        truth["viscous_damping"] = float(b0 * np.mean(b_t[moving]))
        details.update(damping_keeps=keep, damping_fade_deg=fade)
    if "inertia" in effects:
        from scipy.signal import bilinear

        f_n, zeta = float(rng.uniform(3.0, 8.0)), float(rng.uniform(0.1, 0.4))
        w = 2.0 * np.pi * f_n
        b_z, a_z = bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], rate)
        response = lfilter(b_z, a_z, acc)
        di = size() / float(np.max(np.abs(response)))
        torque = torque + di * response
        truth["inertia"] = di
        details.update(mount_hz=f_n, mount_damping=zeta)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        pen_rate = np.gradient(pen, t)
        share = float(rng.uniform(0.3, 0.6))
        elastic = pen / max(float(pen.max()), 1e-12)
        entering = np.where(pen > 0.0, np.clip(pen_rate, 0.0, None), 0.0)
        viscous = entering / max(float(entering.max()), 1e-12) * share
        shape = elastic + viscous
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", contact_damping_share=share)
    if "activation_burst" in effects:
        unit, info = _biphasic(rng, t)
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * unit
        truth["activation_burst"] = amp
        details.update(info)
    if "sensor_drift" in effects:
        period = float(rng.uniform(8.0, 30.0))
        phase = float(rng.uniform(0.0, period))
        saw = ((t + phase) % period) / period
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * saw
        truth["sensor_drift"] = None
        details.update(auto_zero_s=period)
    if "time_delay" in effects:
        start, ppm = float(rng.uniform(0.05, 0.45)), float(rng.uniform(100.0, 400.0))
        lag = start + ppm * 1e-6 * t
        torque = np.interp(t - lag, t, torque, left=torque[0])
        truth["time_delay"] = float(np.mean(lag))
        details.update(lag_start_s=start, lag_drift_ppm=ppm)
    load = np.abs(torque - np.median(torque))
    scale = 0.6 + 0.8 * load / max(float(load.max()), 1e-12)
    torque = torque + rng.normal(0.0, 1.0, t.size) * sd * scale + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.015),
                                            angle_quantum_deg=(0.005, 0.04), clock_fraction=3e-4, drop_fraction=0.015,
                                            run_s=0.1, nan_fraction=0.004)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "bouc_wen", "generate_i", "recruited"]
