"""A fifteenth generator family for the diagnosis, written after the fourteenth's run, before the engine change of its
round, and run once on that change's frozen engine.

The second to fourteenth families (:mod:`benchmarks.family_b_truth` … ``family_n_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses (checked against their
docstrings and :mod:`analysis.diagnosis.causes` before it was run; the near relations are said at each cause).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
segments' draw, the recording's damage and the protocol's set-up of :mod:`benchmarks.family_scaffold`).

- Passive moment: one tissue resisting each end of a joint's range, its stress following Ogden's one-term
  hyperelastic law in uniaxial tension, (2μ/α)·(λ^{α−1} − λ^{−α/2−1}) (α 6–14), its stretch λ = 1 + x̄/L from the
  angle past an onset smoothed over a normally distributed slack, x̄ = x·Φ(x/w) + w·φ(x/w) (w 2–6°: fibres taut at
  angles spread about the onset; the tenth family recruited fibres one by one from a table, the fourteenth smoothed
  its AFO's onset along a hyperbola), the onset toward a two-joint muscle moved by the other joint's angle, plus a
  small linear term. The AFO: a polypropylene shell yielding by Ramberg and Osgood's law, the bend b (past an
  engagement smoothed the same way) given by the torque τ as b = (τ/k)·(1 + a·(τ/τ_y)^{n−1}) (a 0.3–1, n 3–6,
  τ_y 40–80 % of its torque at a 15° bend) and solved for τ (the fourteenth family's shell softened as a tanh of the
  bend; this one is linear at small bends and yields as a power of its torque).
- Motion: two-speed strokes: slow (3–6 °/s) through the outer thirds of the range, fast (10–20 °/s) through the middle
  third, the speed a smooth function of the angle (raised-cosine transitions), easing into each end over 1–3°, with
  dwells of 0.2–1 s; 2–4 cycles (earlier families changed speed between cycles or wandered in time, never by angle).
  The AFO: hand bends to 12–20° (raised-cosine loading over 1–2.5 s), a hold at the peak during which the operator's
  push creeps the bend on by 0.5–1.5° (exponentially over 0.3–0.8 s), a release of 0.5–1.5 s and a rest of 0.3–1 s;
  4–6 bends.
- Limb: segment parameters drawn per trial (the fourteenth family's spread: family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing whose breakaway grows with the time it rested (stiction ageing), the level after a rest of
    t_r at F·(1 + a·ln(1 + t_r/t₀)) (a 0.3–0.6, t₀ 0.1–0.5 s) falling back to F over the first 0.5–2° travelled (a
    displacement decay, not a Stribeck speed), its sign an algebraic sigmoid θ̇/√(θ̇² + v_ε²) (v_ε 0.3–1 °/s; the
    tenth family's rate-and-state ageing acted through a state variable in speed); magnitude: its mean level over
    the moving samples;
  * damping: a hydraulic damper with a relief valve: b·θ̇ up to a cracking speed v_c (30–70 % of the trial's peak
    speed), then a slope of 10–30 % of b beyond (a kink in speed; the seventh family's saturation was smooth);
    magnitude: the least-squares coefficient of its torque on θ̇ over the moving samples;
  * stop: an end stop behind a slipping clutch (a torque limiter): linear in its compression up to a slip torque
    reached after 1–4°, flat beyond, anywhere in the last third of either end of a joint's range (the AFO's at the
    top of its bend); named only;
  * delay: the torque through a Chebyshev type-I low-pass (order 2–3, pass-band ripple 0.5–2 dB, cut-off 3–15 Hz,
    unit gain at DC as a calibrated channel has) behind a transport delay of 0–0.4 s (earlier families' filters were
    Butterworth, Bessel, boxcar, sinc³, a median, first- and second-order sections, none rippled); magnitude: the
    total group delay at low frequency;
  * activation: a Weibull-shaped pulse, (t/λ)^{k−1}·e^{−(t/λ)^k} normalised to its peak (k 1.5–3, λ 0.2–0.8 s), of
    either sign; magnitude: its peak;
  * limb-weight error: the dynamometer's gravity compensation set with the segment's direction off by 5–20°, so
    the weight moment it removes is m·g·r·cos(ψ + δ) for the true m·g·r·cos(ψ) (an error of the shape
    cos(ψ + δ) − cos(ψ)); magnitude: its peak moment error;
  * drift: the zero shifting once along a logistic curve (10–90 % in 10–40 s, centred 20–80 % through the trial),
    as a bridge does when the room's humidity changes; named only;
  * series compliance: a strap preloaded by its buckle: no give below a preload torque (0.5–2 N·m, or 10–25 % of
    the AFO's peak), then c·(|τ| − τ_p) (a dead zone in torque; the sixth family's dead band was in angle);
    magnitude: the least-squares slope of its give on the torque (°/N·m);
  * inertia error: a mass clipped to the attachment partway through (30–70 % of the trial), counterweighted, its
    ΔI·θ̈ from then on; magnitude: the least-squares coefficient of its torque on θ̈ over the trial.
- Nuisances: 100–1000 Hz; white noise plus the motor's PWM beat, a chirp sweeping 5–20 Hz over the trial
  (0.3–0.6 × the noise SD); a torque ADC that sticks now and then (0–0.5 % of rows start a hold of 2–10 samples);
  a torque gain error of ±1.5 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter;
  dropped rows singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle
  offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import cheby1, group_delay, lfilter, lfilter_zi
from scipy.special import ndtr

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


def smooth_excess(x: np.ndarray, width: float) -> np.ndarray:
    """The mean of (x − s)₊ over a slack s normally distributed about 0 with SD ``width``: x·Φ(x/w) + w·φ(x/w)."""
    z = np.asarray(x, dtype=float) / width
    return np.asarray(x) * ndtr(z) + width * np.exp(-0.5 * z * z) / np.sqrt(2.0 * np.pi)


def ogden_stress(stretch: np.ndarray, alpha: float) -> np.ndarray:
    """Ogden's one-term uniaxial stress per unit 2μ/α at ``stretch`` λ (zero at λ ≤ 1): λ^{α−1} − λ^{−α/2−1}."""
    lam = np.maximum(np.asarray(stretch, dtype=float), 1.0)
    return lam ** (alpha - 1.0) - lam ** (-alpha / 2.0 - 1.0)


