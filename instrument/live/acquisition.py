"""The acquisition engine: any set of devices, one clock, one start and stop, recording and live views.

Each device's driver already reads on its own thread (``StreamingDevice``); the engine adds one
pump thread per device that moves blocks to (1) the trial writer, whose queue never blocks, and
(2) a preallocated ring buffer per device that live consumers (GUI, relaxation check) copy from.
A slow consumer only sees older data; it cannot slow or block recording. Device errors (lost
link, silence) are recorded as events in the trial, in order with the data.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from drivers import DeviceStats, DeviceTimeoutError, DriverError, SampleBlock, StreamingDevice

from .recording import DeviceSpec, TrialWriter

log = logging.getLogger(__name__)

#: a live consumer of every block: (device name, channels) → None
Sink = Callable[[str, dict[str, np.ndarray]], None]


class RingBuffer:
    """The last ``capacity`` samples of each channel of one device, preallocated.

    Writers and readers hold the lock only for a memcpy; readers get copies.
    """

    def __init__(self, layout: dict[str, tuple[tuple[int, ...], str]], capacity: int) -> None:
        self.capacity = int(capacity)
        self._data = {k: np.zeros((self.capacity, *shape), dtype=dtype) for k, (shape, dtype) in layout.items()}
        self._lock = threading.Lock()
        self.total = 0  # samples ever written

    def write(self, channels: dict[str, np.ndarray]) -> None:
        n = len(channels["counter"])
        if n == 0:
            return
        with self._lock:
            start = self.total % self.capacity
            for k, buf in self._data.items():
                src = channels[k][-self.capacity:]
                m = src.shape[0]
                first = min(m, self.capacity - start)
                buf[start:start + first] = src[:first]
                if m > first:
                    buf[:m - first] = src[first:]
            self.total += n

    def latest(self, n: int | None = None) -> dict[str, np.ndarray]:
        """Copies of the last ``n`` samples (all held, if None), oldest first."""
        with self._lock:
            held = min(self.total, self.capacity)
            n = held if n is None else min(n, held)
            end = self.total % self.capacity
            idx = (np.arange(end - n, end)) % self.capacity
            return {k: buf[idx] for k, buf in self._data.items()}

    def since(self, total_mark: int) -> tuple[dict[str, np.ndarray], int]:
        """Samples written after ``total_mark`` (as returned before), and the new mark."""
        with self._lock:
            total = self.total
        return self.latest(total - total_mark), total


@dataclass
class DeviceReport:
    """What one device did during an acquisition."""

    name: str
    samples: int = 0
    errors: list[str] = field(default_factory=list)
    stats: dict[str, Any] = field(default_factory=dict)

    def counts(self) -> dict[str, int]:
        return {"samples": self.samples, "lost_samples": int(self.stats.get("lost_samples", 0)),
                "gaps": int(self.stats.get("gaps", 0))}


def device_health_text(name: str, state: str, stats: DeviceStats) -> str:
    """One device's part of the operator's health line: state, rate, gaps and lost samples, and, when
    there were any, unanswered polls (a slow host or a silent line) apart from bad frames (a damaged line), and
    commands the device answered only on a repeat (a lost reply: the operator sees it, nothing hides it)."""
    rate = stats.rate_hz()
    if not np.isfinite(rate):
        return f"{name}: {state}"
    text = f"{name}: {state}, {rate:.0f} Hz, {stats.gaps} gaps, {stats.lost_samples} lost"
    if stats.poll_timeouts:
        text += f", {stats.poll_timeouts} unanswered polls"
    bad = stats.crc_errors + stats.malformed_frames
    if bad:
        text += f", {bad} bad frames"
    if stats.command_retries:
        text += f", {stats.command_retries} commands answered only when sent again"
    return text


#: the devices' nominal sample rates (Hz), which size the ring buffers; one definition
NOMINAL_RATES_HZ = {"force_plate": 1000.0, "torque_sensor": 500.0, "dynamometer": 100.0, "mocap": 100.0}


class AcquisitionEngine:
    """Runs ``devices`` together, recording to ``writer`` (optional) and filling ring buffers.

    :param devices: name → opened-or-not driver (names become the trial's device names).
    :param ring_seconds: history each ring buffer holds, at the device's nominal rate.
    :param nominal_rates_hz: name → rate used to size the ring buffers, over :data:`NOMINAL_RATES_HZ`
        (a device named in neither: 1000 Hz).
    """

    def __init__(self, devices: dict[str, StreamingDevice], *, ring_seconds: float = 30.0,
                 nominal_rates_hz: dict[str, float] | None = None, sinks: list[Sink] | None = None) -> None:
        self.devices = devices
        #: live consumers beyond the rings (a Lab Streaming Layer outlet, ...): a sink that fails is
        #: dropped and logged; it never slows or stops the recording
        self.sinks: list[Sink] = list(sinks or [])
        self.ring_seconds = ring_seconds
        self.nominal_rates_hz = {**NOMINAL_RATES_HZ, **(nominal_rates_hz or {})}
        self.rings: dict[str, RingBuffer] = {}
        self.reports = {n: DeviceReport(n) for n in devices}
        self.writer: TrialWriter | None = None
        self._threads: list[threading.Thread] = []
        self._running = threading.Event()
        self.recording_error: Exception | None = None

    def open(self) -> None:
        """Open every device (before :meth:`specs`, so layouts with per-stream shapes are known)."""
        for dev in self.devices.values():
            dev.open()
        for name, dev in self.devices.items():
            cap = int(self.ring_seconds * self.nominal_rates_hz.get(name, 1000.0))
            self.rings[name] = RingBuffer(dev.channel_layout(), max(cap, 64))

    def specs(self) -> dict[str, DeviceSpec]:
        """Layout and identity (calibration, zero offsets, settings) of every device, for the trial file."""
        return {n: DeviceSpec(d.channel_layout(), d.identity()) for n, d in self.devices.items()}

    def start(self, writer: TrialWriter | None = None) -> None:
        """Start every device, then the pumps (a common start: no device's data is taken before)."""
        if not self.rings:
            self.open()
        self.writer = writer
        self._running.set()
        for dev in self.devices.values():
            dev.start()
        for name, dev in self.devices.items():
            t = threading.Thread(target=self._pump, args=(name, dev), name=f"pump-{name}", daemon=True)
            t.start()
            self._threads.append(t)

    def stop(self) -> dict[str, DeviceReport]:
        """Stop every device, move what is still queued, and report per device."""
        for dev in self.devices.values():
            dev.stop()
        self._running.clear()
        for t in self._threads:
            t.join(5.0)
        self._threads.clear()
        for name, dev in self.devices.items():
            blocks, errors = dev.read_available()
            for b in blocks:
                self._take(name, b)
            for e in errors:
                self._error(name, e)
            self.reports[name].stats = dev.stats.as_dict()
        return self.reports

    def close(self) -> None:
        for dev in self.devices.values():
            dev.close()

    # ------------------------------------------------------------------ pumps
    def _pump(self, name: str, dev: StreamingDevice) -> None:
        while self._running.is_set():
            try:
                block = dev.read(timeout=0.1)
            except DeviceTimeoutError as err:
                if "no data within" not in str(err):
                    self._error(name, err)
                continue
            except DriverError as err:
                self._error(name, err)
                continue
            self._take(name, block)

    def _take(self, name: str, block: SampleBlock) -> None:
        channels = block.channels()
        self.reports[name].samples += len(block)
        self.rings[name].write(channels)
        for sink in list(self.sinks):
            try:
                sink(name, channels)
            except Exception as err:  # a live consumer's failure must never reach the recording
                self.sinks.remove(sink)
                log.error("live sink %r dropped: %s", sink, err)
        if self.writer is not None and self.recording_error is None:
            try:
                self.writer.append(name, channels)
            except Exception as err:
                self.recording_error = err
                log.error("recording stopped: %s", err)

    def _error(self, name: str, err: DriverError) -> None:
        self.reports[name].errors.append(f"{type(err).__name__}: {err}")
        if self.writer is not None:
            self.writer.log_event("device_error", device=name, error=type(err).__name__, message=str(err))
