"""One exception hierarchy for every driver.

``DriverError``
 ├── ``DeviceNotAvailableError``   back end missing (import failed) or URL scheme unknown
 ├── ``DeviceInitializationError`` device found but could not be opened or configured
 ├── ``DeviceOperationError``      an operation failed on an open device
 │    ├── ``ConnectionLostError``  the link vanished mid-stream (the driver keeps reconnecting)
 │    ├── ``CounterResyncError``   the device counter jumped implausibly; the samples were kept
 │    └── ``CommandRefusedError``  the device answered a command with a refusal
 ├── ``DeviceTimeoutError``        the device stayed silent (also a ``TimeoutError``)
 └── ``LimitViolationError``       a command outside the configured safety limits (also a ``ValueError``);
                                   refused by the driver before anything is sent

Foreign exceptions (``serial.SerialException``, ``can.CanError``, ``pymodbus`` errors, ``OSError``)
are converted at the boundary with :func:`error_check` and chained with ``from``.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager


class DriverError(Exception):
    """Base class of every driver error.

    :param message: what went wrong, naming the device.
    :param error_code: optional device or OS error code, appended to the message.
    """

    def __init__(self, message: str, error_code: int | None = None) -> None:
        self.error_code = error_code
        text = message if error_code is None else f"{message} [error code {error_code}]"
        super().__init__(text)


class DeviceNotAvailableError(DriverError):
    """The back end cannot be used here: unknown URL scheme or its library failed to import."""


class DeviceInitializationError(DriverError):
    """The device could not be opened or configured (port absent, refused, wrong settings)."""


class DeviceOperationError(DriverError):
    """An operation on an open device failed."""


class ConnectionLostError(DeviceOperationError):
    """The link to the device vanished while streaming; the reader keeps trying to reconnect."""


class CounterResyncError(DeviceOperationError):
    """The device's sample counter jumped where no gap is plausible (a restarted or corrupted
    counter); the driver kept the samples and took the new counter as its reference."""


class CommandRefusedError(DeviceOperationError):
    """The device answered a command with a refusal (wrong state, out of its own range)."""


class DeviceTimeoutError(DriverError, TimeoutError):
    """The device did not answer or stream within the timeout."""


class LimitViolationError(DriverError, ValueError):
    """A command would exceed the configured range-of-motion, speed or torque limits."""


@contextmanager
def error_check(
    message: str,
    error_type: type[DriverError] = DeviceOperationError,
) -> Iterator[None]:
    """Convert any foreign exception raised in the block into ``error_type``.

    ``DriverError`` passes through unchanged; ``TimeoutError`` becomes ``DeviceTimeoutError``.
    """
    try:
        yield
    except DriverError:
        raise
    except TimeoutError as err:
        raise DeviceTimeoutError(f"{message}: {err}") from err
    except Exception as err:
        code = getattr(err, "errno", None)
        raise error_type(f"{message}: {err}", error_code=code if isinstance(code, int) else None) from err
