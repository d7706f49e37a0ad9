"""Force plate amplifier wire protocol (pure encode/decode; no I/O).

Every frame, in both directions::

    offset  size  field
    0       1     sync 0xA5
    1       1     kind   (0x01 sample, 0x02 command, 0x03 reply, 0x04 info)
    2       2     payload length L, uint16 little-endian
    4       L     payload
    4+L     2     CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF) of bytes 1 .. 3+L, little-endian

Sample payload (29 bytes): flags u8 (bit 0 trigger input, bit 1 ADC overload), sample counter
u32 LE (wraps at 2**32), six int32 LE ADC counts of the bridge channels in the order
Fx Fy Fz Mx My Mz. The driver converts counts to volts (``volts_per_count``), subtracts the
zero offsets and applies the 6×6 sensitivity matrix (loads = S · (v − v0)).

Command payload (5 bytes): command u8, argument u32 LE. Reply payload (2 bytes): command u8,
status u8. Info payload: see :class:`PlateInfo`. The parser hunts for the sync byte, checks
the kind and length, then the CRC; a frame that fails is counted and the parser resumes one
byte after its sync byte, so one bad frame never costs the next one.
"""

from __future__ import annotations

import binascii
import enum
import struct
from dataclasses import dataclass, field

import numpy as np

SYNC = 0xA5
HEADER = struct.Struct("<BBH")
SAMPLE_PAYLOAD = struct.Struct("<BI6i")
COMMAND_PAYLOAD = struct.Struct("<BI")
REPLY_PAYLOAD = struct.Struct("<BB")
INFO_PAYLOAD = struct.Struct("<IIf36f6f3f2f16s")
SAMPLE_FRAME_BYTES = HEADER.size + SAMPLE_PAYLOAD.size + 2
MAX_PAYLOAD = 512
COUNTER_BITS = 32


class Kind(enum.IntEnum):
    SAMPLE = 0x01
    COMMAND = 0x02
    REPLY = 0x03
    INFO = 0x04


class Command(enum.IntEnum):
    START = 0x01
    STOP = 0x02
    SET_RATE = 0x03
    GET_INFO = 0x04
    PING = 0x05


class Status(enum.IntEnum):
    OK = 0
    BAD_ARGUMENT = 1
    BAD_STATE = 2
    UNKNOWN_COMMAND = 3


#: sample rates the amplifier accepts, Hz (AMTI Gen5's list, 10 Hz to 2000 Hz)
SUPPORTED_RATES_HZ = (10, 20, 50, 100, 200, 250, 500, 600, 800, 900, 1000, 1200, 1500, 1800, 2000)


def max_sample_rate_hz(baud: int) -> float:
    """Highest sample rate a serial link of ``baud`` can carry (Hz): 35-byte frames, 10 bits a byte."""
    return baud / (SAMPLE_FRAME_BYTES * 10)


def crc16(data: bytes) -> int:
    """CRC-16/CCITT-FALSE of ``data`` (``binascii.crc_hqx`` with init 0xFFFF)."""
    return binascii.crc_hqx(data, 0xFFFF)


def encode_frame(kind: int, payload: bytes) -> bytes:
    """One complete frame of ``kind`` around ``payload``."""
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"payload of {len(payload)} bytes exceeds {MAX_PAYLOAD}")
    body = HEADER.pack(SYNC, kind, len(payload))[1:] + payload
    return bytes([SYNC]) + body + struct.pack("<H", crc16(body))


def encode_sample(counter: int, counts: np.ndarray | list[int], flags: int = 0) -> bytes:
    """Sample frame: ``counts`` are the six int32 ADC readings (Fx Fy Fz Mx My Mz)."""
    c = [int(x) for x in counts]
    return encode_frame(Kind.SAMPLE, SAMPLE_PAYLOAD.pack(flags, counter & 0xFFFFFFFF, *c))


def encode_command(command: Command, argument: int = 0) -> bytes:
    return encode_frame(Kind.COMMAND, COMMAND_PAYLOAD.pack(command, argument))


def encode_reply(command: int, status: Status) -> bytes:
    return encode_frame(Kind.REPLY, REPLY_PAYLOAD.pack(command, status))


@dataclass(frozen=True)
class PlateInfo:
    """Identity and calibration the amplifier reports (kept with every trial).

    :ivar serial_number: plate serial number.
    :ivar rate_hz: current sample rate in Hz.
    :ivar volts_per_count: ADC scale in V per count.
    :ivar sensitivity: 6×6 matrix, loads [N, N, N, N·m, N·m, N·m] = S · volts.
    :ivar zero_v: six zero offsets in V, subtracted before ``sensitivity``.
    :ivar origin_m: calibration origin relative to the surface centre (x, y, z) in m; z < 0 below.
    :ivar size_m: plate width (x) and length (y) in m.
    :ivar model: model string.
    """

    serial_number: int
    rate_hz: int
    volts_per_count: float
    sensitivity: np.ndarray
    zero_v: np.ndarray
    origin_m: np.ndarray
    size_m: tuple[float, float]
    model: str = ""

    def to_payload(self) -> bytes:
        return INFO_PAYLOAD.pack(
            self.serial_number, self.rate_hz, self.volts_per_count,
            *np.asarray(self.sensitivity, dtype=float).ravel(), *np.asarray(self.zero_v, dtype=float),
            *np.asarray(self.origin_m, dtype=float), *self.size_m, self.model.encode()[:16])

    @classmethod
    def from_payload(cls, payload: bytes) -> PlateInfo:
        if len(payload) != INFO_PAYLOAD.size:
            raise ValueError(f"info payload has {len(payload)} bytes, expected {INFO_PAYLOAD.size}")
        v = INFO_PAYLOAD.unpack(payload)
        return cls(
            serial_number=v[0], rate_hz=v[1], volts_per_count=v[2],
            sensitivity=np.array(v[3:39]).reshape(6, 6), zero_v=np.array(v[39:45]),
            origin_m=np.array(v[45:48]), size_m=(v[48], v[49]),
            model=v[50].rstrip(b"\0").decode(errors="replace"))

    def as_dict(self) -> dict[str, object]:
        return {
            "serial_number": self.serial_number, "rate_hz": self.rate_hz,
            "volts_per_count": self.volts_per_count, "sensitivity": self.sensitivity.tolist(),
            "zero_v": self.zero_v.tolist(), "origin_m": self.origin_m.tolist(),
            "size_m": list(self.size_m), "model": self.model,
        }


