"""Isokinetic dynamometers (Biodex-System-4-class) on a CAN bus.

Open by URL; the scheme is the python-can interface, the host the channel::

    open_dynamometer("virtual://dyno")                 # the simulator's bus
    open_dynamometer("socketcan://can0?node=16&rate=100")
    open_dynamometer("canopen://socketcan/can0?node=3")  # a CiA 402 servo drive (CANopen)

Every motion command is checked against :class:`DynamometerLimits` before it is sent; a command
outside them, or a value the wire cannot carry (NaN, inf, below its resolution, above its range),
raises :class:`~drivers.errors.LimitViolationError` and nothing reaches the bus. The limits
themselves are validated the same way when they are made.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import asdict, dataclass
from typing import Any, ClassVar

from ..base import StreamingDevice
from ..blocks import DynamometerBlock
from ..errors import LimitViolationError
from ..url import DeviceUrl, load_backend
from . import protocol as p

_CAN = ("drivers.dynamometer.can_driver", "CanDynamometer")
#: scheme (python-can interface) -> (module, class); imported only when asked for
BACKENDS: dict[str, tuple[str, str]] = {
    name: _CAN for name in ("virtual", "socketcan", "pcan", "kvaser", "vector", "slcan", "udp_multicast", "ixxat")
}
#: a CiA 402 servo drive over CANopen: canopen://<python-can interface>/<channel>
BACKENDS["canopen"] = ("drivers.dynamometer.canopen_driver", "CanopenDynamometer")


def _wire(value: float, lsb: float, low: int, high: int, what: str, unit: str) -> int:
    """``value / lsb`` rounded, refused (typed) when it is not finite or leaves ``low..high``."""
    if not math.isfinite(value):
        raise LimitViolationError(f"{what} must be finite, got {value}")
    scaled = value / lsb
    if not (math.isfinite(scaled) and low - 1 <= scaled <= high + 1):
        raw = None
    else:
        raw = round(scaled)
    if raw is None or not low <= raw <= high:
        raise LimitViolationError(f"{what} {value:g} {unit} is not representable on the wire "
                                  f"({low * lsb:g}..{high * lsb:g} {unit} in steps of {lsb:g})")
    return raw


def position_wire(position_rad: float) -> int:
    """A position in wire units (0.01°, i16)."""
    return _wire(math.degrees(position_rad), p.POSITION_LSB_DEG, -32768, 32767, "position", "°")


def speed_wire(speed_rad_s: float) -> int:
    """A speed in wire units (0.01 °/s, u16); zero is not a speed."""
    return _wire(math.degrees(speed_rad_s), p.SPEED_LSB_DEG_S, 1, 65535, "speed", "°/s")


def torque_limit_wire(torque_nm: float) -> int:
    """A torque limit in wire units (0.1 N·m, u16); zero is not a limit."""
    return _wire(torque_nm, p.TORQUE_LIMIT_LSB_NM, 1, 65535, "torque limit", "N·m")


@dataclass(frozen=True)
class DynamometerLimits:
    """Safety envelope the driver enforces (SI: rad, rad/s, N·m).

    :ivar rom_min_rad: lowest position any command may reach.
    :ivar rom_max_rad: highest position any command may reach.
    :ivar max_speed_rad_s: highest speed any command may set.
    :ivar max_torque_nm: highest torque limit any command may set.
    """

    rom_min_rad: float
    rom_max_rad: float
    max_speed_rad_s: float
    max_torque_nm: float

    @classmethod
    def from_degrees(cls, rom_min_deg: float, rom_max_deg: float, max_speed_deg_s: float,
                     max_torque_nm: float) -> DynamometerLimits:
        """Limits given in degrees (as a clinician sets them)."""
        return cls(math.radians(rom_min_deg), math.radians(rom_max_deg), math.radians(max_speed_deg_s), max_torque_nm)

    def __post_init__(self) -> None:
        values = {"rom_min_rad": self.rom_min_rad, "rom_max_rad": self.rom_max_rad,
                  "max_speed_rad_s": self.max_speed_rad_s, "max_torque_nm": self.max_torque_nm}
        for what, value in values.items():
            if not math.isfinite(value):
                raise LimitViolationError(f"limit {what} must be finite, got {value}")
        if not self.rom_min_rad < self.rom_max_rad:
            raise LimitViolationError("rom_min_rad must be below rom_max_rad")
        if self.max_speed_rad_s <= 0 or self.max_torque_nm <= 0:
            raise LimitViolationError("speed and torque limits must be positive")
        # every limit must be something the wire can carry, or a command inside it could not be sent
        for rad in (self.rom_min_rad, self.rom_max_rad):
            position_wire(rad)
        speed_wire(self.max_speed_rad_s)
        torque_limit_wire(self.max_torque_nm)

    def check_position(self, position_rad: float) -> None:
        if not self.rom_min_rad <= position_rad <= self.rom_max_rad:  # NaN fails this too
            raise LimitViolationError(
                f"target {math.degrees(position_rad):.2f}° outside the allowed range "
                f"{math.degrees(self.rom_min_rad):.1f}..{math.degrees(self.rom_max_rad):.1f}°")

    def check_speed(self, speed_rad_s: float) -> None:
        if not 0 < speed_rad_s <= self.max_speed_rad_s:
            raise LimitViolationError(
                f"speed {math.degrees(speed_rad_s):.2f}°/s outside 0..{math.degrees(self.max_speed_rad_s):.1f}°/s")

    def check_torque(self, torque_nm: float) -> None:
        if not 0 < torque_nm <= self.max_torque_nm:
            raise LimitViolationError(f"torque limit {torque_nm:.1f} N·m outside 0..{self.max_torque_nm:.1f} N·m")

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


#: a conservative default for a relaxed-subject passive test: 0–100°, 30°/s, 150 N·m
#: the subject's safety envelope (range of motion °, speed °/s, torque N·m): the one definition the
#: driver, the simulator's defaults and the runner's live checks all use
SUBJECT_ENVELOPE_DEG = (-35.0, 95.0)
SUBJECT_MAX_SPEED_DEG_S = 30.0
SUBJECT_MAX_TORQUE_NM = 150.0
DEFAULT_LIMITS = DynamometerLimits.from_degrees(*SUBJECT_ENVELOPE_DEG, SUBJECT_MAX_SPEED_DEG_S, SUBJECT_MAX_TORQUE_NM)


class Dynamometer(StreamingDevice):
    """An isokinetic dynamometer: streams :class:`~drivers.blocks.DynamometerBlock`, takes motion commands."""

    kind: ClassVar[str] = "dynamometer"
    block_type = DynamometerBlock

    @abstractmethod
    def set_passive_isokinetic(self, speed_rad_s: float) -> None:
        """Passive isokinetic mode at ``speed_rad_s`` (checked against the limits)."""

    @abstractmethod
    def set_range_of_motion(self, min_rad: float, max_rad: float) -> None:
        """Device range-of-motion stops (checked against the limits)."""

    @abstractmethod
    def set_torque_limit(self, torque_nm: float) -> None:
        """Device torque limit (checked against the limits)."""

    @abstractmethod
    def move_to(self, target_rad: float) -> None:
        """Start an isokinetic move to ``target_rad`` (checked against the limits)."""

    @abstractmethod
    def halt(self) -> None:
        """Controlled stop: decelerate and hold."""

    @abstractmethod
    def emergency_stop(self) -> float:
        """Emergency stop: highest-priority frame, latched by the device until :meth:`reset`.

        Returns the host time (s, :func:`~drivers.clock.monotonic_s`) the command left.
        """

    @abstractmethod
    def stop_latched_since(self, since_s: float) -> bool:
        """True once the device has reported, after host time ``since_s``, that the arm is latched stopped."""

    @property
    @abstractmethod
    def telemetry_period_s(self) -> float:
        """Seconds between telemetry samples."""

    @abstractmethod
    def suspend_heartbeat(self, suspended: bool = True) -> None:
        """Stop (or resume) the host heartbeat: the device's watchdog then stops any motion."""

    @abstractmethod
    def reset(self) -> None:
        """Clear a latched emergency stop or fault."""


def open_dynamometer(url: str, **kwargs: Any) -> Dynamometer:
    """Make (not yet open) the dynamometer driver for ``url``.

    :raises DeviceNotAvailableError: unknown interface or python-can back end not importable.
    """
    parsed = DeviceUrl.parse(url)
    table = BACKENDS
    if parsed.scheme not in table:  # any interface python-can knows, by its own name
        import can

        if parsed.scheme in can.VALID_INTERFACES:
            table = {**BACKENDS, parsed.scheme: _CAN}
    cls = load_backend(table, parsed, "dynamometer")
    return cls.from_url(parsed, **kwargs)  # type: ignore[attr-defined]  # every backend has one
