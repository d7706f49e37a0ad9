"""Rotary torque transducers behind an RS-485 Modbus RTU transmitter (DYJN-104 + ATO-type).

Open by URL::

    open_torque_sensor("modbus-rtu:///dev/ttyUSB0?unit=1&baud=115200&word_order=big")
    open_torque_sensor("modbus-rtu+socket://127.0.0.1:5021?unit=1&baud=115200")  # RTU over a TCP cable
    open_torque_sensor("modbus-tcp://127.0.0.1:5020?unit=1")                       # Modbus TCP gateway
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any, ClassVar

from ..base import StreamingDevice
from ..blocks import TorqueBlock
from ..url import DeviceUrl, load_backend

_MODBUS = ("drivers.torque.modbus_driver", "ModbusTorqueSensor")
#: scheme -> (module, class); imported only when asked for
BACKENDS: dict[str, tuple[str, str]] = {"modbus-rtu": _MODBUS, "modbus-rtu+socket": _MODBUS, "modbus-tcp": _MODBUS}


class TorqueSensor(StreamingDevice):
    """A polled torque sensor: streams :class:`~drivers.blocks.TorqueBlock` in N·m."""

    kind: ClassVar[str] = "torque_sensor"
    block_type = TorqueBlock

    @abstractmethod
    def tare(self) -> float:
        """Zero the sensor at the current reading; returns the new zero offset (N·m)."""

    @property
    @abstractmethod
    def poll_rate_limit_hz(self) -> float:
        """Highest poll rate the link allows (Hz)."""


def open_torque_sensor(url: str, **kwargs: Any) -> TorqueSensor:
    """Make (not yet open) the torque sensor driver for ``url``.

    :raises DeviceNotAvailableError: unknown scheme.
    :raises ValueError: unknown URL option or a rate the baud cannot carry.
    """
    parsed = DeviceUrl.parse(url)
    cls = load_backend(BACKENDS, parsed, "torque sensor")
    return cls.from_url(parsed, **kwargs)  # type: ignore[attr-defined]  # every backend has one
