"""A thirteenth generator family for the diagnosis, written after the twelfth's run and run once on the engine as it stood.

The second to twelfth families (:mod:`benchmarks.family_b_truth` … ``family_l_truth``) became development data once
run. This one draws every cause from a law none of them or the engine's library uses (checked against their
docstrings and :mod:`analysis.diagnosis.causes` before it was run; the near relations are said at each cause).
Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring contract of
:mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw, the
recording's damage and the protocol's set-up of :mod:`benchmarks.family_scaffold`).

- Passive moment: the worm-like chain (Marko & Siggia's interpolation, the entropic elasticity of titin and
  collagen) at each end of a joint's range, k·(1/(4(1 − x/L)²) − 1/4 + x/L) for x the angle past an onset and L a
  contour 1.15–1.6 × the end's reach (it diverges beyond the range: the sixth family's Gent-like law has a pole in
  x², this one a double pole in x), the onset toward a two-joint muscle moved by the other joint's angle, plus a
  small linear term. The AFO: the same law of the bend past an engagement reached through a softplus of 0.5–2°,
  contour 1.6–2.5 × its largest bend.
- Motion: a torque-limited servo: the path is isokinetic strokes at 3–15 °/s with cubic speed ramps of 0.15–0.4 s
  and holds of 0.3–1.5 s (2–4 cycles), but the motor slows under load, its speed falling by a share s (0.2–0.5) of
  the passive moment over its largest value (the motion depends on the torque it meets). The AFO: bends to 8–20°
  along cubic smoothsteps of 0.6–2 s with holds of 0–0.5 s, a hand tremor of 6–10 Hz and 0.05–0.2° on the bends,
  slowed by the spring's load in the same way.
- Limb: segment parameters drawn per trial (shank 4.3–4.8 % of body mass, its centre 40–44 % down from the knee,
  radius of gyration 28–31 % of its length; foot 1.2–1.5 %, 42–48 %, 23–27 %).
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: a bearing with a damaged race: a level rippling with the angle, F₀·(1 + r·cos(2πθ/P + φ)) (r 0.2–0.5,
    P 4–15°), its sign the direction of motion (zero below 0.05 °/s; the eleventh family's lip seal grew along the
    range, the twelfth's cross-talk periodic in angle was noise, not friction); magnitude: its mean level over the
    moving samples;
  * damping: load-dependent viscosity, b₀·(1 + η·|P(θ)|/max|P|)·θ̇ (η 1–3: tissue that resists motion more where it
    is loaded; the sixth family's viscosity rose linearly along the range); magnitude: the least-squares coefficient
    of its torque on θ̇ over the moving samples;
  * stop: a foam stop that takes a set: within a contact k·δⁿ (n 1.2–1.8), and each contact leaves the stop deeper
    by 10–30 % of that contact's deepest penetration (crushed foam), anywhere in the last third of either end of a
    joint's range (the AFO's at the top of its bend); named only;
  * delay: a torque channel behind two cascaded first-order low-passes (a heavily filtered amplifier output, each
    τ 0.02–0.22 s), no transport delay (the fourth family's 5–30 ms amplifier sat in front of a pure delay);
    magnitude: its group delay at low frequency (2τ, for the sampled filter exactly);
  * activation: a Gaussian-envelope contraction (SD 0.1–0.5 s) carrying a physiological tremor (8–12 Hz, 30–60 % of
    the envelope), of one sign (the eighth family's clonus is rectified beats under a rising envelope); magnitude:
    the envelope's peak (the contraction's level about which the tremor rides);
  * limb-weight error: soft tissue shifting along the segment with the joint: the centre of mass moves linearly with
    the angle from one end of the range to the other (its moment error ∝ (u − ½)·cos ψ, u 0 → 1 along the range),
    where the engine takes it fixed; sized as the others (for the segment's own mass a shift of a few cm, kept in the
    trial's details); magnitude: the peak moment error;
  * drift: a room's thermostat cycling: the zero follows a square wave (period 20–60 s, duty 30–70 %) through the
    bridge's thermal lag (4–12 s), of either sign (the fifth family's thermal cycle was a sinusoid, the ninth's
    auto-zero a sawtooth reset to zero); named only;
  * series compliance: a pad pressed into tissue, a Hertzian give ∝ |τ|^{2/3} (steepest at small torque; the third
    and fifth families' straps stiffened with load through a saturating law); magnitude: the least-squares slope of
    its give on the torque (°/N·m);
  * inertia error: a linkage whose reflected inertia changes with its configuration, J(θ) = J₀·(1 + r·cos(2πθ/P))
    (r 0.1–0.3, P 20–60°), its torque J(θ)·θ̈ + ½J′(θ)·θ̇²; magnitude: the least-squares coefficient of its torque
    on θ̈.
- Nuisances: 100–1000 Hz; white noise plus impulsive spikes (0.02–0.1 % of rows, 5–15 × the noise SD, of either
  sign: interference picked up by the cable); a torque gain error of ±1.5 %; quantised torque and angle; the clock
  fast or slow by up to 0.02 % with jitter; dropped rows singly (0–1 %) and in runs; NaN cells in any column
  (≤ 0.3 %, time included); torque and angle offsets.

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
#: how much larger an end's moment grows per degree its onset moves into the range with the other joint (1/deg)
COUPLING_PER_DEG = 0.02


def worm_like_chain(x: np.ndarray, contour: float) -> np.ndarray:
    """Marko–Siggia's force–extension interpolation, 1/(4(1 − x/L)²) − 1/4 + x/L, for ``x`` past the onset (zero
    before it; same units as ``contour``, which must exceed every ``x``)."""
    r = np.clip(np.clip(x, 0.0, None) / contour, 0.0, 0.99)  # clipped short of the pole (a bisection's far guesses)
    return 0.25 / (1.0 - r) ** 2 - 0.25 + r


def _smoothstep(n: int) -> np.ndarray:
    """0 → 1 over ``n`` samples along a cubic smoothstep."""
    u = np.linspace(0.0, 1.0, max(n, 2))
    return u * u * (3.0 - 2.0 * u)


def servo_strokes(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """The commanded path (deg): cycles between ``lo`` and ``hi`` at 3–15 °/s with cubic speed ramps of 0.15–0.4 s and
    holds of 0.3–1.5 s at each end (the load's slowing is applied by :func:`slowed_by_load`)."""
    speed, ramp = float(rng.uniform(3.0, 15.0)), float(rng.uniform(0.15, 0.4))
    out = [np.full(int(rng.uniform(0.3, 1.5) * rate), lo)]
    for _ in range(int(rng.integers(2, 5))):
        for a, b in ((lo, hi), (hi, lo)):
            duration = abs(b - a) / speed + ramp
            t = np.arange(0.0, duration, 1.0 / rate)
            u = np.clip(np.minimum(t, duration - t) / ramp, 0.0, 1.0)
            v = u * u * (3.0 - 2.0 * u)
            s = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]))])
            out.append(a + (b - a) * s / s[-1])
            out.append(np.full(int(rng.uniform(0.3, 1.5) * rate), b))
    return np.concatenate(out)