def ramberg_osgood_torque(bend: np.ndarray, k: float, yield_nm: float, a: float, n: float) -> np.ndarray:
    """The torque τ ≥ 0 (N·m) of a shell bent by ``bend`` ≥ 0 (deg) when b = (τ/k)·(1 + a·(τ/τ_y)^{n−1}): solved by
    bisection (the right side is increasing in τ)."""
    b = np.maximum(np.asarray(bend, dtype=float), 0.0)
    lo, hi = np.zeros_like(b), k * b + 1e-12  # the linear torque bounds it from above
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        too_big = mid / k * (1.0 + a * (mid / yield_nm) ** (n - 1.0)) > b
        hi, lo = np.where(too_big, mid, hi), np.where(too_big, lo, mid)
    return 0.5 * (lo + hi)


def two_speed_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The commanded angle (deg): strokes between ``lo`` and ``hi``, slow (3–6 °/s) through the outer thirds, fast
    (10–20 °/s) through the middle third (raised-cosine transitions over a tenth of the range), easing into each end
    over 1–3° (the speed falling as the square root of the distance left, to a floor of 0.3 °/s), dwells of
    0.2–1 s at each end; 2–4 cycles."""
    slow, fast = float(rng.uniform(3.0, 6.0)), float(rng.uniform(10.0, 20.0))
    ease = float(rng.uniform(1.0, 3.0))
    span = hi - lo
    grid = np.linspace(lo, hi, 4001)
    u = (grid - lo) / span

    def window(edge: float, rising: bool) -> np.ndarray:
        s = np.clip((u - edge) / 0.1 + 0.5, 0.0, 1.0)
        w = 0.5 - 0.5 * np.cos(np.pi * s)
        return w if rising else 1.0 - w

    middle = window(1.0 / 3.0, True) * window(2.0 / 3.0, False)
    speed = slow + (fast - slow) * middle
    to_end = np.minimum(grid - lo, hi - grid)
    speed = speed * np.clip(np.sqrt(to_end / ease), 0.0, 1.0)
    speed = np.maximum(speed, 0.3)
    # time at each grid angle going up (trapezoidal dt = dθ / v)
    dt = np.diff(grid) / (0.5 * (speed[1:] + speed[:-1]))
    t_up = np.concatenate([[0.0], np.cumsum(dt)])
    parts = []
    for _ in range(int(rng.integers(2, 5))):
        for up in (True, False):
            parts.append(np.full(int(rng.uniform(0.2, 1.0) * rate), lo if up else hi))
            t = np.arange(0.0, t_up[-1], 1.0 / rate)
            stroke = np.interp(t, t_up, grid)
            parts.append(stroke if up else lo + hi - stroke)
    parts.append(np.full(int(rng.uniform(0.2, 1.0) * rate), lo))
    return np.concatenate(parts)


def creeping_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 4–6 bends to 12–20°, each loaded along a raised cosine over 1–2.5 s, held while the bend creeps
    on by 0.5–1.5° (exponentially, time constant 0.3–0.8 s, held 1–2 s), released along a raised cosine over
    0.5–1.5 s, rests of 0.3–1 s."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 7))):
        peak, creep = float(rng.uniform(12.0, 18.5)), float(rng.uniform(0.5, 1.5))
        up = np.linspace(0.0, 1.0, int(rng.uniform(1.0, 2.5) * rate))
        hold_t = np.arange(1, int(rng.uniform(1.0, 2.0) * rate) + 1) / rate
        held = peak + creep * (1.0 - np.exp(-hold_t / float(rng.uniform(0.3, 0.8))))
        down = np.linspace(0.0, 1.0, int(rng.uniform(0.5, 1.5) * rate))
        parts += [peak * (0.5 - 0.5 * np.cos(np.pi * up)), held, float(held[-1]) * (0.5 + 0.5 * np.cos(np.pi * down)),
                  np.zeros(int(rng.uniform(0.3, 1.0) * rate))]
    return np.concatenate(parts)


def aged_friction(t: np.ndarray, vel_deg_s: np.ndarray, deg: np.ndarray, ageing: float, age_scale_s: float,
                  decay_deg: float, v_eps_deg_s: float) -> np.ndarray:
    """A friction per unit kinetic level (resisting increasing angle) whose breakaway after a rest of t_r is
    1 + a·ln(1 + t_r/t₀), falling back to 1 over the first ``decay_deg`` travelled (e^{−travel/decay}); the sign an
    algebraic sigmoid θ̇/√(θ̇² + v_ε²). A rest: |θ̇| below 0.2 °/s."""
    resting = np.abs(vel_deg_s) < 0.2
    level = np.ones(t.size)
    rest_start, excess, moved_from = float(t[0]), 0.0, float(deg[0])
    was_resting = bool(resting[0])
    for i in range(t.size):
        if resting[i]:
            if not was_resting:
                rest_start = float(t[i])
            was_resting = True
            continue
        if was_resting:  # a start: the breakaway this rest earned
            excess, moved_from = ageing * float(np.log1p((float(t[i]) - rest_start) / age_scale_s)), float(deg[i])
            was_resting = False
        level[i] = 1.0 + excess * float(np.exp(-abs(float(deg[i]) - moved_from) / decay_deg))
    return level * vel_deg_s / np.sqrt(vel_deg_s**2 + v_eps_deg_s**2)


def relief_valve_damper(vel: np.ndarray, cracking: float, slope_after: float) -> np.ndarray:
    """A damper's torque per unit coefficient: θ̇ up to ``cracking`` (same units), then the cracking value plus
    ``slope_after`` × the speed beyond it, odd in θ̇."""
    speed = np.abs(vel)
    return np.sign(vel) * np.where(speed <= cracking, speed, cracking + slope_after * (speed - cracking))


def clutch_stop(deg: np.ndarray, at_deg: float, high: bool, slip_deg: float) -> np.ndarray:
    """An end stop behind a slipping clutch, per unit slip torque (toward the range's inside, positive at the high
    end): its compression past the stop over ``slip_deg``, clipped at 1."""
    sign = 1.0 if high else -1.0
    return sign * np.clip(sign * (deg - at_deg) / slip_deg, 0.0, 1.0)


def chebyshev_channel(x: np.ndarray, rate: float, order: int, ripple_db: float, cutoff_hz: float
                      ) -> tuple[np.ndarray, float]:
    """``x`` through a Chebyshev type-I low-pass at ``rate`` Hz, its gain at DC made 1 (an even order's sits at the
    bottom of its ripple: a calibrated channel reads a steady torque right), started at rest on ``x[0]``; returns
    (the output, its group delay at low frequency in s)."""
    b, a = cheby1(order, ripple_db, cutoff_hz, fs=rate)
    b = b * (np.sum(a) / np.sum(b))
    y, _ = lfilter(b, a, x, zi=lfilter_zi(b, a) * float(x[0]))
    _, gd = group_delay((b, a), w=[1e-4], fs=rate)
    return y, float(gd[0]) / rate


def weibull_pulse(t: np.ndarray, onset_s: float, shape: float, scale_s: float) -> np.ndarray:
    """A Weibull density's shape from ``onset_s``, (u/λ)^{k−1}·e^{−(u/λ)^k}, normalised to peak 1 (k > 1)."""
    u = np.clip(t - onset_s, 0.0, None) / scale_s
    y = u ** (shape - 1.0) * np.exp(-(u**shape))
    return y / float(np.max(y))


