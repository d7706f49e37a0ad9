"""Dynamometer on a CiA 402 servo drive over CANopen (the ``canopen`` library, python-can underneath).

URL ``canopen://<python-can interface>/<channel>?node=16&rate=100[&bitrate=1000000][&eds=path]``::

    open_dynamometer("canopen://virtual/dyno402")              # the simulated drive
    open_dynamometer("canopen://socketcan/can0?node=3&rate=500")
    open_dynamometer("canopen://slcan//dev/ttyACM0?bitrate=500000")

At open the driver waits for the drive's heartbeat, checks that it is a CiA 402 device (0x1000),
and configures by SDO, reading every value back and refusing to open when one differs: the software
position limits (0x607D), max torque (0x6072, per mille of the rated torque 0x6076), max profile velocity
(0x607F), quick stop "ramp, then SWITCH ON DISABLED" (0x605A = 2), halt on the quick-stop ramp
(0x605D = 2), the drive's heartbeat (0x1017), its consumer watching the host (0x1016, the watchdog)
and the TPDO event timers (0x1800/0x1801 sub 5) for the sample rate. The TPDO mapping is read from the
drive and must match its EDS. Then the host heartbeat starts and NMT goes OPERATIONAL.

Telemetry: each sample tick the drive sends TPDO1 (position, torque, sample counter) and TPDO2
(velocity, statusword, sample counter); the two halves are paired by the counter, which also gives
gaps as on every other back end. Commands: profile position mode for moves (the drive plans the
isokinetic trapezoid at the profile velocity and stops at the target itself, so a sweep's end does not
depend on the host's timing), the state machine walked with acknowledged SDO writes, the emergency
stop a quick-stop controlword on RPDO1 (highest-priority path a drive offers besides NMT; confirmed by
the statusword, re-sent by the runner while unconfirmed).
"""

from __future__ import annotations

import logging
import math
import queue
import struct
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import can
import canopen
import numpy as np

from ..base import COMMAND_ATTEMPTS
from ..blocks import DynamometerBlock
from ..clock import CounterClock, CounterUnwrapper, monotonic_s
from ..errors import (
    CommandRefusedError,
    DeviceInitializationError,
    DeviceNotAvailableError,
    DeviceTimeoutError,
    LimitViolationError,
    error_check,
)
from ..url import DeviceUrl
from . import DEFAULT_LIMITS, Dynamometer, DynamometerLimits
from . import cia402 as c
from . import protocol as p
from .cia402 import PowerState

log = logging.getLogger(__name__)

#: telemetry rates the event timer (whole ms) can give
RATES_HZ = (100, 125, 200, 250, 500, 1000)
#: how long a state change may take to show in the statusword (s)
STATE_TIMEOUT_S = 0.5
#: how long the SDO client waits for the drive's answer to one request (s); a drive answers in
#: milliseconds, a starved host's simulated drive (or a busy gateway) in tenths of a second
SDO_RESPONSE_TIMEOUT_S = 1.0


def summary_state(statusword: int, velocity_counts: int, quick_stopped: bool = False) -> p.State:
    """The drive's state in the frame-set's words (the recording's one state channel); ``quick_stopped``:
    the host sent a quick stop since the last reset (SWITCH ON DISABLED is then the e-stop's end)."""
    power = c.state_of(statusword)
    if power == PowerState.QUICK_STOP_ACTIVE or (quick_stopped and power == PowerState.SWITCH_ON_DISABLED):
        return p.State.ESTOP
    if power in (PowerState.FAULT, PowerState.FAULT_REACTION_ACTIVE):
        return p.State.FAULT
    if power == PowerState.OPERATION_ENABLED:
        moving = velocity_counts != 0 or not statusword & c.SW_TARGET_REACHED
        return p.State.MOVING if moving else p.State.HOLDING
    return p.State.IDLE


class _FrameCounter(can.Listener):
    """Counts what the canopen network drops silently: error frames and frames on ids nobody serves."""

    def __init__(self, device: CanopenDynamometer) -> None:
        self.device = device

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame:
            self.device.stats.crc_errors += 1
        elif msg.arbitration_id not in self.device._known_ids:
            self.device.stats.garbage_bytes += len(msg.data)


