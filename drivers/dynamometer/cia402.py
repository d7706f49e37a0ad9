"""CiA 402 (CANopen drive profile) for the dynamometer: the drive's object dictionary, its units,
the power state machine's words, and the TPDO layout, shared by the ``canopen://`` driver and the
simulated drive (pure definitions, no bus).

The object dictionary is the drive's EDS (:data:`EDS_PATH`, read with :func:`canopen.import_od`);
a lab's drive brings its own EDS and the same objects. Units of this drive (its factor group): position
0.001°, velocity 0.001 °/s, acceleration 0.001 °/s², torque per mille of the rated torque 0x6076 (mN·m).

Sources: CiA 402 state machine and objects as summarised in ``canopen/profiles/p402.py``; CiA 301 for
NMT, heartbeat (0x1016/0x1017), EMCY and PDO mapping (0x1A00: ``index << 16 | subindex << 8 | bits``).
"""

from __future__ import annotations

import enum
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Any

EDS_PATH = Path(__file__).with_name("cia402_dynamometer.eds")

#: this drive's units (its factor group): counts per degree, per °/s, per °/s²
POSITION_COUNTS_PER_DEG = 1000.0
VELOCITY_COUNTS_PER_DEG_S = 1000.0
ACCELERATION_COUNTS_PER_DEG_S2 = 1000.0
#: the host's node id on the bus (its heartbeat is 0x700 + this; the drive's consumer watches it)
HOST_NODE_ID = 0x7F
#: host heartbeat period, and the drive's consumer timeout for it (the watchdog), s
HOST_HEARTBEAT_S = 0.1
HEARTBEAT_CONSUMER_S = 0.5
#: the drive's own heartbeat period (s); the host calls the drive lost after three missed
DRIVE_HEARTBEAT_S = 0.1
#: how long (s) the host waits for the drive's first heartbeat when it connects: longer than the three periods that
#: mean lost once connected, because the first may follow the drive's boot-up and a simulated drive on a loaded host
#: may not be scheduled for a while (the demo beside two CPU burners waited past 0.5 s: "no heartbeat from node 16";
#: with 2 s the suite beside them passed)
FIRST_HEARTBEAT_WAIT_S = 2.0
#: the sample counter's width (object 0x2000, U16)
COUNTER_BITS = 16

# objects
DEVICE_TYPE, CONSUMER_HEARTBEAT, PRODUCER_HEARTBEAT = 0x1000, 0x1016, 0x1017
TPDO1_COMM, TPDO2_COMM, TPDO1_MAP, TPDO2_MAP, RPDO1_COMM = 0x1800, 0x1801, 0x1A00, 0x1A01, 0x1400
SAMPLE_COUNTER = 0x2000
ERROR_CODE, CONTROLWORD, STATUSWORD = 0x603F, 0x6040, 0x6041
QUICK_STOP_OPTION, HALT_OPTION = 0x605A, 0x605D
MODES_OF_OPERATION, MODES_DISPLAY = 0x6060, 0x6061
POSITION_ACTUAL, VELOCITY_ACTUAL, TORQUE_ACTUAL = 0x6064, 0x606C, 0x6077
MAX_TORQUE, RATED_TORQUE = 0x6072, 0x6076
TARGET_POSITION, SOFTWARE_POSITION_LIMIT, MAX_PROFILE_VELOCITY, TARGET_VELOCITY = 0x607A, 0x607D, 0x607F, 0x60FF
PROFILE_VELOCITY, PROFILE_ACCELERATION, PROFILE_DECELERATION, QUICK_STOP_DECELERATION = 0x6081, 0x6083, 0x6084, 0x6085
CIA402_PROFILE = 0x0192

#: quick stop: decelerate on the quick-stop ramp, then SWITCH ON DISABLED (option 2). Not "stay in QUICK STOP
#: ACTIVE" (5–8): from there an enable-operation word (transition 16) re-enables the drive, and a host's
#: command sequence in flight when the e-stop arrives (a move's set-point words) would do exactly that.
#: From SWITCH ON DISABLED only the full shutdown → switch on → enable walk moves the arm, which the
#: driver refuses after an e-stop until reset. Halt: decelerate on the quick-stop ramp too
QUICK_STOP_THEN_DISABLE = 2
HALT_ON_QUICK_STOP_RAMP = 2

#: EMCY error codes (CiA 301 / 402)
EMCY_HEARTBEAT = 0x8130
EMCY_POSITION_LIMIT = 0x8612
EMCY_TORQUE = 0x8311
EMCY_SPEED = 0x8400


class Mode(enum.IntEnum):
    """Modes of operation (0x6060)."""

    PROFILE_POSITION = 1
    PROFILE_VELOCITY = 3


