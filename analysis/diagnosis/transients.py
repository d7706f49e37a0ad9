"""A transient against its own surroundings: a half-sine's matched filter with each window's mean and slope taken out,
scanned over a residual and put in units of its own robust spread.

It judges whether an activation burst the search placed stands out of the residual as a single isolated event
(engine._Search.burst_scan). The criterion judges every cause at the residual's effective
sample size, which the slowest noise sets; a short burst does not have to stand out of noise that slow, only of the
noise at its own time scale, which is what the scan's spread measures, whatever the noise's spectrum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import correlate
from scipy.stats import norm


@dataclass(frozen=True)
class TransientScan:
    """How far one event stands out of a residual's scan (:func:`isolated_transient`), in units of the scan's robust
    spread."""

    z_event: float        # at the event's start (within half its duration)
    z_elsewhere: float    # the largest more than two durations away from it
    z_critical: float     # the family-wise level over every window and searched duration

    @property
    def isolated(self) -> bool:
        """The event passes the level and nothing else in the trial does: one transient, not a recurring misfit."""
        return self.z_event > self.z_critical and self.z_elsewhere <= self.z_critical


def scan(t: np.ndarray, residual: np.ndarray, duration_s: float) -> tuple[np.ndarray, np.ndarray, int] | None:
    """(the finite samples' times in s, |z| of the filter at every window start, samples per duration) of ``residual``
    (N·m) scanned with a half-sine of ``duration_s``; None where the data are too short for a spread.

    The filter is the half-sine padded by one duration on each side, with its mean and slope over those three durations
    taken out, at unit norm: it answers to a bump against its surroundings, not to an offset or a slow wander. Window
    ``i`` covers samples ``i`` to ``i + 3m``, its bump starting at sample ``i + m``. Its output is put in units of its
    robust spread (1.4826 × the median absolute deviation over the trial), which an event itself barely moves."""
    ok = np.isfinite(residual) & np.isfinite(t)
    t, e = np.asarray(t, dtype=float)[ok], np.asarray(residual, dtype=float)[ok]
    if e.size < 3 or duration_s <= 0.0:
        return None
    m = max(3, int(round(duration_s / float(np.median(np.diff(t))))))
    kernel = np.concatenate([np.zeros(m), np.sin(np.pi * np.linspace(0.0, 1.0, m)), np.zeros(m)])
    x = np.linspace(-1.0, 1.0, kernel.size)
    trend = np.column_stack([np.ones_like(x), x])
    kernel = kernel - trend @ np.linalg.lstsq(trend, kernel, rcond=None)[0]
    kernel /= np.linalg.norm(kernel)
    if e.size < 4 * kernel.size:  # too short a trial for the scan's spread to mean anything
        return None
    out = correlate(e, kernel, mode="valid")
    centred = np.abs(out - np.median(out))
    spread = 1.4826 * float(np.median(centred))
    if spread <= 0.0:
        return None
    return t, centred / spread, m


def revisit_differenced(theta_rad: np.ndarray, omega_rad_s: np.ndarray, residual: np.ndarray, bin_rad: float,
                        still_rad_s: float, min_passes: int = 3) -> np.ndarray:
    """``residual`` (N·m) less what the same state shows on every pass through it: the median, over the passes moving
    the same way (or resting) through the same angle bin of ``bin_rad``, of each pass's mean residual there; NaN where
    fewer than ``min_passes`` passes reach the bin. A pass is a run of samples moving one way (|ω| ≥ ``still_rad_s``)
    or resting.

    What a model gets wrong as a function of the state (a law's misfit at every reversal, a passive curve's at every
    pass, a stop's) recurs at each pass and cancels; an event of time (a burst) sits in one pass, which the median of
    three or more passes leaves out of the control (with two it would be their mean: half the event, and its echo in
    the other pass)."""
    theta = np.asarray(theta_rad, dtype=float)
    direction = np.where(np.abs(omega_rad_s) < still_rad_s, 0, np.sign(omega_rad_s)).astype(int)
    passes = np.concatenate([[0], np.cumsum(direction[1:] != direction[:-1])])
    bins = np.floor((theta - float(np.min(theta))) / bin_rad).astype(int)
    n_pass, n_bin = int(passes[-1]) + 1, int(bins.max()) + 1
    flat = passes * n_bin + bins
    ok = np.isfinite(residual)
    sums = np.bincount(flat[ok], weights=np.asarray(residual, dtype=float)[ok], minlength=n_pass * n_bin)
    counts = np.bincount(flat[ok], minlength=n_pass * n_bin)
    with np.errstate(invalid="ignore", divide="ignore"):
        table = (sums / counts).reshape(n_pass, n_bin)
    pass_direction = direction[np.searchsorted(passes, np.arange(n_pass))]
    control = np.full((n_pass, n_bin), np.nan)
    for d in (-1, 0, 1):
        rows = np.flatnonzero(pass_direction == d)
        if rows.size < min_passes:
            continue
        sub = table[rows]
        enough = np.isfinite(sub).sum(axis=0) >= min_passes
        if enough.any():
            control[np.ix_(rows, np.flatnonzero(enough))] = np.nanmedian(sub[:, enough], axis=0)
    return np.asarray(residual - control[passes, bins], dtype=float)


def revisited_share(t: np.ndarray, theta_rad: np.ndarray, omega_rad_s: np.ndarray, start_s: float, duration_s: float,
                    bin_rad: float, still_rad_s: float, min_passes: int = 2) -> float:
    """The share of a half-sine event of ``duration_s`` starting at ``start_s`` (weighted by its shape, over the samples
    moving at ``still_rad_s`` or faster) that lies in states the trial also reaches on other passes: angle bins of
    ``bin_rad`` that at least ``min_passes`` passes moving the same way reach (:func:`revisit_differenced`'s passes and
    bins). An event at angles the trial moves through only then is a function of time or of those angles alike: no
    model in angle can be checked against it elsewhere. Resting samples are not weighed: a joint turning back short of
    its end rests at an angle once, which every other pass crosses moving; an event within a rest is judged as before
    (1.0 when nothing moves in it)."""
    tt = np.asarray(t, dtype=float)
    theta = np.asarray(theta_rad, dtype=float)
    reached = np.isfinite(revisit_differenced(theta, omega_rad_s, np.zeros(theta.size), bin_rad, still_rad_s,
                                              min_passes))
    inside = (tt > start_s) & (tt < start_s + duration_s) & (np.abs(np.asarray(omega_rad_s, dtype=float)) >= still_rad_s)
    weight = np.sin(np.pi * (tt[inside] - start_s) / duration_s)
    total = float(weight.sum())
    return float(np.dot(weight, reached[inside])) / total if total > 0.0 else 1.0


def _level(times: np.ndarray, duration_s: float, alpha: float, searched_durations: int) -> float:
    """The scan's family-wise level: Gaussian, two-sided, at ``alpha`` over the trial's independent windows (its
    length over ``duration_s``) times the ``searched_durations``."""
    windows = max(float(times[-1] - times[0]) / duration_s, 1.0) * max(searched_durations, 1)
    return float(norm.isf(alpha / 2.0 / windows))


def isolated_transient(t: np.ndarray, residual: np.ndarray, start_s: float, duration_s: float, alpha: float,
                       searched_durations: int) -> TransientScan:
    """How far the half-sine of ``duration_s`` starting at ``start_s`` stands out of ``residual`` (N·m at times ``t``
    in s) in :func:`scan`. The level is Gaussian, two-sided, at ``alpha`` family-wise over the trial's independent
    windows (its length over ``duration_s``) times the ``searched_durations`` a search tried. A second crossing more
    than two durations away says the residual holds recurring structure (a law's misfit at every reversal, a passive
    curve's at every pass), which one burst does not explain."""
    scanned = scan(t, residual, duration_s)
    if scanned is None:
        return TransientScan(0.0, 0.0, math.inf)
    times, z, m = scanned
    at = int(np.searchsorted(times, start_s)) - m
    near = z[max(at - m // 2, 0):max(min(at + m // 2 + 1, z.size), 0)]
    away = np.ones(z.size, dtype=bool)
    away[max(at - 2 * m, 0):max(min(at + 2 * m + 1, z.size), 0)] = False
    return TransientScan(float(near.max()) if near.size else 0.0, float(z[away].max()) if away.any() else 0.0,
                         _level(times, duration_s, alpha, searched_durations))




@dataclass(frozen=True)
class _StepBasis:
    """A basis's orthonormal columns Q, their suffix sums (row i: Σ_{j≥i} Q_j, which is Qᵀ of a hard step at i) and a
    target's residual on them: made once, so every set of steps beside the basis costs O(n·p) and no factorisation."""

    q: np.ndarray
    suffix_q: np.ndarray
    suffix_q_norm2: np.ndarray
    residual: np.ndarray

    @classmethod
    def of(cls, x: np.ndarray, y: np.ndarray) -> _StepBasis:
        q, _ = np.linalg.qr(x)
        suffix_q = np.cumsum(q[::-1], axis=0)[::-1]
        return cls(q, suffix_q, np.sum(suffix_q * suffix_q, axis=1), y - q @ (q.T @ y))

    def steps(self, at: list[int]) -> np.ndarray:
        """Orthonormal columns (n, len(at)) spanning hard steps at the sample indices ``at``, orthogonal to Q."""
        n = self.q.shape[0]
        out = np.zeros((n, 0))
        for i in at:
            v = (np.arange(n) >= i).astype(float) - self.q @ self.suffix_q[i]
            v -= out @ (out.T @ v)
            norm = float(np.linalg.norm(v))
            if norm > 1e-9 * math.sqrt(n):
                out = np.column_stack([out, v / norm])
        return out


def _best_step(basis: _StepBasis, tt: np.ndarray, steps: list[int], min_level_s: float) -> tuple[int, float]:
    """The sample index where a hard step beside ``basis`` and hard steps at ``steps`` most lowers the residual sum of
    squares, and by how much (-inf: no place far enough from the ends and the others). Every candidate at once: for a
    step at sample i the gain is (Σ_{j≥i} r_j)² / ‖(I − QQᵀ) h_i‖², with suffix sums of the residual r and of the
    orthonormal columns Q's rows."""
    n = tt.size
    u = basis.steps(steps)
    r = basis.residual - u @ (u.T @ basis.residual)
    suffix_r = np.cumsum(r[::-1])[::-1]
    suffix_u = np.cumsum(u[::-1], axis=0)[::-1]
    norm = (n - np.arange(n)) - basis.suffix_q_norm2 - np.sum(suffix_u * suffix_u, axis=1)
    allowed = (tt - tt[0] >= min_level_s) & (tt[-1] - tt >= min_level_s)
    for i in steps:
        allowed &= np.abs(tt - tt[i]) >= min_level_s
    gain = np.where(allowed & (norm > 1e-9 * n), suffix_r ** 2 / np.maximum(norm, 1e-300), -np.inf)
    best = int(np.argmax(gain))
    return best, float(gain[best])


def offset_steps(t: np.ndarray, basis: np.ndarray, y: np.ndarray, min_level_s: float, max_steps: int,
                 widths_s: tuple[float, ...]) -> list[list[tuple[float, float]]]:
    """For each count k = 1, 2, … up to ``max_steps``, the k steps in ``y`` (N·m) beside the columns of ``basis``
    (n, p) that lower its residual sum of squares most, as (time, width) in s, searched forward and back: the k − 1
    before and the best next one (:func:`_best_step`), each then moved in turn to its best place given the others,
    twice over; then, from the largest count down, each set replaced by the one larger less its least needed step
    (moved likewise) where that fits better (a greedy order alone takes the middle of a staircase first). No level
    held shorter than ``min_level_s`` (between two steps, or from a trial's end). Each step's width is the linear ramp
    among ``widths_s`` that best fits its own step, put back into the residual, within ``min_level_s`` / 2, and no
    wider than leaves the levels beside it ``min_level_s`` before its ramp starts (the first width always allowed).
    Rows with a NaN are skipped; a list shorter than ``max_steps`` where no more fit.

    An offset that jumps (a knocked cable, a loose connector, an auto-zero) is a function of time: at a state the trial
    passes through before and after the jump the torque differs by the jump, which a function of the state does
    not. How many steps a trial holds is the criterion's to judge (each step's time and width counted as parameters)."""
    tt = np.asarray(t, dtype=float)
    ok = np.isfinite(tt) & np.isfinite(y) & np.all(np.isfinite(basis), axis=1)
    tt, yy, x = tt[ok], np.asarray(y, dtype=float)[ok], np.asarray(basis, dtype=float)[ok]
    if tt.size < 8:
        return []
    basis_once = _StepBasis.of(x, yy)
    sets: list[list[int]] = []
    steps: list[int] = []
    for _ in range(max_steps):  # forward: the sets before, one step more, each moved to its best place
        nxt, gain = _best_step(basis_once, tt, steps, min_level_s)
        if not np.isfinite(gain) or gain <= 0.0:
            break
        steps = _exchanged(basis_once, tt, [*steps, nxt], min_level_s)
        sets.append(steps)
    for k in range(len(sets) - 2, -1, -1):  # backward: each set against the one larger less its least needed step
        larger = sets[k + 1]
        fewer = min(([i for i in larger if i != drop] for drop in larger), key=lambda s: _rss(basis_once, s))
        fewer = _exchanged(basis_once, tt, fewer, min_level_s)
        if _rss(basis_once, fewer) < _rss(basis_once, sets[k]):
            sets[k] = fewer
    return [_with_widths(basis_once, yy, tt, steps, min_level_s, widths_s) for steps in sets]


def _rss(basis: _StepBasis, steps: list[int]) -> float:
    """The residual sum of squares beside ``basis`` and hard steps at the sample indices ``steps``."""
    u = basis.steps(steps)
    r = basis.residual - u @ (u.T @ basis.residual)
    return float(r @ r)


def _exchanged(basis: _StepBasis, tt: np.ndarray, steps: list[int], min_level_s: float) -> list[int]:
    """``steps`` with each in turn moved to its best place given the others, twice over, sorted."""
    steps = list(steps)
    for _round in range(2):
        for k in range(len(steps)):
            moved, moved_gain = _best_step(basis, tt, steps[:k] + steps[k + 1:], min_level_s)
            if np.isfinite(moved_gain):
                steps[k] = moved
    return sorted(steps)


def _with_widths(basis: _StepBasis, y: np.ndarray, tt: np.ndarray, steps: list[int], min_level_s: float,
                 widths_s: tuple[float, ...]) -> list[tuple[float, float]]:
    """(time, width) of hard steps at the sample indices ``steps``: each width the ramp among ``widths_s`` fitting best,
    with a level, that step's own fitted part put back into the whole fit's residual within ``min_level_s`` / 2."""
    n = tt.size
    u = basis.steps(steps)
    r = basis.residual - u @ (u.T @ basis.residual)
    # each step's own coefficient: the hard steps' least squares on what the basis leaves (their span is u's)
    hard = np.column_stack([(np.arange(n) >= i).astype(float) - basis.q @ basis.suffix_q[i] for i in steps])
    coef = np.linalg.lstsq(hard, basis.residual, rcond=None)[0]
    out = []
    edges = [float(tt[0]), *(float(tt[i]) for i in steps), float(tt[-1])]
    for k, i in enumerate(steps):
        at = 0.5 * float(tt[i - 1] + tt[i])
        near = np.abs(tt - at) <= 0.5 * min_level_s
        local = r[near] + coef[k] * (tt[near] >= tt[i])
        # no wider than keeps the levels beside it flat for min_level_s: ramps chained at the shortest spacing are a
        # smooth curve in time, not jumps
        room = 2.0 * (min(edges[k + 1] - edges[k], edges[k + 2] - edges[k + 1]) - min_level_s)
        best = (math.inf, float(widths_s[0]))
        for w in (w for w in widths_s if w <= max(room, 0.0) or w == widths_s[0]):
            design = np.column_stack([np.ones(int(near.sum())), ramp_step(tt[near], at, w)])
            res = local - design @ np.linalg.lstsq(design, local, rcond=None)[0]
            if float(res @ res) < best[0]:
                best = (float(res @ res), float(w))
        out.append((at, best[1]))
    return out


def ramp_step(t: np.ndarray, at_s: float, width_s: float) -> np.ndarray:
    """0 before and 1 after a linear ramp of ``width_s`` (s) centred on ``at_s`` (a plain step for a width of 0)."""
    tt = np.asarray(t, dtype=float)
    if width_s <= 0.0:
        return (tt >= at_s).astype(float)
    return np.clip((tt - at_s) / width_s + 0.5, 0.0, 1.0)


__all__ = ["TransientScan", "isolated_transient", "offset_steps", "ramp_step", "revisit_differenced", "revisited_share",
           "scan"]
