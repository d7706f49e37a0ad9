"""``StreamingDevice``: the small abstract base every device kind builds on (as python-can's ``BusABC``).

Subclasses implement three hooks: ``_open_internal``, ``_read_internal`` and ``_close_internal``
(plus optional ``_on_stream_start``). The base owns the reader thread, the output queue, gap
and counter bookkeeping, silence detection, reconnection and the context manager, written once.

Events reach the consumer in order through :meth:`StreamingDevice.read`: data blocks, and the
errors that happened between them (``ConnectionLostError``, ``DeviceTimeoutError``). Nothing the
device delivered is dropped by the driver: the output queue is unbounded, so a slow consumer
costs memory, never samples.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from abc import ABC, abstractmethod
from dataclasses import asdict, dataclass, field
from typing import Any, ClassVar

import numpy as np

from .blocks import SampleBlock
from .clock import monotonic_s
from .errors import (
    ConnectionLostError,
    CounterResyncError,
    DeviceInitializationError,
    DeviceOperationError,
    DeviceTimeoutError,
    DriverError,
)

log = logging.getLogger(__name__)
log.addHandler(logging.NullHandler())


#: an idempotent command (start, stop, a register or object write the device reads back) is sent at most
#: this many times before the driver reports "no reply"; each repeat is counted in ``command_retries``
COMMAND_ATTEMPTS = 2


@dataclass
class DeviceStats:
    """Running counts for one device since :meth:`StreamingDevice.start`."""

    samples: int = 0
    blocks: int = 0
    gaps: int = 0
    lost_samples: int = 0
    duplicate_samples: int = 0
    crc_errors: int = 0
    malformed_frames: int = 0
    garbage_bytes: int = 0
    unsolicited_frames: int = 0
    counter_resyncs: int = 0
    timeouts: int = 0
    poll_timeouts: int = 0  # polls the device left unanswered (a slow host or a silent line), not bad frames
    command_retries: int = 0  # idempotent commands answered only when sent again (a reply lost or late)
    disconnects: int = 0
    reconnects: int = 0
    first_time_s: float = float("nan")
    last_time_s: float = float("nan")
    last_counter: int = -1
    last_counter_valid: bool = False
    reader_cpu_s: float = 0.0
    gap_log: list[tuple[int, int]] = field(default_factory=list)

    def rate_hz(self) -> float:
        """Mean received sample rate in Hz over the stream so far."""
        span = self.last_time_s - self.first_time_s
        return (self.samples - 1) / span if self.samples > 1 and span > 0 else float("nan")

    def as_dict(self) -> dict[str, Any]:
        """Plain-dict snapshot (JSON-serialisable) with the rate added."""
        d = asdict(self)
        d["rate_hz"] = self.rate_hz()
        d["gap_log"] = [list(g) for g in self.gap_log[-100:]]
        return d


class StreamingDevice(ABC):
    """A device that streams samples, read by a background thread.

    :param name: device name put in every block.
    :param silence_timeout_s: no sample for this long is reported once as ``DeviceTimeoutError``.
    :param reconnect_interval_s: wait between reconnection attempts after the link is lost.
    """

    kind: ClassVar[str] = "device"
    block_type: ClassVar[type[SampleBlock]] = SampleBlock
    #: a counter this far at or below the last one is a repeat (dropped)
    reorder_window: ClassVar[int] = 8
    #: the largest forward counter step taken as a gap; larger steps are a resync (samples kept)
    max_counter_jump: ClassVar[int] = 10_000

    def __init__(
        self,
        *,
        name: str | None = None,
        silence_timeout_s: float = 1.0,
        reconnect_interval_s: float = 0.2,
    ) -> None:
        self.name = name or self.kind
        self.silence_timeout_s = silence_timeout_s
        self.reconnect_interval_s = reconnect_interval_s
        self.stats = DeviceStats()
        self._events: queue.Queue[SampleBlock | DriverError] = queue.Queue()
        self._thread: threading.Thread | None = None
        self._running = threading.Event()
        self._stop_requested = threading.Event()
        self._lock = threading.RLock()
        self._connected = False
        self._is_closed = False
        self._silent_reported = False
        self._last_data_s = 0.0

    # ------------------------------------------------------------------ hooks
    @abstractmethod
    def _open_internal(self) -> None:
        """Open the link and configure the device. Raise ``DriverError`` on failure."""

    @abstractmethod
    def _read_internal(self) -> SampleBlock | None:
        """Return the next block, or ``None`` if nothing arrived within a short poll (≤ 50 ms).

        Raise ``ConnectionLostError`` if the link is gone; bad frames are counted in ``self.stats``.
        """

    @abstractmethod
    def _close_internal(self) -> None:
        """Release the link. Must not raise."""

    def _on_stream_start(self) -> None:  # noqa: B027 - an optional hook; doing nothing is the default
        """Tell the device to start streaming (after every (re)connection). Default: nothing."""

    def _on_stream_stop(self) -> None:  # noqa: B027 - an optional hook; doing nothing is the default
        """Tell the device to stop streaming and hand what is still in flight to :meth:`_deliver`.

        Must not raise. Default: nothing.
        """

    def channel_layout(self) -> dict[str, tuple[tuple[int, ...], str]]:
        """Per-sample shape and dtype of every channel this device streams (valid once open)."""
        return dict(self.block_type.LAYOUT)

    def identity(self) -> dict[str, Any]:
        """Device identity and settings for the trial record (override to add calibration etc.)."""
        return {"kind": self.kind, "name": self.name, "driver": type(self).__name__}

    # ------------------------------------------------------------------ public API
    @property
    def connected(self) -> bool:
        """True while the link is up."""
        return self._connected

    @property
    def closed(self) -> bool:
        """True once :meth:`close` ran (a device closed on purpose, not a lost link)."""
        return self._is_closed

    def open(self) -> None:
        """Open the device (idempotent).

        :raises DeviceInitializationError: the device could not be opened.
        """
        with self._lock:
            if self._is_closed:
                raise DeviceInitializationError(f"{self.name}: device was closed; make a new driver")
            if not self._connected:
                self._open_internal()
                self._connected = True

    def start(self) -> None:
        """Open if needed, tell the device to stream and start the reader thread."""
        self.open()
        if self._thread is not None:
            return
        self.stats = DeviceStats()
        self._on_stream_start()
        self._last_data_s = monotonic_s()
        self._stop_requested.clear()
        self._running.set()
        self._thread = threading.Thread(target=self._reader, name=f"{self.name}-reader", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop the reader thread and the device stream; keeps the link open and queued data readable."""
        self._running.clear()
        self._stop_requested.set()
        thread, self._thread = self._thread, None
        if thread is not None:
            thread.join(timeout=2.0)
        if self._connected:
            self._on_stream_stop()

    def close(self) -> None:
        """Stop and release the device (idempotent)."""
        if self._is_closed:
            return
        self.stop()
        with self._lock:
            self._close_internal()
            self._connected = False
            self._is_closed = True

    def read(self, timeout: float | None = 1.0) -> SampleBlock:
        """Next block of samples.

        :param timeout: seconds to wait; ``None`` waits forever.
        :raises DeviceTimeoutError: nothing arrived in ``timeout``, or the device went silent.
        :raises ConnectionLostError: the link dropped at this point of the stream.
        """
        try:
            item = self._events.get(timeout=timeout)
        except queue.Empty:
            raise DeviceTimeoutError(f"{self.name}: no data within {timeout} s") from None
        if isinstance(item, DriverError):
            raise item
        return item

    def read_available(self) -> tuple[list[SampleBlock], list[DriverError]]:
        """Everything queued now, without waiting: (blocks, errors in order)."""
        blocks: list[SampleBlock] = []
        errors: list[DriverError] = []
        while True:
            try:
                item = self._events.get_nowait()
            except queue.Empty:
                return blocks, errors
            (errors if isinstance(item, DriverError) else blocks).append(item)  # type: ignore[arg-type]  # the queue holds blocks and errors; the isinstance test sorts them

    def __enter__(self) -> StreamingDevice:
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ reader thread
    def _reader(self) -> None:
        try:
            self._reader_loop()
        finally:
            self.stats.reader_cpu_s = time.thread_time()

    def _reader_loop(self) -> None:
        while self._running.is_set():
            if not self._connected:
                self._try_reconnect()
                continue
            try:
                block = self._read_internal()
            except ConnectionLostError as err:
                self._lost(err)
                continue
            except DriverError as err:  # one bad operation: report in order, keep going
                self._events.put(err)
                continue
            except Exception as err:
                log.exception("%s: unexpected reader error", self.name)
                self._lost(ConnectionLostError(f"{self.name}: unexpected reader error: {err!r}"))
                continue
            try:
                self._handle_block(block)
            except Exception as err:
                log.exception("%s: unexpected error handling a block", self.name)
                self._events.put(DeviceOperationError(f"{self.name}: a block could not be handled: {err!r}"))

    def _handle_block(self, block: SampleBlock | None) -> None:
        """Silence bookkeeping, then account for and queue a non-empty block."""
        now = monotonic_s()
        if block is None or len(block) == 0:
            if not self._silent_reported and now - self._last_data_s > self.silence_timeout_s:
                self._silent_reported = True
                self.stats.timeouts += 1
                self._events.put(DeviceTimeoutError(
                    f"{self.name}: silent for {now - self._last_data_s:.2f} s "
                    f"(after counter {self.stats.last_counter})"))
            return
        self._last_data_s = now
        self._silent_reported = False
        self._deliver(block)

    def _deliver(self, block: SampleBlock) -> None:
        """Account for ``block`` and queue it for the consumer (also used by hooks that drain on stop)."""
        block = self._account(block)
        if len(block):
            self._events.put(block)

    def _account(self, block: SampleBlock) -> SampleBlock:
        """Update gap/duplicate counts; drop repeated samples; resynchronise on an implausible counter.

        A counter at or just below the last one (within :attr:`reorder_window`) is a repeat and is
        dropped. One that moves forward by up to :attr:`max_counter_jump` leaves a gap of lost
        samples. Any other jump (a device that restarted its counter, a corrupted counter with a
        valid checksum) is no reason to discard data: the sample is kept, the counter taken as the
        new reference, and a :class:`~drivers.errors.CounterResyncError` event reports it in order.
        """
        counters = block.counter
        s = self.stats
        keep = np.ones(len(counters), dtype=bool)
        last = s.last_counter
        seen = s.last_counter_valid
        for i, c in enumerate(counters.tolist()):
            if seen and last - self.reorder_window <= c <= last:
                keep[i] = False
                s.duplicate_samples += 1
                continue
            if seen and last < c <= last + self.max_counter_jump:
                if c > last + 1:
                    s.gaps += 1
                    s.lost_samples += c - last - 1
                    s.gap_log.append((last, c))
            elif seen:
                s.counter_resyncs += 1
                self._events.put(CounterResyncError(
                    f"{self.name}: counter jumped from {last} to {c}; resynchronised, samples kept"))
            last, seen = c, True
        s.last_counter, s.last_counter_valid = int(last), seen
        if not keep.all():
            block = type(block)(**{  # type: ignore[arg-type]  # the same fields, rows kept
                f: (v[keep] if isinstance(v, np.ndarray) else v)
                for f, v in vars(block).items()
            })
        if len(block):
            if s.samples == 0:
                s.first_time_s = float(block.time_s[0])
            s.last_time_s = float(block.time_s[-1])
            s.samples += len(block)
            s.blocks += 1
        return block

    def _lost(self, err: ConnectionLostError) -> None:
        self.stats.disconnects += 1
        self._events.put(err)
        with self._lock:
            self._close_internal()
            self._connected = False

    def _try_reconnect(self) -> None:
        if self._stop_requested.wait(self.reconnect_interval_s):
            return
        try:
            with self._lock:
                self._open_internal()
                self._connected = True
            self._on_stream_start()
            self.stats.reconnects += 1
            self._last_data_s = monotonic_s()
            log.info("%s: reconnected", self.name)
        except Exception as err:
            log.debug("%s: reconnect failed: %s", self.name, err)
            with self._lock:
                try:
                    self._close_internal()
                except Exception:
                    pass
                self._connected = False
