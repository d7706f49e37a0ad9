"""Every device stream as a Lab Streaming Layer outlet, so LabRecorder captures the instrument beside EMG and EEG.

One outlet per device of an :class:`~instrument.live.acquisition.AcquisitionEngine` (it is the
engine's live sink): channel labels and units in the stream's description (XDF's ``channels``
convention), the device's nominal rate, and each sample stamped with the device's own host time
(``time.monotonic``, the same steady clock as ``pylsl.local_clock``, so LabRecorder's clock
offsets apply unchanged). The sample counter is a channel, so a receiver counts gaps as the
instrument does. The stream carries the subject's pseudonym at most, never a name; its
``source_id`` names the lab session, so a lab's streams stay apart.

``pylsl`` (it ships liblsl in its wheel) is imported when a publisher is made: the instrument runs
without it.
"""

from __future__ import annotations

import logging
from typing import Any

import numpy as np

from drivers import StreamingDevice

log = logging.getLogger(__name__)

#: the unit of a channel, by the suffix of its name (SI; XDF unit strings)
UNIT_BY_SUFFIX = (("_rad_s", "rad/s"), ("_rad", "rad"), ("_nm", "N.m"), ("_n", "N"), ("_m", "m"), ("_rpm", "rpm"),
                  ("_deg", "deg"), ("_v", "V"))
#: the LSL content type of each device kind
CONTENT_TYPE = {"dynamometer": "Torque", "torque_sensor": "Torque", "force_plate": "Force", "mocap": "Mocap"}
#: the nominal rate (Hz) of a device kind whose driver does not report one
DEFAULT_RATE_HZ = {"dynamometer": 100.0, "torque_sensor": 100.0, "force_plate": 1000.0, "mocap": 100.0}


#: the outlets' manufacturer field (an XDF importer recognises the instrument's own streams by it)
MANUFACTURER = "afo-gait-instrument"


def unit_of(channel: str) -> str:
    """The channel's unit from its name's suffix (``torque_nm`` → ``N.m``; a count has none)."""
    for suffix, unit in UNIT_BY_SUFFIX:
        if channel.endswith(suffix):
            return unit
    return "count" if channel == "counter" else ""


def channel_labels(layout: dict[str, tuple[tuple[int, ...], str]]) -> list[tuple[str, str, str]]:
    """(label, unit, source channel) of every scalar the stream carries, in order; the time is the
    sample's LSL time stamp, not a channel."""
    out = []
    for name, (shape, _) in layout.items():
        if name == "time_s":
            continue
        size = int(np.prod(shape)) if shape else 1
        if not shape:
            out.append((name, unit_of(name), name))
        elif len(shape) == 1 and shape[0] <= 3:
            out += [(f"{name}_{'xyz'[i]}", unit_of(name), name) for i in range(shape[0])]
        else:
            out += [(f"{name}_{i}", unit_of(name), name) for i in range(size)]
    return out


class LslPublisher:
    """The engine's sink that pushes every block to its device's outlet.

    :param devices: the engine's devices; an outlet goes up when its device is open (now, or at its first block).
    :param source: the stream names' prefix (``instrument`` → ``instrument-dynamometer``).
    :param session: the lab session's id, in every outlet's ``source_id``.
    :param subject_code: the subject's pseudonym, or None (never a name).
    """

    def __init__(self, devices: dict[str, StreamingDevice], *, source: str = "instrument", session: str = "0",
                 subject_code: str | None = None) -> None:
        from drivers.lsl import import_pylsl

        pylsl = import_pylsl()
        self._pylsl = pylsl
        self.devices, self.source, self.session, self.subject_code = devices, source, session, subject_code
        self.outlets: dict[str, Any] = {}
        self.labels: dict[str, list[tuple[str, str, str]]] = {}
        self._sources: dict[str, list[str]] = {}
        self.pushed: dict[str, int] = dict.fromkeys(devices, 0)
        for name, dev in devices.items():
            if dev.connected:  # open already: its layout is known, the outlet goes up now
                self._outlet(name, dev)

    def _outlet(self, name: str, dev: StreamingDevice) -> Any:
        """Make the device's outlet (once its layout is known: at the first block, or now if open)."""
        pylsl, source, session, subject_code = self._pylsl, self.source, self.session, self.subject_code
        if name in self.outlets:
            return self.outlets[name]
        labels = channel_labels(dev.channel_layout())
        rate = float(getattr(dev, "telemetry_rate_hz", 0.0) or getattr(dev, "rate_hz", 0.0)
                     or getattr(dev, "output_rate_hz", 0.0) or DEFAULT_RATE_HZ.get(name, 0.0))
        info = pylsl.StreamInfo(f"{source}-{name}", CONTENT_TYPE.get(name, "Misc"), len(labels), rate,
                                pylsl.cf_double64, f"{source}:{session}:{name}")
        channels = info.desc().append_child("channels")
        for label, unit, _ in labels:
            ch = channels.append_child("channel")
            ch.append_child_value("label", label)
            ch.append_child_value("unit", unit)
        info.desc().append_child_value("manufacturer", MANUFACTURER)
        if subject_code:
            info.desc().append_child_value("subject", subject_code)
        self.outlets[name] = pylsl.StreamOutlet(info, chunk_size=0, max_buffered=60)
        self.labels[name] = labels
        self._sources[name] = list(dict.fromkeys(s for _, _, s in labels))  # the channels, in the labels' order
        return self.outlets[name]

    def __call__(self, name: str, channels: dict[str, np.ndarray]) -> None:
        if name not in self.devices:
            return
        outlet = self._outlet(name, self.devices[name])
        n = len(channels["counter"])
        if n == 0:
            return
        matrix = np.column_stack([np.asarray(channels[src], dtype=float).reshape(n, -1) for src in self._sources[name]])
        outlet.push_chunk(matrix.tolist(), np.asarray(channels["time_s"], dtype=float).tolist())
        self.pushed[name] += n

    def close(self) -> None:
        """Withdraw every outlet (receivers see the streams end)."""
        self.outlets.clear()


__all__ = ["CONTENT_TYPE", "LslPublisher", "channel_labels", "unit_of"]
