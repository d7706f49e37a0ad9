"""Where a trial's devices come from: the lab's hardware by URL (Qt-free).

A source hands out opened-on-demand drivers for one protocol inside a context; the GUI and the
CLI hold it for the length of a trial. The simulated lab's source is
:class:`instrument.sim.source.SimulatedSource`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from drivers import StreamingDevice, open_device

from ..errors import ProtocolError
from ..kinds.base import TrialProtocol
from .lab import LabFile


class HardwareSource:
    """The lab's devices by URL (``force_plate``, ``dynamometer``, ``torque_sensor``, ``mocap``)."""

    simulated = False

    def __init__(self, urls: dict[str, str], lab: LabFile | None = None) -> None:
        self.urls = dict(urls)
        #: the lab file the URLs came from: its envelope goes to the dynamometer driver
        self.lab = lab
        #: a motion-capture stream configured: AADS trials get the live loop; else force-guided
        self.live_markers = "mocap" in self.urls

    @contextmanager
    def devices(self, protocol: TrialProtocol) -> Iterator[dict[str, StreamingDevice]]:
        missing = [n for n in protocol.devices if n not in self.urls]
        if missing:
            raise ProtocolError(f"no URL configured for {', '.join(missing)} (needed by {protocol.name})")
        devices = {n: self.lab.open(n) if self.lab is not None else open_device(n, self.urls[n])
                   for n in protocol.devices}
        if self.lab is not None:  # other systems' streams, recorded into every trial beside the devices
            devices.update({n: self.lab.open(n) for n in self.lab.streams})
        try:
            yield devices
        finally:
            for d in devices.values():
                d.close()

    def metadata(self) -> dict[str, Any]:
        return {"simulated": False, **({"lab_file": str(self.lab.path)} if self.lab is not None else {})}

    @classmethod
    def from_lab_file(cls, path: str | Path) -> HardwareSource:
        """The devices of a lab file (:class:`instrument.live.lab.LabFile`), with its envelope."""
        lab = LabFile.load(path)
        return cls(lab.devices, lab)


__all__ = ["HardwareSource"]
