"""A fourteenth generator family for the diagnosis, written after the thirteenth's run, before the engine change of its
round, and run once on that change's frozen engine.

The second to thirteenth families (:mod:`benchmarks.family_b_truth` … ``family_m_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses (checked against their
docstrings and :mod:`analysis.diagnosis.causes` before it was run; the near relations are said at each cause).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
recording's damage and the protocol's set-up of :mod:`benchmarks.family_scaffold`).

- Passive moment: one muscle group resisting each end of a joint's range, its fibres following Blemker et al.'s
  (2005) passive law, exponential in stretch up to a transition and linear beyond it with the same slope
  (F ∝ e^s − 1, then e^{s*}·(s − s*) + e^{s*} − 1: the stiffening *rate* falls past the transition, where every
  earlier family's end kept or grew its rate), on a moment arm that varies along the range as
  r₀·(1 + a·sin(πu)) (a 0.2–0.6, u 0 → 1 from one end of the range to the other; the third family's muscles had
  constant arms and Thelen's exponential), the onset toward a two-joint muscle moved by the other joint's angle,
  plus a small linear term. The AFO: a thermoplastic shell that softens as it yields,
  k·((1 − q)·b + q·b_y·tanh(b/b_y)) of the bend b past an engagement reached along a hyperbola (q 0.2–0.5, b_y
  4–10°: its torque grows less than in proportion to the bend; earlier families' AFO springs stiffened or stayed
  linear).
- Motion: a quasi-static staircase (ramp-and-hold): steps of 5–15° at 5–20 °/s along a cosine speed profile, each
  held 0.5–2 s, up the range and down again, 2–3 cycles (the fifth family paused once mid-sweep; no family stepped
  through the range). The AFO: a calibration series, bends of growing amplitude (peaks rising from 8° to 18–20° in
  4–7 steps), each loaded and released along a sin² profile over 1–3 s, rests of 0.3–1 s.
- Limb: segment parameters drawn per trial (shank 4.3–4.8 % of body mass, its centre 40–44 % down from the knee,
  radius of gyration 28–31 % of its length; foot 1.2–1.5 %, 42–48 %, 23–27 %).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: grease warming with the work done: a Coulomb level fading with the angle travelled,
    F₀·(1 − r·(1 − e^{−travel/Θ})) (r 0.3–0.6, Θ one to three strokes' travel), its sign a saturation
    clip(θ̇/v_ε, −1, 1) (v_ε 0.2–1 °/s; the ninth family's thixotropic *damping* fell with travel, no friction did;
    the engine's laws are smooth tanh-like signs); magnitude: its mean level over the moving samples;
  * damping: a dashpot behind a linkage with backlash (0.5–3°): after each reversal it is slack until the joint has
    turned through the backlash, then b·θ̇ (the eleventh family's damping differed by direction, not by travel since
    a reversal); magnitude: the least-squares coefficient of its torque on θ̇ over the moving samples;
  * stop: a check strap, a cable across the joint slack until the stop angle, then stretched by a chord's change
    ∝ sin(θ/2 + ψ) − sin(θ_s/2 + ψ) on a moment arm ∝ cos(θ/2 + ψ) (geometry, not a contact law), anywhere in the
    last third of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: the torque sensor on a compliant mount, a second-order response (natural frequency 2–8 Hz, damping ratio
    0.3–0.7: it rings) behind a transport delay of 0–0.3 s (the seventh family's Bessel filter did not ring, the
    fifth's rig resonance was noise at 15–40 Hz); magnitude: the total group delay at low frequency;
  * activation: a startle: a logistic onset (10–90 % in 4.4·r, r 0.01–0.04 s) and an exponential relaxation
    (τ 0.2–0.8 s) from one instant, A·σ((t − t₀)/r)·e^{−(t − t₀)₊/τ}, of either sign (the second family's EMG
    envelope rose as t² and fell as a gamma density); magnitude: its peak;
  * limb-weight error: the dynamometer's axis off the joint's by a fixed offset (1–4 cm at sizes 3–5 × the noise) in
    a drawn direction, so the segment's weight acts on a lever arm off by e·cos(ψ + φ) (φ any direction: the error
    is the weight moment's shape shifted in phase, not scaled); magnitude: its peak moment error;
  * drift: a cable winding up: the zero moves by c per degree travelled and relaxes back with τ 20–60 s
    (dz/dt = c·|θ̇| − z/τ), of either sign (the tenth family's motor warmed with the mechanical power, a function of
    torque; this one follows the travel alone); named only;
  * series compliance: a strap whose give follows the torque through a play operator (a hysteron of width 0.5–2 N·m:
    the give changes only once the torque has reversed by the play), give = c·play(τ); magnitude: the
    least-squares slope of its give on the torque (°/N·m);
  * inertia error: an attachment draining over the trial (a fluid-filled boot), J(t) = J₀·(1 − r·t/T)
    (r 0.3–0.6), its torque J(t)·θ̈ + J′(t)·θ̇; magnitude: the least-squares coefficient of its torque on θ̈.
- Nuisances: 100–1000 Hz; white noise plus physiological artefacts: a heartbeat (a train of 60–120 ms bumps at
  1.0–1.6 Hz, 0.3–0.6 × the noise SD) and breathing (a 0.2–0.35 Hz sinusoid, 0.2–0.5 × the noise SD); a torque gain
  error of ±1.5 %; quantised torque and angle; the clock fast or slow by up to 0.02 % with jitter; dropped rows
  singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import bilinear, group_delay, lfilter, lfilter_zi

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


def blemker_fibre(s: np.ndarray, transition: float) -> np.ndarray:
    """Blemker's passive fibre force per unit scale at normalised stretch ``s`` (zero when slack, s ≤ 0):
    e^s − 1 up to ``transition``, then linear with the slope it has there."""
    s = np.clip(s, 0.0, None)
    e_t = float(np.exp(transition))
    return np.where(s <= transition, np.expm1(np.minimum(s, transition)), e_t - 1.0 + e_t * (s - transition))


def staircase(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The commanded angle (deg): up from ``lo`` to ``hi`` and down again in steps of 5–15° at 5–20 °/s (cosine speed
    profile within each step), each held 0.5–2 s; 2–3 cycles."""
    out = [np.full(int(rng.uniform(0.5, 2.0) * rate), lo)]
    for _ in range(int(rng.integers(2, 4))):
        for a, b in ((lo, hi), (hi, lo)):
            here = a
            while abs(b - here) > 1e-9:
                step = min(float(rng.uniform(5.0, 15.0)), abs(b - here))
                target = here + np.sign(b - here) * step
                n = max(int(step / float(rng.uniform(5.0, 20.0)) * rate), 2)
                u = np.linspace(0.0, 1.0, n)
                out.append(here + (target - here) * 0.5 * (1.0 - np.cos(np.pi * u)))
                out.append(np.full(int(rng.uniform(0.5, 2.0) * rate), target))
                here = target
    return np.concatenate(out)


