"""A tenth generator family for the diagnosis, written before the engine of its round froze and run once after.

The second to ninth families (:mod:`benchmarks.family_b_truth` … ``family_i_truth``) became development data once run.
This one draws every cause from a law none of them or the engine's library uses (checked against their docstrings
before it was run). Nothing is imported from ``analysis``, nor any physics from the other generators (only the scoring
contract of :mod:`benchmarks.family_b_truth`: effects, magnitude keys, the trial record; and the seeding, the subject's draw and
the recording's damage and the protocol's set-up of
:mod:`benchmarks.family_scaffold`).

- Passive moment: a lab's lookup table, not a formula: at each end of a joint's range the stiffness is given at six
  knots 4–8° apart past an onset, rising from zero by random factors of 1.4–2.6 per knot, interpolated by a
  monotone cubic (PCHIP) and held at its last value beyond; the moment is its integral. The onset toward a
  two-joint muscle is moved by the other joint's angle. The AFO: a leaf spring whose stiffness rises over 1–3°
  of engagement (the same monotone table) and then softens by 0–15 % over the bend (the leaf's geometry).
- Motion: bang-bang strokes, each accelerating at a constant 50–200 °/s² to its cruise speed and braking at it to
  stop on its end, the cruise speed stepping from slow to fast (or fast to slow) over the trial between 3 and
  25 °/s; holds of 0–0.6 s (the fourth family's trapezoidal command went through a position loop that overshoots;
  this profile is followed exactly). The AFO: triangular bends (loading 1–3 s to 10–20°, unloading 0.5–2 s), their
  corners rounded by a 50 ms moving average, 0.2–1 s apart.
- Limb: de Leva's (1996) segment parameters: shank 4.33 % of body mass, centre 44.6 % down from the knee, radius
  of gyration 25.5 % of its length; foot 1.37 %, centre 44.2 % of its length, 25.7 %.
- Causes, each sized so its largest torque is 3–5 × the noise SD (a delay and a compliance by their ranges):
  * friction: rate-and-state (Dieterich–Ruina, aging law): F₀·(1 + a·ln(1 + |θ̇|/v*) + b·ln(1 + φ·v*/D_c))·
    tanh(θ̇/0.2 °/s), the state φ (s) growing at rest and renewed over a slip distance D_c 0.2–1°, a 0.05–0.15,
    b 0.1–0.3, v* 1 °/s; magnitude: the level's mean over the moving samples;
  * damping: a fractional (Scott-Blair springpot) element, η·D^α θ with α 0.6–0.9 (Grünwald–Letnikov, the angle
    from its start); magnitude: the least-squares coefficient of its torque on θ̇ over the moving samples;
  * stop: a progressive-rate spring, k·δ·(1 + δ/δ_r) (δ_r 1–5°), losing 10–30 % of its torque while unloading (a
    hysteretic stop), anywhere in the last third of either end of a joint's range (the AFO's at its top); named
    only;
  * delay: a transport delay of 0–0.45 s behind a sigma-delta converter's sinc³ decimation filter (three cascaded
    moving averages, output at 10–50 Hz, read back by linear interpolation); magnitude: the transport delay plus
    the filter's group delay;
  * activation: a lognormal pulse (Plamondon's kinematic theory), its log-time SD 0.25–0.6 and its peak 0.1–0.5 s
    after its onset, of either sign; magnitude: its peak;
  * limb-weight error: a support sling, a bungee from a point above the segment to its distal part carrying part
    of its weight, its tension growing with its stretch and its moment arm with the segment's orientation;
    magnitude: its moment's peak;
  * drift: the bridge's thermal-mechanical settling with an overshoot, A·e^{−t/τ}·cos(2πt/P + φ) (τ 20–60 s,
    P 30–90 s); named only;
  * series compliance: a strap softening with load (tissue yielding under it), give c·τ·(1 + |τ|/τ_y), τ_y 5–20
    N·m (knee, ankle) or 2–6 N·m (AFO); magnitude: c, the compliance at low load (°/N·m);
  * inertia error: a motor's rotor behind a gear (reflected inertia J), its torque J·θ̈/η while the joint speeds
    it up and J·θ̈·η while it drives the joint back (η 0.6–0.9, blended over the sign of θ̇·θ̈); magnitude: the
    least-squares coefficient of its torque on θ̈.
- Nuisances: 100–1000 Hz; Laplace-distributed white noise whose level swells and ebbs by ±20–40 % at 0.1–0.3 Hz
  (a non-stationary amplifier); a torque gain error of ±2 %; quantised torque and angle; the clock fast or slow by
  up to 0.02 % with jitter; dropped rows singly (0–1.5 %) and in runs; NaN cells in any column (≤ 0.4 %, time
  included); torque and angle offsets.

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
    coupled_onsets,
    damage_recording,
    draw_subject,
    kinematics,
    protocol_set_up,
    segment_direction,
    trial_rng,
)

NOISE_SD_NM = {"afo": 0.06, "knee": 0.19, "ankle": 0.12}
#: de Leva (1996): mass fraction, centre from the proximal joint and radius of gyration (fractions of the length)
SHANK = (0.0433, 0.4459, 0.255)
FOOT = (0.0137, 0.4415, 0.257)


def table_moment(x_deg: np.ndarray, spacing_deg: float, stiffness: np.ndarray) -> np.ndarray:
    """The moment (stiffness units × degrees) at ``x_deg`` degrees past an onset of a stiffness tabulated at knots
    ``spacing_deg`` apart (the first at the onset), interpolated by a monotone cubic (PCHIP) and held at its last
    value beyond the table: ∫₀ˣ k(s) ds, zero before the onset."""
    from scipy.interpolate import PchipInterpolator

    knots = spacing_deg * np.arange(stiffness.size)
    far = max(float(np.max(x_deg)), float(knots[-1]))
    grid = np.linspace(0.0, far, 6001)
    k = np.where(grid <= knots[-1], PchipInterpolator(knots, stiffness)(np.minimum(grid, knots[-1])), stiffness[-1])
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(grid))])
    return np.interp(np.clip(x_deg, 0.0, None), grid, integral)


def _table(rng: np.random.Generator, knots: int = 6) -> np.ndarray:
    """A stiffness table rising from zero: the first step 1, then each knot 1.4–2.6 × the one before."""
    return np.concatenate([[0.0], np.cumprod(np.r_[1.0, rng.uniform(1.4, 2.6, knots - 2)])])


def _bang_bang(rng: np.random.Generator, lo: float, hi: float, rate: float) -> np.ndarray:
    """Strokes (deg) between ``lo`` and ``hi``: constant acceleration to a cruise speed, cruise, constant braking
    onto the end; the cruise speed stepping from slow to fast (or back) over the strokes, 3–25 °/s."""
    accel = float(rng.uniform(50.0, 200.0))
    strokes = 2 * int(rng.integers(2, 4))
    speeds = np.linspace(float(rng.uniform(3.0, 6.0)), float(rng.uniform(15.0, 25.0)), strokes)
    if rng.random() < 0.5:
        speeds = speeds[::-1]
    out = [np.full(int(rng.uniform(0.2, 0.6) * rate), lo)]
    for i, cruise in enumerate(speeds):
        a, b = (lo, hi) if i % 2 == 0 else (hi, lo)
        dist = abs(b - a)
        v = min(float(cruise), float(np.sqrt(accel * dist)))  # a short stroke never reaches its cruise speed
        t_acc = v / accel
        t_total = 2.0 * t_acc + (dist - accel * t_acc**2) / v
        t = np.arange(0.0, t_total, 1.0 / rate)
        s = np.where(t < t_acc, 0.5 * accel * t**2,
                     np.where(t < t_total - t_acc, 0.5 * accel * t_acc**2 + v * (t - t_acc),
                              dist - 0.5 * accel * (t_total - t) ** 2))
        out += [a + np.sign(b - a) * np.clip(s, 0.0, dist), np.full(int(rng.uniform(0.0, 0.6) * rate), b)]
    return np.concatenate(out)


def _triangles(rng: np.random.Generator, rate: float) -> np.ndarray:
    """AFO bends (deg): linear loading over 1–3 s to 10–20°, linear unloading over 0.5–2 s, corners rounded by a
    50 ms moving average."""
    parts = [np.zeros(int(0.4 * rate))]
    for _ in range(int(rng.integers(4, 8))):
        peak = float(rng.uniform(10.0, 20.0))
        parts += [np.linspace(0.0, peak, int(rng.uniform(1.0, 3.0) * rate)),
                  np.linspace(peak, 0.0, int(rng.uniform(0.5, 2.0) * rate)),
                  np.zeros(int(rng.uniform(0.2, 1.0) * rate))]
    deg = np.concatenate(parts)
    width = max(1, int(0.05 * rate))
    return np.convolve(np.pad(deg, width, mode="edge"), np.ones(width) / width, mode="same")[width:-width]


def _passive(kind: str, deg: np.ndarray, fixed: dict[str, float], c: dict[str, Any], lo: float, hi: float
             ) -> np.ndarray:
    """Resistance (N·m) toward increasing angle."""
    if kind == "afo":
        engaged = table_moment(deg - c["engage"], c["spacing"], c["table"])
        return c["k"] * engaged * (1.0 - c["soften"] * np.clip(deg / 20.0, 0.0, 1.0))
    # the ends toward the two-joint muscles moved by the other joint's angle
    on_low, on_high = coupled_onsets(kind, c["on_low"], c["on_high"], c["shift"], fixed)
    low = table_moment(on_low - deg, c["spacing_low"], c["table_low"])
    high = table_moment(deg - on_high, c["spacing_high"], c["table_high"])
    low_ref = float(table_moment(np.array([c["on_low"] - lo]), c["spacing_low"], c["table_low"])[0])
    high_ref = float(table_moment(np.array([hi - c["on_high"]]), c["spacing_high"], c["table_high"])[0])
    return -c["t_low"] * low / max(low_ref, 1e-9) + c["t_high"] * high / max(high_ref, 1e-9)


def _coefficients(rng: np.random.Generator, kind: str, lo: float, hi: float) -> dict[str, Any]:
    if kind == "afo":
        return {"k": float(rng.uniform(0.3, 1.0)), "engage": float(rng.uniform(1.0, 4.0)),
                "spacing": float(rng.uniform(1.0, 3.0)) / 2.0, "table": np.array([0.0, 0.3, 1.0]),
                "soften": float(rng.uniform(0.0, 0.15))}
    span = hi - lo
    big = {"knee": (4.0, 14.0), "ankle": (3.0, 10.0)}[kind]
    small = (1.0, 4.0)
    return {"t_low": rng.uniform(*big) if kind == "knee" else rng.uniform(*small),
            "t_high": rng.uniform(*small) if kind == "knee" else rng.uniform(*big),
            "on_low": lo + rng.uniform(0.25, 0.45) * span, "on_high": hi - rng.uniform(0.25, 0.45) * span,
            "spacing_low": float(rng.uniform(4.0, 8.0)), "spacing_high": float(rng.uniform(4.0, 8.0)),
            "table_low": _table(rng), "table_high": _table(rng), "shift": float(rng.uniform(0.05, 0.2))}


def _limb(kind: str, rad: np.ndarray, fixed: dict[str, float], mass: float, shank: float, foot: float
          ) -> tuple[np.ndarray, float]:
    """(the weight's moment against increasing angle, N·m; the limb's inertia about the joint, kg·m²)."""
    if kind == "afo":
        return np.zeros_like(rad), 0.0
    psi = segment_direction(kind, rad, fixed)
    if kind == "knee":
        m_s, m_f = SHANK[0] * mass, FOOT[0] * mass
        r_s = SHANK[1] * shank
        moment = -(m_s * r_s + m_f * shank) * GRAVITY * np.cos(psi)
        return moment, m_s * (r_s**2 + (SHANK[2] * shank) ** 2) + m_f * shank**2
    m_f = FOOT[0] * mass
    r_f = FOOT[1] * foot
    return m_f * GRAVITY * r_f * np.cos(psi), m_f * (r_f**2 + (FOOT[2] * foot) ** 2)


def sling_moment(psi: np.ndarray, radius_m: float, anchor_m: tuple[float, float], slack_m: float) -> np.ndarray:
    """The moment (N·m per N/m of the bungee's stiffness) about the joint of a bungee from ``anchor_m`` (x forward,
    y up, m, from the joint) to a point ``radius_m`` along a segment at direction ``psi`` (rad): its tension the
    stiffness times its stretch past ``slack_m`` (none when slack), along the bungee; z-moment r × F."""
    ax, ay = radius_m * np.cos(psi), radius_m * np.sin(psi)
    dx, dy = anchor_m[0] - ax, anchor_m[1] - ay
    length = np.hypot(dx, dy)
    tension = np.clip(length - slack_m, 0.0, None)
    return ax * tension * dy / length - ay * tension * dx / length


def rate_and_state(vel_deg_s: np.ndarray, t: np.ndarray, a: float, b: float, slip_deg: float) -> np.ndarray:
    """The friction level (units of F₀) of the aging law: F₀·(1 + a·ln(1 + |v|/v*) + b·ln(1 + φ·v*/D_c)), dφ/dt =
    1 − |v|·φ/D_c (v* = 1 °/s), φ starting at its steady sliding value at v*; integrated exactly per sample."""
    v_star = 1.0
    speed = np.abs(vel_deg_s)
    phi = np.empty(t.size)
    p = slip_deg / v_star
    for i in range(t.size):
        dt = t[i] - t[i - 1] if i else 0.0
        rate = speed[i] / slip_deg
        p = p + dt if rate < 1e-9 else 1.0 / rate + (p - 1.0 / rate) * np.exp(-rate * dt)
        phi[i] = p
    return 1.0 + a * np.log1p(speed / v_star) + b * np.log1p(phi * v_star / slip_deg)


def fractional_derivative(x: np.ndarray, order: float, dt: float) -> np.ndarray:
    """Grünwald–Letnikov derivative of ``order`` (0–1) of ``x`` sampled every ``dt`` (from its first sample: x is
    taken relative to it, so a constant start has none), by FFT convolution with the GL weights."""
    from scipy.signal import fftconvolve

    k = np.arange(1, x.size)
    weights = np.concatenate([[1.0], np.cumprod(1.0 - (order + 1.0) / k)])
    return fftconvolve(x - x[0], weights)[: x.size] / dt**order


def sinc3(x: np.ndarray, rate: float, out_hz: float) -> tuple[np.ndarray, float]:
    """``x`` through a sigma-delta converter's sinc³ decimator (three cascaded moving averages of one output period),
    sampled at ``out_hz`` and read back at ``rate`` by linear interpolation; and the filter's group delay (s)."""
    m = max(1, int(round(rate / out_hz)))
    box = np.ones(m) / m
    y = x.copy()
    for _ in range(3):
        y = np.convolve(np.pad(y, (m - 1, 0), mode="edge"), box, mode="valid")  # causal
    idx = np.arange(0, x.size, m)
    out = np.interp(np.arange(x.size), idx, y[idx])
    return out, 3.0 * (m - 1) / 2.0 / rate


