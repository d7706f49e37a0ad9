"""A simulated CiA 402 servo drive moving a seated subject's leg: a CANopen slave node
(:class:`canopen.LocalNode` with the drive's EDS) on a python-can bus.

What a host sees is what a drive on the market shows it: NMT, heartbeat producer (0x1017) and
consumer (0x1016, the watchdog on the host), SDO access to the object dictionary, the power state
machine driven by the controlword (0x6040, by SDO or RPDO1), EMCY on every fault, and two TPDOs per
sample tick (position, torque and the sample counter; velocity, statusword and the counter) at the
rate the event timer (0x1800/0x1801 sub 5, ms) sets.

Motion: profile position mode (a move to 0x607A at the profile velocity 0x6081, trapezoidal with
0x6083/0x6084) and profile velocity mode (0x60FF). The drive enforces its envelope whatever the host
sends: a move ends at the software position limits 0x607D (fault 0x8612 if the arm would pass one,
also when they are narrowed mid-move), a shaft torque over 0x6072 faults (0x8311), a speed over 0x607F
faults (0x8400), a host heartbeat older than the consumer time faults (0x8130). Quick stop, halt and
every fault reaction decelerate on the quick-stop ramp (0x6085). Telemetry torque comes from
:class:`~drivers.simulation.seated_leg.SeatedLeg` plus sensor noise, as in the frame-set simulator.

``lose_estop_frames`` drops the next N quick-stop controlwords (a frame the host sent that never
arrives); ``lose_sdo_requests`` leaves the next N SDO requests unanswered;
``faults`` (drop, corrupt, truncate, garbage, silence) act on the TPDOs as on the other
simulators' telemetry.
"""

from __future__ import annotations

import struct
import threading
import time
from typing import Any

import can
import canopen
import numpy as np
from canopen.objectdictionary import ODVariable

from ..simulation.faults import FaultConfig
from ..simulation.seated_leg import SeatedLeg
from . import cia402 as c
from . import protocol as p
from .cia402 import PowerState

#: the frame-set's state names for a 402 drive's state (the acquisition records one state channel)
SUMMARY = {PowerState.QUICK_STOP_ACTIVE: p.State.ESTOP, PowerState.FAULT_REACTION_ACTIVE: p.State.FAULT,
           PowerState.FAULT: p.State.FAULT}