def growing_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg) of growing amplitude: peaks from 8° to 18–20° in 4–7 steps, each loaded and released along
    sin² over 1–3 s, rests of 0.3–1 s."""
    peaks = np.linspace(8.0, float(rng.uniform(18.0, 20.0)), int(rng.integers(4, 8)))
    parts = [np.zeros(int(0.4 * rate))]
    for peak in peaks:
        u = np.linspace(0.0, 1.0, int(rng.uniform(1.0, 3.0) * rate))
        parts += [float(peak) * np.sin(np.pi * u) ** 2, np.zeros(int(rng.uniform(0.3, 1.0) * rate))]
    return np.concatenate(parts)


def faded_friction(vel_deg_s: np.ndarray, travel_deg: np.ndarray, fade: float, travel_scale_deg: float,
                   v_eps_deg_s: float) -> np.ndarray:
    """A Coulomb friction per unit level fading with the angle travelled (resisting increasing angle):
    (1 − fade·(1 − e^{−travel/Θ}))·clip(θ̇/v_ε, −1, 1)."""
    level = 1.0 - fade * (1.0 - np.exp(-travel_deg / travel_scale_deg))
    return level * np.clip(vel_deg_s / v_eps_deg_s, -1.0, 1.0)


def backlash_dashpot(deg: np.ndarray, vel: np.ndarray, backlash_deg: float) -> np.ndarray:
    """Velocity (same units as ``vel``) a dashpot behind a linkage with ``backlash_deg`` of play feels: zero after each
    reversal of direction until the joint has turned through the play, ``vel`` after."""
    out = np.zeros_like(vel)
    direction, turn_at = 0.0, float(deg[0])
    for i in range(deg.size):
        d = float(np.sign(vel[i])) if abs(vel[i]) > 0.0 else 0.0
        if d != 0.0 and d != direction:
            direction, turn_at = d, float(deg[i])
        if direction != 0.0 and abs(float(deg[i]) - turn_at) >= backlash_deg:
            out[i] = vel[i]
    return out


def check_strap(deg: np.ndarray, at_deg: float, high: bool, skew_deg: float) -> np.ndarray:
    """A check strap's unit torque shape (toward the range's inside, positive at the high end): its stretch a chord's
    change past the stop, sin(θ/2 + ψ) − sin(θ_s/2 + ψ) (mirrored at the low end), times the moment arm cos(θ/2 + ψ)."""
    sign = 1.0 if high else -1.0
    x = np.radians(sign * (deg - at_deg))  # past the stop (rad), positive inside the strap's reach
    psi = np.radians(skew_deg)
    stretch = np.clip(np.sin(x / 2.0 + psi) - np.sin(psi), 0.0, None)
    return sign * stretch * np.cos(x / 2.0 + psi)


def mount_response(x: np.ndarray, rate: float, natural_hz: float, damping_ratio: float) -> tuple[np.ndarray, float]:
    """``x`` through a second-order sensor mount (bilinear transform at ``rate`` Hz), started at rest on ``x[0]``;
    returns (the output, its group delay at low frequency in s)."""
    w = 2.0 * np.pi * natural_hz
    b, a = bilinear([w * w], [1.0, 2.0 * damping_ratio * w, w * w], fs=rate)
    y, _ = lfilter(b, a, x, zi=lfilter_zi(b, a) * float(x[0]))
    _, gd = group_delay((b, a), w=[1e-4], fs=rate)
    return y, float(gd[0]) / rate


def startle(t: np.ndarray, onset_s: float, rise_s: float, relax_s: float) -> np.ndarray:
    """A logistic onset of scale ``rise_s`` and an exponential relaxation of ``relax_s`` from ``onset_s``, peak 1."""
    z = np.clip((t - onset_s) / rise_s, -60.0, 60.0)
    shape = 1.0 / (1.0 + np.exp(-z)) * np.exp(-np.clip(t - onset_s, 0.0, None) / relax_s)
    return shape / float(np.max(shape))


def cable_winding(t: np.ndarray, vel_deg_s: np.ndarray, relax_s: float) -> np.ndarray:
    """A zero that winds up by one unit per degree travelled and relaxes back with ``relax_s``: dz/dt = |θ̇| − z/τ."""
    z = np.zeros(t.size)
    for i in range(1, t.size):
        dt = float(t[i] - t[i - 1])
        a = np.exp(-dt / relax_s)
        z[i] = a * z[i - 1] + relax_s * (1.0 - a) * abs(float(vel_deg_s[i]))
    return z


def play_operator(x: np.ndarray, width: float) -> np.ndarray:
    """The play (backlash) hysteron of ``width``: its output follows ``x`` only once ``x`` has moved half the width
    past it, holding otherwise; started at ``x[0]``."""
    out = np.empty(x.size)
    y, half = float(x[0]), 0.5 * width
    for i, v in enumerate(x.tolist()):
        y = min(max(y, v - half), v + half)
        out[i] = y
    return out


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        x = deg - c["engage"]
        bend = 0.5 * (x + np.sqrt(x * x + c["soft"] ** 2))  # a hyperbola: smooth through the engagement
        return c["k"] * ((1.0 - c["q"]) * bend + c["q"] * c["yield"] * np.tanh(bend / c["yield"]))
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    lo, span = c["lo"], c["hi"] - c["lo"]

    def path(a: np.ndarray | float) -> np.ndarray:  # ∫ (1 + a·sin(πu)) dθ, deg
        return np.asarray(a) - c["arm_var"] * span / np.pi * np.cos(np.pi * (np.asarray(a) - lo) / span)

    def arm(a: np.ndarray) -> np.ndarray:
        return 1.0 + c["arm_var"] * np.sin(np.pi * np.clip((a - lo) / span, 0.0, 1.0))

    low = arm(deg) * blemker_fibre((path(on_low) - path(deg)) / c["scale_low"], c["trans_low"])
    high = arm(deg) * blemker_fibre((path(deg) - path(on_high)) / c["scale_high"], c["trans_high"])
    low_ref = float(arm(np.array(lo)) * blemker_fibre((path(c["on_low"]) - path(lo)) / c["scale_low"], c["trans_low"]))
    high_ref = float(arm(np.array(c["hi"])) * blemker_fibre((path(c["hi"]) - path(c["on_high"])) / c["scale_high"],
                                                            c["trans_high"]))
    return -c["t_low"] * low / low_ref + c["t_high"] * high / high_ref + c["linear"] * (deg - 0.5 * (lo + c["hi"]))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its moment at a 15° bend, 10–25 N·m
        engage, soft = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.5, 2.0))
        q, b_y = float(rng.uniform(0.2, 0.5)), float(rng.uniform(4.0, 10.0))
        x = 15.0 - engage
        bend15 = 0.5 * (x + np.sqrt(x * x + soft**2))
        unit15 = (1.0 - q) * bend15 + q * b_y * np.tanh(bend15 / b_y)
        return {"k": float(rng.uniform(10.0, 25.0)) / float(unit15), "engage": engage, "soft": soft, "q": q,
                "yield": b_y}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    arm_var = float(rng.uniform(0.2, 0.6))
    out: dict[str, Any] = {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
                           "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
                           "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
                           "arm_var": arm_var, "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}
    for end, reach in (("low", on_low - lo), ("high", hi - on_high)):
        # the normalised stretch the end reaches at the range's end (2.5–5) and the transition (50–85 % of it)
        s_end = float(rng.uniform(2.5, 5.0))
        path_reach = reach * (1.0 + 0.5 * arm_var)  # about the path length over the reach
        out[f"scale_{end}"] = path_reach / s_end
        out[f"trans_{end}"] = float(rng.uniform(0.5, 0.85)) * s_end
    return out


def generate_n(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((14, 14, 11), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: staircase(r, a, b, rate),
                                         lambda r: growing_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(deg)))])
    stroke_travel = 2.0 * (float(deg.max()) - float(deg.min())) if kind != "afo" else 2.0 * float(deg.max())

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap with play in its give: give = c·play(τ)
        c_give, width = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.5, 2.0))
        for _ in range(3):  # the joint turns by the angle less the give, which depends on the torque it meets
            give = c_give * play_operator(_passive(kind, joint_deg, fixed, coef), width)
            joint_deg = deg - give
        tau_j = _passive(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, play_Nm=width)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    weight, inertia, psi = load.moment_nm, load.inertia_kgm2, load.direction_rad
    seg_mass = load.shank_kg + load.foot_kg  # the moving segments' mass
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # the dynamometer's axis off the joint's: the weight's lever arm off by e·cos(ψ + φ)
        phi = float(rng.uniform(0.0, 2.0 * np.pi))
        unit = np.cos(psi + phi)
        sign = -1.0 if kind == "knee" else 1.0
        error = sign * size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(axis_offset_m=truth["gravity_error"] / (seg_mass * GRAVITY * max(float(np.max(np.abs(unit))),
                                                                                       1e-12)),
                       axis_offset_direction_deg=float(np.degrees(phi)))
    if "coulomb_friction" in effects:
        fade, scale = float(rng.uniform(0.3, 0.6)), float(rng.uniform(1.0, 3.0)) * stroke_travel
        unit = faded_friction(vel_deg, travel, fade, scale, float(rng.uniform(0.2, 1.0)))
        f0 = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(np.abs(unit[moving])))
        details.update(friction_fade=fade, friction_fade_travel_deg=scale)
    if "viscous_damping" in effects:
        backlash = float(rng.uniform(0.5, 3.0))
        unit = backlash_dashpot(deg, vel, backlash)
        b = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + b * unit
        v_m, u_m = vel[moving], b * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(damper_backlash_deg=backlash)
    if "inertia" in effects:
        drain = float(rng.uniform(0.3, 0.6))
        duration = float(t[-1] - t[0])
        j_rel = 1.0 - drain * (t - t[0]) / duration
        unit = j_rel * acc - drain / duration * vel
        d_inertia = size() / float(np.max(np.abs(unit)))
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(drained_share=drain)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        skew = float(rng.uniform(5.0, 40.0))
        shape = check_strap(deg, at, high, skew)
        torque = torque + size() * shape / max(float(np.max(np.abs(shape))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", strap_skew_deg=skew)
    if "activation_burst" in effects:
        onset = float(rng.uniform(0.15, 0.8)) * float(t[-1])
        rise, relax = float(rng.uniform(0.01, 0.04)), float(rng.uniform(0.2, 0.8))
        peak = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * startle(t, onset, rise, relax)
        truth["activation_burst"] = peak
        details.update(startle_onset_s=onset, startle_rise_s=rise, startle_relax_s=relax)
    if "sensor_drift" in effects:
        relax = float(rng.uniform(20.0, 60.0))
        wind = cable_winding(t, vel_deg, relax)
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * wind / max(float(np.max(np.abs(wind))), 1e-12)
        truth["sensor_drift"] = None
        details.update(winding_relax_s=relax)
    if "time_delay" in effects:
        transport = float(rng.uniform(0.0, 0.3))
        natural, zeta = float(rng.uniform(2.0, 8.0)), float(rng.uniform(0.3, 0.7))
        torque, filter_delay = mount_response(torque, rate, natural, zeta)
        torque = np.interp(t - transport, t, torque)
        truth["time_delay"] = transport + filter_delay
        details.update(transport_s=transport, mount_natural_hz=natural, mount_damping_ratio=zeta,
                       mount_delay_s=filter_delay)
    noise = rng.normal(0.0, sd, t.size)
    beat_hz, beat_width = float(rng.uniform(1.0, 1.6)), float(rng.uniform(0.06, 0.12))
    phase = (t * beat_hz + float(rng.random())) % 1.0
    beats = np.exp(-0.5 * ((phase - 0.5) / (beat_width * beat_hz / 2.355)) ** 2)
    noise += float(rng.uniform(0.3, 0.6)) * sd * beats
    noise += float(rng.uniform(0.2, 0.5)) * sd * np.sin(2.0 * np.pi * float(rng.uniform(0.2, 0.35)) * t
                                                        + float(rng.uniform(0.0, 2.0 * np.pi)))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "backlash_dashpot", "blemker_fibre",
           "cable_winding", "check_strap", "faded_friction", "generate_n", "growing_bends", "mount_response",
           "play_operator", "staircase", "startle"]
