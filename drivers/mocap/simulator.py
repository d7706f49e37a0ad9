"""A motion-capture system watching the AADS jig: marker noise and occlusions, registered by name.

Like python-can's virtual bus, a simulator registers itself in a process-wide table and the
``sim://NAME`` back end finds it there. Frame ``k`` shows the jig at ``k / rate_hz`` seconds after
the simulator's time origin, which the lab shares with the force plate simulator (the optical
system and the plate amplifier are hardware-synchronised in a real lab too).
"""

from __future__ import annotations

import itertools
import threading
import time

import numpy as np

from ..simulation.aads_jig import AadsJig

_registry: dict[str, MarkerSimulator] = {}
_registry_lock = threading.Lock()
_ids = itertools.count()


def find_simulator(name: str) -> MarkerSimulator | None:
    with _registry_lock:
        return _registry.get(name)


class MarkerSimulator:
    """Markers of ``jig`` at ``rate_hz``.

    :param noise_m: marker position noise SD (m) per axis.
    :param occlusion_rate: probability per marker per frame of a missing (NaN) marker.
    :param time_origin_s: ``time.monotonic()`` of frame 0 (default: now).
    """

    def __init__(self, jig: AadsJig, rate_hz: int = 100, *, noise_m: float = 2e-4, occlusion_rate: float = 0.0,
                 time_origin_s: float | None = None, seed: int = 0, name: str | None = None) -> None:
        self.jig = jig
        self.rate_hz = rate_hz
        self.noise_m = noise_m
        self.occlusion_rate = occlusion_rate
        self.time_origin_s = time.monotonic() if time_origin_s is None else time_origin_s
        self.rng = np.random.default_rng(seed + 7)
        self.labels = tuple(jig.state(np.zeros(1)).markers_m)
        self.name = name or f"markers-{next(_ids)}"
        self.vanished = False
        self._table: np.ndarray | None = None
        #: the frame at which the operator began the trial's bends (see ForcePlateSimulator.begin_bends)
        self.bend_origin: int | None = None
        #: held while frames are drawn, so that the lab's :meth:`SimulatedLab.begin_bends` starts the
        #: bends at a frame no driver has read yet
        self.lock = threading.Lock()
        #: one past the newest frame any driver has read
        self.frames_served = 0
        self._noise_table: np.ndarray | None = None
        self._noise_seed = seed + 7
        with _registry_lock:
            _registry[self.name] = self

    @property
    def url(self) -> str:
        return f"sim://{self.name}?rate={self.rate_hz}"

    def frames_due(self, now_s: float) -> int:
        """Frames the system has captured up to host monotonic time ``now_s``."""
        return int((now_s - self.time_origin_s) * self.rate_hz)

    def frames(self, first: int, count: int) -> np.ndarray:
        """Noisy marker positions (count, markers, 3) in m for frames ``first``..``first+count-1``."""
        with self.lock:
            self.frames_served = max(self.frames_served, first + count)
            return self._frames(first, count)

    def _frames(self, first: int, count: int) -> np.ndarray:
        n = int(round(self.jig.profile.duration_s * self.rate_hz))
        if self._table is None:
            st = self.jig.state(np.arange(n) / self.rate_hz)
            self._table = np.stack([st.markers_m[k] for k in self.labels], axis=1)
        frames = np.arange(first, first + count)
        index = frames % n if self.bend_origin is None else np.clip(frames - self.bend_origin, 0, n - 1)
        pos = self._table[index].copy()
        if self.noise_m > 0:
            if self.bend_origin is None:
                pos += self.rng.normal(0.0, self.noise_m, pos.shape)
            else:  # drawn per frame from the bends' start: the same trial whenever the host reads it
                if self._noise_table is None:
                    self._noise_table = np.random.default_rng(self._noise_seed).normal(0.0, 1.0, (1 << 14, *pos.shape[1:]))
                pos += self.noise_m * self._noise_table[(frames - self.bend_origin) % (1 << 14)]
        if self.occlusion_rate > 0:
            pos[self.rng.random(pos.shape[:2]) < self.occlusion_rate] = np.nan
        return pos

    def close(self) -> None:
        with _registry_lock:
            _registry.pop(self.name, None)
