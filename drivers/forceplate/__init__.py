"""Force plate amplifiers (AMTI-Optima/Gen5-class): six channels, 10–2000 Hz, framed serial stream.

Open by URL::

    open_force_plate("serial:///dev/ttyACM0?baud=921600&rate=1000")
    open_force_plate("socket://127.0.0.1:5555")          # the simulator, or a serial-to-TCP bridge
    open_force_plate("/dev/pts/4")                        # a bare device path means serial://
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any, ClassVar

import numpy as np

from ..base import StreamingDevice
from ..blocks import ForcePlateBlock
from ..url import DeviceUrl, load_backend

#: scheme -> (module, class); modules are imported only when asked for
BACKENDS: dict[str, tuple[str, str]] = {
    "serial": ("drivers.forceplate.serial_driver", "SerialForcePlate"),
    "socket": ("drivers.forceplate.serial_driver", "SerialForcePlate"),
    "rfc2217": ("drivers.forceplate.serial_driver", "SerialForcePlate"),
}


class ForcePlate(StreamingDevice):
    """A force plate: streams :class:`~drivers.blocks.ForcePlateBlock` in N and N·m."""

    kind: ClassVar[str] = "force_plate"
    block_type = ForcePlateBlock

    @abstractmethod
    def tare(self, samples: int = 200, timeout_s: float = 5.0) -> np.ndarray:
        """Zero the plate: average ``samples`` unloaded samples into new zero offsets (V), returned."""

    @property
    @abstractmethod
    def rate_hz(self) -> float:
        """Sample rate in Hz."""


def open_force_plate(url: str, **kwargs: Any) -> ForcePlate:
    """Make (not yet open) the force plate driver for ``url``.

    :raises DeviceNotAvailableError: unknown scheme or back end not importable.
    :raises ValueError: unknown URL option.
    """
    if "://" not in url:
        url = f"serial://{url}"
    parsed = DeviceUrl.parse(url)
    cls = load_backend(BACKENDS, parsed, "force plate")
    return cls.from_url(parsed, **kwargs)  # type: ignore[attr-defined]  # every backend has one