@dataclass
class ParsedSamples:
    """Decoded sample frames of one ``feed``: flags (n,), counters (n,), counts (n, 6)."""

    flags: np.ndarray
    counters: np.ndarray
    counts: np.ndarray


@dataclass
class FrameParser:
    """Incremental frame parser with resynchronisation and error counts."""

    crc_errors: int = 0
    malformed_frames: int = 0
    garbage_bytes: int = 0
    _buffer: bytearray = field(default_factory=bytearray)

    def feed(self, data: bytes) -> tuple[ParsedSamples, list[tuple[Kind, bytes]]]:
        """Add bytes; return decoded samples and any other complete frames (kind, payload)."""
        buf = self._buffer
        buf += data
        pos = 0
        samples: list[tuple[int, ...]] = []
        others: list[tuple[Kind, bytes]] = []
        n = len(buf)
        while pos < n:
            if buf[pos] != SYNC:
                nxt = buf.find(SYNC, pos)
                skip = (n if nxt < 0 else nxt) - pos
                self.garbage_bytes += skip
                pos += skip
                continue
            if n - pos < HEADER.size:
                break
            _, kind, length = HEADER.unpack_from(buf, pos)
            valid_kind = kind in Kind._value2member_map_
            if not valid_kind or length > MAX_PAYLOAD or (kind == Kind.SAMPLE and length != SAMPLE_PAYLOAD.size):
                self.malformed_frames += 1
                pos += 1
                continue
            end = pos + HEADER.size + length + 2
            if end > n:
                break
            body = bytes(buf[pos + 1:end - 2])
            (crc,) = struct.unpack_from("<H", buf, end - 2)
            if crc != crc16(body):
                self.crc_errors += 1
                pos += 1
                continue
            payload = body[3:]
            if kind == Kind.SAMPLE:
                samples.append(SAMPLE_PAYLOAD.unpack(payload))
            else:
                others.append((Kind(kind), payload))
            pos = end
        del buf[:pos]
        if samples:
            arr = np.array(samples, dtype=np.int64)
            parsed = ParsedSamples(arr[:, 0].astype(np.uint8), arr[:, 1], arr[:, 2:8])
        else:
            parsed = ParsedSamples(np.zeros(0, np.uint8), np.zeros(0, np.int64), np.zeros((0, 6), np.int64))
        return parsed, others

    def pending_bytes(self) -> int:
        """Bytes held back waiting for the rest of a frame."""
        return len(self._buffer)


def loads_from_counts(counts: np.ndarray, info: PlateInfo, zero_v: np.ndarray) -> np.ndarray:
    """Six loads (Fx Fy Fz N, Mx My Mz N·m) per row from ADC ``counts`` (n, 6)."""
    volts = counts.astype(np.float64) * info.volts_per_count
    return (volts - zero_v) @ np.asarray(info.sensitivity).T


def counts_from_loads(loads: np.ndarray, info: PlateInfo) -> np.ndarray:
    """Inverse of :func:`loads_from_counts` with the device's own zero (used by the simulator)."""
    volts = np.linalg.solve(np.asarray(info.sensitivity), np.atleast_2d(loads).T).T + info.zero_v
    return np.round(volts / info.volts_per_count).astype(np.int64)


def centre_of_pressure(
    force_n: np.ndarray, moment_nm: np.ndarray, origin_m: np.ndarray, min_fz_n: float = 5.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Centre of pressure on the top surface and free moment, per sample.

    The moment is about the calibration origin, which sits at ``origin_m`` relative to the
    surface centre (z < 0: below the surface). With h = −origin_z the surface height above the
    origin, a force F applied at surface point p = (x, y, h) gives M = p × F + (0, 0, Tz), so
    x = (h·Fx − My)/Fz, y = (Mx + h·Fy)/Fz and Tz = Mz − x·Fy + y·Fx (x, y then shifted by the
    origin's offset to surface coordinates). NaN where |Fz| < ``min_fz_n``.

    :returns: (cop_m of shape (n, 2), free_moment_nm of shape (n,)).
    """
    fx, fy, fz = force_n[:, 0], force_n[:, 1], force_n[:, 2]
    mx, my, mz = moment_nm[:, 0], moment_nm[:, 1], moment_nm[:, 2]
    h = -float(origin_m[2])
    with np.errstate(divide="ignore", invalid="ignore"):
        ok = np.abs(fz) >= min_fz_n
        x = np.where(ok, (h * fx - my) / fz, np.nan)
        y = np.where(ok, (mx + h * fy) / fz, np.nan)
        tz = np.where(ok, mz - x * fy + y * fx, np.nan)
    cop = np.column_stack([x + origin_m[0], y + origin_m[1]])
    return cop, tz
