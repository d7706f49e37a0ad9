"""A sixteenth generator family for the diagnosis, written after the fifteenth's run, before the engine change of its
round, and to be run once on that change's frozen engine.

The second to fifteenth families (:mod:`benchmarks.family_b_truth` … ``family_o_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses (checked against their
docstrings and :mod:`analysis.diagnosis.causes` before it was run; the near relations are said at each cause).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
segments' draw, the recording's damage and the protocol's set-up of :mod:`benchmarks.family_scaffold`).

- Passive moment with memory: Fung's quasi-linear viscoelasticity (QLV), the torque the convolution of an elastic
  response's rate with a reduced relaxation function G(t) = g∞ + (1 − g∞)·e^{−t/τ} (g∞ 0.8–0.95, τ 0.5–3 s), so the
  passive torque relaxes at every dwell and lags on every stroke in *clean* trials (no earlier family's baseline had
  memory; the eleventh's stop and the fifth's damping had a Maxwell arm). The elastic response at each end of a
  joint's range: an exponential of the smooth excess past an onset, A·(e^{x̄/w} − 1), x̄ the softplus of the angle
  past the onset over 1–3° (w 4–12°), the onset toward a two-joint muscle moved by the other joint's angle, plus a
  small linear term. The AFO: a dorsiflexion-assist spring fitted with a preload, its torque jumping to the preload
  P at engagement (a logistic over 0.2–0.6°) and linear beyond, P + k·b (P 10–30 % of its torque at a 15° bend; earlier
  AFO springs all started from zero), through the same relaxation.
- Motion: a perturbation protocol: slow triangular strokes (2–6 °/s) with a sinusoidal dither on top (amplitude
  0.4–1.5°, 0.5–2 Hz), so the joint reverses direction many times per stroke (earlier families reversed only at the
  range's ends or at a jog), dwells of 0.3–1 s at the ends, 2–3 cycles, the dither fading over the last 2° to each
  end. The AFO: bends loaded linearly over 0.8–2 s to 12–20°, unloaded more slowly (1.2–3 s) to a partial release at
  2–6° before the next bend, every third bend released to 0° (minor hysteresis loops; the twelfth family eased off and
  pressed again at the top only).
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a velocity-weakening dip after breakaway, F(v) = F_k·(1 − d·(|v|/v_m)·e^{1 − |v|/v_m}) (d 0.3–0.6, v_m
    1–4 °/s: the level falls below the kinetic one at moderate speed and recovers, where Stribeck's rises at low
    speed), different per direction by a factor 0.6–0.8 or 1.25–1.65, its sign a logistic of θ̇ over 0.1–0.4 °/s;
    magnitude: its mean over the moving samples;
  * damping: a generalised Maxwell (Wiechert) body of two arms, the velocity through first-order lags of 0.02–0.1 s
    and 0.3–1.5 s weighted 30–70 % (the fifth family's had one arm; the engine's viscoelastic law one lag); magnitude:
    the low-speed damping, the sum of the arms' coefficients;
  * stop: a pneumatic bumper (an adiabatic gas spring), P₀·A·((1 − δ/δ₀)^{−γ} − 1) for δ past the stop (γ 1.2–1.4,
    the sweep's deepest δ 20–60 % of δ₀; the fifth family's foam had a simple pole, the sixth's Gent law a pole in δ²),
    anywhere in the last third of either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0–0.4 s behind a linear-phase FIR low-pass (a Hamming-windowed sinc, cut-off 4–15 Hz,
    31–201 taps at the recording's rate: a ringing impulse response whose delay is half its length; the fifth family's
    boxcar did not ring); magnitude: the transport delay plus half the filter's length;
  * activation: a sustained contraction of 1.5–4 s with cosine-tapered (Tukey) edges, taper 20–50 % of it, fading
    linearly by 0–40 % across its plateau (fatigue), of either sign (earlier bursts were shorter than 1.5 s of
    plateau or had none); magnitude: its peak;
  * limb-weight error: a counterweighted accessory on a 2:1 gear from the segment (a cable reel), its unbalance
    turning twice as fast as the segment: an error of the shape cos(2ψ + φ), φ any phase (every earlier error was a
    sinusoid of the segment's own direction or a nonlinear support); magnitude: its peak;
  * drift: pink (1/f) noise in the bridge's zero, the spectrum ∝ 1/f between 1/T and 0.5 Hz (the second and fourth
    families' random walks are 1/f²), its largest excursion from its mean 3–5 × the noise SD; named only;
  * series compliance: a Bowden cable whose sheath friction makes the give depend on the direction of motion,
    c·τ·(1 + h·s(θ̇)) (h 0.2–0.5, s a logistic sign over 0.5 °/s; the eleventh family's strap gave on one sign of the
    torque, the fourteenth's through a play operator); magnitude: the least-squares slope of its give on the torque;
  * inertia error: a flywheel driven through a one-way clutch, adding its inertia while the joint speeds it up in
    the clutch's direction (θ̇ > 0 and θ̈ > 0, blended over 0.5 °/s and 5 °/s²) and freewheeling otherwise; magnitude:
    the least-squares coefficient of its torque on θ̈ over the trial.
- Nuisances: 100–1000 Hz; white noise plus mains hum (50 Hz, its frequency off by up to ±0.1 Hz, 0.2–0.4 × the noise
  SD; at 100 Hz it aliases to just under the Nyquist frequency), and electrical spikes (0.05–0.2 % of samples,
  4–10 × the noise SD, either sign); a torque gain error of ±1.5 %; quantised torque and angle; the clock fast or slow
  by up to 0.02 % with jitter; dropped rows singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time
  included); torque and angle offsets.

Angles in degrees at the edges, SI in the returned arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.signal import firwin, lfilter

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


def softplus_excess(x: np.ndarray, width: float) -> np.ndarray:
    """The angle past an onset, rounded over ``width`` (same units): w·ln(1 + e^{x/w})."""
    z = np.asarray(x, dtype=float) / width
    return width * np.logaddexp(0.0, z)


def qlv_relaxed(elastic: np.ndarray, t: np.ndarray, g_inf: float, tau_s: float) -> np.ndarray:
    """Fung's quasi-linear viscoelastic torque: ∫ G(t − s)·dT_e(s) with G(t) = g∞ + (1 − g∞)·e^{−t/τ}, the history
    starting at rest on the first sample (T = g∞·T_e + (1 − g∞)·h, h the elastic increments decayed by e^{−Δt/τ} per
    sample of the uniform time ``t``)."""
    decay = float(np.exp(-(t[1] - t[0]) / tau_s)) if t.size > 1 else 0.0
    h = lfilter([1.0], [1.0, -decay], np.diff(elastic, prepend=0.0))
    return g_inf * elastic + (1.0 - g_inf) * h


def dithered_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): triangular strokes between ``lo`` and ``hi`` at 2–6 °/s with a sinusoidal dither on top
    (0.4–1.5° at 0.5–2 Hz), fading over the last 2° to each end so the strokes still turn at the range's ends;
    dwells of 0.3–1 s at each end; 2–3 cycles."""
    speed = float(rng.uniform(2.0, 6.0))
    amplitude, freq = float(rng.uniform(0.4, 1.5)), float(rng.uniform(0.5, 2.0))
    parts = []
    for _ in range(int(rng.integers(2, 4))):
        for up in (True, False):
            parts.append(np.full(int(rng.uniform(0.3, 1.0) * rate), lo if up else hi))
            ramp = np.arange(0.0, (hi - lo) / speed, 1.0 / rate) * speed
            parts.append(lo + ramp if up else hi - ramp)
    parts.append(np.full(int(rng.uniform(0.3, 1.0) * rate), lo))
    base = np.concatenate(parts)
    t = np.arange(base.size) / rate
    fade = np.clip(np.minimum(base - lo, hi - base) / 2.0, 0.0, 1.0)
    dither = amplitude * np.sin(2.0 * np.pi * freq * t + float(rng.uniform(0.0, 2.0 * np.pi)))
    # the dither is scaled by the distance to the nearer end, never pushing past it
    return np.clip(base + fade * np.minimum(1.0, np.minimum(base - lo, hi - base) / amplitude) * dither, lo, hi)