def logistic_shift(t: np.ndarray, centre_s: float, rise_s: float) -> np.ndarray:
    """A unit step along a logistic curve rising from 10 % to 90 % in ``rise_s`` about ``centre_s``."""
    z = np.clip((t - centre_s) * 2.0 * np.log(9.0) / rise_s, -60.0, 60.0)
    return 1.0 / (1.0 + np.exp(-z))


def preloaded_give(torque: np.ndarray, preload: float) -> np.ndarray:
    """A strap's give per unit compliance: zero below the ``preload`` torque, (|τ| − preload) beyond, with τ's sign."""
    return np.sign(torque) * np.maximum(np.abs(torque) - preload, 0.0)


def stuck_adc(rng: np.random.Generator, x: np.ndarray, share: float) -> np.ndarray:
    """``x`` with 0–``share`` of its samples starting a hold: the value repeated for the next 2–10 samples."""
    y = x.copy()
    for start in np.flatnonzero(rng.random(x.size) < rng.uniform(0.0, share)):
        y[start:start + int(rng.integers(2, 11))] = x[start]
    return y


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        bend = smooth_excess(deg - c["engage"], c["soft"])
        return ramberg_osgood_torque(bend, c["k"], c["yield"], c["a"], c["n"])
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)

    def end(x: np.ndarray, which: str) -> np.ndarray:
        return ogden_stress(1.0 + smooth_excess(x, c[f"w_{which}"]) / c[f"len_{which}"], c[f"alpha_{which}"])

    low_ref = float(end(np.array(c["on_low"] - c["lo"]), "low"))
    high_ref = float(end(np.array(c["hi"] - c["on_high"]), "high"))
    return (-c["t_low"] * end(on_low - deg, "low") / low_ref + c["t_high"] * end(deg - on_high, "high") / high_ref
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, soft = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.5, 2.0))
        a, n = float(rng.uniform(0.3, 1.0)), float(rng.uniform(3.0, 6.0))
        tau15, share = float(rng.uniform(10.0, 25.0)), float(rng.uniform(0.4, 0.8))
        bend15 = float(smooth_excess(np.array(15.0 - engage), soft))
        # k from the torque at 15°: 15°-bend = (τ15/k)·(1 + a·(1/share)^{n−1})
        k = tau15 / bend15 * (1.0 + a * (1.0 / share) ** (n - 1.0))
        return {"k": k, "yield": share * tau15, "a": a, "n": n, "engage": engage, "soft": soft}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    out: dict[str, Any] = {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
                           "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
                           "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
                           "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}
    for which, reach in (("low", on_low - lo), ("high", hi - on_high)):
        # the stretch the end reaches at the range's end: 1.15–1.5
        out[f"alpha_{which}"] = float(rng.uniform(6.0, 14.0))
        out[f"w_{which}"] = float(rng.uniform(2.0, 6.0))
        out[f"len_{which}"] = reach / float(rng.uniform(0.15, 0.5))
    return out


def generate_o(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((15, 15, 15), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: two_speed_strokes(r, a, b, rate),
                                         lambda r: creeping_bends(r, rate))
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
    if "series_compliance" in effects:  # a preloaded strap: give = c·(|τ| − τ_p)₊ with τ's sign
        c_give = float(rng.uniform(0.03, 0.15))
        peak = float(np.max(np.abs(_passive(kind, deg, fixed, coef))))
        preload = float(rng.uniform(0.5, 2.0)) if kind != "afo" else float(rng.uniform(0.1, 0.25)) * peak
        for _ in range(3):  # the joint turns by the angle less the give, which depends on the torque it meets
            joint_deg = deg - c_give * preloaded_give(_passive(kind, joint_deg, fixed, coef), preload)
        tau_j = _passive(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, preload_Nm=preload)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    weight, inertia, amplitude, psi = load.moment_nm, load.inertia_kgm2, load.amplitude_nm, load.direction_rad
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # the device's gravity compensation computed with the segment's direction off by δ
        delta = float(rng.uniform(5.0, 20.0)) * float(rng.choice([-1.0, 1.0]))
        unit = np.cos(psi + np.radians(delta)) - np.cos(psi)
        sign = -1.0 if kind == "knee" else 1.0
        error = sign * size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(compensation_direction_error_deg=delta, weight_moment_amplitude_Nm=amplitude)
    if "coulomb_friction" in effects:
        unit = aged_friction(t, vel_deg, deg, float(rng.uniform(0.3, 0.6)), float(rng.uniform(0.1, 0.5)),
                             float(rng.uniform(0.5, 2.0)), float(rng.uniform(0.3, 1.0)))
        f0 = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(np.abs(unit[moving])))
    if "viscous_damping" in effects:
        cracking = float(rng.uniform(0.3, 0.7)) * float(np.max(np.abs(vel)))
        slope_after = float(rng.uniform(0.1, 0.3))
        unit = relief_valve_damper(vel, cracking, slope_after)
        b = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + b * unit
        v_m, u_m = vel[moving], b * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(damper_cracking_rad_s=cracking, damper_slope_after=slope_after)
    if "inertia" in effects:
        clip_at = float(t[0]) + float(rng.uniform(0.3, 0.7)) * float(t[-1] - t[0])
        unit = np.where(t >= clip_at, acc, 0.0)
        d_inertia = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(clipped_on_s=clip_at, clipped_inertia_kgm2=d_inertia)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        slip = float(rng.uniform(1.0, 4.0))
        torque = torque + size() * clutch_stop(deg, at, high, slip)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", clutch_slip_deg=slip)
    if "activation_burst" in effects:
        shape, scale = float(rng.uniform(1.5, 3.0)), float(rng.uniform(0.2, 0.8))
        onset = float(rng.uniform(0.1, 0.75)) * float(t[-1])
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * weibull_pulse(t, onset, shape, scale)
        truth["activation_burst"] = peak
        details.update(pulse_onset_s=onset, pulse_shape=shape, pulse_scale_s=scale)
    if "sensor_drift" in effects:
        centre = float(rng.uniform(0.2, 0.8)) * float(t[-1])
        rise = float(rng.uniform(10.0, 40.0))
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * logistic_shift(t, centre, rise)
        truth["sensor_drift"] = None
        details.update(drift_centre_s=centre, drift_rise_s=rise)
    if "time_delay" in effects:
        transport = float(rng.uniform(0.0, 0.4))
        order, ripple, cutoff = int(rng.integers(2, 4)), float(rng.uniform(0.5, 2.0)), float(rng.uniform(3.0, 15.0))
        torque, filter_delay = chebyshev_channel(torque, rate, order, ripple, cutoff)
        torque = np.interp(t - transport, t, torque)
        truth["time_delay"] = transport + filter_delay
        details.update(transport_s=transport, filter_order=order, filter_ripple_db=ripple, filter_cutoff_hz=cutoff,
                       filter_delay_s=filter_delay)
    noise = rng.normal(0.0, sd, t.size)
    f0, f1 = 5.0, 20.0  # the PWM beat's chirp, Hz
    duration = max(float(t[-1]), 1e-9)
    phase = 2.0 * np.pi * (f0 * t + 0.5 * (f1 - f0) / duration * t * t) + float(rng.uniform(0.0, 2.0 * np.pi))
    noise += float(rng.uniform(0.3, 0.6)) * sd * np.sin(phase)
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    torque = stuck_adc(rng, torque, 0.005)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "aged_friction", "chebyshev_channel",
           "clutch_stop", "creeping_bends", "generate_o", "logistic_shift", "ogden_stress", "preloaded_give",
           "ramberg_osgood_torque", "relief_valve_damper", "smooth_excess", "stuck_adc", "two_speed_strokes",
           "weibull_pulse"]
