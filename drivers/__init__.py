"""Device drivers: force plate (serial), dynamometer (CAN), torque sensor (Modbus RTU).

Devices are opened by URL; each kind has a small abstract base and a back-end table with lazy
import, so a missing vendor library breaks only its own back end::

    from drivers import open_force_plate, open_dynamometer, open_torque_sensor
"""

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

__all__ = [
    "CommandRefusedError", "ConnectionLostError", "CounterResyncError", "DeviceInitializationError", "DeviceNotAvailableError",
    "DeviceOperationError", "DeviceStats", "DeviceTimeoutError", "DriverError", "Dynamometer",
    "DynamometerBlock", "DynamometerLimits", "ForcePlate", "ForcePlateBlock", "LimitViolationError",
    "MarkerBlock", "MarkerStream", "open_marker_stream",
    "SampleBlock", "StreamingDevice", "TorqueBlock", "TorqueSensor", "open_dynamometer", "open_force_plate",
    "open_torque_sensor",
]