def partial_release_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 5–8 bends loaded linearly over 0.8–2 s to 12–20°, unloaded over 1.2–3 s to a partial release at
    2–6° (every third bend, and the last, to 0° with a rest of 0.3–1 s)."""
    parts = [np.zeros(int(0.4 * rate))]
    level = 0.0
    count = int(rng.integers(5, 9))
    for i in range(count):
        peak = float(rng.uniform(12.0, 19.0))
        full = i % 3 == 2 or i == count - 1
        bottom = 0.0 if full else float(rng.uniform(2.0, 6.0))
        up = np.linspace(level, peak, int(rng.uniform(0.8, 2.0) * rate))
        down = np.linspace(peak, bottom, int(rng.uniform(1.2, 3.0) * rate))
        parts += [up[1:], down[1:]]
        if full:
            parts.append(np.zeros(int(rng.uniform(0.3, 1.0) * rate)))
        level = bottom
    return np.concatenate(parts)


def dip_friction(vel_deg_s: np.ndarray, dip: float, v_dip: float, ratio: float, v_sign: float) -> np.ndarray:
    """A friction per unit kinetic level (resisting increasing angle): 1 − d·(|v|/v_m)·e^{1 − |v|/v_m} (a dip to 1 − d at
    |v| = v_m, recovering beyond), × ``ratio`` moving toward lower angles, its sign a logistic of θ̇ over ``v_sign``."""
    speed = np.abs(vel_deg_s)
    level = 1.0 - dip * (speed / v_dip) * np.exp(1.0 - speed / v_dip)
    level = np.where(vel_deg_s < 0.0, ratio * level, level)
    return level * np.tanh(vel_deg_s / (2.0 * v_sign))  # tanh(x/2) = 2σ(x) − 1: the logistic sign


def first_order_lag(x: np.ndarray, t: np.ndarray, tau_s: float) -> np.ndarray:
    """``x`` through a first-order lag of ``tau_s`` on the uniform time ``t`` (exact for x held over each step),
    starting at ``x[0]``."""
    a = float(np.exp(-(t[1] - t[0]) / tau_s)) if t.size > 1 else 0.0
    return np.asarray(lfilter([1.0 - a], [1.0, -a], x, zi=[a * float(x[0])])[0])


def wiechert_damping(vel: np.ndarray, t: np.ndarray, tau_fast: float, tau_slow: float, share_fast: float
                     ) -> np.ndarray:
    """Two Maxwell arms' torque per unit low-speed damping: the velocity through lags of ``tau_fast`` and ``tau_slow``
    (s), weighted ``share_fast`` and 1 − ``share_fast`` (at a steady speed it is the speed)."""
    return share_fast * first_order_lag(vel, t, tau_fast) + (1.0 - share_fast) * first_order_lag(vel, t, tau_slow)


def gas_bumper(deg: np.ndarray, at_deg: float, high: bool, closed_deg: float, gamma: float) -> np.ndarray:
    """An adiabatic gas spring's torque per unit P₀·A, toward the range's inside (positive at the high end):
    (1 − δ/δ₀)^{−γ} − 1 for the penetration δ past ``at_deg`` (δ₀ = ``closed_deg``, never reached)."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (deg - at_deg), 0.0, 0.95 * closed_deg)
    return sign * ((1.0 - depth / closed_deg) ** (-gamma) - 1.0)


