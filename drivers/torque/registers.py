"""Register map and wire timing of the ATO-type RS-485 torque transmitter (Modbus RTU).

Holding registers, read with function 0x03 and written with 0x06::

    address  regs  content
    0x0000   2     torque, float32, N·m (tare applied)
    0x0002   2     shaft speed, float32, rpm
    0x0004   2     sample counter, uint32 in the float word order: conversions since power-up
    0x0014   1     baud code: 1=9600 2=14400 3=19200 4=38400 5=57600 6=115200
    0x0015   1     unit id (1..247)
    0x0016   1     float word order: 0 = big (high word first, "ABCD"), 1 = little ("CDAB")
    0x0017   1     output data rate, Hz (read only; 0 or an exception response: no sample counter)
    0x0020   1     tare: write 1 to zero the torque at the current reading
    0x0021   2     zero offset in force, float32, N·m (read only)
    0x0040   2     history: sample counter of the newest conversion, uint32 (with an output rate)
    0x0042   16    history: the newest 8 conversions, float32 each, newest first (tare applied)

The float word order differs between transmitter batches, so it is a per-device setting.

A transmitter with an output data rate converts at that rate on its own clock and answers a poll
with its latest conversion, numbered by the sample counter: polled faster than it converts, it
repeats a sample (the driver keeps it once); the history block holds its newest 8 conversions, so a
host that stalls for up to 8 conversion periods still reads every one, and a longer stall is a
counted gap.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from pymodbus.client.mixin import ModbusClientMixin

TORQUE = 0x0000
SPEED = 0x0002
SAMPLE_COUNT = 0x0004
BAUD_CODE = 0x0014
UNIT_ID = 0x0015
WORD_ORDER = 0x0016
OUTPUT_RATE = 0x0017
TARE = 0x0020
ZERO_OFFSET = 0x0021
HISTORY = 0x0040
HISTORY_DEPTH = 8
REGISTER_COUNT = HISTORY + 2 + 2 * HISTORY_DEPTH

BAUD_CODES: dict[int, int] = {1: 9600, 2: 14400, 3: 19200, 4: 38400, 5: 57600, 6: 115200}
WordOrder = Literal["big", "little"]

#: a read of n holding registers: request 8 bytes; response 5 + 2n bytes (id, fc, count, data, CRC)
REQUEST_BYTES = 8
BITS_PER_CHAR = 10  # start + 8 data + stop (8N1)
DEVICE_TURNAROUND_S = 0.0001


def poll_period_s(baud: int, registers: int = 2) -> float:
    """Shortest time for one read of ``registers`` holding registers at ``baud`` (s).

    Request and response characters at 10 bits each, plus the 3.5-character silent interval that
    ends each RTU frame, plus the device's turnaround (0.1 ms). At 115200 baud a 2-register read
    takes 17 characters (1.476 ms) + 2 × 0.304 ms + 0.1 ms = 2.18 ms: about 458 polls/s.
    """
    chars = REQUEST_BYTES + 5 + 2 * registers
    char_s = BITS_PER_CHAR / baud
    return chars * char_s + 2 * 3.5 * char_s + DEVICE_TURNAROUND_S


def max_poll_rate_hz(baud: int, registers: int = 2) -> float:
    """Highest poll rate the wire allows (Hz); see :func:`poll_period_s`."""
    return 1.0 / poll_period_s(baud, registers)


def decode_float(registers: list[int], word_order: WordOrder) -> float:
    """float32 from two registers in the device's word order."""
    value = ModbusClientMixin.convert_from_registers(registers, ModbusClientMixin.DATATYPE.FLOAT32, word_order=word_order)
    assert isinstance(value, float)
    return value


def encode_float(value: float, word_order: WordOrder) -> list[int]:
    """Two registers holding ``value`` as float32 in ``word_order``."""
    return list(ModbusClientMixin.convert_to_registers(
        float(value), ModbusClientMixin.DATATYPE.FLOAT32, word_order=word_order))


def decode_uint32(registers: list[int], word_order: WordOrder) -> int:
    """uint32 from two registers in the device's word order."""
    value = ModbusClientMixin.convert_from_registers(registers, ModbusClientMixin.DATATYPE.UINT32, word_order=word_order)
    assert isinstance(value, int)
    return value


def encode_uint32(value: int, word_order: WordOrder) -> list[int]:
    """Two registers holding ``value`` (mod 2**32) as uint32 in ``word_order``."""
    return list(ModbusClientMixin.convert_to_registers(
        int(value) % (1 << 32), ModbusClientMixin.DATATYPE.UINT32, word_order=word_order))


@dataclass(frozen=True)
class RegisterMap:
    """Addresses, overridable for transmitters that place them elsewhere."""

    torque: int = TORQUE
    speed: int = SPEED
    sample_count: int = SAMPLE_COUNT
    baud_code: int = BAUD_CODE
    tare: int = TARE
    zero_offset: int = ZERO_OFFSET
    word_order: int = WORD_ORDER
    output_rate: int = OUTPUT_RATE
    history: int = HISTORY
