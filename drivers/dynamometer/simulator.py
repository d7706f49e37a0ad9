"""Dynamometer simulator: a device node on a python-can bus moving a seated subject's leg.

It runs the device side of :mod:`drivers.dynamometer.protocol` on its own ``can.Bus`` (the
``virtual`` interface in tests), ticking at the telemetry rate on an absolute schedule:
commands are acknowledged, moves follow a trapezoidal velocity profile at the set speed, the
watchdog stops motion when host heartbeats stop, and the emergency stop latches. Like the
hardware it stands for, the device enforces its own envelope while moving, whatever the host
sends: the arm stops at the range-of-motion stop (fault ``ROM_LIMIT``, also when the ROM is
narrowed mid-move), a shaft torque over the set limit latches ``TORQUE_LIMIT`` (whenever the
arm is held), a speed above the set speed latches ``SPEED_LIMIT``; a status frame goes out at once
on every state change. Telemetry torque comes from
:class:`~drivers.simulation.seated_leg.SeatedLeg` plus sensor noise.

``lose_estop_frames`` makes the next N emergency-stop frames vanish on the bus (a frame the
host sent that never arrives), for testing the host's confirmation and re-send.

CAN faults map to what a CAN controller shows software: ``corrupt_rate`` → error frames (the
hardware discards frames with a bad CRC), ``truncate_rate`` → a telemetry frame with a short
DLC, ``garbage_rate`` → frames on unknown ids, ``drop_rate`` → telemetry never sent (counter
gap), ``disconnect_after_s``/``silence_after_s`` → the node falls silent (bus-off) and returns.
"""

from __future__ import annotations

import threading
import time

import can
import numpy as np

from ..simulation.faults import FaultConfig
from ..simulation.seated_leg import SeatedLeg
from . import protocol as p


