"""Another system's stream over the Lab Streaming Layer (a goniometer's angles, an EMG system's channels),
subscribed by name, type or source id and streamed as :class:`~drivers.blocks.StreamBlock`.

Open by URL::

    open_lsl_stream("lsl://?type=EMG")                 # the one stream of that type
    open_lsl_stream("lsl://?name=Trigno%20Goniometer") # by name (or source_id=...)

Time: the inlet applies LSL's clock offset (``proc_clocksync``), smooths the sender's stamps
(``proc_dejitter``) and keeps them increasing (``proc_monotonize``); each sample's LSL time is recorded
(``lsl_time_s``) and mapped to the instrument's monotonic clock (``time_s``) by the offset between the
two clocks measured at open. Counter: the sample's position on the stream's nominal rate since its
first sample (``round((t − t₀) · rate)``), so a gap in the stream is a jump in the counter and is
counted as on every other device; a stream without a nominal rate is numbered sample by sample.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ..base import StreamingDevice
from ..blocks import StreamBlock
from ..clock import monotonic_s
from ..errors import DeviceInitializationError, DeviceNotAvailableError
from ..url import DeviceUrl

#: how long (s) to look for the stream at open, unless the URL says (``timeout=``)
RESOLVE_TIMEOUT_S = 5.0
#: how long (s) to listen for a second stream matching the same name or type (an ambiguous name is refused)
AMBIGUITY_WINDOW_S = 0.5
#: liblsl's settings (warnings only); a lab's own ``LSLAPICFG`` wins
LSL_CONFIG = Path(__file__).with_name("lsl_api.cfg")


def import_pylsl() -> Any:
    """pylsl, with liblsl told (before it loads) to log warnings and errors only, unless the lab configured it."""
    os.environ.setdefault("LSLAPICFG", str(LSL_CONFIG))
    import pylsl

    return pylsl


class LslStream(StreamingDevice):
    """One LSL stream, resolved by ``prop`` = ``value`` (``name``, ``type`` or ``source_id``)."""

    kind: ClassVar[str] = "lsl"
    block_type = StreamBlock

    def __init__(self, prop: str, value: str, *, timeout: float = RESOLVE_TIMEOUT_S, **kwargs: Any) -> None:
        if prop not in ("name", "type", "source_id"):
            raise ValueError(f"an LSL stream is named by name, type or source_id, not {prop!r}")
        self.prop, self.value, self.resolve_timeout_s = prop, value, timeout
        self.labels: tuple[str, ...] = ()
        self.units: tuple[str, ...] = ()
        self.nominal_rate_hz = 0.0
        self.stream_name = self.stream_type = self.source_id = ""
        self._inlet: Any = None
        self._clock_offset_s = 0.0
        self._first_lsl_s: float | None = None
        self._next_index = 0
        super().__init__(**kwargs)

    @classmethod
    def from_url(cls, url: DeviceUrl, **kwargs: Any) -> LslStream:
        opts = url.take({"name": str, "type": str, "source_id": str, "timeout": float})
        keys = [k for k in ("name", "type", "source_id") if k in opts]
        if len(keys) != 1:
            raise ValueError(f"{url.text!r}: name the stream by exactly one of name=, type=, source_id=")
        timeout = float(opts.get("timeout", RESOLVE_TIMEOUT_S))  # type: ignore[arg-type]  # a float by take()
        return cls(keys[0], str(opts[keys[0]]), timeout=timeout, **kwargs)

    def channel_layout(self) -> dict[str, tuple[tuple[int, ...], str]]:
        layout = dict(StreamBlock.LAYOUT)
        layout["values"] = ((len(self.labels),), "f8")
        return layout

    def _open_internal(self) -> None:
        pylsl = import_pylsl()
        found = pylsl.resolve_byprop(self.prop, self.value, minimum=1, timeout=self.resolve_timeout_s)
        if found:  # a second stream of that name or type may answer a little later: look once more, briefly
            found = pylsl.resolve_byprop(self.prop, self.value, minimum=2, timeout=AMBIGUITY_WINDOW_S) or found
        if not found:
            raise DeviceNotAvailableError(f"{self.name}: no LSL stream with {self.prop} {self.value!r} answered "
                                          f"within {self.resolve_timeout_s:g} s")
        if len({i.source_id() or i.uid() for i in found}) > 1:
            names = ", ".join(sorted({i.name() for i in found}))
            raise DeviceInitializationError(f"{self.name}: {len(found)} LSL streams have {self.prop} {self.value!r} "
                                            f"({names}); name one by name= or source_id=")
        flags = pylsl.proc_clocksync | pylsl.proc_dejitter | pylsl.proc_monotonize
        inlet = pylsl.StreamInlet(found[0], max_buflen=60, processing_flags=flags)
        inlet.open_stream(timeout=self.resolve_timeout_s)
        info = inlet.info(timeout=self.resolve_timeout_s)
        labels: list[str] = []
        units: list[str] = []
        channel = info.desc().child("channels").child("channel")
        while not channel.empty():
            labels.append(channel.child_value("label") or f"ch{len(labels) + 1}")
            units.append(channel.child_value("unit") or "")
            channel = channel.next_sibling()
        if not labels:  # a stream without a description: numbered channels, no unit
            labels = [f"ch{k + 1}" for k in range(info.channel_count())]
            units = [""] * len(labels)
        if len(labels) != info.channel_count():
            raise DeviceInitializationError(f"{self.name}: the stream describes {len(labels)} channels but sends "
                                            f"{info.channel_count()}")
        self.labels, self.units = tuple(labels), tuple(units)
        self.nominal_rate_hz = float(info.nominal_srate())
        self.stream_name, self.stream_type, self.source_id = info.name(), info.type(), info.source_id()
        # LSL's clock and the instrument's: the closest pair of readings of many
        pairs = []
        for _ in range(16):
            before = monotonic_s()
            lsl_now = pylsl.local_clock()
            after = monotonic_s()
            pairs.append((after - before, 0.5 * (before + after) - lsl_now))
        self._clock_offset_s = min(pairs)[1]
        self._inlet = inlet

    def _close_internal(self) -> None:
        inlet, self._inlet = self._inlet, None
        if inlet is not None:
            try:
                inlet.close_stream()
            except Exception:  # closing must not raise; the sender may already be gone
                pass

    def _on_stream_start(self) -> None:
        self._first_lsl_s = None
        self._next_index = 0

    def _read_internal(self) -> StreamBlock | None:
        if self._inlet is None:
            raise DeviceInitializationError(f"{self.name}: not open")
        samples, stamps = self._inlet.pull_chunk(timeout=0.02, max_samples=4096)
        if not stamps:
            return None
        values = np.asarray(samples, dtype=float).reshape(len(stamps), len(self.labels))
        lsl_time = np.asarray(stamps, dtype=float)
        if self.nominal_rate_hz > 0:
            if self._first_lsl_s is None:
                self._first_lsl_s = float(lsl_time[0])
            counter = np.rint((lsl_time - self._first_lsl_s) * self.nominal_rate_hz).astype(np.int64)
        else:
            counter = np.arange(self._next_index, self._next_index + len(stamps), dtype=np.int64)
            self._next_index += len(stamps)
        return StreamBlock(device=self.name, counter=counter, time_s=lsl_time + self._clock_offset_s,
                           values=values, lsl_time_s=lsl_time)

    def identity(self) -> dict[str, Any]:
        d = super().identity()
        d.update(protocol="Lab Streaming Layer", stream_name=self.stream_name, stream_type=self.stream_type,
                 source_id=self.source_id, labels=list(self.labels), units=list(self.units),
                 nominal_rate_hz=self.nominal_rate_hz,
                 resolved_by={self.prop: self.value})
        return d


def open_lsl_stream(url: str, **kwargs: Any) -> LslStream:
    """Make (not yet open) the LSL stream for ``url`` (``lsl://?type=EMG``, ``lsl://?name=...``)."""
    parsed = DeviceUrl.parse(url)
    if parsed.scheme != "lsl":
        raise DeviceNotAvailableError(f"no LSL back end for scheme {parsed.scheme!r}; use lsl://?name=... or ?type=...")
    return LslStream.from_url(parsed, **kwargs)


__all__ = ["LslStream", "import_pylsl", "open_lsl_stream", "RESOLVE_TIMEOUT_S"]
