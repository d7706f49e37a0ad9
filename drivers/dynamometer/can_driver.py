"""Dynamometer driver on any python-can interface."""

from __future__ import annotations

import threading
from typing import Any

import can
import numpy as np

from ..blocks import DynamometerBlock
from ..clock import CounterClock, CounterUnwrapper, monotonic_s
from ..errors import (
    CommandRefusedError,
    DeviceInitializationError,
    DeviceTimeoutError,
    DriverError,
    LimitViolationError,
    error_check,
)
from ..url import DeviceUrl
from . import DEFAULT_LIMITS, Dynamometer, DynamometerLimits, position_wire, speed_wire, torque_limit_wire
from . import protocol as p


class CanDynamometer(Dynamometer):
    """Reads telemetry and status, sends commands with acknowledgement, and keeps the heartbeat.

    :param interface: python-can interface name (``virtual``, ``socketcan``, ...).
    :param channel: python-can channel.
    :param node: device node id.
    :param rate: telemetry rate to request in Hz (100–1000).
    :param limits: the safety envelope every command is checked against.
    :param bitrate: CAN bit rate in bit/s (for interfaces that set it).
    """

    def __init__(self, interface: str, channel: str, *, node: int = p.NODE_ID_DEFAULT, rate: int = 100,
                 limits: DynamometerLimits = DEFAULT_LIMITS, bitrate: int = 1_000_000,
                 command_timeout_s: float = 0.5, **kwargs: Any) -> None:
        if not 100 <= rate <= 1000:
            raise ValueError(f"telemetry rate must be 100..1000 Hz, got {rate}")
        self.interface, self.channel, self.node = interface, channel, node
        self.ids = p.ids(node)
        self.telemetry_rate_hz = rate
        self.limits = limits
        self.bitrate = bitrate
        self.command_timeout_s = command_timeout_s
        self.status: p.Status | None = None
        #: host time (s) the last status frame arrived
        self.status_time_s = float("-inf")
        self._bus: can.BusABC | None = None
        self._send_lock = threading.Lock()
        self._acks: dict[int, p.Result] = {}
        self._ack_cond = threading.Condition()
        self._seq = 0
        self._unwrap = CounterUnwrapper(p.COUNTER_BITS)
        self._clock = CounterClock(rate)
        self._heartbeat_stop = threading.Event()
        self._heartbeat_thread: threading.Thread | None = None
        self._heartbeat_suspended = False
        self._reader_owns_bus = False  # once streaming, only the reader thread receives
        super().__init__(**kwargs)

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> CanDynamometer:
        opts = url.take({"node": int, "rate": int, "bitrate": int})
        channel = url.host or url.path or "0"  # a device path keeps its leading slash
        return cls(url.scheme, channel, **{**opts, **kwargs})

    # -- link
    def _open_internal(self) -> None:
        with error_check(f"{self.name}: cannot open CAN {self.interface}:{self.channel}", DeviceInitializationError):
            extra: dict[str, Any] = {} if self.interface == "virtual" else {"bitrate": self.bitrate}
            self._bus = can.Bus(interface=self.interface, channel=self.channel, **extra)
        self._start_heartbeat()
        self._reader_owns_bus = False  # the device must answer before we call it open
        self._command(p.Command.SET_TELEMETRY_RATE, self.telemetry_rate_hz)

    def _close_internal(self) -> None:
        self._heartbeat_stop.set()
        if self._heartbeat_thread is not None:
            self._heartbeat_thread.join(1.0)
            self._heartbeat_thread = None
        if self._bus is not None:
            try:
                self._bus.shutdown()
            except Exception:
                pass
            self._bus = None

    def _on_stream_start(self) -> None:
        self._unwrap.reset()
        self._clock.reset()
        self._reader_owns_bus = True

    # -- heartbeat
    def _start_heartbeat(self) -> None:
        self._heartbeat_stop.clear()
        self._heartbeat_thread = threading.Thread(target=self._heartbeat, name=f"{self.name}-heartbeat", daemon=True)
        self._heartbeat_thread.start()

    def _heartbeat(self) -> None:
        count = 0
        while True:
            if not self._heartbeat_suspended:
                count = (count + 1) & 0xFF
                try:
                    self._send(self.ids["heartbeat"], bytes([count]))
                except DriverError:
                    pass
            if self._heartbeat_stop.wait(p.HEARTBEAT_PERIOD_S):
                return

    def suspend_heartbeat(self, suspended: bool = True) -> None:
        """Stop (or resume) sending heartbeats, as a hung host would: the device watchdog must trip."""
        self._heartbeat_suspended = suspended

    # -- sending
    def _send(self, arbitration_id: int, data: bytes) -> None:
        if self._bus is None:
            raise DeviceInitializationError(f"{self.name}: not open")
        with self._send_lock, error_check(f"{self.name}: CAN send failed"):
            self._bus.send(can.Message(arbitration_id=arbitration_id, data=data, is_extended_id=False))

    def _command(self, command: p.Command, *args: int) -> None:
        """Send a command and wait for its acknowledgement."""
        with self._ack_cond:
            self._seq = (self._seq + 1) & 0xFF
            seq = self._seq
            self._acks.pop(seq, None)
        self._send(self.ids["command"], p.encode_command(command, seq, *args))
        deadline = monotonic_s() + self.command_timeout_s
        with self._ack_cond:
            while seq not in self._acks:
                left = deadline - monotonic_s()
                if left <= 0:
                    raise DeviceTimeoutError(f"{self.name}: no acknowledgement of {command.name}")
                if self._reader_owns_bus and self._thread is not None:
                    self._ack_cond.wait(min(left, 0.02))
                else:
                    self._ack_cond.release()
                    try:
                        self._poll(0.01)
                    finally:
                        self._ack_cond.acquire()
            result = self._acks.pop(seq)
        if result != p.Result.OK:
            raise CommandRefusedError(f"{self.name}: {command.name} refused: {result.name}", error_code=int(result))

    # -- receiving
    def _poll(self, timeout: float) -> list[p.Telemetry]:
        """Drain frames for up to ``timeout`` s; handle acks/status; return telemetry."""
        if self._bus is None:
            raise DeviceInitializationError(f"{self.name}: not open")
        out: list[p.Telemetry] = []
        wait = timeout
        for _ in range(256):
            with error_check(f"{self.name}: CAN receive failed"):
                msg = self._bus.recv(timeout=wait)
            if msg is None:
                break
            wait = 0.0
            if msg.is_error_frame:
                self.stats.crc_errors += 1
                continue
            aid, data = msg.arbitration_id, bytes(msg.data)
            if aid == self.ids["telemetry"]:
                try:
                    out.append(p.Telemetry.decode(data))
                except ValueError:
                    self.stats.malformed_frames += 1
            elif aid == self.ids["ack"]:
                try:
                    command, seq, result = p.decode_ack(data)
                except ValueError:
                    self.stats.malformed_frames += 1
                    continue
                with self._ack_cond:
                    self._acks[seq] = result
                    self._ack_cond.notify_all()
            elif aid == self.ids["status"]:
                try:
                    self.status = p.Status.decode(data)
                    self.status_time_s = monotonic_s()
                except ValueError:
                    self.stats.malformed_frames += 1
            elif aid in (self.ids["command"], self.ids["heartbeat"], self.ids["estop"]):
                continue
            else:
                self.stats.garbage_bytes += len(data)
        return out

    def _read_internal(self) -> DynamometerBlock | None:
        arrival = monotonic_s()
        frames = self._poll(0.02)
        if not frames:
            return None
        counters = np.array([self._unwrap.unwrap(f.counter) for f in frames], dtype=np.int64)
        state = self.status.state if self.status is not None else p.State.IDLE
        return DynamometerBlock(
            device=self.name, counter=counters, time_s=self._clock.stamp(counters, arrival),
            torque_nm=np.array([f.torque_nm for f in frames]),
            position_rad=np.deg2rad([f.position_deg for f in frames]),
            velocity_rad_s=np.deg2rad([f.velocity_deg_s for f in frames]),
            state=np.full(len(frames), int(state), dtype=np.uint8))

    # -- commands (checked against the limits before anything is sent)
    def set_passive_isokinetic(self, speed_rad_s: float) -> None:
        self.limits.check_speed(speed_rad_s)
        raw = speed_wire(speed_rad_s)
        self._command(p.Command.SET_MODE, p.Mode.PASSIVE_ISOKINETIC)
        self._command(p.Command.SET_SPEED, raw)

    def set_range_of_motion(self, min_rad: float, max_rad: float) -> None:
        self.limits.check_position(min_rad)
        self.limits.check_position(max_rad)
        if not min_rad < max_rad:
            raise LimitViolationError("min_rad must be below max_rad")
        self._command(p.Command.SET_ROM, position_wire(min_rad), position_wire(max_rad))

    def set_torque_limit(self, torque_nm: float) -> None:
        self.limits.check_torque(torque_nm)
        self._command(p.Command.SET_TORQUE_LIMIT, torque_limit_wire(torque_nm))

    def move_to(self, target_rad: float) -> None:
        self.limits.check_position(target_rad)
        self._command(p.Command.START, position_wire(target_rad))

    def halt(self) -> None:
        self._command(p.Command.STOP)

    def emergency_stop(self) -> float:
        """Sent at once on the highest-priority id; no acknowledgement is awaited.

        Returns the host time (s) the frame was handed to the bus; :meth:`stop_latched_since`
        tells when the device has shown the stop.
        """
        sent = monotonic_s()
        self._send(self.ids["estop"], p.encode_estop())
        return sent

    def stop_latched_since(self, since_s: float) -> bool:
        """True once a status frame that arrived after host time ``since_s`` shows the arm latched
        stopped (emergency stop, or a fault the device latched itself)."""
        status = self.status
        return (status is not None and self.status_time_s >= since_s
                and status.state in (p.State.ESTOP, p.State.FAULT))

    @property
    def telemetry_period_s(self) -> float:
        """Seconds between telemetry frames at the requested rate."""
        return 1.0 / self.telemetry_rate_hz

    def reset(self) -> None:
        self._command(p.Command.RESET)

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        d.update(interface=self.interface, channel=self.channel, node=self.node, bitrate=self.bitrate,
                 telemetry_rate_hz=self.telemetry_rate_hz, limits=self.limits.as_dict(), protocol="dynamometer-can/1")
        return d
