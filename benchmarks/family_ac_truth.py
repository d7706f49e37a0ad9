"""A twenty-ninth generator family for the diagnosis, written (2026-12-07, thirty-eighth stop) after the twenty-eighth
family's run and before any further engine change, nothing diagnosed on it; to be run once on the next change's frozen
engine.

The second to twenty-eighth families (:mod:`benchmarks.family_b_truth` … ``family_ab_truth``) are development data
once run. Every law below was checked against the spent families' docstrings (a grep of each law's name and form) and
against :mod:`analysis.diagnosis.causes`. Near relations, stated: the segment's sag gives a second harmonic in the
segment's direction, as the nineteenth family's shifting soft tissue did beside a mass error (here alone); the
Ramberg–Osgood give with n = 2 is the tenth family's softening strap (here n 3–5); the flywheel's play is the
fourteenth family's backlash, there in front of a dashpot. Nothing is imported from ``analysis``, nor any physics from
the other generators (only the scoring contract of :mod:`benchmarks.family_b_truth` and the scaffolding of
:mod:`benchmarks.family_scaffold`).

- Passive moment: at each end of a joint's range a fibre family of Holzapfel, Gasser & Ogden (2000), per unit
  (λ² − 1)·e^{k₂(λ² − 1)²} for the fibre's stretch λ = 1 + x̄/L (x̄ the softplus of the angle past an onset over 1–3°,
  L 1–2.5 × the end's reach, k₂ 0.1–0.6); the steep end sized by its torque at the range's end, the onset toward a
  two-joint muscle moved by the other joint's angle; a small linear term. The AFO: a polypropylene shell, linear past
  an engagement of 0.5–2° (softplus), in parallel with a dorsal strap of the same fibre law taut from 4–10°.
- Motion: a random-target protocol: the range's ends reached twice each, in order, with 3–6 targets drawn inside the
  range inserted among them; each stroke a minimum-jerk (quintic) path at its own mean speed of 3–7 °/s, a hold of
  0–1 s at every target, a 0.5–1.5 s hold at the middle first. The AFO: 6–10 bends whose peaks rise from 10–12° to
  18–20° and fall back (a tent), each loaded along a half-cosine over 1.2–2.5 s, released along a minimum-jerk path
  over 0.4–1 s, rested 0.4–1.2 s at 0°.
- Limb: segment parameters drawn per trial (family_scaffold.draw_segments).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a rolling bearing after Palmgren, a load part and a viscous part growing as the speed's ⅔ power,
    tanh(v/ε)·(1 + p·|v/v_max|^{2/3}) (ε 0.1–0.3 °/s, p 0.25–0.65: the speed part 20–40 % of the level at the trial's
    peak speed); magnitude: its mean |F| over the moving samples;
  * damping: a thixotropic fluid after Moore (1959), a structure s rebuilding at rest and broken down by motion,
    ds/dt = (1 − s)/T_b − a·s·|θ̇| (T_b 2–8 s, a·(median speed) 0.5–2 /s, s = 1 at the start), its coefficient
    b₀·(1 + r·s) (r 0.5–1.5); magnitude: the least-squares slope of its torque on θ̇;
  * stop: a rubber bumper in compression following Mooney & Rivlin, −2(λ − λ⁻²)(C₁ + C₂/λ) for λ = 1 − δ/h (C₂/C₁
    0.1–0.5, the bumper's thickness h 1.3–2.5 × the deepest the joint presses it), anywhere in the last 5–30 % of
    either end of a joint's range (the AFO's at the top of its bend); named only;
  * delay: a transport delay of 0.02–0.45 s behind a causal Savitzky–Golay smoother (a quadratic fitted to the last
    0.1–0.4 s, evaluated at the newest sample: no lag on a polynomial up to that order); magnitude: the transport
    delay;
  * activation: an inverse Gaussian (Wald) density pulse, u^{−3/2}·e^{−λ(u − μ)²/(2μ²u)} (μ 0.2–0.8 s, λ 1–6 × μ:
    from strongly right-skewed to near-Gaussian), starting anywhere in 10–80 % of the trial, of either sign; magnitude:
    its peak;
  * limb-weight error: the segment sagging along its length in its cuff (a compliant attachment), by d·sin ψ (gravity's
    component along it), its weight's moment error m·g·d·sin ψ·cos ψ; magnitude: its peak;
  * drift: a loose connector, the zero toggling between two levels (a random telegraph, 2–5 switches at least a tenth
    of the trial apart, each along a logistic of 0.3–1.5 s); named only;
  * series compliance: a strap following Ramberg & Osgood, give c·τ·(1 + α|τ/τ_y|^{n−1}) (n 3–5, α 0.3–1, τ_y
    0.6–1 × the largest torque); magnitude: the least-squares slope of the give on the torque;
  * inertia error: a flywheel behind a coupling with play (0.5–2° of backlash) and a rubber element (critically
    damped, 4–10 Hz), its torque J·φ̈ for φ the flywheel's angle; magnitude: the least-squares coefficient of its torque
    on θ̈.
- Nuisances, each below what should be named: 100–1000 Hz; Gaussian noise with electromagnetic spikes (0.02–0.1 % of
  the samples, 3–6 × the noise SD, either sign); the angle encoder's eccentricity (a once-per-turn error of
  0.03–0.1°); a constant torque gain error of ±1 %; quantised torque and angle; the clock fast or slow by up to 0.02 %
  with jitter; rows dropped singly (0–1 %) and in runs; NaN cells in any column (≤ 0.3 %, time included); torque and
  angle offsets.

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


def hgo_fibre(x_deg: np.ndarray, smoothing_deg: float, reach_deg: float, k2: float) -> np.ndarray:
    """A fibre family per unit after Holzapfel, Gasser & Ogden (2000): (λ² − 1)·e^{k₂(λ² − 1)²} (zero at λ = 1), the
    stretch λ = 1 + x̄/L with x̄ = s·ln(1 + e^{x/s}) the softplus of the angle ``x_deg`` past the onset over
    s = ``smoothing_deg`` and L = ``reach_deg``."""
    x = np.asarray(x_deg, dtype=float) / smoothing_deg
    stretch = 1.0 + smoothing_deg * np.logaddexp(0.0, x) / reach_deg
    e = stretch**2 - 1.0
    return np.asarray(e * np.exp(k2 * e * e), dtype=float)


def minimum_jerk(a: float, b: float, mean_speed: float, rate: float) -> np.ndarray:
    """A stroke (deg, excluding its start) from ``a`` to ``b`` along the quintic 10s³ − 15s⁴ + 6s⁵ at ``mean_speed``
    °/s."""
    n = max(2, int(np.ceil(abs(b - a) / mean_speed * rate)))
    s = np.arange(1, n + 1) / n
    return np.asarray(a + (b - a) * s**3 * (10.0 - 15.0 * s + 6.0 * s * s), dtype=float)


def random_targets(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The angle (deg): a 0.5–1.5 s hold at the range's middle, then minimum-jerk strokes through the targets lo, hi,
    lo, hi with 3–6 targets drawn inside the range inserted among them at random places, each stroke at a mean speed
    of 3–7 °/s, each target held 0–1 s; back to the middle at the end."""
    mid = 0.5 * (lo + hi)
    targets = [lo, hi, lo, hi]
    for _ in range(int(rng.integers(3, 7))):
        targets.insert(int(rng.integers(0, len(targets) + 1)), float(rng.uniform(lo, hi)))
    targets.append(mid)
    parts = [np.full(int(rng.uniform(0.5, 1.5) * rate), mid)]
    at = mid
    for target in targets:
        if abs(target - at) < 0.5:
            continue
        parts.append(minimum_jerk(at, target, float(rng.uniform(3.0, 7.0)), rate))
        parts.append(np.full(int(rng.uniform(0.0, 1.0) * rate), target))
        at = target
    return np.concatenate(parts)