class PowerState(enum.Enum):
    """The CiA 402 power state machine's states."""

    NOT_READY_TO_SWITCH_ON = "NOT READY TO SWITCH ON"
    SWITCH_ON_DISABLED = "SWITCH ON DISABLED"
    READY_TO_SWITCH_ON = "READY TO SWITCH ON"
    SWITCHED_ON = "SWITCHED ON"
    OPERATION_ENABLED = "OPERATION ENABLED"
    QUICK_STOP_ACTIVE = "QUICK STOP ACTIVE"
    FAULT_REACTION_ACTIVE = "FAULT REACTION ACTIVE"
    FAULT = "FAULT"


#: statusword (mask, value) of each state
STATE_BITS: dict[PowerState, tuple[int, int]] = {
    PowerState.NOT_READY_TO_SWITCH_ON: (0x4F, 0x00),
    PowerState.SWITCH_ON_DISABLED: (0x4F, 0x40),
    PowerState.READY_TO_SWITCH_ON: (0x6F, 0x21),
    PowerState.SWITCHED_ON: (0x6F, 0x23),
    PowerState.OPERATION_ENABLED: (0x6F, 0x27),
    PowerState.QUICK_STOP_ACTIVE: (0x6F, 0x07),
    PowerState.FAULT_REACTION_ACTIVE: (0x4F, 0x0F),
    PowerState.FAULT: (0x4F, 0x08),
}
#: statusword bits beside the state
SW_REMOTE, SW_TARGET_REACHED, SW_INTERNAL_LIMIT, SW_SETPOINT_ACK = 1 << 9, 1 << 10, 1 << 11, 1 << 12

#: controlword commands (bits 7, 3, 2, 1, 0) and bits
CW_SHUTDOWN, CW_SWITCH_ON, CW_ENABLE_OPERATION, CW_DISABLE_VOLTAGE, CW_QUICK_STOP = 0x06, 0x07, 0x0F, 0x00, 0x02
CW_FAULT_RESET, CW_NEW_SETPOINT, CW_CHANGE_IMMEDIATELY, CW_HALT = 0x80, 0x10, 0x20, 0x100

#: states in which the arm is stopped and stays stopped until the host re-enables it
LATCHED = (PowerState.QUICK_STOP_ACTIVE, PowerState.FAULT_REACTION_ACTIVE, PowerState.FAULT)
#: after a quick stop: those, or SWITCH ON DISABLED where the quick stop (option 2) ends
STOPPED_AFTER_QUICK_STOP = (*LATCHED, PowerState.SWITCH_ON_DISABLED)


def state_of(statusword: int) -> PowerState:
    """The power state a statusword shows."""
    for state, (mask, value) in STATE_BITS.items():
        if statusword & mask == value:
            return state
    return PowerState.NOT_READY_TO_SWITCH_ON


def statusword_of(state: PowerState, extra: int = 0) -> int:
    """A statusword for ``state`` with ``extra`` bits (remote, target reached, ...)."""
    return STATE_BITS[state][1] | SW_REMOTE | extra


@dataclass(frozen=True)
class PdoLayout:
    """One TPDO's mapped objects as ``(index, subindex, bits)``, and their struct format (little-endian)."""

    entries: tuple[tuple[int, int, int], ...]
    fmt: struct.Struct

    @classmethod
    def from_mapping(cls, words: list[int], signed: dict[int, bool]) -> PdoLayout:
        """From 0x1A0n's mapping words (``index << 16 | subindex << 8 | bits``); ``signed[index]`` names the
        signed objects. Raises ``ValueError`` for a width that is not 8, 16 or 32 bits."""
        entries = tuple((w >> 16, (w >> 8) & 0xFF, w & 0xFF) for w in words)
        codes = []
        for index, _, bits in entries:
            if bits not in (8, 16, 32):
                raise ValueError(f"object 0x{index:04X} mapped with {bits} bits")
            code = {8: "b", 16: "h", 32: "i"}[bits]
            codes.append(code if signed.get(index, False) else code.upper())
        return cls(entries, struct.Struct("<" + "".join(codes)))

    def decode(self, data: bytes) -> dict[int, int]:
        """The mapped objects' raw values by index; ``struct.error`` for a frame of the wrong length."""
        return {index: value for (index, _, _), value in zip(self.entries, self.fmt.unpack(data), strict=True)}

    def encode(self, values: dict[int, int]) -> bytes:
        return self.fmt.pack(*(values[index] for index, _, _ in self.entries))


def mapping_words(od: Any, map_index: int) -> list[int]:
    """A TPDO's mapping words as the object dictionary ``od`` (EDS defaults) holds them."""
    record = od[map_index]
    return [int(record[k].default) for k in range(1, int(record[0].default) + 1)]


def signed_objects(od: Any) -> dict[int, bool]:
    """Which single-value objects in ``od`` are signed (INTEGER8/16/32)."""
    from canopen.objectdictionary import ODVariable
    from canopen.objectdictionary.datatypes import SIGNED_TYPES

    return {index: obj.data_type in SIGNED_TYPES for index, obj in ((o.index, o) for o in od.values())
            if isinstance(obj, ODVariable)}
