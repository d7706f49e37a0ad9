"""Torque sensor driver with the pymodbus client (RTU over any pyserial URL, or TCP).

pymodbus's asyncio client is used on a private event loop owned by the reader thread: its
synchronous serial client sleeps in 1 ms steps while waiting for a reply and reached only
75 polls/s at 115200 baud here, against about 380/s for the asyncio client on the same link.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import logging
import math
import queue
import threading
import time
from collections.abc import Awaitable, Callable
from typing import Any, TypeVar

import numpy as np
from pymodbus import FramerType, ModbusException
from pymodbus.client import AsyncModbusSerialClient, AsyncModbusTcpClient
from pymodbus.exceptions import ConnectionException
from pymodbus.framer.rtu import FramerRTU

from ..blocks import TorqueBlock
from ..clock import CounterUnwrapper, monotonic_s
from ..errors import (
    CommandRefusedError,
    ConnectionLostError,
    DeviceInitializationError,
    DeviceTimeoutError,
    error_check,
)
from ..url import DeviceUrl
from . import TorqueSensor
from . import registers as r

# pymodbus logs every failed transaction at ERROR; the driver counts and reports them itself
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

#: the transmitter's register layout unless the URL or the caller gives another
DEFAULT_REGISTERS = r.RegisterMap()

RPM_TO_RAD_S = 2 * np.pi / 60.0
T = TypeVar("T")
#: requests sent at open (and for a tare's write and read-back) before a unit is reported as not answering: one
#: poll's timeout is a sample period, which a loaded host can miss (the demo's lab day failed a tare's read-back
#: beside two busy-loop processes and the test suite's workers)
OPEN_ATTEMPTS = 3


class ModbusTorqueSensor(TorqueSensor):
    """Polls torque (and optionally speed) as fast as the link allows, or at ``rate`` Hz.

    A transmitter that publishes an output data rate (register 0x0017) numbers its conversions
    (0x0004) and keeps its newest 8 in a history block (0x0040): each poll reads the block, each
    conversion is kept once with the device's counter (a poll that finds nothing new is counted in
    :attr:`repeat_polls`), a host stall shorter than 8 conversions loses nothing, and a longer one is
    a counted gap. Without
    it, every poll attempt takes the next value of the driver's own counter, so a poll that fails
    (timeout, bad CRC, exception response) is a counted gap. Either way never a silent hole.

    :param port: pyserial URL or path (RTU), or ``host:port`` (TCP).
    :param framing: ``"rtu"`` or ``"tcp"``.
    :param unit: Modbus unit (device) id.
    :param baud: serial baud (RTU).
    :param word_order: float word order of this transmitter.
    :param rate: poll rate in Hz; None polls back to back.
    :param read_speed: also read the speed registers (slows the poll by 4 characters); a transmitter
        with a sample counter is read through its history block, which holds torque only.
    :param timeout_s: response timeout of one poll.
    """

    def __init__(self, port: str, *, framing: str = "rtu", unit: int = 1, baud: int = 115200,
                 word_order: r.WordOrder = "big", rate: float | None = None, read_speed: bool = False,
                 timeout_s: float = 0.05, registers: r.RegisterMap = DEFAULT_REGISTERS, **kwargs: Any) -> None:
        if framing not in ("rtu", "tcp"):
            raise ValueError("framing must be 'rtu' or 'tcp'")
        if word_order not in ("big", "little"):
            raise ValueError("word_order must be 'big' or 'little'")
        if framing == "rtu" and baud not in r.BAUD_CODES.values():
            raise ValueError(f"baud {baud} not one of {sorted(r.BAUD_CODES.values())}")
        self.port, self.framing, self.unit, self.baud = port, framing, unit, baud
        self.word_order: r.WordOrder = word_order
        #: True once the transmitter's own word-order register agreed with ``word_order``
        self.word_order_confirmed = False
        self.read_speed = read_speed
        self.registers = registers
        self.timeout_s = timeout_s
        self._nregs = 4 if read_speed else 2
        limit = self.poll_rate_limit_hz
        if rate is not None and rate > limit:
            raise ValueError(f"{rate} Hz exceeds the {limit:.0f} polls/s that {baud} baud allows")
        self.rate_hz = rate
        self._client: AsyncModbusSerialClient | AsyncModbusTcpClient | None = None
        self._loop = asyncio.new_event_loop()
        self._loop_owner: threading.Thread | None = None
        self._calls: queue.Queue[tuple[Callable[[], Awaitable[Any]], concurrent.futures.Future[Any]]] = queue.Queue()
        self._counter = 0
        self._next_poll = 0.0
        self._bad_crc_seen = False
        self._reply_bytes_seen = False
        self.zero_offset_nm = float("nan")
        #: the transmitter's output data rate (Hz) when it numbers its samples, else None (set at open)
        self.output_rate_hz: float | None = None
        #: polls that found the sample a previous poll had read (a transmitter with a counter)
        self.repeat_polls = 0
        self._unwrap = CounterUnwrapper(32)
        self._last_sample: tuple[int, float] | None = None  # (device counter, host time s) of the newest sample
        super().__init__(**kwargs)

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> ModbusTorqueSensor:
        opts = url.take({"unit": int, "baud": int, "word_order": str, "rate": float, "speed": bool,
                         "timeout": float})
        if "speed" in opts:
            opts["read_speed"] = opts.pop("speed")
        if "timeout" in opts:
            opts["timeout_s"] = opts.pop("timeout")
        if url.scheme == "modbus-tcp":
            return cls(f"{url.host}:{url.port or 502}", framing="tcp", **{**opts, **kwargs})
        port = f"socket://{url.host}:{url.port}" if url.scheme == "modbus-rtu+socket" else url.path
        return cls(port, framing="rtu", **{**opts, **kwargs})

    @property
    def poll_rate_limit_hz(self) -> float:
        if self.framing == "tcp":
            return 5000.0
        return r.max_poll_rate_hz(self.baud, self._nregs)

    # -- link
    def _trace(self, sending: bool, data: bytes) -> bytes:
        """Check the CRC of every RTU response ourselves, so bad frames are counted as such."""
        if not sending and data:
            self._reply_bytes_seen = True
        if not sending and self.framing == "rtu" and len(data) >= 4:
            if not FramerRTU.check_CRC(data[:-2], int.from_bytes(data[-2:], "big")):
                self._bad_crc_seen = True
        return data

    async def _connect(self) -> bool:
        """Make the client inside the loop (pymodbus binds it to the running loop) and connect."""
        if self.framing == "tcp":
            host, port = self.port.rsplit(":", 1)
            self._client = AsyncModbusTcpClient(host, port=int(port), timeout=self.timeout_s, retries=0,
                                                reconnect_delay=0)
        else:
            self._client = AsyncModbusSerialClient(self.port, framer=FramerType.RTU, baudrate=self.baud,
                                                   timeout=self.timeout_s, retries=0, reconnect_delay=0,
                                                   trace_packet=self._trace)
        return bool(await self._client.connect())

    def _open_internal(self) -> None:
        with error_check(f"{self.name}: cannot open {self.port}", DeviceInitializationError):
            ok = self._run(self._connect)
        if not ok:
            self._close_internal()
            raise DeviceInitializationError(f"{self.name}: cannot connect to {self.port}")
        # the transmitter must answer before we call it open; one poll's timeout is short (a sample period),
        # so a busy host or a frame lost on the wire gets OPEN_ATTEMPTS requests before "does not answer"
        regs = self._read_zero_offset()
        if regs is None:
            self._close_internal()
            raise DeviceInitializationError(f"{self.name}: unit {self.unit} on {self.port} does not answer")
        self.zero_offset_nm = r.decode_float(regs, self.word_order)
        self._check_word_order()
        self._probe_sample_counter()

    def _read_zero_offset(self) -> list[int] | None:
        """The zero-offset registers, asked up to :data:`OPEN_ATTEMPTS` times (each failure counted as a poll's);
        None when every request failed."""
        for _ in range(OPEN_ATTEMPTS):
            regs = self._read_registers(self.registers.zero_offset, 2)
            if regs is not None:
                return regs
        return None

    def _probe_sample_counter(self) -> None:
        """Read the output data rate: a transmitter that publishes one numbers its conversions, and the
        poll then reads its history block (the newest conversions with their counter) in one request."""
        published = self._read_registers(self.registers.output_rate, 1, probe=True)
        if not published or published[0] == 0:
            self.output_rate_hz = None
            self._nregs = 4 if self.read_speed else 2
            return
        self.output_rate_hz = float(published[0])
        self._nregs = 2 + 2 * r.HISTORY_DEPTH
        self._unwrap.reset()
        self._last_sample = None
        # every conversion is read only if a poll comes at least once per HISTORY_DEPTH conversions
        polls = min(self.rate_hz or math.inf, self.poll_rate_limit_hz)
        need = self.output_rate_hz / r.HISTORY_DEPTH
        if polls < need:
            how = f"rate={self.rate_hz:g}" if self.rate_hz is not None and self.rate_hz < self.poll_rate_limit_hz \
                else f"{self.baud} baud"
            raise DeviceInitializationError(
                f"{self.name}: {how} polls {polls:.1f}/s, but the transmitter converts at {self.output_rate_hz:g} Hz and "
                f"holds {r.HISTORY_DEPTH} conversions: at least {need:.1f} polls/s are needed or conversions are lost")

    def _check_word_order(self) -> None:
        """Refuse to open with a float word order the transmitter says it does not use: a wrong one
        reads 1.5 N·m as 516607 N·m, silently. A transmitter without the register is taken at the
        URL's word."""
        published = self._read_registers(self.registers.word_order, 1, probe=True)
        if published is None:
            self.word_order_confirmed = False
            return
        device = {0: "big", 1: "little"}.get(published[0])
        if device != self.word_order:
            self._close_internal()
            raise DeviceInitializationError(
                f"{self.name}: the transmitter publishes float word order "
                f"{device or f'code {published[0]}'} (register 0x{self.registers.word_order:04x}) but this "
                f"driver was opened with word_order={self.word_order}; set word_order={device} in its URL")
        self.word_order_confirmed = True

    def _close_internal(self) -> None:
        if self._client is not None:
            try:
                self._client.close()
            except Exception:
                pass
            self._client = None

    def _run(self, make: Callable[[], Awaitable[T]]) -> T:
        """Run a client coroutine on the driver's loop, from whichever thread calls.

        The reader thread owns the loop while streaming; other threads hand it the call.
        """
        owner = self._loop_owner
        if owner is None or owner is threading.current_thread() or not owner.is_alive():
            return self._loop.run_until_complete(make())  # type: ignore[arg-type]  # pymodbus's coroutine types are looser than the loop's
        future: concurrent.futures.Future[Any] = concurrent.futures.Future()
        self._calls.put((make, future))
        return future.result(timeout=5.0)

    def _service_calls(self) -> None:
        while True:
            try:
                make, future = self._calls.get_nowait()
            except queue.Empty:
                return
            try:
                future.set_result(self._loop.run_until_complete(make()))  # type: ignore[arg-type]  # pymodbus's coroutine types are looser than the loop's
            except BaseException as err:
                future.set_exception(err)

    def _read_registers(self, address: int, count: int, *, probe: bool = False) -> list[int] | None:
        """One FC03 read; None if it failed in a way that is counted (timeout, CRC, exception).

        ``probe``: asking whether an optional register exists, so an exception response (no such
        register) is an answer, not a bad frame."""
        client = self._client
        if client is None:
            raise ConnectionLostError(f"{self.name}: not connected")
        self._bad_crc_seen = self._reply_bytes_seen = False
        try:
            rr = self._run(lambda: client.read_holding_registers(address, count=count, device_id=self.unit))
        except ConnectionException as err:
            raise ConnectionLostError(f"{self.name}: link to {self.port} lost: {err}") from err
        except (TimeoutError, ModbusException):
            if self._bad_crc_seen:
                self.stats.crc_errors += 1
            elif not self._reply_bytes_seen:  # silence: the poll timed out (a loaded host, a dead line)
                self.stats.poll_timeouts += 1
            else:
                self.stats.malformed_frames += 1
            return None
        except OSError as err:
            raise ConnectionLostError(f"{self.name}: link to {self.port} lost: {err}") from err
        except Exception:
            self.stats.malformed_frames += 1
            return None
        if rr.isError():
            if not probe:
                self.stats.malformed_frames += 1
            return None
        if self._client is None or not self._client.connected:
            raise ConnectionLostError(f"{self.name}: link to {self.port} lost")
        registers = list(getattr(rr, "registers", None) or [])
        if len(registers) != count:  # a valid CRC around the wrong register count: a bad frame, counted
            self.stats.malformed_frames += 1
            return None
        return registers

    # -- polling
    def _read_internal(self) -> TorqueBlock | None:
        """Poll for ~20 ms and return what was read as one block."""
        self._loop_owner = threading.current_thread()
        self._service_calls()
        counters: list[int] = []
        times: list[float] = []
        torque: list[float] = []
        speed: list[float] = []
        end = monotonic_s() + 0.02
        while monotonic_s() < end:
            if self.rate_hz is not None:
                now = monotonic_s()
                if self._next_poll > now:
                    if self._next_poll > end:
                        break
                    _sleep_until(self._next_poll)
                self._next_poll = max(self._next_poll + 1.0 / self.rate_hz, monotonic_s() - 0.5 / self.rate_hz)
            t_request = monotonic_s()
            self._counter += 1
            if self.output_rate_hz is not None:
                self._poll_history(t_request, counters, times, torque, speed)
                continue
            regs = self._read_registers(self.registers.torque, self._nregs)
            if regs is None:
                continue
            counters.append(self._counter)
            times.append(0.5 * (t_request + monotonic_s()))
            torque.append(r.decode_float(regs[0:2], self.word_order))
            speed.append(r.decode_float(regs[2:4], self.word_order) * RPM_TO_RAD_S if self.read_speed else np.nan)
        if not counters:
            return None
        return TorqueBlock(device=self.name, counter=np.array(counters, dtype=np.int64), time_s=np.array(times),
                           torque_nm=np.array(torque), speed_rad_s=np.array(speed))

    def _poll_history(self, t_request: float, counters: list[int], times: list[float], torque: list[float],
                      speed: list[float]) -> None:
        """One read of the history block: every conversion newer than the last one kept, oldest first.

        The newest is stamped with the poll's midpoint, older ones one conversion period earlier each.
        A poll that finds nothing new is counted in :attr:`repeat_polls`; conversions older than the
        block's depth that no poll saw show as a gap in the counter."""
        assert self.output_rate_hz is not None
        regs = self._read_registers(self.registers.history, self._nregs)
        if regs is None:
            return
        t_newest = 0.5 * (t_request + monotonic_s())
        newest = self._unwrap.unwrap(r.decode_uint32(regs[0:2], self.word_order))
        last = self._last_sample[0] if self._last_sample is not None else newest - 1
        fresh = [i for i in range(r.HISTORY_DEPTH - 1, -1, -1) if last < newest - i]
        if not fresh:
            self.repeat_polls += 1
            return
        for i in fresh:
            counters.append(newest - i)
            times.append(t_newest - i / self.output_rate_hz)
            torque.append(r.decode_float(regs[2 + 2 * i:4 + 2 * i], self.word_order))
            speed.append(np.nan)
        self._last_sample = (newest, t_newest)

    def sample_at(self, host_time_s: float) -> int | None:
        """The device sample counter at host time ``host_time_s`` (s, :func:`~drivers.clock.monotonic_s`),
        from the newest sample read and the output data rate; None for a transmitter without a counter
        or before the first sample."""
        if self.output_rate_hz is None or self._last_sample is None:
            return None
        sample, t = self._last_sample
        return sample + int(np.floor((host_time_s - t) * self.output_rate_hz))

    def read_torque_nm(self) -> float:
        """One poll of the torque register outside streaming (N·m).

        :raises DeviceTimeoutError: the poll failed (timeout, bad CRC or exception response).
        """
        regs = self._read_registers(self.registers.torque, 2)
        if regs is None:
            raise DeviceTimeoutError(f"{self.name}: torque poll failed")
        return r.decode_float(regs, self.word_order)

    def tare(self) -> float:
        """Write the tare register, then read back the new zero offset (N·m).

        :raises CommandRefusedError: the transmitter answered with an exception.
        :raises DeviceTimeoutError: no answer.
        """
        client = self._client
        if client is None:
            raise ConnectionLostError(f"{self.name}: not connected")
        # a configuration command, not a poll: OPEN_ATTEMPTS tries each for the write and the read-back (a tare
        # written twice at rest zeroes the same reading)
        for attempt in range(OPEN_ATTEMPTS):
            try:
                rr = self._run(lambda: client.write_register(self.registers.tare, 1, device_id=self.unit))
                break
            except (TimeoutError, ModbusException) as err:
                if attempt == OPEN_ATTEMPTS - 1:
                    raise DeviceTimeoutError(f"{self.name}: tare not answered after {OPEN_ATTEMPTS} tries: {err}"
                                             ) from err
        if rr.isError():
            raise CommandRefusedError(f"{self.name}: tare refused ({rr})")
        regs = self._read_zero_offset()
        if regs is None:
            raise DeviceTimeoutError(f"{self.name}: zero offset not readable after tare ({OPEN_ATTEMPTS} tries)")
        self.zero_offset_nm = r.decode_float(regs, self.word_order)
        return self.zero_offset_nm

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        d.update(port=self.port, framing=self.framing, unit=self.unit, baud=self.baud, word_order=self.word_order,
                 poll_rate_hz=self.rate_hz, poll_rate_limit_hz=self.poll_rate_limit_hz,
                 zero_offset_nm=self.zero_offset_nm, registers=vars(self.registers),
                 output_rate_hz=self.output_rate_hz, sample_counter=self.output_rate_hz is not None)
        return d


def _sleep_until(deadline: float) -> None:
    while (left := deadline - monotonic_s()) > 0:
        time.sleep(min(left, 0.001))
