"""Torque transmitter simulator: a pymodbus server whose registers follow the replica leg.

Two ways to reach it:

- ``modbus-tcp``: the pymodbus server itself (Modbus TCP/MBAP framing) on 127.0.0.1;
- ``modbus-rtu``: RTU framing on a loopback port that stands in for the RS-485 cable. A bridge
  between the cable port and the pymodbus RTU server holds every frame for its time on the wire
  (10 bits per character at the configured baud plus the 3.5-character frame gap), so the poll
  rate a driver reaches is the one the real baud allows, and it injects the byte-level faults.
"""

from __future__ import annotations

import asyncio
import select
import socket
import threading
import time

import numpy as np
from pymodbus import FramerType
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import SimData, SimDevice
from pymodbus.simulator.simutils import DataType

from ..simulation.faults import ByteFaults, FaultConfig
from ..simulation.replica_leg import ReplicaLeg
from ..simulation.tcp_link import TcpDeviceLink
from . import registers as r

#: conversions the transmitter averages for a tare
TARE_CONVERSIONS = 32


class TorqueSensorSimulator:
    """One transmitter (unit ``unit``) measuring ``leg``.

    :param framing: ``"rtu"`` (throttled bridge, the URL is ``modbus-rtu+socket://``) or ``"tcp"``.
    :param baud: emulated RS-485 baud (must be one of the transmitter's codes).
    :param word_order: float word order the device uses.
    :param noise_nm: torque noise SD in N·m.
    :param offset_nm: the transducer's zero offset before any tare, N·m.
    :param output_rate_hz: converts on its own clock at this rate (Hz) and numbers its conversions
        (registers 0x0004 and 0x0017), each conversion's noise drawn from the seed and its number
        counted from the hold schedule's start, so the same seed reads the same samples whatever the
        host's timing; None: a transmitter without a counter, a fresh conversion at every poll.
    """

    def __init__(self, leg: ReplicaLeg | None = None, *, framing: str = "rtu", unit: int = 1,
                 baud: int = 115200, word_order: r.WordOrder = "big", noise_nm: float = 0.01,
                 offset_nm: float = 0.35, faults: FaultConfig | None = None, seed: int = 0,
                 output_rate_hz: float | None = None) -> None:
        if baud not in r.BAUD_CODES.values():
            raise ValueError(f"baud {baud} not one of {sorted(r.BAUD_CODES.values())}")
        if framing not in ("rtu", "tcp"):
            raise ValueError("framing must be 'rtu' or 'tcp'")
        self.leg = leg or ReplicaLeg()
        self.framing, self.unit, self.baud, self.word_order = framing, unit, baud, word_order
        self.noise_nm, self.offset_nm = noise_nm, offset_nm
        #: False while the operator has the shank (and its springs) off the sensor, e.g. to tare
        self.shank_attached = True
        self.zero_nm = 0.0
        self.faults = faults or FaultConfig()
        self.rng = np.random.default_rng(seed)
        self.seed = seed
        if output_rate_hz is not None and not 1 <= output_rate_hz <= 65535:
            raise ValueError(f"output rate {output_rate_hz} Hz outside the register's 1–65535")
        self.output_rate_hz = output_rate_hz
        #: device sample at which the hold schedule began (counter mode; see :meth:`start_schedule`)
        self.schedule_origin_sample = 0
        self._tares = 0
        self._conversions: dict[tuple[int, int, bool], float] = {}  # recent conversions (before the tare)
        self.byte_faults = ByteFaults(self.faults, seed + 7)
        self.reads = 0
        self._t0 = time.monotonic()
        #: host time (s) at which the replica leg's hold schedule began (see :meth:`start_schedule`)
        self._schedule_origin_s = self._t0
        self._loop = asyncio.new_event_loop()
        self._server_port = self._free_port()
        self._ready = threading.Event()
        self._stop = threading.Event()
        self._server_thread = threading.Thread(target=self._serve, name="torque-sim-modbus", daemon=True)
        self._server_thread.start()
        if not self._ready.wait(5.0):
            raise RuntimeError("pymodbus simulator did not start")
        self._bridge: threading.Thread | None = None
        self.link: TcpDeviceLink | None = None
        if framing == "rtu":
            self.link = TcpDeviceLink()
            self._bridge = threading.Thread(target=self._run_bridge, name="torque-sim-rs485", daemon=True)
            self._bridge.start()

    @staticmethod
    def _free_port() -> int:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            return s.getsockname()[1]

    @property
    def url(self) -> str:
        """The driver URL for this simulator."""
        if self.framing == "tcp":
            return f"modbus-tcp://127.0.0.1:{self._server_port}?unit={self.unit}&word_order={self.word_order}"
        assert self.link is not None
        return (f"modbus-rtu+socket://127.0.0.1:{self.link.port}?unit={self.unit}&baud={self.baud}"
                f"&word_order={self.word_order}")

    def start_schedule(self, lead_s: float = 0.1) -> float:
        """The operator starts the leg's hold schedule ``lead_s`` seconds from now (at its first angle
        until then); returns the host time (s, ``time.monotonic``) of the first hold's start. With an
        output rate the start falls on a conversion, :attr:`schedule_origin_sample`."""
        if self.output_rate_hz is None:
            self._schedule_origin_s = time.monotonic() + lead_s
            return self._schedule_origin_s
        self.schedule_origin_sample = self.sample_now() + int(np.ceil(lead_s * self.output_rate_hz))
        self._schedule_origin_s = self._t0 + self.schedule_origin_sample / self.output_rate_hz
        return self._schedule_origin_s

    def sample_now(self) -> int:
        """The number of the newest conversion (counter mode)."""
        assert self.output_rate_hz is not None
        return int(np.floor((time.monotonic() - self._t0) * self.output_rate_hz))

    def _seeded_normal(self, *key: int) -> float:
        return float(np.random.default_rng([self.seed, *key]).normal())

    # -- the device's registers
    def raw_torque_nm(self, t_s: float) -> float:
        """Load + zero offset + noise at schedule time ``t_s`` (s), a fresh conversion (no counter)."""
        knee = self.leg.knee_deg(np.array([t_s]))
        noise = self.noise_nm * self.faults.noise_scale * float(self.rng.normal())
        load = float(self.leg.torque_nm(knee)[0]) if self.shank_attached else 0.0
        return load + self.offset_nm + noise

    def conversion_nm(self, sample: int) -> float:
        """The conversion numbered ``sample`` (counter mode): its noise is drawn from the seed and the
        sample's place relative to the schedule's start, so it does not depend on when it is read."""
        assert self.output_rate_hz is not None
        key = (sample, self.schedule_origin_sample, self.shank_attached)
        cached = self._conversions.get(key)
        if cached is not None:
            return cached
        k = sample - self.schedule_origin_sample
        load = float(self.leg.torque_nm(self.leg.knee_deg(np.array([k / self.output_rate_hz])))[0]) \
            if self.shank_attached else 0.0
        noise = self.noise_nm * self.faults.noise_scale * self._seeded_normal(1, k + (1 << 40))
        value = load + self.offset_nm + noise
        self._conversions[key] = value
        while len(self._conversions) > 4 * r.HISTORY_DEPTH:
            self._conversions.pop(next(iter(self._conversions)))
        return value

    def _tare_zero_nm(self, t_s: float) -> float:
        """The new zero: the mean of the transmitter's 32 tare conversions (counter mode; their noise
        drawn from the seed and the tare's number), else one fresh conversion."""
        if self.output_rate_hz is None:
            return self.raw_torque_nm(t_s)
        self._tares += 1
        load = float(self.leg.torque_nm(self.leg.knee_deg(np.array([t_s])))[0]) if self.shank_attached else 0.0
        noise = np.random.default_rng([self.seed, 2, self._tares]).normal(size=TARE_CONVERSIONS).mean()
        return load + self.offset_nm + self.noise_nm * self.faults.noise_scale * float(noise)

    async def _action(self, function_code: int, start_address: int, address: int, count: int,
                      regs: list[int], set_values: list[int] | list[bool] | None) -> None:
        t = time.monotonic() - self._schedule_origin_s
        if function_code == 6 and address == r.TARE and set_values and set_values[0] == 1:
            self.zero_nm = self._tare_zero_nm(t)
        if function_code == 3:
            self.reads += 1
            if self.output_rate_hz is None:
                raw, sample = self.raw_torque_nm(t), 0
            else:
                sample = self.sample_now()
                raw = self.conversion_nm(sample)
                t = (sample - self.schedule_origin_sample) / self.output_rate_hz
            values = {
                r.TORQUE: r.encode_float(raw - self.zero_nm, self.word_order),
                r.SPEED: r.encode_float(float(self.leg.speed_rpm(np.array([t]))[0]), self.word_order),
                r.SAMPLE_COUNT: r.encode_uint32(sample, self.word_order),
                r.ZERO_OFFSET: r.encode_float(self.zero_nm, self.word_order),
            }
            if self.output_rate_hz is not None and address + count > r.HISTORY:
                values[r.HISTORY] = r.encode_uint32(sample, self.word_order)
                for i in range(r.HISTORY_DEPTH):
                    values[r.HISTORY + 2 + 2 * i] = r.encode_float(self.conversion_nm(sample - i) - self.zero_nm,
                                                                   self.word_order)
            for base, words in values.items():
                for i, w in enumerate(words):
                    if 0 <= base + i - start_address < len(regs):
                        regs[base + i - start_address] = w
        return None

    def _device(self) -> SimDevice:
        code = {v: k for k, v in r.BAUD_CODES.items()}[self.baud]
        init = [0] * r.REGISTER_COUNT
        init[r.BAUD_CODE], init[r.UNIT_ID] = code, self.unit
        init[r.WORD_ORDER] = 0 if self.word_order == "big" else 1
        init[r.OUTPUT_RATE] = int(round(self.output_rate_hz or 0))
        return SimDevice(id=self.unit, simdata=[SimData(address=0, values=init, datatype=DataType.REGISTERS)],
                         action=self._action)

    def _serve(self) -> None:
        asyncio.set_event_loop(self._loop)
        framer = FramerType.RTU if self.framing == "rtu" else FramerType.SOCKET

        async def main() -> None:
            server = ModbusTcpServer(self._device(), framer=framer, address=("127.0.0.1", self._server_port),
                                     ignore_missing_devices=True)
            await server.serve_forever(background=True)
            self._ready.set()
            while not self._stop.is_set():
                await asyncio.sleep(0.05)
            await server.shutdown()

        self._loop.run_until_complete(main())

    # -- the RS-485 cable
    def _wire_delay(self, nbytes: int) -> None:
        char_s = r.BITS_PER_CHAR / self.baud
        deadline = time.perf_counter() + (nbytes + 3.5) * char_s
        while time.perf_counter() < deadline:
            time.sleep(max(0.0, min(deadline - time.perf_counter(), 0.0002)))

    def _run_bridge(self) -> None:
        assert self.link is not None
        inner: socket.socket | None = None
        vanished_at: float | None = None
        disconnect_done = False
        while not self._stop.is_set():
            now = time.monotonic() - self._t0
            if vanished_at is not None:
                if now - vanished_at >= self.faults.reconnect_after_s:
                    vanished_at = None
                    self.link.listen()
                else:
                    time.sleep(0.01)
                    continue
            if (self.faults.disconnect_after_s is not None and not disconnect_done
                    and now >= self.faults.disconnect_after_s):
                disconnect_done = True
                self.link.vanish()
                vanished_at = now
                continue
            if not self.link.accept(0.05):
                continue
            if inner is None:
                inner = socket.create_connection(("127.0.0.1", self._server_port))
                inner.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            request = self.link.recv(0.05)
            if request is None:
                inner.close()
                inner = None
                continue
            if not request:
                continue
            self._wire_delay(len(request))
            inner.sendall(request)
            response = b""
            deadline = time.monotonic() + 0.5
            while time.monotonic() < deadline:
                ready, _, _ = select.select([inner], [], [], 0.01)
                if ready:
                    response += inner.recv(4096)
                    if len(response) >= 5 and (response[1] & 0x80 or len(response) >= 5 + response[2]):
                        break
            if self.faults.silent_at(now) or not response:
                continue
            out = self.byte_faults.apply(response)
            self._wire_delay(len(out))
            self.link.send(out)
        if inner is not None:
            inner.close()

    def close(self) -> None:
        self._stop.set()
        if self._bridge is not None:
            self._bridge.join(2.0)
        self._server_thread.join(3.0)
        if self.link is not None:
            self.link.close()

    def __enter__(self) -> TorqueSensorSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
