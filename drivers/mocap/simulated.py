"""``sim://NAME``: the driver side of :class:`~drivers.mocap.simulator.MarkerSimulator`."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from ..blocks import MarkerBlock
from ..errors import ConnectionLostError, DeviceNotAvailableError
from ..url import DeviceUrl
from . import MarkerStream
from .simulator import MarkerSimulator, find_simulator


class SimulatedMarkerStream(MarkerStream):
    """Reads frames from a registered :class:`MarkerSimulator` as they fall due (polled every 10 ms)."""

    def __init__(self, source: str, *, rate: int = 100, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.source = source
        self.rate_hz = rate
        self._sim: MarkerSimulator | None = None
        self._next_frame = 0

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> SimulatedMarkerStream:
        opts = url.take({"rate": int})
        return cls(url.host or url.path.strip("/"), **{**opts, **kwargs})  # type: ignore[arg-type]  # URL options are strings the constructor parses

    def _open_internal(self) -> None:
        sim = find_simulator(self.source)
        if sim is None:
            raise DeviceNotAvailableError(f"{self.name}: no simulated motion-capture source {self.source!r}")
        if sim.rate_hz != self.rate_hz:
            raise DeviceNotAvailableError(f"{self.name}: source runs at {sim.rate_hz} Hz, asked for {self.rate_hz} Hz")
        self._sim = sim
        self.labels = sim.labels

    def _on_stream_start(self) -> None:
        assert self._sim is not None
        self._next_frame = self._sim.frames_due(time.monotonic())

    def _read_internal(self) -> MarkerBlock | None:
        sim = self._sim
        if sim is None or sim.vanished or find_simulator(self.source) is None:
            raise ConnectionLostError(f"{self.name}: motion-capture source {self.source!r} went away")
        due = sim.frames_due(time.monotonic())
        if due <= self._next_frame:
            time.sleep(0.01)
            return None
        counter = np.arange(self._next_frame, due, dtype=np.int64)
        self._next_frame = due
        t = sim.time_origin_s + counter / sim.rate_hz
        return MarkerBlock(self.name, counter, t, sim.frames(int(counter[0]), len(counter)))

    def _close_internal(self) -> None:
        self._sim = None

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        # its sync output, wired to the force plate amplifier's trigger input: a pulse on every frame
        # whose counter is a multiple of this (once a second)
        d.update(source=self.source, rate_hz=self.rate_hz, labels=list(self.labels), units="m",
                 sync_pulse_every_frames=int(self.rate_hz))
        return d
