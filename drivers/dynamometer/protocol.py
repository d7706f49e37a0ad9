"""Isokinetic dynamometer CAN protocol (classic CAN, 11-bit identifiers, 1 Mbit/s; pure encode/decode).

Identifiers are a function code plus the node id N (default 0x10), lower id = higher priority::

    id          dir          DLC  payload (little-endian)
    0x080 + N   host→device  2    EMERGENCY STOP: magic 0x70E5 (u16)
    0x180 + N   device→host  8    TELEMETRY: counter u16, torque i16 [0.01 N·m],
                                  position i16 [0.01°], velocity i16 [0.02 °/s]
    0x200 + N   host→device  8    COMMAND: code u8, sequence u8, arguments (6 bytes, see Command)
    0x280 + N   device→host  8    STATUS (10 Hz, and at once on every state change): state u8,
                                  mode u8, faults u8 (bit flags),
                                  telemetry rate u16 [Hz], torque limit u16 [0.1 N·m], spare u8
    0x300 + N   device→host  3    ACK: code u8, sequence u8, result u8 (Result)
    0x700 + N   host→device  1    HOST HEARTBEAT: counter u8, every 100 ms; the device's watchdog
                                  stops any motion (state FAULT, fault WATCHDOG) if none arrives
                                  for WATCHDOG_TIMEOUT_S while it is moving

Telemetry torque is the torque the shaft applies in the direction of positive position (so a
limb that resists being moved toward positive angles reads positive). An 8-byte frame with an
11-bit id is at most 135 bits with worst-case stuffing: 1 Mbit/s carries ≥ 7400 frames/s.
"""

from __future__ import annotations

import enum
import struct
from dataclasses import dataclass

NODE_ID_DEFAULT = 0x10
ESTOP_BASE, TELEMETRY_BASE, COMMAND_BASE, STATUS_BASE, ACK_BASE, HEARTBEAT_BASE = (
    0x080, 0x180, 0x200, 0x280, 0x300, 0x700)
ESTOP_MAGIC = 0x70E5
WATCHDOG_TIMEOUT_S = 0.5
HEARTBEAT_PERIOD_S = 0.1
COUNTER_BITS = 16
TORQUE_LSB_NM = 0.01
POSITION_LSB_DEG = 0.01
VELOCITY_LSB_DEG_S = 0.02
TORQUE_LIMIT_LSB_NM = 0.1
SPEED_LSB_DEG_S = 0.01
CAN_BITS_PER_8_BYTE_FRAME = 135  # 11-bit id, 8 data bytes, worst-case bit stuffing + IFS

TELEMETRY = struct.Struct("<Hhhh")


def max_frame_rate_hz(bitrate: int = 1_000_000) -> float:
    """Highest rate of 8-byte frames a bus of ``bitrate`` bit/s carries (worst-case stuffing)."""
    return bitrate / CAN_BITS_PER_8_BYTE_FRAME
STATUS = struct.Struct("<BBBHHB")
ACK = struct.Struct("<BBB")


class State(enum.IntEnum):
    IDLE = 0      # holding position, ready
    MOVING = 1    # isokinetic move in progress
    HOLDING = 2   # reached the target, holding
    ESTOP = 3     # emergency stop latched (RESET clears)
    FAULT = 4     # watchdog, torque or ROM fault latched (RESET clears)


class Mode(enum.IntEnum):
    PASSIVE_HOLD = 0
    PASSIVE_ISOKINETIC = 1


class Fault(enum.IntFlag):
    NONE = 0
    ESTOP = 1
    WATCHDOG = 2
    TORQUE_LIMIT = 4
    ROM_LIMIT = 8
    SPEED_LIMIT = 16


class Command(enum.IntEnum):
    SET_MODE = 0x01          # mode u8
    SET_SPEED = 0x02         # speed u16 [0.01 °/s]
    SET_ROM = 0x03           # min i16, max i16 [0.01°]
    SET_TORQUE_LIMIT = 0x04  # limit u16 [0.1 N·m]
    START = 0x05             # target i16 [0.01°]
    STOP = 0x06
    RESET = 0x07
    SET_TELEMETRY_RATE = 0x08  # rate u16 [Hz]


class Result(enum.IntEnum):
    OK = 0
    OUT_OF_RANGE = 1
    BAD_STATE = 2
    UNKNOWN = 3


_ARGS: dict[Command, str] = {
    Command.SET_MODE: "<B", Command.SET_SPEED: "<H", Command.SET_ROM: "<hh",
    Command.SET_TORQUE_LIMIT: "<H", Command.START: "<h", Command.STOP: "<",
    Command.RESET: "<", Command.SET_TELEMETRY_RATE: "<H",
}


