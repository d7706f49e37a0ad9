"""A twenty-eighth generator family for the diagnosis, written (2026-12-07, thirty-seventh stop) after the twenty-seventh
family's run and before any further engine change, nothing diagnosed on it; to be run once on the next change's frozen
engine.

The second to twenty-seventh families (:mod:`benchmarks.family_b_truth` … ``family_aa_truth``) are development data
once run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes` (its Dahl friction rules that out here). Near relations, stated: the foam
liner's give saturates like the twenty-seventh family's locking strap (there a tanh); the charge amplifier's leak
follows the torque through a lag like the twenty-fifth family's self-heating (there the squared torque, rising);
damping that changes along the range (the twentieth's and twenty-sixth's, there linear in the angle). Nothing is
imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth` and the scaffolding of :mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range Demiray's (1972) exponential strain-energy law in uniaxial tension,
  a·e^{b(I₁ − 3)/2}·(λ² − 1/λ), I₁ = λ² + 2/λ, the stretch λ = 1 + x̄/L (x̄ the softplus of the angle past an onset
  over 1–3°, L 0.7–2 × the end's reach, b 0.3–1.5); the steep end sized by its torque at the range's end, the onset
  toward a two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a leaf wrapping onto a
  curved former, its free length shortening as it bends, stiffness k₀/(1 − θ/θ_f)³ (θ_f 40–80°) past an engagement
  of 0.5–2° (softplus).
- Motion: preconditioning strokes of growing amplitude: 4–6 cycles about the range's middle, the first covering
  50–70 % of the range, the last all of it; each stroke at a constant 3–7 °/s reached and left through a smoothstep
  speed change of 0.2–0.5 s; a 0.5–1.5 s hold at the start. The AFO: 5–8 bends to 10–20°, loaded over 1.5–3 s,
  held 0.3–1 s at the top, released over 0.5–1.2 s (smoothstep), rested 0.3–1 s at 0–1°.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a seal in stick-slip, its Coulomb level tanh(v/ε) (ε 0.2–0.5 °/s) carrying a sawtooth of 1–4 Hz while
    it slides (the force building as the seal sticks and dropping as it slips, 30–60 % peak to peak); magnitude: its
    mean |F| over the moving samples;
  * damping: a squeeze film whose gap closes toward either end of the range, b₀·θ̇/(1 − s·u²)^{3/2} (u from −1 to 1
    along the range, s 0.6–0.85); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a stack of Belleville (disc) springs, Almen and László's law δ[(h − δ)(h − δ/2) + 1] in the washer's
    thickness (h 0.4–1.2: degressive through its travel) over 0.3–1° per unit, then solid (5–10 × its first
    stiffness) once flat, anywhere in the last 5–30 % of either end of a joint's range (the AFO's at the top of its
    bend); named only;
  * delay: a send-on-delta logger (a new value sent when the torque has moved 0.3–1 × the noise SD from the last
    sent, or 50–100 ms after it) behind a transport latency of 0.03–0.45 s; magnitude: the latency plus the held
    value's age weighted by the torque's squared rate (the lag a least-squares shift sees);
  * activation: a beta-density pulse u^{p−1}(1 − u)^{q−1} over 0.5–2.5 s (p, q 2–5: skewed either way), anywhere in
    10–85 % of the trial, of either sign; magnitude: its peak;
  * limb-weight error: the joint's instantaneous centre of rotation rolling with the angle (the femoral condyles'
    roll-back; the talus's), the segment's weight acting at a lever off by e·u (u from −1 to 1 along the range): its
    moment error ∝ u·cos ψ; magnitude: its peak;
  * drift: a piezoelectric torque sensor's charge leaking away: the torque's own history through a first-order lag
    of 20–80 s, subtracted from the zero set at the start; named only;
  * series compliance: a foam liner under the cuff that bottoms out, its give c·τ_d·(1 − e^{−|τ|/τ_d})·sgn τ
    (τ_d 0.4–1 × the largest torque); magnitude: the least-squares slope of the give on the torque;
  * inertia error: a centrifugal flyweight accessory, its inertia J(ω) = J₀(1 + g(ω/ω_max)²) (g 0.3–1), its torque
    d(Jω)/dt = J₀·θ̈·(1 + 3g(ω/ω_max)²); magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise plus a neighbouring treadmill's
  interference (a sinusoid of 0.5–2 Hz at 0.2–0.4 × the noise SD); the torque ADC's integral non-linearity (a cubic
  of ±0.2–0.5 % of its full scale); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast
  or slow by up to 0.02 % with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %,
  time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

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

NOISE_SD_NM = {"afo": 0.065, "knee": 0.16, "ankle": 0.12}
#: how far (deg) an end's onset moves per degree of the other joint's angle away from its middle setting
COUPLING_SHIFT = (0.05, 0.2)


def demiray_end(x_deg: np.ndarray, onset_smoothing_deg: float, reach_deg: float, b: float) -> np.ndarray:
    """An end per unit a following Demiray's (1972) law in uniaxial tension, e^{b(I₁ − 3)/2}·(λ² − 1/λ) (zero at
    λ = 1), I₁ = λ² + 2/λ, the stretch λ = 1 + x̄/L with x̄ = s·ln(1 + e^{x/s}) the softplus of the angle ``x_deg``
    past the onset over s = ``onset_smoothing_deg`` and L = ``reach_deg``."""
    x = np.asarray(x_deg, dtype=float) / onset_smoothing_deg
    stretch = 1.0 + onset_smoothing_deg * np.logaddexp(0.0, x) / reach_deg
    i1 = stretch**2 + 2.0 / stretch
    return np.asarray(np.exp(0.5 * b * (i1 - 3.0)) * (stretch**2 - 1.0 / stretch), dtype=float)


def leaf_on_former(deg: np.ndarray, engage_deg: float, smoothing_deg: float, former_deg: float) -> np.ndarray:
    """An orthosis's leaf per unit initial stiffness wrapping onto a former: the torque ∫k₀/(1 − θ/θ_f)³ dθ =
    θ_f/2·((1 − θ̄/θ_f)^{−2} − 1) for θ̄ the softplus (over ``smoothing_deg``) of the bend past ``engage_deg`` (deg);
    θ_f = ``former_deg`` (> the largest bend)."""
    d = np.asarray(deg, dtype=float) - engage_deg
    bend = smoothing_deg * (np.logaddexp(0.0, d / smoothing_deg) - np.logaddexp(0.0, -engage_deg / smoothing_deg))
    bend = np.clip(bend, 0.0, 0.95 * former_deg)
    return np.asarray(0.5 * former_deg * ((1.0 - bend / former_deg) ** -2 - 1.0), dtype=float)


def smoothstep_stroke(a: float, b: float, speed: float, change_s: float, rate: float) -> np.ndarray:
    """One stroke (deg, excluding its start) from ``a`` to ``b`` at ``speed`` °/s, the speed rising from and falling
    to zero along a smoothstep (3s² − 2s³) over ``change_s`` each (shortened on a short stroke), scaled to end at
    ``b`` exactly."""
    distance = abs(b - a)
    change = min(change_s, distance / speed)
    cruise = max(distance / speed - change, 0.0)
    n = max(2, int(np.ceil((cruise + 2.0 * change) * rate)))
    tt = np.arange(1, n + 1) / rate
    total = cruise + 2.0 * change

    def step(u: np.ndarray) -> np.ndarray:
        s = np.clip(u, 0.0, 1.0)
        return s * s * (3.0 - 2.0 * s)

    profile = step(tt / change) * step((total - tt) / change)
    travel = np.cumsum(profile)
    return np.asarray(a + np.sign(b - a) * distance * travel / travel[-1], dtype=float)


def growing_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the range's middle, then 4–6 cycles of strokes about it, the first
    reaching 50–70 % of the range, the amplitude growing linearly to the whole range by the last cycle, each stroke at
    a constant 3–7 °/s reached through a smoothstep speed change of 0.2–0.5 s; back to the middle at the end."""
    speed, change = float(rng.uniform(3.0, 7.0)), float(rng.uniform(0.2, 0.5))
    cycles = int(rng.integers(4, 7))
    first = float(rng.uniform(0.5, 0.7))
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    at = mid
    for k in range(cycles):
        share = first + (1.0 - first) * k / (cycles - 1)
        for target in (mid + share * half, mid - share * half):
            parts.append(smoothstep_stroke(at, target, speed, change, rate))
            at = target
    parts.append(smoothstep_stroke(at, mid, speed, change, rate))
    return np.concatenate(parts)