def tremor_bends(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): to 8–20° along cubic smoothsteps of 0.6–2 s, held 0–0.5 s, released, rests of 0.2–1 s; a hand
    tremor of 6–10 Hz and 0.05–0.2° on the bends (none at rest)."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(8.0, 20.0))
        parts += [peak * _smoothstep(int(rng.uniform(0.6, 2.0) * rate)),
                  np.full(int(rng.uniform(0.0, 0.5) * rate), peak),
                  peak * (1.0 - _smoothstep(int(rng.uniform(0.6, 2.0) * rate))),
                  np.zeros(int(rng.uniform(0.2, 1.0) * rate))]
    deg = np.concatenate(parts)
    t = np.arange(deg.size) / rate
    tremor = float(rng.uniform(0.05, 0.2)) * np.sin(2.0 * np.pi * float(rng.uniform(6.0, 10.0)) * t
                                                   + float(rng.uniform(0.0, 2.0 * np.pi)))
    return deg + tremor * np.clip(deg / 2.0, 0.0, 1.0)


def slowed_by_load(deg: np.ndarray, load: np.ndarray, share: float, rate: float) -> np.ndarray:
    """The path ``deg`` (sampled at ``rate`` Hz as commanded) as a torque-limited motor follows it: each step takes
    1 / (1 − ``share``·|load|/max|load|) times as long, and the path is resampled at ``rate`` on the slowed clock."""
    peak = float(np.max(np.abs(load)))
    slow = 1.0 - share * np.abs(load) / peak if peak > 0 else np.ones_like(load)
    step = 0.5 * (1.0 / slow[1:] + 1.0 / slow[:-1]) / rate
    clock = np.concatenate([[0.0], np.cumsum(step)])
    return np.interp(np.arange(int(np.floor(clock[-1] * rate + 1e-9)) + 1) / rate, clock, deg)


