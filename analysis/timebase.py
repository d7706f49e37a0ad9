"""Streams of different rates on one time base: interpolation that never bridges a gap."""

from __future__ import annotations

import numpy as np


def uniform_grid(t_start_s: float, t_end_s: float, rate_hz: float) -> np.ndarray:
    """Sample times from ``t_start_s`` to at most ``t_end_s`` at ``rate_hz``."""
    n = int(np.floor((t_end_s - t_start_s) * rate_hz + 1e-9)) + 1
    return t_start_s + np.arange(max(n, 0)) / rate_hz


def resample(time_s: np.ndarray, values: np.ndarray, grid_s: np.ndarray, *, max_gap_s: float) -> np.ndarray:
    """Linear interpolation of ``values`` (n, ...) onto ``grid_s``; NaN outside the data and inside gaps.

    A grid point is NaN when its neighbouring samples are more than ``max_gap_s`` apart (a lost
    stretch is never papered over) or when either neighbour is NaN.
    """
    t = np.asarray(time_s, dtype=float)
    v = np.asarray(values, dtype=float)
    flat = v.reshape(v.shape[0], -1)
    out = np.full((grid_s.size, flat.shape[1]), np.nan)
    if t.size < 2:
        return out.reshape((grid_s.size, *v.shape[1:]))
    idx = np.clip(np.searchsorted(t, grid_s, side="right") - 1, 0, t.size - 2)
    t0, t1 = t[idx], t[idx + 1]
    w = (grid_s - t0) / (t1 - t0)
    ok = (grid_s >= t[0]) & (grid_s <= t[-1]) & (t1 - t0 <= max_gap_s)
    res = flat[idx] * (1 - w)[:, None] + flat[idx + 1] * w[:, None]
    out[ok] = res[ok]
    return out.reshape((grid_s.size, *v.shape[1:]))


def align(streams: dict[str, tuple[np.ndarray, np.ndarray, float]], rate_hz: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Put streams on one grid over the span they all cover.

    :param streams: name → (time_s, values, nominal rate Hz); gaps longer than 2.5 sample periods become NaN.
    :returns: (grid time_s, name → values on the grid).
    """
    start = max(float(t[0]) for t, _, _ in streams.values())
    end = min(float(t[-1]) for t, _, _ in streams.values())
    grid = uniform_grid(start, end, rate_hz)
    return grid, {n: resample(t, v, grid, max_gap_s=2.5 / r) for n, (t, v, r) in streams.items()}
