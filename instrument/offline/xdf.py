"""XDF files from LabRecorder as trials of the store (``instrument import-xdf``).

A lab that records everything with LabRecorder (the instrument's outlets beside EMG, goniometers,
EEG, mocap) brings the session back as one XDF file; each file becomes one trial of the given kind:

* the instrument's own streams (``instrument-<device>``, manufacturer ``afo-gait-instrument``, as
  :class:`instrument.live.lsl.LslPublisher` sends them) become that device's channels again, matched by
  their labels (``force_n_x`` … back into ``force_n``), the counter included, so gaps count as recorded;
* every other stream becomes a stream device like an LSL inlet's (``values`` with its labels and units,
  ``lsl_time_s``), named by its stream name (``EMG`` → ``emg``); a goniometer's ``hip_flexion`` channel
  then gives the passive fit the measured hip angle as in a live recording.

Time: pyxdf's clock synchronisation and dejitter put every stream on the recording computer's LSL
clock; ``time_s`` is that time. The trial has no protocol marks (no ``sweep_start``): tables take the
movement itself. A file pyxdf cannot read, a stream whose labels do not match its device, or a trial
kind whose devices are missing is refused in one line naming the file; nothing is written then.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from drivers.blocks import DynamometerBlock, ForcePlateBlock, SampleBlock, StreamBlock, TorqueBlock

from ..errors import CorruptFileError
from ..kinds.base import TrialProtocol
from ..live.lsl import MANUFACTURER, channel_labels
from ..live.recording import DeviceSpec, TrialWriter
from ..live.session import settings_snapshot
from ..store import SessionStore

#: the instrument's devices an outlet can carry, by the block they stream
DEVICE_BLOCKS: dict[str, type[SampleBlock]] = {"dynamometer": DynamometerBlock, "force_plate": ForcePlateBlock,
                                                "torque_sensor": TorqueBlock}


class XdfImportError(CorruptFileError):
    """An XDF file that cannot become a trial (unreadable, or without what the trial kind needs)."""


def _first(d: Any, key: str, default: Any = None) -> Any:
    """pyxdf's XML dicts hold every value in a one-element list."""
    if not isinstance(d, dict) or key not in d or not d[key]:
        return default
    return d[key][0]


def _channels(info: dict[str, Any]) -> tuple[list[str], list[str]]:
    desc = _first(info, "desc") or {}
    chans = _first(desc, "channels") or {}
    labels, units = [], []
    for ch in (chans.get("channel") or []) if isinstance(chans, dict) else []:
        labels.append(str(_first(ch, "label", "")))
        units.append(str(_first(ch, "unit", "")))
    return labels, units


def _device_channels(kind: str, name: str, labels: list[str], data: np.ndarray,
                     stamps: np.ndarray) -> tuple[dict[str, tuple[tuple[int, ...], str]], dict[str, np.ndarray]]:
    """An instrument outlet's columns back into its device's channels (layout and arrays)."""
    layout = dict(DEVICE_BLOCKS[kind].LAYOUT)
    expected = channel_labels(layout)
    index = {label: k for k, label in enumerate(labels)}
    missing = [label for label, _, _ in expected if label not in index]
    if missing:
        raise ValueError(f"stream {name!r}: no channel {', '.join(missing[:4])} (the {kind}'s outlet sends them)")
    channels: dict[str, np.ndarray] = {}
    for source in dict.fromkeys(s for _, _, s in expected):
        cols = [index[label] for label, _, s in expected if s == source]
        shape, dtype = layout[source]
        values = data[:, cols].reshape((len(stamps), *shape)) if shape else data[:, cols[0]]
        target = np.dtype(dtype)
        if target.kind in "iu" and values.size and not (
                np.all(np.isfinite(values)) and np.iinfo(target).min <= np.min(values)
                and np.max(values) <= np.iinfo(target).max):
            raise ValueError(f"stream {name!r}: channel {source} holds values that are no {target} (NaN, infinite or "
                             "out of range): the file is damaged")
        channels[source] = values.astype(target)
    channels["time_s"] = stamps.astype(float)
    return layout, channels


def _stream_channels(info: dict[str, Any], labels: list[str], units: list[str], data: np.ndarray,
                     stamps: np.ndarray) -> tuple[dict[str, tuple[tuple[int, ...], str]], dict[str, np.ndarray], dict[str, Any]]:
    rate = float(_first(info, "nominal_srate", "0") or 0.0)
    n = data.shape[1] if data.ndim == 2 else 1
    labels = labels if len(labels) == n else [f"ch{k + 1}" for k in range(n)]
    units = units if len(units) == n else [""] * n
    if rate > 0 and len(stamps):
        ticks = np.rint((stamps - stamps[0]) * rate)
        if not np.all(np.abs(ticks) < 2.0 ** 62):
            raise ValueError(f"stream {str(_first(info, 'name', ''))!r}: its time stamps span more than a counter holds "
                             f"at {rate:g} Hz: the file is damaged")
        counter = ticks.astype(np.int64)
    else:
        counter = np.arange(len(stamps), dtype=np.int64)
    layout = dict(StreamBlock.LAYOUT)
    layout["values"] = ((n,), "f8")
    channels = {"counter": counter, "time_s": stamps.astype(float), "values": data.reshape(len(stamps), n).astype(float),
                "lsl_time_s": stamps.astype(float)}
    identity = {"kind": "lsl", "protocol": "Lab Streaming Layer (XDF)", "stream_name": str(_first(info, "name", "")),
                "stream_type": str(_first(info, "type", "")), "source_id": str(_first(info, "source_id", "")),
                "labels": labels, "units": units, "nominal_rate_hz": rate}
    return layout, channels, identity