def lognormal_pulse(t: np.ndarray, onset: float, peak_after: float, sigma: float) -> np.ndarray:
    """Plamondon's lognormal pulse, its peak 1 at ``peak_after`` s past ``onset``, log-time SD ``sigma``."""
    s = t - onset
    mu = np.log(peak_after) + sigma**2
    safe = np.where(s > 0, s, 1.0)
    p = np.where(s > 0, np.exp(-((np.log(safe) - mu) ** 2) / (2.0 * sigma**2)) / safe, 0.0)
    return p / max(float(p.max()), 1e-300)


def generate_j(kind: str, effects: tuple[str, ...] = (), seed: int = 0) -> FamilyBTrial:
    """One trial of ``kind`` hiding ``effects`` (names as :data:`EFFECTS`), drawn from ``seed``."""
    rng = trial_rng((10, 10, 3), kind, effects, seed)
    rate = float(rng.choice([100.0, 250.0, 500.0, 1000.0]))
    subject = draw_subject(rng)
    fixed, lo, hi, deg = protocol_set_up(rng, kind, lambda r, a, b: _bang_bang(r, a, b, rate), lambda r: _triangles(r, rate))
    t, rad, vel, acc = kinematics(deg, rate)
    coef = _coefficients(rng, kind, lo, hi)
    sd = NOISE_SD_NM[kind] * rng.uniform(0.8, 1.25)
    details: dict[str, Any] = {"rate_hz": rate, "noise_sd_Nm": sd}
    truth: dict[str, float | None] = {}
    moving = np.abs(vel) > np.radians(0.5)

    def size() -> float:
        return float(rng.uniform(3.0, 5.0)) * sd

    joint_deg = deg
    if "series_compliance" in effects:  # a strap softening with load: its give grows faster than the torque
        c0 = float(rng.uniform(0.03, 0.12))
        yield_nm = float(rng.uniform(2.0, 6.0)) if kind == "afo" else float(rng.uniform(5.0, 20.0))
        give = np.zeros_like(deg)
        for _ in range(40):  # the give answers to the torque it lets through: iterate to the fixed point
            load = _passive(kind, deg - give, fixed, coef, lo, hi)
            give = c0 * load * (1.0 + np.abs(load) / yield_nm)
        joint_deg = deg - give
        truth["series_compliance"] = c0
        details.update(yield_Nm=yield_nm)
    joint = np.radians(joint_deg)
    shank, foot = subject["shank_length_m"], subject["foot_length_m"]
    weight, inertia = _limb(kind, joint, fixed, subject["mass_kg"], shank, foot)
    torque = _passive(kind, joint_deg, fixed, coef, lo, hi) + weight + inertia * acc
    if "gravity_error" in effects:
        # a support sling: a bungee from above the segment's distal part, taut over the range
        length = 0.8 * (shank if kind == "knee" else foot)
        psi = segment_direction(kind, joint, fixed)
        mid = float(np.median(psi))
        anchor = (length * np.cos(mid) + float(rng.uniform(-0.1, 0.1)), float(rng.uniform(0.3, 0.6)))
        reach = np.hypot(anchor[0] - length * np.cos(psi), anchor[1] - length * np.sin(psi))
        slack = float(rng.uniform(0.6, 0.9)) * float(reach.min())
        shape = sling_moment(psi, length, anchor, slack)
        at_mid = int(np.argmin(np.abs(psi - mid)))
        sign = -np.sign(weight[at_mid] * shape[at_mid]) or 1.0  # it carries the weight: against its moment
        moment = size()
        torque = torque + sign * moment * shape / max(float(np.max(np.abs(shape))), 1e-12)
        truth["gravity_error"] = moment
        details.update(sling_anchor_m=anchor, sling_slack_m=slack)
    if "coulomb_friction" in effects:
        a_rs, b_rs, slip = float(rng.uniform(0.05, 0.15)), float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.2, 1.0))
        level = rate_and_state(np.degrees(vel), t, a_rs, b_rs, slip)
        unit = level * np.tanh(np.degrees(vel) / 0.2)
        f0 = size() / float(np.max(np.abs(unit)))
        torque = torque + f0 * unit
        truth["coulomb_friction"] = float(f0 * np.mean(level[moving]))
        details.update(rate_a=a_rs, state_b=b_rs, slip_deg=slip)
    if "viscous_damping" in effects:
        order = float(rng.uniform(0.6, 0.9))
        unit = fractional_derivative(rad, order, 1.0 / rate)
        eta = size() / float(np.max(np.abs(unit)))
        torque = torque + eta * unit
        v_m, u_m = vel[moving], eta * unit[moving]
        truth["viscous_damping"] = float(np.dot(v_m, u_m) / np.dot(v_m, v_m))
        details.update(fractional_order=order)
    if "inertia" in effects:
        efficiency = float(rng.uniform(0.6, 0.9))
        power = vel * acc
        driving = 0.5 * (1.0 + np.tanh(power / max(float(np.std(power)), 1e-12) / 0.1))  # the joint speeds it up
        unit = acc * (driving / efficiency + (1.0 - driving) * efficiency)
        j_rotor = size() / float(np.max(np.abs(unit)))
        torque = torque + j_rotor * unit
        truth["inertia"] = float(np.dot(acc, j_rotor * unit) / np.dot(acc, acc))
        details.update(gear_efficiency=efficiency)
    if "hard_stop" in effects:
        high = kind == "afo" or bool(rng.random() < 0.5)
        depth = float(rng.uniform(0.04, 0.33))
        at = hi - depth * (hi - lo) if high else lo + depth * (hi - lo)
        pen = np.clip(deg - at, 0.0, None) if high else np.clip(at - deg, 0.0, None)
        progressive = float(rng.uniform(1.0, 5.0))
        loss = float(rng.uniform(0.1, 0.3))
        entering = np.tanh(np.gradient(pen, t) / 0.5)  # +1 loading, −1 unloading (deg/s scale of the blend)
        shape = pen * (1.0 + pen / progressive) * (1.0 - loss * 0.5 * (1.0 - entering))
        k = size() / max(float(shape.max()), 1e-12)
        torque = torque + (1.0 if high else -1.0) * k * shape
        truth["hard_stop"] = None
        details.update(stop_deg=at, stop_end="high" if high else "low", progressive_deg=progressive,
                       unloading_loss=loss)
    if "activation_burst" in effects:
        onset = float(rng.uniform(0.15, 0.8)) * float(t[-1])
        sigma, peak_after = float(rng.uniform(0.25, 0.6)), float(rng.uniform(0.1, 0.5))
        amp = size()
        torque = torque + float(rng.choice([-1.0, 1.0])) * amp * lognormal_pulse(t, onset, peak_after, sigma)
        truth["activation_burst"] = amp
        details.update(burst_onset_s=onset, burst_peak_after_s=peak_after, burst_log_sd=sigma)
    if "sensor_drift" in effects:
        tau, period = float(rng.uniform(20.0, 60.0)), float(rng.uniform(30.0, 90.0))
        phase = float(rng.uniform(0.0, 2.0 * np.pi))
        torque = torque + float(rng.choice([-1.0, 1.0])) * size() * np.exp(-t / tau) * np.cos(
            2.0 * np.pi * t / period + phase)
        truth["sensor_drift"] = None
        details.update(settling_s=tau, overshoot_period_s=period)
    if "time_delay" in effects:
        lag, out_hz = float(rng.uniform(0.0, 0.45)), float(rng.uniform(10.0, 50.0))
        filtered, group = sinc3(torque, rate, out_hz)
        torque = np.interp(t - lag, t, filtered, left=filtered[0])
        truth["time_delay"] = lag + group
        details.update(transport_delay_s=lag, decimated_hz=out_hz)
    swell = 1.0 + float(rng.uniform(0.2, 0.4)) * np.sin(2.0 * np.pi * float(rng.uniform(0.1, 0.3)) * t
                                                        + float(rng.uniform(0.0, 2.0 * np.pi)))
    noise = rng.laplace(0.0, sd / np.sqrt(2.0), t.size) * swell  # a Laplace variable of scale s has SD s·√2
    torque = torque * (1.0 + float(rng.uniform(-0.02, 0.02))) + noise + rng.uniform(-1.0, 1.0)
    stamp, angle, torque = damage_recording(rng, t, rad, torque, rate, torque_quantum_nm=(0.002, 0.015),
                                            angle_quantum_deg=(0.005, 0.04), clock_fraction=2e-4, drop_fraction=0.015,
                                            run_s=0.1, nan_fraction=0.004)
    return FamilyBTrial(kind, stamp, angle, torque, fixed, subject, {e: truth[e] for e in effects}, details)


__all__ = ["EFFECTS", "MAGNITUDE_KEY", "NOISE_SD_NM", "FamilyBTrial", "fractional_derivative", "generate_j",
           "lognormal_pulse", "rate_and_state", "sinc3", "sling_moment", "table_moment"]