class Cia402DriveSimulator:
    """The simulated drive (node ``node`` on ``interface``/``channel``).

    :param device_rom_deg: the arm's mechanical range (°); the software limits may not exceed it.
    """

    def __init__(self, leg: SeatedLeg | None = None, *, channel: str = "dyno402", interface: str = "virtual",
                 node: int = p.NODE_ID_DEFAULT, telemetry_rate_hz: int = 100, start_position_deg: float = 0.0,
                 device_rom_deg: tuple[float, float] = (-60.0, 130.0), noise_nm: float = 0.05,
                 faults: FaultConfig | None = None, seed: int = 0, autostart: bool = True,
                 lose_estop_frames: int = 0, lose_sdo_requests: int = 0) -> None:
        self.leg = leg or SeatedLeg()
        self.node_id = node
        self.device_rom_deg = device_rom_deg
        self.noise_nm = noise_nm
        self.faults = faults or FaultConfig()
        self.rng = np.random.default_rng(seed)
        self._noise = np.random.default_rng([seed, 1]).normal(0.0, 1.0, 1 << 16)
        self._noise_origin = 0
        self.lose_estop_frames = lose_estop_frames
        self.estop_frames_lost = 0
        #: the next this many SDO requests go unanswered (a lost frame, a drive busy past the host's timeout)
        self.lose_sdo_requests = lose_sdo_requests
        self.sdo_requests_lost = 0
        self.network = canopen.Network(can.Bus(interface=interface, channel=channel, receive_own_messages=False))
        self.network.connect()
        self.od = canopen.import_od(str(c.EDS_PATH), node)
        self.node = canopen.LocalNode(node, self.od)
        self.network.add_node(self.node)
        self.network.unsubscribe(self.node.sdo.rx_cobid, self.node.sdo.on_request)
        self.network.subscribe(self.node.sdo.rx_cobid, self._on_sdo_request)
        self.node.add_write_callback(self._on_write)
        self._signed = c.signed_objects(self.od)
        self._layouts = [c.PdoLayout.from_mapping(c.mapping_words(self.od, m), self._signed)
                         for m in (c.TPDO1_MAP, c.TPDO2_MAP)]
        self._lock = threading.RLock()
        # drive state
        self.power = PowerState.SWITCH_ON_DISABLED
        self.mode = 0
        self.error_code = 0
        self.position_deg = start_position_deg
        self.velocity_deg_s = 0.0
        self.acceleration = 0.0
        self.target_deg: float | None = None
        self.velocity_target_deg_s: float | None = None
        self.halted = False
        #: a quick stop brought the drive here (SWITCH ON DISABLED reads as the e-stop until a shutdown word)
        self.quick_stopped = False
        self.setpoint_ack = False
        self.internal_limit = False
        self._last_controlword = 0
        self.counter = 0
        self.sent = 0
        self.last_heartbeat_s: float | None = None
        self.log: list[tuple[float, str]] = []
        self._stop = threading.Event()
        self._t0 = time.monotonic()
        self._thread: threading.Thread | None = None
        self.network.subscribe(0x700 + c.HOST_NODE_ID, self._on_host_heartbeat)
        self.network.subscribe(0x200 + node, self._on_rpdo)
        self._publish()
        self.node.nmt.state = "INITIALISING"  # boot-up message
        self.node.nmt.state = "PRE-OPERATIONAL"  # heartbeat producer starts (0x1017)
        if autostart:
            self.start()

    # -- the object dictionary's values
    def _variable(self, index: int, sub: int) -> ODVariable:
        obj = self.od[index]
        if not isinstance(obj, ODVariable):
            obj = obj[sub]
        assert isinstance(obj, ODVariable)
        return obj

    def _get(self, index: int, sub: int = 0) -> int:
        return int(self._variable(index, sub).decode_raw(self.node.get_data(index, sub)))

    def _set(self, index: int, value: int, sub: int = 0) -> None:
        self.node.set_data(index, sub, self._variable(index, sub).encode_raw(value), check_writable=False)

    @property
    def rate_hz(self) -> float:
        return 1000.0 / max(self._get(c.TPDO1_COMM, 5), 1)

    @property
    def rom_deg(self) -> tuple[float, float]:
        """The software position limits (°)."""
        return (self._get(c.SOFTWARE_POSITION_LIMIT, 1) / c.POSITION_COUNTS_PER_DEG,
                self._get(c.SOFTWARE_POSITION_LIMIT, 2) / c.POSITION_COUNTS_PER_DEG)

    @rom_deg.setter
    def rom_deg(self, value: tuple[float, float]) -> None:
        """Narrow the limits from the drive's side (a test of the drive's own stop)."""
        self._set(c.SOFTWARE_POSITION_LIMIT, round(value[0] * c.POSITION_COUNTS_PER_DEG), 1)
        self._set(c.SOFTWARE_POSITION_LIMIT, round(value[1] * c.POSITION_COUNTS_PER_DEG), 2)

    @property
    def state(self) -> p.State:
        """The state in the frame-set's words (IDLE, MOVING, HOLDING, ESTOP, FAULT)."""
        if self.power in SUMMARY:
            return SUMMARY[self.power]
        if self.power == PowerState.SWITCH_ON_DISABLED and self.quick_stopped:
            return p.State.ESTOP  # the quick stop's end (option 2), until the host walks the machine again
        if self.power == PowerState.OPERATION_ENABLED:
            moving = self.target_deg is not None or self.velocity_target_deg_s is not None or self.velocity_deg_s != 0
            return p.State.MOVING if moving else p.State.HOLDING
        return p.State.IDLE

    @property
    def time_s(self) -> float:
        return time.monotonic() - self._t0

    @property
    def movement_time_s(self) -> float:
        """Time (s) counted in ticks from the last accepted set-point: the subject's clock."""
        return (self.counter - self._noise_origin) / self.rate_hz

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="dyno402-sim", daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        if self._thread:
            self._thread.join(2.0)
        self.node.nmt.stop_heartbeat()
        self.network.disconnect()

    def __enter__(self) -> Cia402DriveSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- host traffic (the network's notifier thread)
    def _on_sdo_request(self, can_id: int, data: bytearray, timestamp: float) -> None:
        is_abort = data[0] & 0xE0 == 0x80  # the client's abort after its timeout is not a request
        if self.lose_sdo_requests > 0 and not is_abort:
            self.lose_sdo_requests -= 1
            self.sdo_requests_lost += 1
            return
        self.node.sdo.on_request(can_id, data, timestamp)

    def _on_host_heartbeat(self, can_id: int, data: bytearray, timestamp: float) -> None:
        self.last_heartbeat_s = time.monotonic()

    def _on_rpdo(self, can_id: int, data: bytearray, timestamp: float) -> None:
        if len(data) != 2:
            return
        word = struct.unpack("<H", bytes(data))[0]
        if self._is_quick_stop(word) and self.lose_estop_frames > 0:
            self.lose_estop_frames -= 1
            self.estop_frames_lost += 1
            return
        with self._lock:
            self._controlword(word)
            # the RPDO's object: an SDO read of 0x6040 shows the last word (stored as-is, not a second command)
            self.node.data_store.setdefault(c.CONTROLWORD, {})[0] = self._variable(c.CONTROLWORD, 0).encode_raw(word)
            self._publish()

    def _on_write(self, index: int, subindex: int, od: Any, data: bytes) -> None:
        """SDO writes: the controlword drives the state machine; set-points are checked when they are used."""
        if index == c.CONTROLWORD:
            with self._lock:
                self._controlword(int(od.decode_raw(data)))
                self._publish()
        elif index == c.MODES_OF_OPERATION:
            value = int(od.decode_raw(data))
            if value not in (m.value for m in c.Mode):
                raise canopen.SdoAbortedError(0x06090030)  # value range of parameter exceeded
            with self._lock:
                self.mode = value
                self._publish()
        elif index == c.SOFTWARE_POSITION_LIMIT and subindex in (1, 2):
            limit_deg = int(od.decode_raw(data)) / c.POSITION_COUNTS_PER_DEG
            if not self.device_rom_deg[0] <= limit_deg <= self.device_rom_deg[1]:
                raise canopen.SdoAbortedError(0x06090030)
        elif index in (c.TPDO1_COMM, c.TPDO2_COMM) and subindex == 5:
            ms = int(od.decode_raw(data))
            if not 1 <= ms <= 100:
                raise canopen.SdoAbortedError(0x06090030)

    @staticmethod
    def _is_quick_stop(word: int) -> bool:
        return word & 0x86 == c.CW_QUICK_STOP

    def _controlword(self, word: int) -> None:
        """CiA 402 transitions (numbers as in the profile) on a controlword."""
        s, now = self.power, self.time_s
        rising = word & ~self._last_controlword
        self._last_controlword = word
        if s == PowerState.FAULT:
            if rising & c.CW_FAULT_RESET and self._host_alive(time.monotonic()):
                self.power, self.error_code = PowerState.SWITCH_ON_DISABLED, 0  # 15
                self.log.append((now, "fault reset"))
            return
        if s == PowerState.FAULT_REACTION_ACTIVE:
            return
        if word & 0x82 == c.CW_DISABLE_VOLTAGE:
            if s != PowerState.SWITCH_ON_DISABLED:
                self._stop_motion()
            self.power = PowerState.SWITCH_ON_DISABLED  # 7, 9, 10, 12
            return
        if self._is_quick_stop(word):
            if s == PowerState.OPERATION_ENABLED:
                self.power = PowerState.QUICK_STOP_ACTIVE  # 11
                self.quick_stopped = True
                self._brake("quick stop")
            elif s in (PowerState.READY_TO_SWITCH_ON, PowerState.SWITCHED_ON):
                self.power = PowerState.SWITCH_ON_DISABLED  # 7, 10
            return
        command = word & 0x8F
        if command in (c.CW_SHUTDOWN, c.CW_SHUTDOWN | 0x08) and word & 0x87 == c.CW_SHUTDOWN:
            if s in (PowerState.SWITCH_ON_DISABLED, PowerState.SWITCHED_ON, PowerState.OPERATION_ENABLED):
                if s == PowerState.OPERATION_ENABLED:
                    self._stop_motion()
                self.power = PowerState.READY_TO_SWITCH_ON  # 2, 6, 8
                self.quick_stopped = False
        elif command == c.CW_SWITCH_ON:
            if s == PowerState.READY_TO_SWITCH_ON:
                self.power = PowerState.SWITCHED_ON  # 3
            elif s == PowerState.OPERATION_ENABLED:
                self._stop_motion()
                self.power = PowerState.SWITCHED_ON  # 5
        elif command == c.CW_ENABLE_OPERATION:
            if s == PowerState.SWITCHED_ON:
                self.power = PowerState.OPERATION_ENABLED  # 4
            elif s == PowerState.QUICK_STOP_ACTIVE and self._get(c.QUICK_STOP_OPTION) in (5, 6, 7, 8):
                if self.velocity_deg_s == 0.0:
                    self.power = PowerState.OPERATION_ENABLED  # 16
            if self.power == PowerState.OPERATION_ENABLED:
                self._operate(word, rising)

    def _operate(self, word: int, rising: int) -> None:
        """Operation enabled: halt, and the mode's set-points."""
        self.halted = bool(word & c.CW_HALT)
        if self.halted:
            if self.target_deg is not None or self.velocity_target_deg_s is not None:
                self._brake("halt")
            return
        if self.mode == c.Mode.PROFILE_POSITION:
            if rising & c.CW_NEW_SETPOINT:
                if not self._host_alive(time.monotonic()):
                    self.log.append((self.time_s, "set-point refused: no host heartbeat"))
                    return
                lo, hi = self.rom_deg
                target = self._get(c.TARGET_POSITION) / c.POSITION_COUNTS_PER_DEG
                self.internal_limit = not lo <= target <= hi
                self.target_deg = min(max(target, lo), hi)
                self.velocity_target_deg_s = None
                self.setpoint_ack = True
                self._noise_origin = self.counter + 1
            elif not word & c.CW_NEW_SETPOINT:
                self.setpoint_ack = False
        elif self.mode == c.Mode.PROFILE_VELOCITY:
            self.target_deg = None
            self.velocity_target_deg_s = self._get(c.TARGET_VELOCITY) / c.VELOCITY_COUNTS_PER_DEG_S

    def _stop_motion(self) -> None:
        self.target_deg = None
        self.velocity_target_deg_s = None

    def _brake(self, why: str) -> None:
        """Decelerate on the quick-stop ramp to standstill (the motion targets cleared)."""
        self._stop_motion()
        self.log.append((self.time_s, why))

    def _fault(self, code: int, why: str) -> None:
        if self.power in (PowerState.FAULT, PowerState.FAULT_REACTION_ACTIVE):
            return
        self.power = PowerState.FAULT_REACTION_ACTIVE  # 13: the reaction is the quick-stop ramp
        self.error_code = code
        self._brake(why)
        try:
            self.node.emcy.send(code, 0x01)
        except Exception:  # an EMCY that cannot go out must not stop the drive's own reaction
            pass

    def _host_alive(self, now: float) -> bool:
        word = self._get(c.CONSUMER_HEARTBEAT, 1)
        timeout_s = (word & 0xFFFF) / 1000.0
        if timeout_s == 0:
            return True  # no consumer configured
        return self.last_heartbeat_s is not None and now - self.last_heartbeat_s <= timeout_s

    # -- motion and physics (the tick thread)
    def _step(self, dt: float, now: float) -> None:
        v_old = self.velocity_deg_s
        quick = self._get(c.QUICK_STOP_DECELERATION) / c.ACCELERATION_COUNTS_PER_DEG_S2
        if self.power == PowerState.OPERATION_ENABLED and not self._host_alive(now) and (
                self.target_deg is not None or self.velocity_target_deg_s is not None or v_old != 0):
            self._fault(c.EMCY_HEARTBEAT, "host heartbeat lost")
        if self.power == PowerState.OPERATION_ENABLED and self.target_deg is not None and not self.halted:
            accel = self._get(c.PROFILE_ACCELERATION) / c.ACCELERATION_COUNTS_PER_DEG_S2
            speed = self._get(c.PROFILE_VELOCITY) / c.VELOCITY_COUNTS_PER_DEG_S
            err = self.target_deg - self.position_deg
            v_want = np.sign(err) * min(speed, np.sqrt(2 * accel * abs(err)))
            v_new = v_old + float(np.clip(v_want - v_old, -accel * dt, accel * dt))
            if abs(v_new * dt) >= abs(err) or abs(err) < 1e-3:
                self.position_deg, v_new, self.target_deg = self.target_deg, 0.0, None
            self.velocity_deg_s = v_new
        elif self.power == PowerState.OPERATION_ENABLED and self.velocity_target_deg_s is not None and not self.halted:
            accel = self._get(c.PROFILE_ACCELERATION) / c.ACCELERATION_COUNTS_PER_DEG_S2
            self.velocity_deg_s = v_old + float(np.clip(self.velocity_target_deg_s - v_old, -accel * dt, accel * dt))
        else:  # quick stop, halt, fault reaction, power off: the quick-stop ramp to standstill
            self.velocity_deg_s = float(np.sign(v_old) * max(abs(v_old) - quick * dt, 0.0))
        if self.target_deg is not None or self.velocity_deg_s != 0.0:
            step = 0.5 * (v_old + self.velocity_deg_s) * dt if self.target_deg is None else self.velocity_deg_s * dt
            lo, hi = self.rom_deg
            speed_max = self._get(c.MAX_PROFILE_VELOCITY) / c.VELOCITY_COUNTS_PER_DEG_S
            if abs(self.velocity_deg_s) > speed_max * 1.05 + 0.1:
                self._fault(c.EMCY_SPEED, f"speed {self.velocity_deg_s:.1f}°/s over {speed_max:g}°/s")
            if not lo <= self.position_deg + step <= hi:
                self.position_deg = min(max(self.position_deg, lo), hi)
                self.velocity_deg_s = 0.0
                self._fault(c.EMCY_POSITION_LIMIT, f"software position limit at {self.position_deg:.2f}° "
                                                   f"({lo:g}..{hi:g}°)")
            elif self.position_deg != self.target_deg:
                self.position_deg += step
        if self.power == PowerState.FAULT_REACTION_ACTIVE and self.velocity_deg_s == 0.0:
            self.power = PowerState.FAULT  # 14
        if (self.power == PowerState.QUICK_STOP_ACTIVE and self.velocity_deg_s == 0.0
                and self._get(c.QUICK_STOP_OPTION) in (1, 2, 3, 4)):
            self.power = PowerState.SWITCH_ON_DISABLED  # 12: the ramp done, the drive disabled
        self.acceleration = (self.velocity_deg_s - v_old) / dt if dt > 0 else 0.0

    def torque_nm(self) -> float:
        tau = float(self.leg.shaft_torque_nm(np.array([self.movement_time_s]), np.array([self.position_deg]),
                                             np.array([self.velocity_deg_s]), np.array([self.acceleration]))[0])
        noise = float(self._noise[(self.counter - self._noise_origin) % (1 << 16)])
        return tau + self.noise_nm * self.faults.noise_scale * noise

    def _publish(self) -> None:
        """The drive's actual values into its object dictionary (what an SDO read or a TPDO shows)."""
        extra = (c.SW_TARGET_REACHED if self.target_deg is None and self.velocity_deg_s == 0.0 else 0) | (
            c.SW_INTERNAL_LIMIT if self.internal_limit else 0) | (c.SW_SETPOINT_ACK if self.setpoint_ack else 0)
        self._set(c.STATUSWORD, c.statusword_of(self.power, extra))
        self._set(c.MODES_DISPLAY, self.mode)
        self._set(c.ERROR_CODE, self.error_code)
        self._set(c.POSITION_ACTUAL, round(self.position_deg * c.POSITION_COUNTS_PER_DEG))
        self._set(c.VELOCITY_ACTUAL, round(self.velocity_deg_s * c.VELOCITY_COUNTS_PER_DEG_S))
        self._set(c.SAMPLE_COUNTER, self.counter & 0xFFFF)

    def _telemetry(self, t_stream: float) -> None:
        self.counter += 1
        tau = self.torque_nm()
        rated_nm = self._get(c.RATED_TORQUE) / 1000.0
        limit_nm = self._get(c.MAX_TORQUE) * rated_nm / 1000.0
        if self.power == PowerState.OPERATION_ENABLED and abs(tau) > limit_nm:  # the motor holds the arm
            self._fault(c.EMCY_TORQUE, f"torque {tau:.1f} N·m over {limit_nm:g} N·m")
        self._set(c.TORQUE_ACTUAL, int(np.clip(round(1000.0 * tau / rated_nm), -32768, 32767)))
        self._publish()
        f = self.faults
        if self.node.nmt.state != "OPERATIONAL" or f.silent_at(t_stream) or f.vanished_at(t_stream):
            return
        if f.drop_rate and self.rng.random() < f.drop_rate:
            return
        if f.corrupt_rate and self.rng.random() < f.corrupt_rate:
            assert self.network.bus is not None
            self.network.bus.send(can.Message(is_error_frame=True, arbitration_id=0, data=b""))
            return
        values = {i: self._get(i) for layout in self._layouts for i, _, _ in layout.entries}
        frames = [layout.encode(values) for layout in self._layouts]
        if f.truncate_rate and self.rng.random() < f.truncate_rate:
            frames[0] = frames[0][: int(self.rng.integers(1, 8))]
        if f.garbage_rate and self.rng.random() < f.garbage_rate:
            self.network.send_message(int(self.rng.integers(0x400, 0x4FF)), self.rng.bytes(int(self.rng.integers(0, 9))))
        for cob, data in zip((c.TPDO1_COMM, c.TPDO2_COMM), frames, strict=True):
            self.network.send_message(self._get(cob, 1) & 0x7FF, data)
        self.sent += 1

    def _run(self) -> None:
        next_tick = time.monotonic()
        last = next_tick
        while not self._stop.is_set():
            now = time.monotonic()
            with self._lock:
                while next_tick <= now:
                    self._step(next_tick - last, next_tick)
                    last = next_tick
                    self._telemetry(next_tick - self._t0)
                    next_tick += 1.0 / self.rate_hz
            self._stop.wait(max(0.0, next_tick - time.monotonic()))