def rippled_friction(deg: np.ndarray, vel_deg_s: np.ndarray, ripple: float, period_deg: float, phase: float
                     ) -> np.ndarray:
    """A damaged bearing's friction per unit level (resisting increasing angle): (1 + r·cos(2πθ/P + φ)) times the
    direction of motion, zero below 0.05 °/s."""
    direction = np.where(np.abs(vel_deg_s) < 0.05, 0.0, np.sign(vel_deg_s))
    return (1.0 + ripple * np.cos(2.0 * np.pi * deg / period_deg + phase)) * direction


def thermostat_drift(t: np.ndarray, period_s: float, duty: float, lag_s: float, phase: float) -> np.ndarray:
    """A zero following a square wave (1 for the first ``duty`` of each ``period_s``, else 0, shifted by ``phase`` of
    a period) through a first-order thermal lag of ``lag_s`` s, started at the wave's mean."""
    cycle = ((t - t[0]) / period_s + phase) % 1.0
    square = (cycle < duty).astype(float)
    y = np.empty(t.size)
    y[0] = duty
    for i in range(1, t.size):
        a = np.exp(-(t[i] - t[i - 1]) / lag_s)
        y[i] = a * y[i - 1] + (1.0 - a) * square[i]
    return y - duty


def foam_stop(deg: np.ndarray, at_deg: float, high: bool, exponent: float, set_share: float) -> np.ndarray:
    """A foam stop's unit torque shape (toward the range's inside, positive at the high end): δⁿ past the stop, the
    stop moved deeper after each contact by ``set_share`` of that contact's deepest penetration."""
    sign = 1.0 if high else -1.0
    out = np.zeros(deg.size)
    stop = at_deg
    deepest = 0.0
    for i, a in enumerate(deg.tolist()):
        pen = sign * (a - stop)
        if pen > 0.0:
            out[i] = pen**exponent
            deepest = max(deepest, pen)
        elif deepest > 0.0:  # the contact ended: the foam keeps a share of it
            stop += sign * set_share * deepest
            deepest = 0.0
    return sign * out


def cascaded_low_pass(x: np.ndarray, tau_s: float, rate: float) -> tuple[np.ndarray, float]:
    """``x`` through two identical first-order low-passes (time constant ``tau_s``, sampled exactly at ``rate`` Hz),
    started at rest on ``x[0]``; returns (the output, its group delay at zero frequency in s)."""
    a = float(np.exp(-1.0 / (rate * tau_s)))
    y = x
    for _ in range(2):
        y, _ = lfilter([1.0 - a], [1.0, -a], y, zi=[a * float(y[0])])
    return y, 2.0 * a / (1.0 - a) / rate


def tremor_burst(t: np.ndarray, centre_s: float, sd_s: float, tremor_hz: float, ripple: float, phase: float
                 ) -> np.ndarray:
    """A Gaussian envelope (peak 1 at ``centre_s``, SD ``sd_s``) times 1 + ``ripple``·sin(2π·f·t + φ): the envelope's
    peak is 1, the product's up to 1 + ``ripple``."""
    env = np.exp(-0.5 * ((t - centre_s) / sd_s) ** 2)
    return env * (1.0 + ripple * np.sin(2.0 * np.pi * tremor_hz * t + phase))


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any]) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        bend = c["soft"] * np.logaddexp(0.0, (deg - c["engage"]) / c["soft"])
        return c["k"] * worm_like_chain(bend, c["contour"])
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    t_low = c["t_low"] * np.exp(COUPLING_PER_DEG * (on_low - c["on_low"]))
    t_high = c["t_high"] * np.exp(COUPLING_PER_DEG * (c["on_high"] - on_high))
    # each end's contour from its nominal onset, so that a moved onset never reaches the pole inside the range
    low = worm_like_chain(on_low - deg, c["contour_low"]) / worm_like_chain(np.array(c["reach_low"]), c["contour_low"])
    high = worm_like_chain(deg - on_high, c["contour_high"]) / worm_like_chain(np.array(c["reach_high"]),
                                                                                c["contour_high"])
    return -t_low * low + t_high * high + c["linear"] * (deg - 0.5 * (c["lo"] + c["hi"]))


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float, largest_bend: float) -> dict[str, Any]:
    if kind == "afo":  # sized by its moment at a 15° bend, 10–25 N·m
        engage, soft = float(rng.uniform(1.0, 4.0)), float(rng.uniform(0.5, 2.0))
        contour = float(rng.uniform(1.6, 2.5)) * largest_bend
        bend15 = soft * np.logaddexp(0.0, (min(15.0, 0.9 * largest_bend) - engage) / soft)
        return {"k": float(rng.uniform(10.0, 25.0)) / float(worm_like_chain(np.array(bend15), contour)),
                "engage": engage, "soft": soft, "contour": contour}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    on_low, on_high = lo + rng.uniform(0.2, 0.45) * span, hi - rng.uniform(0.2, 0.45) * span
    shift = float(rng.uniform(0.05, 0.2))
    # the farthest past its onset an end reaches, the onset moved by the other joint (hip 15–90° about 55°, knee
    # 0–90° about 45°: 45° either way at most)
    farthest_low, farthest_high = on_low - lo + 45.0 * shift, hi - on_high + 45.0 * shift
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": on_low, "on_high": on_high, "shift": shift,
            "reach_low": on_low - lo, "reach_high": hi - on_high,
            "contour_low": float(rng.uniform(1.15, 1.6)) * farthest_low,
            "contour_high": float(rng.uniform(1.15, 1.6)) * farthest_high,
            "linear": float(rng.uniform(0.0, 0.02)), "lo": lo, "hi": hi}