def fir_channel(x: np.ndarray, rate: float, taps: int, cutoff_hz: float) -> tuple[np.ndarray, float]:
    """``x`` through a linear-phase Hamming-windowed sinc low-pass of ``taps`` (odd) at ``rate`` Hz, unit gain at DC,
    started at rest on ``x[0]``; returns (the output, its delay (taps − 1)/2 samples in s)."""
    taps = taps + 1 - taps % 2
    b = firwin(taps, min(cutoff_hz, 0.45 * rate), fs=rate)
    b = b / np.sum(b)
    y = lfilter(b, [1.0], np.concatenate([np.full(taps - 1, x[0]), x]))[taps - 1:]
    return y, (taps - 1) / 2.0 / rate


def tukey_contraction(t: np.ndarray, onset_s: float, length_s: float, taper: float, fade: float) -> np.ndarray:
    """A contraction from ``onset_s`` lasting ``length_s``: cosine-tapered edges over ``taper`` of its length (half at
    each end), its level fading linearly by ``fade`` from start to end; peak 1."""
    u = (t - onset_s) / length_s
    inside = (u >= 0.0) & (u <= 1.0)
    edge = taper / 2.0
    w = np.ones_like(t)
    rising, falling = u < edge, u > 1.0 - edge
    w[rising] = 0.5 - 0.5 * np.cos(np.pi * u[rising] / edge)
    w[falling] = 0.5 - 0.5 * np.cos(np.pi * (1.0 - u[falling]) / edge)
    y = np.where(inside, w * (1.0 - fade * np.clip(u, 0.0, 1.0)), 0.0)
    return y / max(float(np.max(y)), 1e-12)