def held_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 5–8 bends to 10–20° loaded over 1.5–3 s, held 0.3–1 s, released over
    0.5–1.2 s (smoothstep in angle) to 0–1° (0° after the last), rested 0.3–1 s."""
    parts = [np.zeros(int(0.5 * rate))]
    base = 0.0
    count = int(rng.integers(5, 9))
    for k in range(count):
        peak = float(rng.uniform(10.0, 20.0))
        back = 0.0 if k == count - 1 else float(rng.uniform(0.0, 1.0))
        for a, b, lo_s, hi_s in ((base, peak, 1.5, 3.0), (peak, back, 0.5, 1.2)):
            n = int(rng.uniform(lo_s, hi_s) * rate)
            s = np.arange(1, n + 1) / n
            parts.append(a + (b - a) * s * s * (3.0 - 2.0 * s))
            if b == peak:
                parts.append(np.full(int(rng.uniform(0.3, 1.0) * rate), peak))
        parts.append(np.full(int(rng.uniform(0.3, 1.0) * rate), back))
        base = back
    parts.append(np.zeros(int(0.5 * rate)))
    return np.concatenate(parts)


def stick_slip_friction(t: np.ndarray, vel_deg_s: np.ndarray, epsilon_deg_s: float, slip_hz: float,
                        depth: float) -> np.ndarray:
    """A seal's friction per unit mean level: tanh(v/ε)·(1 + d·(s − ½)) with s a sawtooth of ``slip_hz`` (rising
    from 0 to 1 as the seal sticks, dropping as it slips), d = ``depth`` peak to peak."""
    saw = np.mod(slip_hz * np.asarray(t, dtype=float), 1.0)
    return np.asarray(np.tanh(np.asarray(vel_deg_s, dtype=float) / epsilon_deg_s) * (1.0 + depth * (saw - 0.5)),
                      dtype=float)


def squeeze_film_damper(vel: np.ndarray, u: np.ndarray, squeeze: float) -> np.ndarray:
    """A squeeze film's torque per unit mid-range coefficient: θ̇/(1 − s·u²)^{3/2} (u ∈ [−1, 1] the position in the
    range, s = ``squeeze`` < 1)."""
    return np.asarray(np.asarray(vel, dtype=float) / (1.0 - squeeze * np.asarray(u, dtype=float) ** 2) ** 1.5,
                      dtype=float)


def belleville_stop(deg: np.ndarray, at_deg: float, high: bool, unit_deg: float, height: float, solid_ratio: float
                    ) -> np.ndarray:
    """A disc-spring stack per unit (toward the range's inside, positive at the high end): Almen and László's
    δ[(h − δ)(h − δ/2) + 1] in δ = depth/``unit_deg`` (h = ``height``), then solid past δ = h: a contact of
    ``solid_ratio`` × its first stiffness (h² + 1), joined over 0.1 unit; depth past ``at_deg``."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, None) / unit_deg
    flat = np.minimum(depth, height)
    spring = flat * ((height - flat) * (height - 0.5 * flat) + 1.0)
    join = 0.1
    solid = solid_ratio * (height**2 + 1.0) * join * (np.logaddexp(0.0, (depth - height) / join)
                                                      - np.logaddexp(0.0, -height / join))
    return np.asarray(sign * np.where(depth > 0.0, spring + solid, 0.0), dtype=float)


def send_on_delta(torque: np.ndarray, t: np.ndarray, threshold: float, heartbeat_s: float, latency_s: float
                  ) -> tuple[np.ndarray, float]:
    """(the torque as a send-on-delta logger passes it: a value sent when it has moved ``threshold`` from the last
    sent, or ``heartbeat_s`` after it, held between, then delivered ``latency_s`` late; the delay in s: the latency
    plus the held value's age averaged with the torque's squared rate as weight, the lag a least-squares shift
    sees)."""
    values = np.asarray(torque, dtype=float)
    sent_index = np.empty(values.size, dtype=int)
    last = 0
    for i in range(values.size):
        if abs(values[i] - values[last]) >= threshold or t[i] - t[last] >= heartbeat_s:
            last = i
        sent_index[i] = last
    held = values[sent_index]
    rate2 = np.gradient(values, t) ** 2
    age = float(np.sum(rate2 * (t - t[sent_index])) / max(float(np.sum(rate2)), 1e-300))
    late = np.interp(t - latency_s, t, held, left=held[0])
    return late, latency_s + age


def beta_pulse(t: np.ndarray, start_s: float, duration_s: float, p: float, q: float) -> np.ndarray:
    """A pulse per unit peak: u^{p−1}(1 − u)^{q−1} for u = (t − t₀)/T in [0, 1], zero outside (p, q > 1)."""
    u = (np.asarray(t, dtype=float) - start_s) / duration_s
    inside = (u > 0.0) & (u < 1.0)
    uc = np.clip(u, 1e-12, 1.0 - 1e-12)
    shape = np.where(inside, uc ** (p - 1.0) * (1.0 - uc) ** (q - 1.0), 0.0)
    return np.asarray(shape / max(float(np.max(shape)), 1e-300), dtype=float)


def rolling_centre(u: np.ndarray, direction_rad: np.ndarray) -> np.ndarray:
    """The weight's moment error per unit lever error of a centre of rotation rolling with the angle: u·cos ψ (u the
    position in the range from −1 to 1, ψ the segment's direction)."""
    return np.asarray(np.asarray(u, dtype=float) * np.cos(np.asarray(direction_rad, dtype=float)), dtype=float)


def charge_leak(torque: np.ndarray, t: np.ndarray, time_constant_s: float) -> np.ndarray:
    """A piezoelectric sensor's drift (N·m): minus the torque's history through a first-order lag of
    ``time_constant_s``, less its start (the zero set at the start)."""
    values = np.asarray(torque, dtype=float)
    lagged = np.empty(values.size)
    state = values[0]
    dt = np.diff(t, prepend=t[0])
    for i in range(values.size):
        state += (values[i] - state) * (1.0 - np.exp(-dt[i] / time_constant_s))
        lagged[i] = state
    return np.asarray(-(lagged - values[0]), dtype=float)


def foam_liner_give(torque: np.ndarray, compliance: float, bottom_nm: float) -> np.ndarray:
    """The liner's give (deg): ``compliance``·τ_d·(1 − e^{−|τ|/τ_d})·sgn τ, τ_d = ``bottom_nm``."""
    tau = np.asarray(torque, dtype=float)
    return np.asarray(compliance * bottom_nm * (1.0 - np.exp(-np.abs(tau) / bottom_nm)) * np.sign(tau), dtype=float)


def flyweight_torque(vel: np.ndarray, acc: np.ndarray, gain: float) -> np.ndarray:
    """A flyweight accessory's torque per unit rest inertia: d(Jω)/dt = θ̈·(1 + 3g(ω/ω_max)²), J = 1 + g(ω/ω_max)²,
    ω_max the trial's peak speed, g = ``gain``."""
    w = np.asarray(vel, dtype=float)
    ratio = w / max(float(np.max(np.abs(w))), 1e-12)
    return np.asarray(np.asarray(acc, dtype=float) * (1.0 + 3.0 * gain * ratio * ratio), dtype=float)


def adc_nonlinearity(torque: np.ndarray, full_scale_nm: float, share: float) -> np.ndarray:
    """The torque through an ADC with an integral non-linearity: τ + e·FS·(x³ − x)·(3√3/2) for x = τ/FS (the cubic's
    peak error on ±FS is e·FS, e = ``share``)."""
    x = np.asarray(torque, dtype=float) / full_scale_nm
    return np.asarray(torque + share * full_scale_nm * (x**3 - x) * 1.5 * np.sqrt(3.0), dtype=float)


def _position(deg: np.ndarray, bottom: float, top: float) -> np.ndarray:
    """The angle's position in the range, −1 at ``bottom`` to 1 at ``top`` (deg)."""
    return np.asarray((2.0 * np.asarray(deg, dtype=float) - bottom - top) / (top - bottom), dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        return c["k"] * leaf_on_former(deg, c["engage"], c["smooth"], c["former"])
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * demiray_end(on_low - deg, c["smooth"], c["reach_low"], c["b"])
            + c["a_high"] * demiray_end(deg - on_high, c["smooth"], c["reach_high"], c["b"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, smooth, former = float(rng.uniform(0.5, 2.0)), 0.5, float(rng.uniform(40.0, 80.0))
        return {"engage": engage, "smooth": smooth, "former": former,
                "k": float(rng.uniform(10.0, 25.0)) / float(leaf_on_former(np.array(15.0), engage, smooth, former))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(1.0, 3.0))
    reach_low = (on_low - lo) * float(rng.uniform(0.7, 2.0))
    reach_high = (hi - on_high) * float(rng.uniform(0.7, 2.0))
    b = float(rng.uniform(0.3, 1.5))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(demiray_end(np.array(on_low - lo), smooth, reach_low, b)),
            "a_high": t_high / float(demiray_end(np.array(hi - on_high), smooth, reach_high, b)),
            "reach_low": reach_low, "reach_high": reach_high, "b": b, "smooth": smooth,
            "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ab(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((28, 28, 28), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: growing_strokes(r, a, b, rate),
                                         lambda r: held_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)
    u = _position(deg, bottom, top)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a foam liner that bottoms out
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, bottom_nm = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.4, 1.0)) * tau_max
        joint_deg = behind_strap(deg, lambda d: foam_liner_give(_elastic(kind, d, fixed, coef), c_give, bottom_nm))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, bottom_Nm=bottom_nm)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the centre of rotation rolling with the angle
        unit = rolling_centre(u, load.direction_rad)
        error = size() * float(rng.choice([-1.0, 1.0])) * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = stick_slip_friction(t, np.degrees(vel), float(rng.uniform(0.2, 0.5)), float(rng.uniform(1.0, 4.0)),
                                   float(rng.uniform(0.3, 0.6)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        unit = squeeze_film_damper(vel, u, float(rng.uniform(0.6, 0.85)))
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        unit = flyweight_torque(vel, acc, float(rng.uniform(0.3, 1.0)))
        flyweights = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + flyweights
        truth["inertia"] = float(np.dot(acc, flyweights) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        unit_deg, height = float(rng.uniform(0.3, 1.0)), float(rng.uniform(0.4, 1.2))
        unit = belleville_stop(deg, at, high_end, unit_deg, height, float(rng.uniform(5.0, 10.0)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", washer_unit_deg=unit_deg)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.85)) * float(t[-1])
        peak = size()
        shape = beta_pulse(t, start, float(rng.uniform(0.5, 2.5)), float(rng.uniform(2.0, 5.0)),
                           float(rng.uniform(2.0, 5.0)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(burst_start_s=start)
    if "sensor_drift" in effects:
        leak = charge_leak(torque, t, float(rng.uniform(20.0, 80.0)))
        torque = torque + size() * leak / max(float(np.max(np.abs(leak))), 1e-12)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        torque, delay = send_on_delta(torque, t, float(rng.uniform(0.3, 1.0)) * sd, float(rng.uniform(0.05, 0.1)),
                                      float(rng.uniform(0.03, 0.45)))
        truth["time_delay"] = delay
    full_scale = 1.5 * max(float(np.max(np.abs(torque))), 1e-9)
    torque = adc_nonlinearity(torque, full_scale, float(rng.uniform(0.002, 0.005)))
    hum = float(rng.uniform(0.2, 0.4)) * sd * np.sin(2.0 * np.pi * float(rng.uniform(0.5, 2.0)) * t
                                                      + float(rng.uniform(0.0, 2.0 * np.pi)))
    torque = (torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + rng.normal(0.0, sd, t.size) + hum
              + rng.uniform(-1.0, 1.0))
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "adc_nonlinearity", "belleville_stop",
           "beta_pulse", "charge_leak", "demiray_end", "flyweight_torque", "foam_liner_give", "generate_ab",
           "growing_strokes", "held_bends", "leaf_on_former", "rolling_centre", "send_on_delta", "smoothstep_stroke",
           "squeeze_film_damper", "stick_slip_friction"]
