"""Force plate amplifier simulator: the AADS jig on a plate, streamed in the real framing over TCP.

The device keeps one sample counter from power-up; streaming (START/STOP) only gates what is
sent, so a silence or a vanished link shows up at the driver as a counter gap of exactly the
samples that were not delivered.
"""

from __future__ import annotations

import threading
import time

import numpy as np

from ..simulation.aads_jig import AadsJig
from ..simulation.faults import ByteFaults, FaultConfig
from ..simulation.tcp_link import TcpDeviceLink
from . import protocol as p


def default_plate_info(rate_hz: int = 1000) -> p.PlateInfo:
    """An AMTI-Optima-like 464 × 508 mm plate with a slightly non-diagonal sensitivity matrix."""
    rng = np.random.default_rng(12345)
    diag = np.array([500.0, 500.0, 1000.0, 100.0, 100.0, 50.0])  # N/V and N·m/V
    cross = rng.normal(0.0, 0.004, (6, 6)) * diag[:, None]
    np.fill_diagonal(cross, 0.0)
    return p.PlateInfo(
        serial_number=60321, rate_hz=rate_hz, volts_per_count=10.0 / 2**23,
        sensitivity=np.diag(diag) + cross, zero_v=rng.normal(0.0, 0.01, 6),
        origin_m=np.array([0.0002, -0.0004, -0.040]), size_m=(0.464, 0.508), model="SIM-OPT464508")