def _device_name(stream_name: str, taken: set[str]) -> str:
    base = re.sub(r"[^0-9a-z]+", "_", stream_name.lower()).strip("_") or "stream"
    name, k = base, 2
    while name in taken:
        name, k = f"{base}_{k}", k + 1
    return name


def read_xdf(path: str | Path) -> dict[str, tuple[DeviceSpec, dict[str, np.ndarray]]]:
    """Every stream of an XDF file as a device of a trial: ``name → (spec, channels)``.

    :raises XdfImportError: pyxdf cannot read the file, it holds no stream with samples, or an instrument
        outlet's channels do not match its device.
    """
    import pyxdf

    p = Path(path)
    try:
        streams, _ = pyxdf.load_xdf(str(p), synchronize_clocks=True, dejitter_timestamps=True)
    except FileNotFoundError as err:
        raise XdfImportError(p, "no such file") from err
    except Exception as err:  # pyxdf raises IOError, struct and XML errors for damaged files
        raise XdfImportError(p, f"not a readable XDF file ({type(err).__name__}: {err})") from err
    devices: dict[str, tuple[DeviceSpec, dict[str, np.ndarray]]] = {}
    for s in streams:
        info = s.get("info", {})
        stamps = np.asarray(s.get("time_stamps", []), dtype=float)
        if stamps.size == 0:
            continue
        if not np.all(np.isfinite(stamps)):
            raise XdfImportError(p, f"stream {_first(info, 'name')!r}: a time stamp is NaN or infinite: the file is "
                                    "damaged")
        try:
            data = np.asarray(s.get("time_series"), dtype=float)
        except (TypeError, ValueError) as err:
            raise XdfImportError(p, f"stream {_first(info, 'name')!r} is not numeric ({err})") from err
        data = data.reshape(len(stamps), -1)
        name = str(_first(info, "name", ""))
        labels, units = _channels(info)
        desc = _first(info, "desc") or {}
        kind = name.removeprefix("instrument-")
        if _first(desc, "manufacturer") == MANUFACTURER and name.startswith("instrument-") and kind in DEVICE_BLOCKS:
            try:
                layout, channels = _device_channels(kind, name, labels, data, stamps)
            except ValueError as err:
                raise XdfImportError(p, str(err)) from err
            identity = {"kind": kind, "protocol": "instrument outlet via LabRecorder (XDF)", "stream_name": name,
                        "source_id": str(_first(info, "source_id", ""))}
            devices[kind] = (DeviceSpec(layout, identity), channels)
        else:
            try:
                layout, channels, identity = _stream_channels(info, labels, units, data, stamps)
            except ValueError as err:
                raise XdfImportError(p, str(err)) from err
            devices[_device_name(name, set(devices) | set(DEVICE_BLOCKS))] = (DeviceSpec(layout, identity), channels)
    if not devices:
        raise XdfImportError(p, "no stream with samples")
    return devices


def import_xdf(path: str | Path, store: SessionStore, session_id: int, protocol: TrialProtocol, *,
               operator: str | None = None,
               devices: dict[str, tuple[DeviceSpec, dict[str, np.ndarray]]] | None = None) -> int:
    """One XDF file as a trial of ``protocol`` in ``store`` (session ``session_id``); returns the trial id.

    :raises XdfImportError: see :func:`read_xdf`, or a device the trial kind needs is not in the file.
    """
    p = Path(path)
    devices = read_xdf(p) if devices is None else devices  # the caller's reading, when it checked the file first
    missing = [d for d in protocol.devices if d not in devices]
    if missing:
        raise XdfImportError(p, f"no {', '.join(missing)} stream (instrument-{missing[0]}): a {protocol.name} trial "
                                f"needs it; the file holds {', '.join(sorted(devices))}")
    trial_id, trial_path = store.begin_trial(session_id, protocol.name, protocol.condition(), operator=operator)
    metadata = settings_snapshot(protocol, {"trial_id": trial_id, "operator": store.operator_code(operator),
                                            "imported_from": {"format": "XDF", "file": p.name,
                                                              "streams": sorted(devices)}})
    writer = TrialWriter(trial_path, {n: spec for n, (spec, _) in devices.items()}, metadata)
    counts: dict[str, dict[str, int]] = {}
    try:
        for name, (_, channels) in devices.items():
            writer.append(name, channels)
            steps = np.diff(channels["counter"])
            lost = int(np.sum(steps[steps > 1] - 1))
            counts[name] = {"samples": len(channels["counter"]), "lost_samples": lost, "gaps": int(np.sum(steps > 1))}
        writer.close("recorded", {"devices": counts, "imported_from": p.name})
    except BaseException:
        writer.abort()
        store.finish_trial(trial_id, "failed", counts, reason=f"import of {p.name} failed")
        raise
    store.finish_trial(trial_id, "recorded", counts)
    return trial_id