def generate_m(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((13, 13, 7), kind, effects, seed)
    rate = float(rng.choice([100.0, 200.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    seg = draw_segments(rng)
    fixed, lo, hi, commanded = protocol_set_up(rng, kind, lambda r, a, b: servo_strokes(r, a, b, rate),
                                               lambda r: tremor_bends(r, rate))
    coef = _coefficients(rng, kind, lo, hi, float(commanded.max()))
    deg = slowed_by_load(commanded, _passive(kind, commanded, fixed, coef), float(rng.uniform(0.2, 0.5)), rate)
    t, rad, vel, acc = kinematics(deg, rate)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd, "segments": seg}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)
    along = np.clip((deg - lo) / max(hi - lo, 1e-9), 0.0, 1.0)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a pad pressed into tissue: give ∝ |τ|^(2/3)
        c_ref, tau_ref = float(rng.uniform(0.03, 0.12)), 10.0

        def give(tau: np.ndarray) -> np.ndarray:
            return c_ref * tau_ref * np.sign(tau) * (np.abs(tau) / tau_ref) ** (2.0 / 3.0)

        # the joint's angle j solves deg − j = give(P(j)), whose left side falls and right side rises with j
        low_j, high_j = deg - 30.0, deg + 30.0
        for _ in range(60):
            mid = 0.5 * (low_j + high_j)
            excess = deg - mid - give(_passive(kind, mid, fixed, coef))
            low_j, high_j = np.where(excess > 0.0, mid, low_j), np.where(excess > 0.0, high_j, mid)
        joint_deg = 0.5 * (low_j + high_j)
        tau_j = _passive(kind, joint_deg, fixed, coef)
        truth["series_compliance"] = float(np.dot(tau_j, deg - joint_deg) / np.dot(tau_j, tau_j))
        details.update(compliance_at_10_Nm_deg_per_Nm=c_ref)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    load = limb_load(kind, joint, fixed, subject["mass_kg"], shank, foot, seg, GRAVITY)
    weight, inertia, cos_psi = load.moment_nm, load.inertia_kgm2, np.cos(load.direction_rad)
    seg_mass = load.shank_kg if kind == "knee" else load.foot_kg  # the moving segment whose centre slides
    passive = _passive(kind, joint_deg, fixed, coef)
    torque = passive + weight + inertia * acc
    if "gravity_error" in effects:
        # the soft tissue's centre of mass slides along the segment with the joint, from −½ to +½ of its shift
        direction = float(rng.choice([-1.0, 1.0]))
        unit = direction * (along - 0.5) * cos_psi  # per unit m·g·shift, the sign of the weight's moment
        sign = -1.0 if kind == "knee" else 1.0
        error = sign * size() * unit / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + error
        truth["gravity_error"] = float(np.max(np.abs(error)))
        # the shift that makes this error with the segment's own mass (1–4 cm for the sizes drawn here)
        details.update(com_shift_m=direction * truth["gravity_error"] / (
            seg_mass * GRAVITY * max(float(np.max(np.abs(unit))), 1e-12)), segment_mass_kg=seg_mass)
    if "coulomb_friction" in effects:
        ripple, period = float(rng.uniform(0.2, 0.5)), float(rng.uniform(4.0, 15.0))
        unit = rippled_friction(joint_deg, np.degrees(vel), ripple, period, float(rng.uniform(0.0, 2.0 * np.pi)))
        f0 = size() / max(float(np.max(np.abs(unit))), 1e-12)
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(np.abs(unit[moving])))
        details.update(friction_ripple=ripple, friction_period_deg=period)
    if "viscous_damping" in effects:
        eta = float(rng.uniform(1.0, 3.0))
        unit = (1.0 + eta * np.abs(passive) / max(float(np.max(np.abs(passive))), 1e-12)) * vel
        b = size() / float(np.max(np.abs(unit)))
        torque = torque + b * unit
        v_m, u_m = vel[moving], b * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(load_dependence=eta)
    if "inertia" in effects:
        ripple, period = float(rng.uniform(0.1, 0.3)), np.radians(float(rng.uniform(20.0, 60.0)))
        phase = 2.0 * np.pi * joint / period
        j_rel = 1.0 + ripple * np.cos(phase)
        dj_rel = -ripple * 2.0 * np.pi / period * np.sin(phase)  # d(J/J₀)/dθ (1/rad)
        unit = j_rel * acc + 0.5 * dj_rel * vel**2
        d_inertia = size() / float(np.max(np.abs(unit)))
        torque = torque + d_inertia * unit
        truth["inertia"] = float(np.dot(acc, d_inertia * unit) / np.dot(acc, acc))
        details.update(linkage_ripple=ripple, linkage_period_deg=float(np.degrees(period)))
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        n, set_share = float(rng.uniform(1.2, 1.8)), float(rng.uniform(0.1, 0.3))
        shape = foam_stop(deg, at, high, n, set_share)
        torque = torque + size() * shape / max(float(np.max(np.abs(shape))), 1e-12)
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", stop_exponent=n, stop_set_share=set_share)
    if "activation_burst" in effects:
        sd_s, tremor_hz = float(rng.uniform(0.1, 0.5)), float(rng.uniform(8.0, 12.0))
        ripple, centre = float(rng.uniform(0.3, 0.6)), float(rng.uniform(0.15, 0.8)) * float(t[-1])
        shape = tremor_burst(t, centre, sd_s, tremor_hz, ripple, float(rng.uniform(0.0, 2.0 * np.pi)))
        peak = size()  # the largest torque; the envelope's peak is that over the ripple's largest excursion
        envelope_peak = peak / float(np.max(np.abs(shape)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * envelope_peak * shape
        truth["activation_burst"] = envelope_peak
        details.update(burst_centre_s=centre, burst_sd_s=sd_s, tremor_hz=tremor_hz, tremor_share=ripple,
                       burst_peak_Nm=peak)
    if "sensor_drift" in effects:
        period, duty, lag = float(rng.uniform(20.0, 60.0)), float(rng.uniform(0.3, 0.7)), float(rng.uniform(4.0, 12.0))
        wave = thermostat_drift(t, period, duty, lag, float(rng.uniform(0.0, 1.0)))
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * wave / max(float(np.max(np.abs(wave))), 1e-12)
        truth["sensor_drift"] = None
        details.update(thermostat_period_s=period, thermostat_duty=duty, thermal_lag_s=lag)
    if "time_delay" in effects:
        tau = float(rng.uniform(0.02, 0.22))
        torque, delay = cascaded_low_pass(torque, tau, rate)
        truth["time_delay"] = delay
        details.update(filter_tau_s=tau)
    noise = rng.normal(0.0, sd, t.size)
    spikes = rng.random(t.size) < float(rng.uniform(0.0002, 0.001))
    noise[spikes] += rng.uniform(5.0, 15.0, int(spikes.sum())) * sd * rng.choice([-1.0, 1.0], int(spikes.sum()))
    torque = torque * (1.0 + float(rng.uniform(-0.015, 0.015))) + noise + rng.uniform(-1.0, 1.0)
    details.update(spikes=int(spikes.sum()))
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.012),
                                            angle_quantum_deg=(0.005, 0.03), clock_fraction=2e-4, drop_fraction=0.01,
                                            run_s=0.1, nan_fraction=0.003)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "cascaded_low_pass", "foam_stop", "generate_m",
           "rippled_friction", "servo_strokes", "slowed_by_load", "thermostat_drift", "tremor_bends", "tremor_burst",
           "worm_like_chain"]