def pink_noise(rng: np.random.Generator, n: int, rate: float, f_high: float = 0.5) -> np.ndarray:
    """Zero-mean noise with a spectrum ∝ 1/f from the record's lowest frequency to ``f_high`` Hz (none above), largest
    excursion from its mean 1."""
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    f = np.fft.rfftfreq(n, 1.0 / rate)
    band = (f > 0.0) & (f <= f_high)
    spectrum[band] = (rng.normal(size=int(band.sum())) + 1j * rng.normal(size=int(band.sum()))) / np.sqrt(f[band])
    y = np.fft.irfft(spectrum, n)
    y = y - float(np.mean(y))
    return y / max(float(np.max(np.abs(y))), 1e-12)


def cable_give(torque: np.ndarray, vel_deg_s: np.ndarray, hysteresis: float) -> np.ndarray:
    """A Bowden cable's give per unit compliance: τ·(1 + h·s(θ̇)), s a logistic sign of θ̇ over 0.5 °/s."""
    return torque * (1.0 + hysteresis * np.tanh(vel_deg_s / 1.0))


def one_way_flywheel(vel: np.ndarray, acc: np.ndarray) -> np.ndarray:
    """The share of a flywheel's inertia a one-way clutch couples: 1 while the joint speeds it up in the clutch's
    direction (θ̇ > 0 and θ̈ > 0, each a logistic over 0.5 °/s and 5 °/s²), 0 when it freewheels."""
    on_speed = 0.5 + 0.5 * np.tanh(np.degrees(vel) / 1.0)
    on_accel = 0.5 + 0.5 * np.tanh(np.degrees(acc) / 10.0)
    return on_speed * on_accel


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The elastic response (N·m, toward increasing angle's resistance) before relaxation."""
    if kind == "afo":
        bend = np.maximum(deg - c["engage"], 0.0)
        preload = c["preload"] / (1.0 + np.exp(-(deg - c["engage"]) / c["snap"]))
        return preload + c["k"] * bend
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)

    def end(x: np.ndarray, which: str) -> np.ndarray:
        return np.expm1(softplus_excess(x, c[f"round_{which}"]) / c[f"w_{which}"])

    low_ref = float(end(np.array(c["on_low"] - c["lo"]), "low"))
    high_ref = float(end(np.array(c["hi"] - c["on_high"]), "high"))
    return (-c["t_low"] * end(on_low - deg, "low") / low_ref + c["t_high"] * end(deg - on_high, "high") / high_ref
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    relax = {"g_inf": float(rng.uniform(0.8, 0.95)), "tau": float(rng.uniform(0.5, 3.0))}
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m
        engage, snap = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.2, 0.6))
        tau15, share = float(rng.uniform(10.0, 25.0)), float(rng.uniform(0.1, 0.3))
        return {"engage": engage, "snap": snap, "preload": share * tau15,
                "k": (1.0 - share) * tau15 / (15.0 - engage), **relax}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    out: dict[str, Any] = {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
                           "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
                           "on_low": on_low, "on_high": on_high, "shift": float(rng.uniform(*COUPLING_SHIFT)),
                           "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi, **relax}
    for which in ("low", "high"):
        out[f"w_{which}"] = float(rng.uniform(4.0, 12.0))
        out[f"round_{which}"] = float(rng.uniform(1.0, 3.0))
    return out


def _passive(kind: str, deg: np.ndarray, t: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle, relaxed by the QLV history."""
    return qlv_relaxed(_elastic(kind, deg, fixed, c), t, c["g_inf"], c["tau"])


def generate_p(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((16, 16, 16), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: dithered_strokes(r, a, b, rate),
                                         lambda r: partial_release_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    vel_deg = np.degrees(vel)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg,
                               "relaxation": {"g_inf": coef["g_inf"], "tau_s": coef["tau"]}}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a Bowden cable: give = c·τ·(1 + h·s(θ̇))
        c_give, hysteresis = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.2, 0.5))
        for _ in range(3):  # the joint turns by the angle less the give, which depends on the torque it meets
            joint_deg = deg - c_give * cable_give(_passive(kind, joint_deg, t, fixed, coef), vel_deg, hysteresis)
        tau_j = _passive(kind, joint_deg, t, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, cable_hysteresis=hysteresis)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    weight, inertia, amplitude, psi = load.moment_nm, load.inertia_kgm2, load.amplitude_nm, load.direction_rad
    passive = _passive(kind, joint_deg, t, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # an accessory's unbalance on a 2:1 gear from the segment: cos(2ψ + φ)
        phase = float(rng.uniform(0.0, 2.0 * np.pi))
        unit = np.cos(2.0 * psi + phase)
        error = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        details.update(geared_unbalance_phase_rad=phase, weight_moment_amplitude_Nm=amplitude)
    if "coulomb_friction" in effects:
        ratio = float(rng.choice([rng.uniform(0.6, 0.8), rng.uniform(1.25, 1.65)]))
        unit = dip_friction(vel_deg, float(rng.uniform(0.3, 0.6)), float(rng.uniform(1.0, 4.0)), ratio,
                            float(rng.uniform(0.1, 0.4)))
        f0 = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(np.abs(unit[moving])))
        details.update(friction_direction_ratio=ratio)
    if "viscous_damping" in effects:
        fast, slow = float(rng.uniform(0.02, 0.1)), float(rng.uniform(0.3, 1.5))
        share = float(rng.uniform(0.3, 0.7))
        unit = wiechert_damping(vel, t, fast, slow, share)
        b = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + b * unit
        truth["viscous_damping"] = b
        details.update(arm_lags_s=(fast, slow), fast_arm_share=share)
    if "inertia" in effects:
        unit = one_way_flywheel(vel, acc) * acc
        d_inertia = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(flywheel_inertia_kgm2=d_inertia)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        reach = depth * (hi - lo) if kind != "afo" else max(float(np.max(deg)) - at, 0.5)
        closed = reach / float(rng.uniform(0.2, 0.6))
        gamma = float(rng.uniform(1.2, 1.4))
        unit = gas_bumper(deg, at, high, closed, gamma)
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", bumper_closed_deg=closed, gamma=gamma)
    if "activation_burst" in effects:
        length = float(rng.uniform(1.5, 4.0))
        onset = float(rng.uniform(0.05, 0.95)) * max(float(t[-1]) - length, 0.0)
        peak = size()
        unit = tukey_contraction(t, onset, length, float(rng.uniform(0.2, 0.5)), float(rng.uniform(0.0, 0.4)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * unit
        truth["activation_burst"] = peak
        details.update(contraction_onset_s=onset, contraction_s=length)
    if "sensor_drift" in effects:
        torque = torque + size() * pink_noise(rng, t.size, rate)
        truth["sensor_drift"] = None
    if "time_delay" in effects:
        transport = float(rng.uniform(0.0, 0.4))
        taps, cutoff = int(rng.integers(31, 202)), float(rng.uniform(4.0, 15.0))
        torque, filter_delay = fir_channel(torque, rate, taps, cutoff)
        torque = np.interp(t - transport, t, torque)
        truth["time_delay"] = transport + filter_delay
        details.update(transport_s=transport, fir_taps=taps, fir_cutoff_hz=cutoff, filter_delay_s=filter_delay)
    noise = rng.normal(0.0, sd, t.size)
    hum_hz = 50.0 + float(rng.uniform(-0.1, 0.1))
    noise += float(rng.uniform(0.2, 0.4)) * sd * np.sin(2.0 * np.pi * hum_hz * t + float(rng.uniform(0.0, 2.0 * np.pi)))
    spikes = rng.random(t.size) < rng.uniform(0.0005, 0.002)
    noise[spikes] += rng.uniform(4.0, 10.0, int(spikes.sum())) * sd * rng.choice([-1.0, 1.0], int(spikes.sum()))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "cable_give", "dip_friction", "dithered_strokes",
           "fir_channel", "gas_bumper", "generate_p", "one_way_flywheel", "partial_release_bends", "pink_noise",
           "qlv_relaxed", "tukey_contraction", "wiechert_damping"]