class ForcePlateSimulator:
    """Serves one simulated amplifier on ``socket://127.0.0.1:PORT``.

    :param jig: what stands on the plate (None: an empty plate, only noise).
    :param baud: serial baud the link emulates; a sample rate needing more is refused.
    :param noise_n: force noise SD in N (moments get ``noise_n`` × 0.05 m).
    """

    def __init__(self, jig: AadsJig | None = None, rate_hz: int = 1000, *, baud: int = 921600,
                 faults: FaultConfig | None = None, noise_n: float = 0.25, port: int = 0,
                 seed: int = 0, autostart: bool = True) -> None:
        self.jig = jig
        #: False while the operator has lifted the AFO off the plate (e.g. to zero it): no load
        self.specimen_on_plate = True
        self.info = default_plate_info(rate_hz)
        self.rate_hz = rate_hz
        self.baud = baud
        self.faults = faults or FaultConfig()
        self.noise_n = noise_n
        self.byte_faults = ByteFaults(self.faults, seed)
        self.rng = np.random.default_rng(seed + 1)
        self.link = TcpDeviceLink(port)
        self.counter = 0
        self.sent_samples = 0
        self.streaming = False
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._t0 = time.monotonic()
        self._stream_t0 = 0.0
        self._vanished_at: float | None = None
        self._disconnect_done = False
        self._table: np.ndarray | None = None
        #: the counter at which the operator began the trial's bends (:meth:`begin_bends`); None: the
        #: operator bends over and over from power-up (a free-running stream)
        self.bend_origin: int | None = None
        #: held while samples are drawn and sent, so that the lab's ``begin_bends`` starts the bends at
        #: a counter not sent yet (a host stall between choosing the counter and setting it cannot put
        #: sent samples on both sides of the cue)
        self.lock = threading.Lock()
        self._noise_table: np.ndarray | None = None
        self._noise_seed = seed + 1
        if autostart:
            self.start()

    def begin_bends(self, origin_counter: int) -> None:
        """The operator starts one pass of the bend profile at device counter ``origin_counter`` and
        rests afterwards; the sensor noise is then drawn per counter from there, so a trial's samples
        do not depend on when the host happened to poll (the demo prints the same numbers twice)."""
        self.bend_origin = int(origin_counter)

    @property
    def url(self) -> str:
        return self.link.url

    @property
    def time_origin_s(self) -> float:
        """``time.monotonic()`` of counter 0: counter ``c`` samples the jig at ``c / rate_hz`` s."""
        return self._t0

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="forceplate-sim", daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        if self._thread:
            self._thread.join(2.0)
        self.link.close()

    def __enter__(self) -> ForcePlateSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- device behaviour
    def _handle(self, kind: p.Kind, payload: bytes) -> bytes:
        if kind != p.Kind.COMMAND or len(payload) != p.COMMAND_PAYLOAD.size:
            return b""
        cmd, arg = p.COMMAND_PAYLOAD.unpack(payload)
        if cmd == p.Command.START:
            if not self.streaming:
                self.streaming = True
                self._stream_t0 = time.monotonic()
                self._next_counter_time = self._stream_t0
            return p.encode_reply(cmd, p.Status.OK)
        if cmd == p.Command.STOP:
            self.streaming = False
            return p.encode_reply(cmd, p.Status.OK)
        if cmd == p.Command.SET_RATE:
            if arg not in p.SUPPORTED_RATES_HZ or arg > p.max_sample_rate_hz(self.baud):
                return p.encode_reply(cmd, p.Status.BAD_ARGUMENT)
            if self.streaming:
                return p.encode_reply(cmd, p.Status.BAD_STATE)
            self.rate_hz = arg
            self.info = p.PlateInfo(**{**self.info.__dict__, "rate_hz": arg})
            return p.encode_reply(cmd, p.Status.OK)
        if cmd == p.Command.GET_INFO:
            return p.encode_frame(p.Kind.INFO, self.info.to_payload())
        if cmd == p.Command.PING:
            return p.encode_reply(cmd, p.Status.OK)
        return p.encode_reply(cmd, p.Status.UNKNOWN_COMMAND)

    def loads_at(self, counters: np.ndarray) -> np.ndarray:
        """Six true loads (n, 6) at device counters, plus sensor noise."""
        counters = np.asarray(counters)
        if self.jig is not None and self.specimen_on_plate:
            # the operator's trial repeats: evaluate the physics once per period, then index it
            n = int(round(self.jig.profile.duration_s * self.rate_hz))
            if self._table is None or self._table.shape[0] != n:
                st = self.jig.state(np.arange(n) / self.rate_hz)
                self._table = np.hstack([st.force_n, st.moment_nm])
            index = counters % n if self.bend_origin is None else np.clip(counters - self.bend_origin, 0, n - 1)
            loads = self._table[index]
        else:
            loads = np.zeros((counters.size, 6))
        sd = self.noise_n * self.faults.noise_scale
        if sd > 0:
            scale = np.array([sd, sd, sd, sd * .05, sd * .05, sd * .05])
            if self.bend_origin is None:
                loads = loads + self.rng.normal(0.0, 1.0, loads.shape) * scale
            else:
                if self._noise_table is None:
                    self._noise_table = np.random.default_rng(self._noise_seed).normal(0.0, 1.0, (1 << 16, 6))
                loads = loads + self._noise_table[(counters - self.bend_origin) % (1 << 16)] * scale
        return loads

    def _run(self) -> None:
        parser = p.FrameParser()
        period = 0.010
        while not self._stop.is_set():
            now = time.monotonic()
            if self._vanished_at is not None:
                if now - self._vanished_at >= self.faults.reconnect_after_s:
                    self._vanished_at = None
                    self.link.listen()
                else:
                    self._advance_counter(now)
                    self._stop.wait(period)
                    continue
            if not self.link.accept(period):
                self._advance_counter(now)
                continue
            data = self.link.recv(0.0)
            if data is None:
                self.streaming = False
                continue
            if data:
                _, frames = parser.feed(data)
                for kind, payload in frames:
                    self.link.send(self._handle(kind, payload))
            if self.streaming:
                stream_t = now - self._stream_t0
                if (self.faults.disconnect_after_s is not None and not self._disconnect_done
                        and stream_t >= self.faults.disconnect_after_s):
                    self._disconnect_done = True
                    self.streaming = False
                    self.link.vanish()
                    self._vanished_at = now
                    continue
                self._emit(now, silent=self.faults.silent_at(stream_t))
            else:
                self._advance_counter(now)
            self._stop.wait(max(0.0, period - (time.monotonic() - now)))

    def _due(self, now: float) -> int:
        return int((now - self._t0) * self.rate_hz) - self.counter

    def _advance_counter(self, now: float) -> None:
        with self.lock:
            self.counter += max(0, self._due(now))

    def _emit(self, now: float, silent: bool) -> None:
        with self.lock:
            n = self._due(now)
            if n <= 0:
                return
            counters = np.arange(self.counter, self.counter + n)
            self.counter += n
            if silent:
                return
            counts = p.counts_from_loads(self.loads_at(counters), self.info)
        # the trigger input: the camera system's sync output, one pulse a second on its frame 0, 100, ...
        # (plate and cameras share a time origin, so that is plate sample 0, 1000, ...)
        trigger = (counters % self.rate_hz) == 0
        out = bytearray()
        for c, row, trig in zip(counters.tolist(), counts, trigger.tolist()):
            out += self.byte_faults.apply(p.encode_sample(c, row, flags=int(trig)))
        if self.link.send(bytes(out)):
            self.sent_samples += n