def tent_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): 0.5 s at 0°, then 6–10 bends whose peaks rise linearly from 10–12° to 18–20° by the middle
    bend (the earlier of two) and fall back to where they started, each loaded along a half-cosine over 1.2–2.5 s,
    released along a minimum-jerk path over 0.4–1 s to 0°, rested 0.4–1.2 s."""
    count = int(rng.integers(6, 11))
    first, top = float(rng.uniform(10.0, 12.0)), float(rng.uniform(18.0, 20.0))
    middle = (count - 1) // 2
    parts = [np.zeros(int(0.5 * rate))]
    for k in range(count):
        share = k / middle if k <= middle else (count - 1 - k) / (count - 1 - middle)
        peak = first + (top - first) * share
        n = int(rng.uniform(1.2, 2.5) * rate)
        s = np.arange(1, n + 1) / n
        parts.append(0.5 * peak * (1.0 - np.cos(np.pi * s)))
        parts.append(minimum_jerk(peak, 0.0, peak / float(rng.uniform(0.4, 1.0)), rate))
        parts.append(np.zeros(int(rng.uniform(0.4, 1.2) * rate)))
    return np.concatenate(parts)


def palmgren_friction(vel_deg_s: np.ndarray, epsilon_deg_s: float, speed_share: float) -> np.ndarray:
    """A rolling bearing's friction per unit load part: tanh(v/ε)·(1 + p·|v/v_max|^{2/3}) (v_max the largest |v|,
    p = ``speed_share``)."""
    v = np.asarray(vel_deg_s, dtype=float)
    ratio = np.abs(v) / max(float(np.max(np.abs(v))), 1e-12)
    return np.asarray(np.tanh(v / epsilon_deg_s) * (1.0 + speed_share * ratio ** (2.0 / 3.0)), dtype=float)


def thixotropic_structure(t: np.ndarray, vel: np.ndarray, rebuild_s: float, breakdown: float) -> np.ndarray:
    """Moore's structure parameter s ∈ (0, 1]: ds/dt = (1 − s)/T_b − a·s·|θ̇| from s = 1, T_b = ``rebuild_s``,
    a = ``breakdown`` (per unit of ``vel``), integrated exactly over each sample interval with the rates held."""
    speed = np.abs(np.asarray(vel, dtype=float))
    out = np.empty(speed.size)
    s = 1.0
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    for i in range(speed.size):
        rate = 1.0 / rebuild_s + breakdown * speed[i]
        steady = (1.0 / rebuild_s) / rate
        s = steady + (s - steady) * np.exp(-rate * dt[i])
        out[i] = s
    return out


def mooney_rivlin_bumper(deg: np.ndarray, at_deg: float, high: bool, thickness_deg: float, c2_over_c1: float
                         ) -> np.ndarray:
    """A rubber bumper per unit C₁ (toward the range's inside, positive at the high end): −2(λ − λ⁻²)(1 + r/λ) for the
    compression λ = 1 − δ/h of its thickness h = ``thickness_deg`` by the depth δ past ``at_deg`` (r = C₂/C₁)."""
    sign = 1.0 if high else -1.0
    depth = np.clip(sign * (np.asarray(deg, dtype=float) - at_deg), 0.0, 0.95 * thickness_deg)
    lam = 1.0 - depth / thickness_deg
    return np.asarray(sign * -2.0 * (lam - lam**-2) * (1.0 + c2_over_c1 / lam), dtype=float)


def savitzky_golay_endpoint(values: np.ndarray, window: int, order: int = 2) -> np.ndarray:
    """A causal Savitzky–Golay smoother: at each sample the polynomial of ``order`` fitted by least squares to the
    last ``window`` samples, evaluated at the newest (the first samples repeat the first value before them)."""
    k = np.arange(-(window - 1), 1, dtype=float)
    design = np.vander(k, order + 1, increasing=True)
    weights = np.linalg.pinv(design)[0]  # the fitted constant term: the value at k = 0
    padded = np.concatenate([np.full(window - 1, values[0]), np.asarray(values, dtype=float)])
    return np.asarray(np.convolve(padded, weights[::-1], mode="valid"), dtype=float)


def wald_pulse(t: np.ndarray, start_s: float, mean_s: float, shape_s: float) -> np.ndarray:
    """An inverse Gaussian density pulse per unit peak: u^{−3/2}·e^{−λ(u − μ)²/(2μ²u)} for u = t − t₀ > 0, zero
    before (μ = ``mean_s``, λ = ``shape_s``)."""
    u = np.asarray(t, dtype=float) - start_s
    uc = np.clip(u, 1e-9, None)
    log = -1.5 * np.log(uc) - shape_s * (uc - mean_s) ** 2 / (2.0 * mean_s**2 * uc)
    shape = np.where(u > 0.0, np.exp(log - np.max(log[u > 0.0], initial=-np.inf)), 0.0)
    return np.asarray(shape / max(float(np.max(shape)), 1e-300), dtype=float)


def sag_moment(direction_rad: np.ndarray) -> np.ndarray:
    """The weight's moment error per unit m·g·d of a segment sagging along its length by d·sin ψ: sin ψ·cos ψ."""
    psi = np.asarray(direction_rad, dtype=float)
    return np.asarray(np.sin(psi) * np.cos(psi), dtype=float)


def telegraph(t: np.ndarray, switch_s: np.ndarray, transition_s: float) -> np.ndarray:
    """A zero toggling between 0 and 1 at each of ``switch_s`` (sorted), each switch along a logistic whose 10–90 %
    rise takes ``transition_s``."""
    tt = np.asarray(t, dtype=float)
    width = transition_s / (2.0 * np.log(9.0))
    level = np.zeros(tt.size)
    for k, at in enumerate(np.sort(np.asarray(switch_s, dtype=float))):
        step = 0.5 * (1.0 + np.tanh((tt - at) / (2.0 * width)))
        level += step if k % 2 == 0 else -step
    return level


def ramberg_osgood_give(torque: np.ndarray, compliance: float, yield_nm: float, alpha: float, exponent: float
                        ) -> np.ndarray:
    """The strap's give (deg): ``compliance``·τ·(1 + α|τ/τ_y|^{n−1}), τ_y = ``yield_nm``, n = ``exponent``."""
    tau = np.asarray(torque, dtype=float)
    return np.asarray(compliance * tau * (1.0 + alpha * np.abs(tau / yield_nm) ** (exponent - 1.0)), dtype=float)


def play(deg: np.ndarray, gap_deg: float) -> np.ndarray:
    """A coupling with play: the output (deg) follows the input once it has taken up half the ``gap_deg`` either way,
    and stays put inside it (the play operator, starting centred)."""
    values = np.asarray(deg, dtype=float)
    half = 0.5 * gap_deg
    out = np.empty(values.size)
    y = float(values[0])
    for i, x in enumerate(values):
        y = min(max(y, x - half), x + half)
        out[i] = y
    return out


def critically_damped(values: np.ndarray, t: np.ndarray, natural_hz: float) -> np.ndarray:
    """``values`` through a critically damped second-order low-pass of ``natural_hz`` (unit gain; semi-implicit
    Euler at the sample times, starting at rest on the first value)."""
    w = 2.0 * np.pi * natural_hz
    x = np.asarray(values, dtype=float)
    y, v = float(x[0]), 0.0
    out = np.empty(x.size)
    dt = np.diff(np.asarray(t, dtype=float), prepend=float(t[0]))
    for i in range(x.size):
        substeps = max(1, int(np.ceil(dt[i] * w / 0.2)))
        h = dt[i] / substeps
        for _ in range(substeps):
            v += h * (w * w * (x[i] - y) - 2.0 * w * v)
            y += h * v
        out[i] = y
    return out


def encoder_eccentricity(rad: np.ndarray, amplitude_deg: float, phase_rad: float) -> np.ndarray:
    """The angle (rad) as an eccentric encoder reads it: θ + e·sin(θ + φ), e = ``amplitude_deg``."""
    theta = np.asarray(rad, dtype=float)
    return np.asarray(theta + np.radians(amplitude_deg) * np.sin(theta + phase_rad), dtype=float)


def _elastic(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """The passive resistance (N·m)."""
    if kind == "afo":
        d = np.asarray(deg, dtype=float)
        shell = c["smooth"] * (np.logaddexp(0.0, (d - c["engage"]) / c["smooth"])
                               - np.logaddexp(0.0, -c["engage"] / c["smooth"]))
        strap = hgo_fibre(d - c["taut"], c["smooth"], c["reach"], c["k2"]) - float(
            hgo_fibre(np.array(-c["taut"]), c["smooth"], c["reach"], c["k2"]))
        return np.asarray(c["k"] * shell + c["strap"] * strap, dtype=float)
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    return (-c["a_low"] * hgo_fibre(on_low - deg, c["smooth"], c["reach_low"], c["k2"])
            + c["a_high"] * hgo_fibre(deg - on_high, c["smooth"], c["reach_high"], c["k2"])
            + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"])))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its torque at a 15° bend, 10–25 N·m, the strap 20–50 % of it there
        engage, smooth, taut = float(rng.uniform(0.5, 2.0)), 0.5, float(rng.uniform(4.0, 10.0))
        reach, k2 = (20.0 - taut) * float(rng.uniform(1.0, 2.5)), float(rng.uniform(0.1, 0.6))
        total, share = float(rng.uniform(10.0, 25.0)), float(rng.uniform(0.2, 0.5))
        shell = smooth * (np.logaddexp(0.0, (15.0 - engage) / smooth) - np.logaddexp(0.0, -engage / smooth))
        strap = float(hgo_fibre(np.array(15.0 - taut), smooth, reach, k2) - hgo_fibre(np.array(-taut), smooth, reach, k2))
        return {"engage": engage, "smooth": smooth, "taut": taut, "reach": reach, "k2": k2,
                "k": (1.0 - share) * total / float(shell), "strap": share * total / strap}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    smooth = float(rng.uniform(1.0, 3.0))
    reach_low = (on_low - lo) * float(rng.uniform(1.0, 2.5))
    reach_high = (hi - on_high) * float(rng.uniform(1.0, 2.5))
    k2 = float(rng.uniform(0.1, 0.6))
    t_low = rng.uniform(*big) if kind == "knee" else rng.uniform(*small)
    t_high = rng.uniform(*small) if kind == "knee" else rng.uniform(*big)
    return {"a_low": t_low / float(hgo_fibre(np.array(on_low - lo), smooth, reach_low, k2)),
            "a_high": t_high / float(hgo_fibre(np.array(hi - on_high), smooth, reach_high, k2)),
            "reach_low": reach_low, "reach_high": reach_high, "k2": k2, "smooth": smooth,
            "on_low": on_low, "on_high": on_high,
            "shift": float(rng.uniform(*COUPLING_SHIFT)), "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_ac(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((29, 29, 29), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: random_targets(r, a, b, rate),
                                         lambda r: tent_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    top, bottom = (float(deg.max()), 0.0) if kind == "afo" else (hi, lo)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a Ramberg–Osgood strap
        tau_max = max(float(np.max(np.abs(_elastic(kind, deg, fixed, coef)))), 1e-9)
        c_give, yield_nm = float(rng.uniform(0.03, 0.15)), float(rng.uniform(0.6, 1.0)) * tau_max
        alpha, exponent = float(rng.uniform(0.3, 1.0)), float(rng.uniform(3.0, 5.0))
        joint_deg = behind_strap(deg, lambda d: ramberg_osgood_give(_elastic(kind, d, fixed, coef), c_give, yield_nm,
                                                                    alpha, exponent))
        tau_j = _elastic(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_deg_per_Nm=c_give, yield_Nm=yield_nm, exponent=exponent)
    joint = np.radians(joint_deg)
    load = limb_load(kind, joint, fixed, subject["mass_kg"], subject["shank_length_m"], subject["foot_length_m"], seg,
                     GRAVITY)
    torque = _elastic(kind, joint_deg, fixed, coef) + load.moment_nm + load.inertia_kgm2 * acc
    if "gravity_error" in effects:  # the segment sagging in its cuff
        unit = sag_moment(load.direction_rad)
        error = size() * float(rng.choice([-1.0, 1.0])) * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
    if "coulomb_friction" in effects:
        unit = palmgren_friction(np.degrees(vel), float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.25, 0.65)))
        friction = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + friction
        truth["coulomb_friction"] = float(np.mean(np.abs(friction[moving])))
    if "viscous_damping" in effects:
        median_speed = max(float(np.median(np.abs(vel[moving]))), 1e-6)
        structure = thixotropic_structure(t, vel, float(rng.uniform(2.0, 8.0)),
                                          float(rng.uniform(0.5, 2.0)) / median_speed)
        unit = vel * (1.0 + float(rng.uniform(0.5, 1.5)) * structure)
        damping = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + damping
        truth["viscous_damping"] = float(np.dot(vel, damping) / np.dot(vel, vel))
    if "inertia" in effects:
        flywheel = critically_damped(play(np.degrees(joint), float(rng.uniform(0.5, 2.0))), t,
                                     float(rng.uniform(4.0, 10.0)))
        unit = np.gradient(np.gradient(np.radians(flywheel), t), t)
        coupled = size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + coupled
        truth["inertia"] = float(np.dot(acc, coupled) / np.dot(acc, acc))
    if "hard_stop" in effects:
        high_end = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.05, 0.3))
        at = top - depth * (top - bottom) if high_end else bottom + depth * (top - bottom)
        deepest = float(np.max(deg - at)) if high_end else float(np.max(at - deg))
        thickness = float(rng.uniform(1.3, 2.5)) * max(deepest, 1e-3)
        unit = mooney_rivlin_bumper(deg, at, high_end, thickness, float(rng.uniform(0.1, 0.5)))
        torque = torque + size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high_end else "low", bumper_thickness_deg=thickness)
    if "activation_burst" in effects:
        start = float(rng.uniform(0.1, 0.8)) * float(t[-1])
        mean = float(rng.uniform(0.2, 0.8))
        peak = size()
        shape = wald_pulse(t, start, mean, float(rng.uniform(1.0, 6.0)) * mean)
        torque = torque + float(rng.choice([-1.0, 1.0])) * peak * shape
        truth["activation_burst"] = peak
        details.update(burst_start_s=start)
    if "sensor_drift" in effects:
        count = int(rng.integers(2, 6))
        while True:
            switches = np.sort(rng.uniform(0.05, 0.95, count)) * float(t[-1])
            if np.all(np.diff(switches) >= 0.1 * float(t[-1])):
                break
        level = telegraph(t, switches, float(rng.uniform(0.3, 1.5)))
        torque = torque + size() * float(rng.choice([-1.0, 1.0])) * level / max(float(np.max(np.abs(level))), 1e-12)
        truth["sensor_drift"] = None
        details.update(switch_s=switches.tolist())
    if "time_delay" in effects:
        window = max(3, int(float(rng.uniform(0.1, 0.4)) * rate))
        latency = float(rng.uniform(0.02, 0.45))
        smoothed = savitzky_golay_endpoint(torque, window)
        torque = np.interp(t - latency, t, smoothed, left=smoothed[0])
        truth["time_delay"] = latency
    spikes = rng.random(t.size) < float(rng.uniform(0.0002, 0.001))
    torque = (torque * (1.0 + float(rng.uniform(-0.01, 0.01))) + rng.normal(0.0, sd, t.size)
              + spikes * rng.choice([-1.0, 1.0], t.size) * rng.uniform(3.0, 6.0, t.size) * sd + rng.uniform(-1.0, 1.0))
    read = encoder_eccentricity(rad, float(rng.uniform(0.03, 0.1)), float(rng.uniform(0.0, 2.0 * np.pi)))
    stamp, angle, torque = damage_recording(rng, t, read, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "critically_damped", "encoder_eccentricity",
           "generate_ac", "hgo_fibre", "minimum_jerk", "mooney_rivlin_bumper", "palmgren_friction", "play",
           "ramberg_osgood_give", "random_targets", "sag_moment", "savitzky_golay_endpoint", "telegraph", "tent_bends",
           "thixotropic_structure", "wald_pulse"]
