"""Stream several devices at once for a fixed time and summarise what arrived (Qt-free)."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

import numpy as np

from drivers import DriverError, SampleBlock, StreamingDevice


@dataclass
class StreamResult:
    """What one device delivered during :func:`stream_devices`."""

    name: str
    blocks: list[SampleBlock] = field(default_factory=list)
    errors: list[DriverError] = field(default_factory=list)
    stats: dict[str, object] = field(default_factory=dict)

    @property
    def samples(self) -> int:
        return sum(len(b) for b in self.blocks)

    def channel(self, name: str) -> np.ndarray:
        return np.concatenate([getattr(b, name) for b in self.blocks]) if self.blocks else np.zeros(0)


def stream_devices(devices: dict[str, StreamingDevice], seconds: float) -> dict[str, StreamResult]:
    """Start every device, collect its blocks for ``seconds`` on one thread each, stop them all."""
    results = {name: StreamResult(name) for name in devices}
    stop = threading.Event()

    def collect(name: str, dev: StreamingDevice) -> None:
        res = results[name]
        while not stop.is_set():
            try:
                res.blocks.append(dev.read(timeout=0.2))
            except DriverError as err:
                if "no data within" not in str(err):
                    res.errors.append(err)
        blocks, errors = dev.read_available()
        res.blocks += blocks
        res.errors += errors

    for dev in devices.values():
        dev.start()
    threads = [threading.Thread(target=collect, args=(n, d), daemon=True) for n, d in devices.items()]
    for t in threads:
        t.start()
    time.sleep(seconds)
    for dev in devices.values():
        dev.stop()
    stop.set()
    for t in threads:
        t.join(2.0)
    for name, dev in devices.items():
        results[name].stats = dev.stats.as_dict()
    return results
