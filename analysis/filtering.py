"""Zero-lag low-pass filtering and differentiation of sampled signals with gaps (SI units).

The filter is a Butterworth low-pass of 2nd order run forward and backward (``sosfiltfilt``), so
4th order overall and without phase lag. A double pass moves the −3 dB point down; the design
cutoff is raised by 1/0.802 (Winter, *Biomechanics and Motor Control of Human Movement*, 4th
ed., §3.4.4.3) so that the filtered signal is −3 dB at the cutoff the caller asked for.
Signals are filtered run by run: samples that are NaN split the signal, and a run too short to
filter (fewer than 16 samples) is returned as NaN, never as unfiltered data.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np
from scipy import signal

from .errors import InputError

#: Winter's correction for a 2nd-order Butterworth run twice
DOUBLE_PASS_CORRECTION = 0.802
MIN_RUN_SAMPLES = 16


def finite_runs(valid: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) index pairs of the runs of True in ``valid``."""
    v = np.concatenate([[False], np.asarray(valid, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(v.astype(np.int8)))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


@lru_cache(maxsize=64)
def _butter_sos(cutoff_hz: float, rate_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """The filter's sections and their steady-state initial conditions (``sosfilt_zi``), designed once."""
    sos = signal.butter(2, cutoff_hz, fs=rate_hz, output="sos")
    return sos, signal.sosfilt_zi(sos)


def _sosfiltfilt(sos: np.ndarray, zi: np.ndarray, x: np.ndarray, padlen: int) -> np.ndarray:
    """``scipy.signal.sosfiltfilt(sos, x, axis=0, padtype="odd", padlen=padlen)`` with its initial
    conditions designed once (the same operations; what scipy recomputes on every call is not)."""
    ext = np.concatenate([2 * x[:1] - x[padlen:0:-1], x, 2 * x[-1:] - x[-2:-(padlen + 2):-1]], axis=0) \
        if padlen > 0 else x
    z = zi.reshape(zi.shape[0], 2, *([1] * (x.ndim - 1)))
    y, _ = signal.sosfilt(sos, ext, axis=0, zi=z * ext[:1])
    y, _ = signal.sosfilt(sos, y[::-1], axis=0, zi=z * y[-1:])
    y = y[::-1]
    return y[padlen:-padlen] if padlen > 0 else y


def lowpass(x: np.ndarray, rate_hz: float, cutoff_hz: float) -> np.ndarray:
    """Zero-lag 4th-order Butterworth low-pass along axis 0; NaN rows split the signal into runs.

    :param x: samples (n, ...) at ``rate_hz``.
    :raises InputError: the cutoff is not below the Nyquist frequency.
    """
    x = np.asarray(x, dtype=float)
    corrected = cutoff_hz / DOUBLE_PASS_CORRECTION
    if not 0 < corrected < 0.5 * rate_hz:
        raise InputError(f"low-pass cutoff {cutoff_hz} Hz (corrected {corrected:.2f} Hz) must be in (0, "
                         f"{0.5 * rate_hz:.1f}) Hz at {rate_hz} Hz sampling")
    sos, zi = _butter_sos(round(corrected, 12), round(float(rate_hz), 12))
    flat = x.reshape(x.shape[0], -1)
    out = np.full_like(flat, np.nan)
    valid = np.all(np.isfinite(flat), axis=1)
    for a, b in finite_runs(valid):
        if b - a >= MIN_RUN_SAMPLES:
            out[a:b] = _sosfiltfilt(sos, zi, flat[a:b], padlen=min(b - a - 1, 3 * 7))
    return out.reshape(x.shape)


def _together(signals: list[np.ndarray], each: Callable[[np.ndarray], np.ndarray]) -> list[np.ndarray]:
    """``each`` (a column-wise operation along axis 0 that splits at NaN rows) over several signals
    sampled together, in as few calls as their gaps allow: signals whose NaN rows are the same go
    as one array (each column is processed on its own either way, so the result is the same as
    one call per signal)."""
    arrays = [np.asarray(x, dtype=float) for x in signals]
    groups: dict[bytes, list[int]] = {}
    for i, x in enumerate(arrays):
        valid = np.all(np.isfinite(x.reshape(x.shape[0], -1)), axis=1)
        groups.setdefault(np.packbits(valid).tobytes() + x.shape[0].to_bytes(8, "little"), []).append(i)
    out: list[np.ndarray] = [np.empty(0)] * len(arrays)
    for members in groups.values():
        flat = [arrays[i].reshape(arrays[i].shape[0], -1) for i in members]
        done = each(np.concatenate(flat, axis=1))
        at = 0
        for i, f in zip(members, flat):
            out[i] = done[:, at:at + f.shape[1]].reshape(arrays[i].shape)
            at += f.shape[1]
    return out


def lowpass_together(signals: list[np.ndarray], rate_hz: float, cutoff_hz: float) -> list[np.ndarray]:
    """:func:`lowpass` of several signals sampled together (one filter call per pattern of gaps)."""
    return _together(signals, lambda x: lowpass(x, rate_hz, cutoff_hz))


def derivative_together(signals: list[np.ndarray], dt_s: float) -> list[np.ndarray]:
    """:func:`derivative` of several signals sampled together (one call per pattern of gaps)."""
    return _together(signals, lambda x: derivative(x, dt_s))


def derivative(x: np.ndarray, dt_s: float) -> np.ndarray:
    """Time derivative along axis 0 by second-order central differences, within finite runs (NaN elsewhere)."""
    x = np.asarray(x, dtype=float)
    flat = x.reshape(x.shape[0], -1)
    out = np.full_like(flat, np.nan)
    valid = np.all(np.isfinite(flat), axis=1)
    for a, b in finite_runs(valid):
        if b - a >= 3:
            out[a:b] = np.gradient(flat[a:b], dt_s, axis=0, edge_order=2)
    return out.reshape(x.shape)