class CanopenDynamometer(Dynamometer):
    """A CiA 402 drive as a :class:`~drivers.dynamometer.Dynamometer`.

    :param interface: python-can interface (``virtual``, ``socketcan``, ``pcan``, ``slcan``, ...).
    :param channel: python-can channel.
    :param node: the drive's node id.
    :param rate: telemetry rate (Hz, one of :data:`RATES_HZ`).
    :param limits: the envelope every command is checked against, and written to the drive.
    :param eds: the drive's EDS (default: the simulated drive's).
    """

    def __init__(self, interface: str, channel: str, *, node: int = p.NODE_ID_DEFAULT, rate: int = 100,
                 limits: DynamometerLimits = DEFAULT_LIMITS, bitrate: int = 1_000_000, eds: str | None = None,
                 **kwargs: Any) -> None:
        if rate not in RATES_HZ:
            raise ValueError(f"telemetry rate must be one of {RATES_HZ} Hz (whole-ms event timer), got {rate}")
        self.interface, self.channel, self.node_id = interface, channel, node
        self.telemetry_rate_hz = rate
        self.limits = limits
        self.bitrate = bitrate
        self.eds = Path(eds) if eds else c.EDS_PATH
        self.network: canopen.Network | None = None
        self.node: canopen.RemoteNode | None = None
        self.rated_torque_nm = float("nan")
        self.statusword = 0
        #: host time (s) the last statusword arrived (TPDO or SDO)
        self.status_time_s = float("-inf")
        self.drive_identity: dict[str, int] = {}
        self.drive_limits: dict[str, float] = {}
        self._quick_stop_sent = False
        self._sdo_lock = threading.Lock()
        self._samples: queue.SimpleQueue[tuple[int, int, int, int, int]] = queue.SimpleQueue()
        self._pending: dict[int, dict[int, dict[int, int]]] = {}
        self._pending_lock = threading.Lock()
        self._layouts: list[c.PdoLayout] = []
        self._tpdo_ids: list[int] = []
        self._known_ids: set[int] = set()
        self._heartbeat_task: Any = None
        self._unwrap = CounterUnwrapper(c.COUNTER_BITS)
        self._clock = CounterClock(rate)
        super().__init__(**kwargs)

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> CanopenDynamometer:
        opts = url.take({"node": int, "rate": int, "bitrate": int, "eds": str})
        if not url.host:
            raise ValueError(f"{url.text!r} names no python-can interface (canopen://<interface>/<channel>)")
        channel = url.path[1:] if url.path.startswith("/") else url.path  # slcan//dev/ttyACM0 keeps its slash
        return cls(url.host, channel or "0", **{**opts, **kwargs})

    # -- link
    def _open_internal(self) -> None:
        network = canopen.Network()
        with error_check(f"{self.name}: cannot open CAN {self.interface}:{self.channel}", DeviceInitializationError):
            extra: dict[str, Any] = {} if self.interface == "virtual" else {"bitrate": self.bitrate}
            network.connect(interface=self.interface, channel=self.channel, **extra)
        self.network = network
        try:
            with error_check(f"{self.name}: cannot read the EDS {self.eds}", DeviceInitializationError):
                od = canopen.import_od(str(self.eds), self.node_id)
            node = network.add_node(self.node_id, od)
            node.sdo.RESPONSE_TIMEOUT = SDO_RESPONSE_TIMEOUT_S
            node.sdo.MAX_RETRIES = 1  # one request per call (the library's count includes it): repeats are ours
            self.node = node
            try:
                node.nmt.wait_for_heartbeat(max(3 * c.DRIVE_HEARTBEAT_S + 0.2, c.FIRST_HEARTBEAT_WAIT_S))
            except canopen.nmt.NmtError:
                raise DeviceNotAvailableError(f"{self.name}: no heartbeat from node {self.node_id} on "
                                              f"{self.interface}:{self.channel}") from None
            device_type = self._read(c.DEVICE_TYPE)
            if device_type & 0xFFFF != c.CIA402_PROFILE:
                raise DeviceInitializationError(f"{self.name}: node {self.node_id} is not a CiA 402 drive "
                                                f"(0x1000 reads 0x{device_type:08X})")
            self.drive_identity = {name: self._read(0x1018, sub) for sub, name in
                                   ((1, "vendor_id"), (2, "product_code"), (3, "revision"), (4, "serial"))}
            node.nmt.state = "PRE-OPERATIONAL"
            self.rated_torque_nm = self._read(c.RATED_TORQUE) / 1000.0
            self._configure(od)
            assert network.notifier is not None
            network.notifier.add_listener(_FrameCounter(self))
            for cob, layout in zip(self._tpdo_ids, self._layouts, strict=True):
                network.subscribe(cob, self._tpdo_callback(self._layouts.index(layout)))
            self._start_heartbeat()
            node.nmt.state = "OPERATIONAL"
            self._read_status()
        except BaseException:
            self._close_internal()
            raise

    def _configure(self, od: Any) -> None:
        """Every setting written by SDO and read back (a drive that keeps another value is refused)."""
        ms = 1000 // self.telemetry_rate_hz
        settings = [
            (c.PRODUCER_HEARTBEAT, 0, round(1000 * c.DRIVE_HEARTBEAT_S)),
            (c.CONSUMER_HEARTBEAT, 1, c.HOST_NODE_ID << 16 | round(1000 * c.HEARTBEAT_CONSUMER_S)),
            (c.QUICK_STOP_OPTION, 0, c.QUICK_STOP_THEN_DISABLE),
            (c.HALT_OPTION, 0, c.HALT_ON_QUICK_STOP_RAMP),
            (c.SOFTWARE_POSITION_LIMIT, 1, self._position_counts(self.limits.rom_min_rad)),
            (c.SOFTWARE_POSITION_LIMIT, 2, self._position_counts(self.limits.rom_max_rad)),
            (c.MAX_TORQUE, 0, self._torque_permille(self.limits.max_torque_nm)),
            (c.MAX_PROFILE_VELOCITY, 0, self._velocity_counts(self.limits.max_speed_rad_s)),
            (c.TPDO1_COMM, 5, ms),
            (c.TPDO2_COMM, 5, ms),
        ]
        for index, sub, value in settings:
            self._write(index, value, sub)
        # the envelope as the drive now holds it (SI), what ``identity()`` reports as read back
        self.drive_limits = {
            "rom_min_rad": math.radians(self._read(c.SOFTWARE_POSITION_LIMIT, 1) / c.POSITION_COUNTS_PER_DEG),
            "rom_max_rad": math.radians(self._read(c.SOFTWARE_POSITION_LIMIT, 2) / c.POSITION_COUNTS_PER_DEG),
            "max_speed_rad_s": math.radians(self._read(c.MAX_PROFILE_VELOCITY) / c.VELOCITY_COUNTS_PER_DEG_S),
            "max_torque_nm": self._read(c.MAX_TORQUE) * self.rated_torque_nm / 1000.0}
        signed = c.signed_objects(od)
        self._layouts, self._tpdo_ids = [], []
        for comm, mapping in ((c.TPDO1_COMM, c.TPDO1_MAP), (c.TPDO2_COMM, c.TPDO2_MAP)):
            words = [self._read(mapping, k) for k in range(1, self._read(mapping, 0) + 1)]
            if words != c.mapping_words(od, mapping):
                raise DeviceInitializationError(f"{self.name}: the drive maps TPDO 0x{mapping:04X} as "
                                                f"{[hex(w) for w in words]}, not as its EDS says")
            self._layouts.append(c.PdoLayout.from_mapping(words, signed))
            self._tpdo_ids.append(self._read(comm, 1) & 0x7FF)
        self._known_ids = {*self._tpdo_ids, 0x700 + self.node_id, 0x580 + self.node_id, 0x600 + self.node_id,
                           0x80 + self.node_id, 0x200 + self.node_id, 0x700 + c.HOST_NODE_ID, 0x000}

    def _close_internal(self) -> None:
        self._stop_heartbeat()
        if self.network is not None:
            try:
                if self.node is not None:
                    self.node.nmt.state = "PRE-OPERATIONAL"  # TPDOs stop
            except Exception:  # closing must not raise; the link may already be gone
                pass
            try:
                self.network.disconnect()
            except Exception:  # as above
                pass
        self.network, self.node = None, None

    def _on_stream_start(self) -> None:
        self._unwrap.reset()
        self._clock.reset()

    # -- units
    @staticmethod
    def _position_counts(rad: float) -> int:
        return round(math.degrees(rad) * c.POSITION_COUNTS_PER_DEG)

    @staticmethod
    def _velocity_counts(rad_s: float) -> int:
        return round(math.degrees(rad_s) * c.VELOCITY_COUNTS_PER_DEG_S)

    def _torque_permille(self, torque_nm: float) -> int:
        value = round(1000.0 * torque_nm / self.rated_torque_nm)
        if not 1 <= value <= 0xFFFF:
            raise LimitViolationError(f"torque limit {torque_nm:g} N·m is not representable as per mille of the "
                                      f"drive's rated {self.rated_torque_nm:g} N·m")
        return value

    # -- SDO (serialised: the SDO client has one response queue)
    def _sdo_object(self, index: int, sub: int) -> Any:
        if self.node is None:
            raise DeviceInitializationError(f"{self.name}: not open")
        obj = self.node.sdo[index]
        return obj if sub == 0 and isinstance(obj, canopen.sdo.SdoVariable) else obj[sub]

    def _read(self, index: int, sub: int = 0) -> int:
        return int(self._sdo_transfer(f"read 0x{index:04X} sub {sub}", lambda: self._sdo_object(index, sub).raw))

    def _write(self, index: int, value: int, sub: int = 0, readback: bool = True) -> None:
        def transfer() -> int:
            obj = self._sdo_object(index, sub)
            obj.raw = value
            return int(obj.raw) if readback else value

        got = self._sdo_transfer(f"write 0x{index:04X} sub {sub} = {value}", transfer)
        if got != value:
            raise DeviceInitializationError(f"{self.name}: 0x{index:04X} sub {sub} reads back {got}, set {value}")

    def _sdo_transfer(self, what: str, transfer: Callable[[], Any]) -> Any:
        """One SDO read or write; a request the drive left unanswered is sent again (reads and writes of
        one value are idempotent) up to :data:`COMMAND_ATTEMPTS` times, each repeat counted in
        ``stats.command_retries`` and logged; an abort is never repeated."""
        for attempt in range(1, COMMAND_ATTEMPTS + 1):
            try:
                with self._sdo_lock, self._sdo_errors(what):
                    return transfer()
            except DeviceTimeoutError:
                if attempt == COMMAND_ATTEMPTS:
                    raise
                self.stats.command_retries += 1
                log.warning("%s: no answer to %s within %g s; sending it again", self.name, what,
                            SDO_RESPONSE_TIMEOUT_S)
        raise AssertionError("unreachable")  # pragma: no cover

    @contextmanager
    def _sdo_errors(self, what: str) -> Iterator[None]:
        """The canopen library's SDO errors as this layer's: an abort is a refusal, silence a timeout."""
        try:
            yield
        except canopen.SdoAbortedError as err:
            raise CommandRefusedError(f"{self.name}: the drive refused to {what}: {err}", error_code=int(err.code)) from err
        except canopen.SdoCommunicationError as err:
            raise DeviceTimeoutError(f"{self.name}: no answer to {what}: {err}") from err
        except can.CanError as err:
            raise DeviceTimeoutError(f"{self.name}: CAN error on {what}: {err}") from err

    def _read_status(self) -> PowerState:
        self.statusword = self._read(c.STATUSWORD)
        self.status_time_s = monotonic_s()
        return c.state_of(self.statusword)

    def _controlword(self, word: int) -> None:
        """A controlword by SDO: the drive's answer confirms it arrived."""
        self._write(c.CONTROLWORD, word, readback=False)

    def _walk(self, word: int, to: PowerState) -> None:
        self._controlword(word)
        deadline = monotonic_s() + STATE_TIMEOUT_S
        while (state := self._read_status()) != to:
            if monotonic_s() > deadline:
                raise CommandRefusedError(f"{self.name}: the drive stays in {state.value} (expected {to.value})")

    def _enable(self) -> None:
        """Walk the state machine to OPERATION ENABLED (refused from a latched stop: :meth:`reset` first)."""
        if self._quick_stop_sent:
            raise CommandRefusedError(f"{self.name}: an emergency stop was sent; reset the dynamometer first")
        state = self._read_status()
        if state in c.LATCHED:
            code = self._read(c.ERROR_CODE)
            raise CommandRefusedError(f"{self.name}: the drive is in {state.value}"
                                      + (f" (error 0x{code:04X})" if code else "") + "; reset it first")
        if state == PowerState.OPERATION_ENABLED:
            return
        if state == PowerState.SWITCH_ON_DISABLED:
            self._walk(c.CW_SHUTDOWN, PowerState.READY_TO_SWITCH_ON)
            state = PowerState.READY_TO_SWITCH_ON
        if state == PowerState.READY_TO_SWITCH_ON:
            self._walk(c.CW_SWITCH_ON, PowerState.SWITCHED_ON)
        self._walk(c.CW_ENABLE_OPERATION, PowerState.OPERATION_ENABLED)

    # -- heartbeat
    def _start_heartbeat(self) -> None:
        if self.network is not None and self._heartbeat_task is None:
            self._heartbeat_task = self.network.send_periodic(0x700 + c.HOST_NODE_ID, b"\x05", c.HOST_HEARTBEAT_S)

    def _stop_heartbeat(self) -> None:
        if self._heartbeat_task is not None:
            try:
                self._heartbeat_task.stop()
            except Exception:  # a task on a closed bus may fail to stop; it is gone with it
                pass
            self._heartbeat_task = None

    def suspend_heartbeat(self, suspended: bool = True) -> None:
        """Stop (or resume) the host heartbeat, as a hung host would: the drive's consumer faults it."""
        if suspended:
            self._stop_heartbeat()
        else:
            self._start_heartbeat()

    # -- telemetry (the network's notifier thread)
    def _tpdo_callback(self, part: int) -> Any:
        layout = self._layouts[part]

        def on_tpdo(can_id: int, data: bytearray, timestamp: float) -> None:
            try:
                values = layout.decode(bytes(data))
            except struct.error:
                self.stats.malformed_frames += 1
                return
            counter = values[c.SAMPLE_COUNTER]
            with self._pending_lock:
                halves = self._pending.setdefault(counter, {})
                halves[part] = values
                if len(halves) == len(self._layouts):
                    del self._pending[counter]
                    merged = {k: v for h in halves.values() for k, v in h.items()}
                    self.statusword, self.status_time_s = merged[c.STATUSWORD], monotonic_s()
                    self._samples.put((counter, merged[c.POSITION_ACTUAL], merged[c.VELOCITY_ACTUAL],
                                       merged[c.TORQUE_ACTUAL], merged[c.STATUSWORD]))
                if len(self._pending) > 8:  # halves whose partner never came: the counter shows the gap
                    for old in sorted(self._pending)[:-4]:
                        del self._pending[old]

        return on_tpdo

    def _read_internal(self) -> DynamometerBlock | None:
        rows = []
        try:
            rows.append(self._samples.get(timeout=0.02))
        except queue.Empty:
            return None
        arrival = monotonic_s()
        while True:
            try:
                rows.append(self._samples.get_nowait())
            except queue.Empty:
                break
        data = np.array(rows, dtype=np.int64)
        counters = np.array([self._unwrap.unwrap(int(k)) for k in data[:, 0]], dtype=np.int64)
        stopped = self._quick_stop_sent
        states = [int(summary_state(int(sw), int(v), stopped)) for v, sw in zip(data[:, 2], data[:, 4], strict=True)]
        return DynamometerBlock(
            device=self.name, counter=counters, time_s=self._clock.stamp(counters, arrival),
            torque_nm=data[:, 3] * (self.rated_torque_nm / 1000.0),
            position_rad=np.deg2rad(data[:, 1] / c.POSITION_COUNTS_PER_DEG),
            velocity_rad_s=np.deg2rad(data[:, 2] / c.VELOCITY_COUNTS_PER_DEG_S),
            state=np.array(states, dtype=np.uint8))

    # -- commands (checked against the limits before anything is sent)
    def set_passive_isokinetic(self, speed_rad_s: float) -> None:
        self.limits.check_speed(speed_rad_s)
        self._write(c.MODES_OF_OPERATION, c.Mode.PROFILE_POSITION)
        deadline = monotonic_s() + STATE_TIMEOUT_S
        while self._read(c.MODES_DISPLAY) != c.Mode.PROFILE_POSITION:  # the display echoes the mode once taken
            if monotonic_s() > deadline:
                raise CommandRefusedError(f"{self.name}: the drive did not take profile position mode")
        self._write(c.PROFILE_VELOCITY, self._velocity_counts(speed_rad_s))

    def set_range_of_motion(self, min_rad: float, max_rad: float) -> None:
        self.limits.check_position(min_rad)
        self.limits.check_position(max_rad)
        if not min_rad < max_rad:
            raise LimitViolationError("min_rad must be below max_rad")
        self._write(c.SOFTWARE_POSITION_LIMIT, self._position_counts(min_rad), 1)
        self._write(c.SOFTWARE_POSITION_LIMIT, self._position_counts(max_rad), 2)

    def set_torque_limit(self, torque_nm: float) -> None:
        self.limits.check_torque(torque_nm)
        self._write(c.MAX_TORQUE, self._torque_permille(torque_nm))

    def move_to(self, target_rad: float) -> None:
        self.limits.check_position(target_rad)
        self._enable()
        self._write(c.TARGET_POSITION, self._position_counts(target_rad))
        enabled = c.CW_ENABLE_OPERATION | c.CW_CHANGE_IMMEDIATELY
        self._controlword(enabled | c.CW_NEW_SETPOINT)
        acknowledged = bool(self._read(c.STATUSWORD) & c.SW_SETPOINT_ACK)
        self._controlword(enabled)
        if not acknowledged:
            raise CommandRefusedError(f"{self.name}: the drive did not acknowledge the set-point "
                                      f"{math.degrees(target_rad):.2f}° (no host heartbeat at the drive?)")

    def halt(self) -> None:
        """Halt on the quick-stop ramp and hold, only from OPERATION ENABLED (a latched or unpowered drive
        already holds, and a halt word must never re-enable it).

        Normally the latest statusword (at most a few telemetry periods old) decides and the halt word goes
        out on RPDO1 at once, then an SDO read of 0x6040 confirms the drive took it. After an
        :meth:`emergency_stop` (until :meth:`reset`) the state is read by SDO first: CAN keeps the order of
        frames, so that read shows a quick stop that arrived, and the halt is sent only when it did not
        (the runner's fallback when the e-stop is never confirmed).

        :raises DeviceTimeoutError: the drive did not take the halt word (the caller sends the e-stop).
        """
        fresh = monotonic_s() - self.status_time_s < 3 * self.telemetry_period_s
        state = c.state_of(self.statusword) if fresh and not self._quick_stop_sent else self._read_status()
        if state != PowerState.OPERATION_ENABLED:
            return
        word = c.CW_ENABLE_OPERATION | c.CW_HALT
        self._send_rpdo(word)
        if self._read(c.CONTROLWORD) != word:
            raise DeviceTimeoutError(f"{self.name}: the drive did not take the halt word (0x6040 reads otherwise)")

    def _send_rpdo(self, word: int) -> None:
        if self.network is None:
            raise DeviceInitializationError(f"{self.name}: not open")
        with error_check(f"{self.name}: CAN send failed"):
            self.network.send_message(0x200 + self.node_id, struct.pack("<H", word))

    def emergency_stop(self) -> float:
        """A quick-stop controlword on RPDO1, no answer awaited; returns the host time it left."""
        self._quick_stop_sent = True  # from now on a halt reads the drive's state first, until reset()
        sent = monotonic_s()
        self._send_rpdo(c.CW_QUICK_STOP)
        return sent

    def stop_latched_since(self, since_s: float) -> bool:
        """True once a statusword that arrived after host time ``since_s`` shows QUICK STOP ACTIVE, a fault, or
        (after a quick stop was sent) SWITCH ON DISABLED, where the quick stop ends."""
        latched = c.STOPPED_AFTER_QUICK_STOP if self._quick_stop_sent else c.LATCHED
        return self.status_time_s >= since_s and c.state_of(self.statusword) in latched

    @property
    def telemetry_period_s(self) -> float:
        return 1.0 / self.telemetry_rate_hz

    def reset(self) -> None:
        """Leave a quick stop or a fault: disable voltage, a fault-reset edge; the drive ends SWITCH ON DISABLED."""
        self._controlword(c.CW_DISABLE_VOLTAGE)
        self._quick_stop_sent = False
        if self._read_status() == PowerState.FAULT:
            self._controlword(c.CW_FAULT_RESET)
            self._controlword(c.CW_DISABLE_VOLTAGE)
        state = self._read_status()
        if state != PowerState.SWITCH_ON_DISABLED:
            code = self._read(c.ERROR_CODE)
            raise CommandRefusedError(f"{self.name}: the drive stays in {state.value} after a reset"
                                      + (f" (error 0x{code:04X})" if code else ""))

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        d.update(interface=self.interface, channel=self.channel, node=self.node_id, bitrate=self.bitrate,
                 telemetry_rate_hz=self.telemetry_rate_hz, limits=self.drive_limits or self.limits.as_dict(),
                 protocol="CiA 402 (CANopen)",
                 eds=self.eds.name, rated_torque_nm=self.rated_torque_nm, drive=self.drive_identity)
        return d
