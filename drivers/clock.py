"""The one monotonic clock every driver stamps samples with, and device-to-host clock mapping."""

from __future__ import annotations

import time

import numpy as np


def monotonic_s() -> float:
    """Seconds on the host's monotonic clock (``time.monotonic``): the instrument's single time base."""
    return time.monotonic()


class CounterClock:
    """Maps a device sample counter to host monotonic time.

    Streams arrive in bursts, so arrival times jitter by milliseconds. The device's own counter
    ticks at a nominal rate; we estimate ``t = counter / rate + offset`` where ``offset`` is the
    smallest observed ``arrival - counter / rate`` (the least-delayed packet) over a sliding
    window, so the estimate follows slow drift between device and host clocks. A smaller offset
    is approached by at most half a sample period per block, so timestamps never run backwards.

    :param rate_hz: nominal device sample rate in Hz.
    :param window_s: how long an offset estimate is trusted, in seconds.
    :param resync_s: an arrival this far (s) from the estimate means the counter jumped: the
        clock anchors again on the arrival instead of stamping samples seconds away from it.
    """

    def __init__(self, rate_hz: float, window_s: float = 10.0, resync_s: float = 1.0) -> None:
        if rate_hz <= 0:
            raise ValueError(f"rate_hz must be > 0, got {rate_hz}")
        self.rate_hz = float(rate_hz)
        self.window_s = window_s
        self.resync_s = resync_s
        self._offset: float | None = None
        self._offset_time = 0.0

    def stamp(self, counters: np.ndarray, arrival_s: float) -> np.ndarray:
        """Timestamps in host seconds for ``counters`` (unwrapped) of a block that arrived at ``arrival_s``."""
        device_s = counters.astype(np.float64) / self.rate_hz
        candidate = arrival_s - float(device_s[-1])
        stale = arrival_s - self._offset_time > self.window_s
        if self._offset is not None and abs(candidate - self._offset) > self.resync_s:
            self._offset = None  # the counter jumped (device reset, corrupted counter): anchor again
        if self._offset is None or stale:
            self._offset = candidate if self._offset is None else max(candidate, self._offset)
            self._offset_time = arrival_s
        elif candidate < self._offset:
            self._offset = max(candidate, self._offset - 0.5 / self.rate_hz)
            self._offset_time = arrival_s
        return device_s + self._offset

    def reset(self) -> None:
        """Forget the offset (after a reconnection the device counter may restart)."""
        self._offset = None


class CounterUnwrapper:
    """Unwraps an ``bits``-bit wrapping device counter to an int64 by the signed modular step.

    Each reading moves the unwrapped value by the shortest step modulo ``2**bits`` from the
    previous reading (forward up to half the modulus, backward otherwise), so one corrupted or
    reset counter moves it once and the next good reading moves it back: it never shifts every
    later sample by a whole modulus.
    """

    def __init__(self, bits: int) -> None:
        self.modulus = 1 << bits
        self._last_raw: int | None = None
        self._value = 0

    def unwrap(self, raw: int) -> int:
        """Unwrapped value of one raw counter reading."""
        if self._last_raw is None:
            self._value = raw
        else:
            step = (raw - self._last_raw) % self.modulus
            self._value += step if step < self.modulus // 2 else step - self.modulus
        self._last_raw = raw
        return self._value

    def reset(self) -> None:
        """Start again (the device restarted its counter)."""
        self._last_raw = None
        self._value = 0