def ids(node: int = NODE_ID_DEFAULT) -> dict[str, int]:
    """Every identifier of node ``node``."""
    if not 0 < node < 0x80:
        raise ValueError(f"node id must be 1..127, got {node}")
    return {"estop": ESTOP_BASE + node, "telemetry": TELEMETRY_BASE + node, "command": COMMAND_BASE + node,
            "status": STATUS_BASE + node, "ack": ACK_BASE + node, "heartbeat": HEARTBEAT_BASE + node}


def _i16(value: float, lsb: float, what: str) -> int:
    raw = round(value / lsb)
    if not -32768 <= raw <= 32767:
        raise ValueError(f"{what} {value} does not fit the wire format (±{32767 * lsb:g})")
    return raw


def _u16(value: float, lsb: float, what: str) -> int:
    raw = round(value / lsb)
    if not 0 <= raw <= 65535:
        raise ValueError(f"{what} {value} does not fit the wire format (0..{65535 * lsb:g})")
    return raw


@dataclass(frozen=True)
class Telemetry:
    """One telemetry sample (wire units: N·m, degrees, degrees per second)."""

    counter: int
    torque_nm: float
    position_deg: float
    velocity_deg_s: float

    def encode(self) -> bytes:
        return TELEMETRY.pack(self.counter & 0xFFFF, _i16(self.torque_nm, TORQUE_LSB_NM, "torque"),
                              _i16(self.position_deg, POSITION_LSB_DEG, "position"),
                              _i16(self.velocity_deg_s, VELOCITY_LSB_DEG_S, "velocity"))

    @classmethod
    def decode(cls, data: bytes) -> Telemetry:
        if len(data) != TELEMETRY.size:
            raise ValueError(f"telemetry needs {TELEMETRY.size} bytes, got {len(data)}")
        c, t, p, v = TELEMETRY.unpack(data)
        return cls(c, t * TORQUE_LSB_NM, p * POSITION_LSB_DEG, v * VELOCITY_LSB_DEG_S)


@dataclass(frozen=True)
class Status:
    state: State
    mode: Mode
    faults: Fault
    telemetry_rate_hz: int
    torque_limit_nm: float

    def encode(self) -> bytes:
        return STATUS.pack(self.state, self.mode, self.faults, self.telemetry_rate_hz,
                           _u16(self.torque_limit_nm, TORQUE_LIMIT_LSB_NM, "torque limit"), 0)

    @classmethod
    def decode(cls, data: bytes) -> Status:
        if len(data) != STATUS.size:
            raise ValueError(f"status needs {STATUS.size} bytes, got {len(data)}")
        s, m, f, r, lim, _ = STATUS.unpack(data)
        return cls(State(s), Mode(m), Fault(f), r, lim * TORQUE_LIMIT_LSB_NM)


def encode_command(command: Command, sequence: int, *args: int) -> bytes:
    """8-byte command payload (arguments already in wire units), zero padded."""
    body = struct.pack("<BB", command, sequence & 0xFF) + struct.pack(_ARGS[command], *args)
    return body.ljust(8, b"\0")


def decode_command(data: bytes) -> tuple[Command, int, tuple[int, ...]]:
    """(command, sequence, arguments); raises ValueError on an unknown code or short frame."""
    if len(data) < 2:
        raise ValueError("command frame shorter than 2 bytes")
    code, seq = data[0], data[1]
    try:
        command = Command(code)
    except ValueError:
        raise ValueError(f"unknown command code 0x{code:02x}") from None
    fmt = _ARGS[command]
    need = struct.calcsize(fmt)
    if len(data) < 2 + need:
        raise ValueError(f"{command.name} needs {need} argument bytes")
    return command, seq, struct.unpack_from(fmt, data, 2)


def encode_estop() -> bytes:
    return struct.pack("<H", ESTOP_MAGIC)


def is_estop(data: bytes) -> bool:
    return len(data) == 2 and struct.unpack("<H", data)[0] == ESTOP_MAGIC


def encode_ack(command: int, sequence: int, result: Result) -> bytes:
    return ACK.pack(command, sequence & 0xFF, result)


def decode_ack(data: bytes) -> tuple[int, int, Result]:
    if len(data) != ACK.size:
        raise ValueError(f"ack needs {ACK.size} bytes, got {len(data)}")
    c, s, r = ACK.unpack(data)
    return c, s, Result(r)
