"""Force plate driver over any pyserial URL (a real port, ``socket://``, ``rfc2217://``, a pty)."""

from __future__ import annotations

import logging
import threading
from typing import Any

import numpy as np
import serial

from ..base import COMMAND_ATTEMPTS
from ..blocks import ForcePlateBlock
from ..clock import CounterClock, CounterUnwrapper, monotonic_s
from ..errors import (
    CommandRefusedError,
    ConnectionLostError,
    DeviceInitializationError,
    DeviceTimeoutError,
    error_check,
)
from ..url import DeviceUrl
from . import ForcePlate
from . import protocol as p

log = logging.getLogger(__name__)

#: replies and other non-sample frames kept for a command to pick up; older ones are dropped and counted
MAX_PENDING_REPLIES = 32


class SerialForcePlate(ForcePlate):
    """Framed six-channel stream; applies the 6×6 calibration and zero offsets, computes the CoP.

    :param port: pyserial URL or device path.
    :param baud: serial baud rate (ignored by sockets and ptys).
    :param rate: sample rate to request in Hz (one of ``protocol.SUPPORTED_RATES_HZ``).
    :param calibration: overrides the amplifier's stored sensitivity/zero (e.g. from the lab's file).
    :param min_fz_n: below this |Fz| the CoP is NaN.
    """

    def __init__(self, port: str, *, baud: int = 921600, rate: int = 1000,
                 calibration: p.PlateInfo | None = None, min_fz_n: float = 5.0,
                 command_timeout_s: float = 1.0, **kwargs: Any) -> None:
        if rate not in p.SUPPORTED_RATES_HZ:
            raise ValueError(f"rate {rate} Hz not supported; choose from {p.SUPPORTED_RATES_HZ}")
        if rate > p.max_sample_rate_hz(baud):
            raise ValueError(
                f"{rate} Hz needs {rate * p.SAMPLE_FRAME_BYTES * 10} bit/s, more than {baud} baud carries")
        self.port = port
        self.baud = baud
        self.requested_rate_hz = rate
        self.calibration = calibration
        self.min_fz_n = min_fz_n
        self.command_timeout_s = command_timeout_s
        self.info: p.PlateInfo | None = None
        self.zero_v: np.ndarray | None = None
        self._serial: serial.SerialBase | None = None
        self._parser = p.FrameParser()
        self._unwrap = CounterUnwrapper(p.COUNTER_BITS)
        self._clock = CounterClock(rate)
        self._replies: list[tuple[p.Kind, bytes]] = []
        self._streaming = False
        self._tare_lock = threading.Lock()
        self._tare_need = 0
        self._tare_volts: list[np.ndarray] = []
        self._tare_done = threading.Event()
        super().__init__(**kwargs)

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> SerialForcePlate:
        opts = url.take({"baud": int, "rate": int, "min_fz": float})
        if "min_fz" in opts:
            opts["min_fz_n"] = opts.pop("min_fz")
        if url.scheme == "serial":
            port = url.path
        else:
            port = f"{url.scheme}://{url.host}:{url.port}"
        return cls(port, **{**opts, **kwargs})

    @property
    def rate_hz(self) -> float:
        return float(self.requested_rate_hz)

    # -- link
    def _open_internal(self) -> None:
        with error_check(f"{self.name}: cannot open {self.port}", DeviceInitializationError):
            self._serial = serial.serial_for_url(self.port, baudrate=self.baud, timeout=0.02)
        self._parser = p.FrameParser()
        self._command(p.Command.STOP)
        self._serial.reset_input_buffer()
        self._parser = p.FrameParser()
        info_payload = self._command(p.Command.GET_INFO, expect=p.Kind.INFO)
        self.info = p.PlateInfo.from_payload(info_payload)
        if self.zero_v is None:
            self.zero_v = (self.calibration or self.info).zero_v.copy()
        self._command(p.Command.SET_RATE, self.requested_rate_hz)

    def _close_internal(self) -> None:
        if self._serial is not None:
            try:
                self._serial.close()
            except Exception:
                pass
            self._serial = None

    def _on_stream_start(self) -> None:
        self._unwrap.reset()
        self._clock.reset()
        self._streaming = True
        self._command(p.Command.START)

    def _on_stream_stop(self) -> None:
        try:
            self._command(p.Command.STOP)  # samples before the STOP reply are delivered
        except Exception:
            pass
        finally:
            self._streaming = False

    def _write(self, data: bytes) -> None:
        if self._serial is None:
            raise ConnectionLostError(f"{self.name}: not connected")
        with error_check(f"{self.name}: write to {self.port} failed", ConnectionLostError):
            self._serial.write(data)

    def _read_bytes(self) -> bytes:
        if self._serial is None:
            raise ConnectionLostError(f"{self.name}: not connected")
        with error_check(f"{self.name}: read from {self.port} failed", ConnectionLostError):
            # ask for at least 16 samples' worth (the AMTI SDK's block); the read returns when they
            # are in or the 20 ms port timeout passes. Not `in_waiting` alone: pyserial's socket://
            # reports 1 for "some bytes", which made the reader fetch one byte per call.
            return self._serial.read(max(self._serial.in_waiting, 16 * p.SAMPLE_FRAME_BYTES))

    def _command(self, command: p.Command, argument: int = 0, expect: p.Kind = p.Kind.REPLY) -> bytes:
        """Send a command and wait for its reply (samples arriving meanwhile are kept).

        Every command of this protocol is idempotent, so one that gets no reply within
        ``command_timeout_s`` is sent again (up to :data:`COMMAND_ATTEMPTS` times, each repeat counted in
        ``stats.command_retries`` and logged) before :class:`DeviceTimeoutError`.
        """
        for attempt in range(COMMAND_ATTEMPTS):
            if attempt:
                self.stats.command_retries += 1
                log.warning("%s: no reply to %s within %g s; sending it again", self.name, command.name,
                            self.command_timeout_s)
            self._write(p.encode_command(command, argument))
            deadline = monotonic_s() + self.command_timeout_s
            while monotonic_s() < deadline:
                for i, (kind, payload) in enumerate(self._replies):
                    if kind == expect and (kind != p.Kind.REPLY or payload[0] == command):
                        del self._replies[i]
                        if kind == p.Kind.REPLY and payload[1] != p.Status.OK:
                            raise CommandRefusedError(
                                f"{self.name}: {command.name} refused: {p.Status(payload[1]).name}",
                                error_code=payload[1])
                        return payload
                block = self._ingest(self._read_bytes(), monotonic_s())
                if block is not None and self._streaming:
                    self._deliver(block)  # samples in flight while we wait are kept, never dropped
        raise DeviceTimeoutError(f"{self.name}: no reply to {command.name} in {COMMAND_ATTEMPTS} attempts of "
                                 f"{self.command_timeout_s} s")

    # -- samples
    def _ingest(self, data: bytes, arrival_s: float) -> ForcePlateBlock | None:
        parsed, others = self._parser.feed(data)
        s = self.stats
        s.crc_errors, s.malformed_frames, s.garbage_bytes = (
            self._parser.crc_errors, self._parser.malformed_frames, self._parser.garbage_bytes)
        self._replies.extend(others)
        if len(self._replies) > MAX_PENDING_REPLIES:  # replies nobody asked for are not kept forever
            s.unsolicited_frames += len(self._replies) - MAX_PENDING_REPLIES
            del self._replies[:-MAX_PENDING_REPLIES]
        if parsed.counters.size == 0 or self.info is None or self.zero_v is None:
            return None
        counters = np.array([self._unwrap.unwrap(int(c)) for c in parsed.counters], dtype=np.int64)
        info = self.calibration or self.info
        volts = parsed.counts.astype(np.float64) * info.volts_per_count
        self._feed_tare(volts)
        loads = (volts - self.zero_v) @ np.asarray(info.sensitivity).T
        force, moment = loads[:, :3], loads[:, 3:]
        cop, tz = p.centre_of_pressure(force, moment, info.origin_m, self.min_fz_n)
        return ForcePlateBlock(
            device=self.name, counter=counters, time_s=self._clock.stamp(counters, arrival_s),
            force_n=force, moment_nm=moment, cop_m=cop, free_moment_nm=tz,
            trigger=(parsed.flags & 1).astype(np.uint8))

    def _read_internal(self) -> ForcePlateBlock | None:
        return self._ingest(self._read_bytes(), monotonic_s())

    # -- zeroing
    def _feed_tare(self, volts: np.ndarray) -> None:
        with self._tare_lock:
            if self._tare_need <= 0:
                return
            self._tare_volts.append(volts[: self._tare_need])
            self._tare_need -= len(self._tare_volts[-1])
            if self._tare_need <= 0:
                self.zero_v = np.concatenate(self._tare_volts).mean(axis=0)
                self._tare_done.set()

    def tare(self, samples: int = 200, timeout_s: float = 5.0) -> np.ndarray:
        """Average the next ``samples`` samples (plate unloaded) into the zero offsets (V).

        The stream must be running. :raises DeviceTimeoutError: not enough samples in time.
        """
        with self._tare_lock:
            self._tare_volts, self._tare_need = [], samples
            self._tare_done.clear()
        if not self._tare_done.wait(timeout_s):
            with self._tare_lock:
                self._tare_need = 0
            raise DeviceTimeoutError(f"{self.name}: tare did not get {samples} samples in {timeout_s} s")
        assert self.zero_v is not None
        return self.zero_v.copy()

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        d.update(port=self.port, baud=self.baud, rate_hz=self.requested_rate_hz,
                 zero_v=None if self.zero_v is None else self.zero_v.tolist(),
                 amplifier=None if self.info is None else self.info.as_dict(),
                 calibration_override=self.calibration is not None)
        return d
