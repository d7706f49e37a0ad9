"""Where a trial's devices come from: the lab's hardware by URL (Qt-free).

A source hands out opened-on-demand drivers for one protocol inside a context; the GUI and the
CLI hold it for the length of a trial. The simulated lab's source is
:class:`instrument.sim.source.SimulatedSource`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from drivers import StreamingDevice, open_device

from ..errors import ProtocolError
from ..kinds.base import TrialProtocol


class HardwareSource:
    """The lab's devices by URL (``force_plate``, ``dynamometer``, ``torque_sensor``, ``mocap``)."""

    simulated = False

    def __init__(self, urls: dict[str, str]) -> None:
        self.urls = dict(urls)
        #: a motion-capture stream configured: AADS trials get the live loop; else force-guided
        self.live_markers = "mocap" in self.urls

    @contextmanager
    def devices(self, protocol: TrialProtocol) -> Iterator[dict[str, StreamingDevice]]:
        missing = [n for n in protocol.devices if n not in self.urls]
        if missing:
            raise ProtocolError(f"no URL configured for {', '.join(missing)} (needed by {protocol.name})")
        devices = {n: open_device(n, self.urls[n]) for n in protocol.devices}
        try:
            yield devices
        finally:
            for d in devices.values():
                d.close()

    def metadata(self) -> dict[str, Any]:
        return {"simulated": False}


__all__ = ["HardwareSource"]
