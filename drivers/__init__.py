"""Device drivers: force plate (serial), dynamometer (CAN), torque sensor (Modbus RTU).

Devices are opened by URL; each kind has a small abstract base and a back-end table with lazy
import, so a missing vendor library breaks only its own back end::

    from drivers import open_force_plate, open_dynamometer, open_torque_sensor
"""

from typing import Any

from .base import DeviceStats, StreamingDevice
from .blocks import DynamometerBlock, ForcePlateBlock, MarkerBlock, SampleBlock, TorqueBlock
from .dynamometer import Dynamometer, DynamometerLimits, open_dynamometer
from .errors import (
    CommandRefusedError,
    ConnectionLostError,
    CounterResyncError,
    DeviceInitializationError,
    DeviceNotAvailableError,
    DeviceOperationError,
    DeviceTimeoutError,
    DriverError,
    LimitViolationError,
)
from .forceplate import ForcePlate, open_force_plate
from .mocap import MarkerStream, open_marker_stream
from .torque import TorqueSensor, open_torque_sensor

#: the opener of each device kind a trial can ask for (``protocol.devices`` names them)
DEVICE_OPENERS = {"force_plate": open_force_plate, "dynamometer": open_dynamometer,
                  "torque_sensor": open_torque_sensor, "mocap": open_marker_stream}


def open_device(kind: str, url: str, **kwargs: Any) -> StreamingDevice:
    """The driver of a device of ``kind`` (``force_plate``, ``dynamometer``, ``torque_sensor``, ``mocap``) at ``url``.

    :raises DeviceNotAvailableError: no such kind of device, or no back end for the URL.
    """
    try:
        opener = DEVICE_OPENERS[kind]
    except KeyError:
        raise DeviceNotAvailableError(f"no device kind {kind!r}; one of {', '.join(DEVICE_OPENERS)}") from None
    return opener(url, **kwargs)  # type: ignore[no-any-return]  # each opener returns its kind's StreamingDevice

__all__ = [
    "DEVICE_OPENERS", "open_device", "CommandRefusedError", "ConnectionLostError", "CounterResyncError",
    "DeviceInitializationError", "DeviceNotAvailableError",
    "DeviceOperationError", "DeviceStats", "DeviceTimeoutError", "DriverError", "Dynamometer",
    "DynamometerBlock", "DynamometerLimits", "ForcePlate", "ForcePlateBlock", "LimitViolationError",
    "MarkerBlock", "MarkerStream", "open_marker_stream",
    "SampleBlock", "StreamingDevice", "TorqueBlock", "TorqueSensor", "open_dynamometer", "open_force_plate",
    "open_torque_sensor",
]