class DynamometerSimulator:
    """The simulated device node.

    :param channel: python-can channel (e.g. ``"dyno"`` on the virtual interface).
    :param device_rom_deg: the mechanical range of the arm, in degrees.
    :param max_speed_deg_s: the device's own speed ceiling.
    """

    def __init__(self, leg: SeatedLeg | None = None, *, channel: str = "dyno", interface: str = "virtual",
                 node: int = p.NODE_ID_DEFAULT, telemetry_rate_hz: int = 100, start_position_deg: float = 0.0,
                 device_rom_deg: tuple[float, float] = (-60.0, 130.0), max_speed_deg_s: float = 300.0,
                 acceleration_deg_s2: float = 60.0, noise_nm: float = 0.05, faults: FaultConfig | None = None,
                 seed: int = 0, autostart: bool = True, max_torque_limit_nm: float = 500.0,
                 lose_estop_frames: int = 0) -> None:
        self.leg = leg or SeatedLeg()
        self.ids = p.ids(node)
        self.bus = can.Bus(interface=interface, channel=channel, receive_own_messages=False)
        self.rate_hz = telemetry_rate_hz
        self.device_rom_deg = device_rom_deg
        self.max_speed_deg_s = max_speed_deg_s
        self.acceleration_deg_s2 = acceleration_deg_s2
        self.noise_nm = noise_nm
        self.faults = faults or FaultConfig()
        self.rng = np.random.default_rng(seed)
        #: torque-sensor noise per telemetry tick, counted from the last accepted START: a sweep's
        #: samples do not depend on when the host's commands happened to arrive
        self._noise = np.random.default_rng([seed, 1]).normal(0.0, 1.0, 1 << 16)
        self._noise_origin = 0
        # device state
        self.state = p.State.IDLE
        self.mode = p.Mode.PASSIVE_HOLD
        self.fault = p.Fault.NONE
        self.position_deg = start_position_deg
        self.velocity_deg_s = 0.0
        self.acceleration = 0.0
        self.speed_deg_s = 5.0
        self.rom_deg = device_rom_deg
        self.max_torque_limit_nm = max_torque_limit_nm
        self.torque_limit_nm = 200.0
        self.lose_estop_frames = lose_estop_frames
        self.estop_frames_lost = 0
        self._status_sent_state: p.State | None = None
        self.target_deg: float | None = None
        self.counter = 0
        self.sent = 0
        self.last_heartbeat_s: float | None = None
        self.log: list[tuple[float, str]] = []
        self._stop = threading.Event()
        self._t0 = time.monotonic()
        self._thread: threading.Thread | None = None
        if autostart:
            self.start()

    @property
    def time_s(self) -> float:
        """Device time since power-up (s)."""
        return time.monotonic() - self._t0

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="dyno-sim", daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        if self._thread:
            self._thread.join(2.0)
        self.bus.shutdown()

    def __enter__(self) -> DynamometerSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- command handling
    def _send(self, arbitration_id: int, data: bytes) -> None:
        try:
            self.bus.send(can.Message(arbitration_id=arbitration_id, data=data, is_extended_id=False))
        except can.CanError:
            pass

    def _latch(self, state: p.State, fault: p.Fault, why: str) -> None:
        self.state = state
        self.fault |= fault
        self.target_deg = None
        self.velocity_deg_s = 0.0
        self.log.append((self.time_s, why))

    def _handle(self, msg: can.Message, now: float) -> None:
        if msg.is_error_frame:
            return
        data = bytes(msg.data)
        if msg.arbitration_id == self.ids["estop"] and p.is_estop(data):
            if self.lose_estop_frames > 0:
                self.lose_estop_frames -= 1
                self.estop_frames_lost += 1
                return
            self._latch(p.State.ESTOP, p.Fault.ESTOP, "emergency stop")
            return
        if msg.arbitration_id == self.ids["heartbeat"]:
            self.last_heartbeat_s = now
            return
        if msg.arbitration_id != self.ids["command"]:
            return
        try:
            command, seq, args = p.decode_command(data)
        except ValueError:
            self._send(self.ids["ack"], p.encode_ack(data[0] if data else 0, data[1] if len(data) > 1 else 0, p.Result.UNKNOWN))
            return
        result = self._execute(command, args, now)
        self._send(self.ids["ack"], p.encode_ack(command, seq, result))

    def _execute(self, command: p.Command, args: tuple[int, ...], now: float) -> p.Result:
        latched = self.state in (p.State.ESTOP, p.State.FAULT)
        if command == p.Command.RESET:
            self.state, self.fault = p.State.IDLE, p.Fault.NONE
            return p.Result.OK
        if command == p.Command.STOP:
            if not latched:
                self.target_deg = None
                self.state = p.State.HOLDING
            return p.Result.OK
        if latched:
            return p.Result.BAD_STATE
        if command == p.Command.SET_MODE:
            self.mode = p.Mode(args[0]) if args[0] in p.Mode._value2member_map_ else self.mode
            return p.Result.OK if args[0] in p.Mode._value2member_map_ else p.Result.OUT_OF_RANGE
        if command == p.Command.SET_SPEED:
            speed = args[0] * p.SPEED_LSB_DEG_S
            if not 0 < speed <= self.max_speed_deg_s:
                return p.Result.OUT_OF_RANGE
            self.speed_deg_s = speed
            return p.Result.OK
        if command == p.Command.SET_ROM:
            lo, hi = args[0] * p.POSITION_LSB_DEG, args[1] * p.POSITION_LSB_DEG
            if not (self.device_rom_deg[0] <= lo < hi <= self.device_rom_deg[1]):
                return p.Result.OUT_OF_RANGE
            self.rom_deg = (lo, hi)
            return p.Result.OK
        if command == p.Command.SET_TORQUE_LIMIT:
            limit = args[0] * p.TORQUE_LIMIT_LSB_NM
            if not 0 < limit <= self.max_torque_limit_nm:
                return p.Result.OUT_OF_RANGE
            self.torque_limit_nm = limit
            return p.Result.OK
        if command == p.Command.SET_TELEMETRY_RATE:
            if not 10 <= args[0] <= 1000:
                return p.Result.OUT_OF_RANGE
            self.rate_hz = args[0]
            return p.Result.OK
        if command == p.Command.START:
            target = args[0] * p.POSITION_LSB_DEG
            host_alive = self.last_heartbeat_s is not None and now - self.last_heartbeat_s <= p.WATCHDOG_TIMEOUT_S
            if self.mode != p.Mode.PASSIVE_ISOKINETIC or not host_alive:
                return p.Result.BAD_STATE
            if not self.rom_deg[0] <= target <= self.rom_deg[1]:
                return p.Result.OUT_OF_RANGE
            self.target_deg = target
            self.state = p.State.MOVING
            self._noise_origin = self.counter + 1  # the next tick is the movement's first
            return p.Result.OK
        return p.Result.UNKNOWN

    # -- motion and physics
    def _step(self, dt: float, now: float) -> None:
        v_old = self.velocity_deg_s
        if self.state == p.State.MOVING and self.target_deg is not None:
            if self.last_heartbeat_s is None or now - self.last_heartbeat_s > p.WATCHDOG_TIMEOUT_S:
                self._latch(p.State.FAULT, p.Fault.WATCHDOG, "host heartbeat lost")
            else:
                err = self.target_deg - self.position_deg
                # trapezoid: speed limited by the set speed and by the distance left to brake
                v_brake = np.sqrt(2 * self.acceleration_deg_s2 * abs(err))
                v_want = np.sign(err) * min(self.speed_deg_s, v_brake)
                dv = np.clip(v_want - v_old, -self.acceleration_deg_s2 * dt, self.acceleration_deg_s2 * dt)
                self.velocity_deg_s = v_old + dv
                step = self.velocity_deg_s * dt
                lo, hi = self.rom_deg
                if abs(self.velocity_deg_s) > self.speed_deg_s * 1.05 + 0.1:
                    self._latch(p.State.FAULT, p.Fault.SPEED_LIMIT,
                                f"speed {self.velocity_deg_s:.1f}°/s over {self.speed_deg_s:g}°/s")
                elif not lo <= self.position_deg + step <= hi:
                    # the ROM stop (the ROM may have been narrowed mid-move): the arm halts at it
                    self.position_deg = min(max(self.position_deg, lo), hi)
                    self._latch(p.State.FAULT, p.Fault.ROM_LIMIT,
                                f"range-of-motion stop at {self.position_deg:.2f}° ({lo:g}..{hi:g}°)")
                elif abs(step) >= abs(err) or abs(err) < 1e-3:
                    self.position_deg, self.velocity_deg_s = self.target_deg, 0.0
                    self.state, self.target_deg = p.State.HOLDING, None
                else:
                    self.position_deg += step
        else:
            self.velocity_deg_s = 0.0
        self.acceleration = (self.velocity_deg_s - v_old) / dt if dt > 0 else 0.0

    @property
    def movement_time_s(self) -> float:
        """Time (s) counted in telemetry ticks from the last accepted START's first tick (from power-up
        before any): the subject's clock, so what the subject does in a movement (an activation burst
        1.2 s in) happens at the same tick, angle and phase in every run, however the host is timed."""
        return (self.counter - self._noise_origin) / self.rate_hz

    def torque_nm(self) -> float:
        """Shaft torque of this tick (N·m): the leg's at the arm's state, plus the sensor's noise."""
        tau = float(self.leg.shaft_torque_nm(np.array([self.movement_time_s]), np.array([self.position_deg]),
                                             np.array([self.velocity_deg_s]), np.array([self.acceleration]))[0])
        return tau + self.noise_nm * self.faults.noise_scale * float(self._noise[(self.counter - self._noise_origin) % (1 << 16)])

    def _telemetry(self, now: float, t_stream: float) -> None:
        c = self.faults
        self.counter += 1
        tau = self.torque_nm()
        if self.state not in (p.State.ESTOP, p.State.FAULT) and abs(tau) > self.torque_limit_nm:
            self._latch(p.State.FAULT, p.Fault.TORQUE_LIMIT, f"torque {tau:.1f} N·m over limit")
        if c.silent_at(t_stream) or self.faults.vanished_at(t_stream):
            return
        if c.drop_rate and self.rng.random() < c.drop_rate:
            return
        if c.corrupt_rate and self.rng.random() < c.corrupt_rate:
            self.bus.send(can.Message(is_error_frame=True, arbitration_id=0, data=b""))
            return
        data = p.Telemetry(self.counter, tau, self.position_deg, self.velocity_deg_s).encode()
        if c.truncate_rate and self.rng.random() < c.truncate_rate:
            data = data[: int(self.rng.integers(1, 8))]
        if c.garbage_rate and self.rng.random() < c.garbage_rate:
            self._send(int(self.rng.integers(0x400, 0x6FF)), self.rng.bytes(int(self.rng.integers(0, 9))))
        self._send(self.ids["telemetry"], data)
        self.sent += 1

    def _run(self) -> None:
        next_tick = time.monotonic()
        next_status = next_tick
        last = next_tick
        while not self._stop.is_set():
            now = time.monotonic()
            while True:
                msg = self.bus.recv(timeout=0)
                if msg is None:
                    break
                if not self.faults.vanished_at(now - self._t0):
                    self._handle(msg, now)
            while next_tick <= now:
                self._step(next_tick - last, next_tick)
                last = next_tick
                self._telemetry(next_tick - self._t0, next_tick - self._t0)
                next_tick += 1.0 / self.rate_hz
            if now >= next_status or self.state != self._status_sent_state:
                next_status = now + 0.1
                if not (self.faults.silent_at(now - self._t0) or self.faults.vanished_at(now - self._t0)):
                    self._status_sent_state = self.state
                    self._send(self.ids["status"], p.Status(self.state, self.mode, self.fault, self.rate_hz,
                                                            self.torque_limit_nm).encode())
            msg = self.bus.recv(timeout=max(0.0, min(next_tick, next_status) - time.monotonic()))
            if msg is not None and not self.faults.vanished_at(time.monotonic() - self._t0):
                self._handle(msg, time.monotonic())
