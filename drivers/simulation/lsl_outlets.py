"""Simulated LSL senders, as a Delsys-like system puts them on the network: a two-channel goniometer
(hip and knee flexion, degrees, 148 Hz) and an EMG system (four muscles, volts, 1111 Hz) whose relaxed
baseline noise carries one activation burst at a seeded time. Each sender stamps its samples on LSL's
clock at its own nominal rate and pushes chunks every 20 ms from a thread, like the vendors' apps.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from ..lsl import import_pylsl

#: Delsys Trigno's published rates: goniometer 148.148 Hz, EMG 1111.111 Hz
GONIOMETER_RATE_HZ = 148.148
EMG_RATE_HZ = 1111.111


@dataclass
class EmgBurst:
    """An activation: the envelope rises to ``amplitude_v`` (RMS, V) for ``duration_s`` from ``start_s``
    (seconds after the sender started), on channel ``channel``."""

    start_s: float
    duration_s: float
    amplitude_v: float
    channel: int = 0


@dataclass
class SimulatedLslSender:
    """One simulated LSL outlet (see the module docstring)."""

    name: str
    stream_type: str
    labels: tuple[str, ...]
    unit: str
    rate_hz: float
    source_id: str
    #: the sender's constant channel values (goniometer) or None for EMG noise
    level: tuple[float, ...] | None = None
    noise: float = 0.0
    bursts: list[EmgBurst] = field(default_factory=list)
    seed: int = 0

    def __post_init__(self) -> None:
        pylsl = import_pylsl()
        info = pylsl.StreamInfo(self.name, self.stream_type, len(self.labels), self.rate_hz, pylsl.cf_float32,
                                self.source_id)
        channels = info.desc().append_child("channels")
        for label in self.labels:
            ch = channels.append_child("channel")
            ch.append_child_value("label", label)
            ch.append_child_value("unit", self.unit)
        info.desc().append_child_value("manufacturer", "simulated (Delsys-like)")
        self._outlet = pylsl.StreamOutlet(info, chunk_size=0, max_buffered=60)
        self._rng = np.random.default_rng(self.seed)
        self._stop = threading.Event()
        self._pushed = 0
        self._clock = pylsl.local_clock
        self._t0 = self._clock()
        self._thread = threading.Thread(target=self._run, name=f"lsl-{self.name}", daemon=True)
        self._thread.start()

    @property
    def clock_origin_s(self) -> float:
        """The sender's start on LSL's clock (s): its sample k is stamped ``clock_origin_s + k / rate_hz``."""
        return self._t0

    @property
    def pushed(self) -> int:
        """Samples sent so far."""
        return self._pushed

    def burst_after(self, delay_s: float, duration_s: float = 0.3, amplitude_v: float = 40e-6,
                    channel: int = 0) -> EmgBurst:
        """An activation ``delay_s`` from now on the sender's clock (a subject tensing during a sweep)."""
        burst = EmgBurst(self._clock() - self._t0 + delay_s, duration_s, amplitude_v, channel)
        self.bursts.append(burst)
        return burst

    def values(self, t_s: np.ndarray) -> np.ndarray:
        """The channels at sender times ``t_s`` (s since start), shape (n, channels)."""
        n, k = t_s.size, len(self.labels)
        base = np.zeros((n, k)) if self.level is None else np.tile(np.asarray(self.level, dtype=float), (n, 1))
        out = base + self.noise * self._rng.standard_normal((n, k))
        for b in self.bursts:
            inside = (t_s >= b.start_s) & (t_s < b.start_s + b.duration_s)
            out[inside, b.channel] += b.amplitude_v * self._rng.standard_normal(int(inside.sum()))
        return out

    def _run(self) -> None:
        while not self._stop.wait(0.02):
            due = int((self._clock() - self._t0) * self.rate_hz)
            if due <= self._pushed:
                continue
            k = np.arange(self._pushed, due)
            t = k / self.rate_hz
            stamps = self._t0 + t
            self._outlet.push_chunk(self.values(t).tolist(), stamps.tolist())
            self._pushed = due

    def close(self) -> None:
        self._stop.set()
        self._thread.join(1.0)
        del self._outlet


def goniometer(source_id: str, *, hip_deg: float = 55.0, knee_deg: float = 0.0, seed: int = 0) -> SimulatedLslSender:
    """A two-channel electro-goniometer (hip and knee flexion, deg) held at ``hip_deg`` / ``knee_deg``."""
    return SimulatedLslSender("Goniometer", "Angle", ("hip_flexion", "knee_flexion"), "degrees", GONIOMETER_RATE_HZ,
                              source_id, level=(hip_deg, knee_deg), noise=0.2, seed=seed)


def emg(source_id: str, *, burst_at_s: float | None = None, seed: int = 0) -> SimulatedLslSender:
    """Four EMG channels (V) of a relaxed subject, 5 µV RMS, with one 40 µV burst on channel 0 at ``burst_at_s``
    (or at a time drawn from ``seed`` between 1 and 3 s when ``burst_at_s`` is None and ``seed`` > 0)."""
    if burst_at_s is None and seed > 0:
        burst_at_s = float(np.random.default_rng([seed, 7]).uniform(1.0, 3.0))
    bursts = [EmgBurst(burst_at_s, 0.3, 40e-6)] if burst_at_s is not None else []
    return SimulatedLslSender("EMG", "EMG", ("rectus_femoris", "biceps_femoris", "gastrocnemius", "soleus"), "V",
                              EMG_RATE_HZ, source_id, noise=5e-6, bursts=bursts, seed=seed)
