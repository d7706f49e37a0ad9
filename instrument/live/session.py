"""Record one trial: devices → acquisition engine → crash-safe trial file → session store."""

from __future__ import annotations

import logging
import platform
import threading
import time
from dataclasses import asdict, dataclass, field, is_dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from drivers import ConnectionLostError, DriverError, StreamingDevice

from .. import __version__
from ..errors import DiskFullError, RecordingError
from ..kinds.base import TrialProtocol
from ..store import SessionStore
from .acquisition import AcquisitionEngine, DeviceReport
from .recording import TrialWriter

log = logging.getLogger(__name__)


@dataclass
class TrialOutcome:
    """What :func:`record_trial` produced."""

    trial_id: int
    path: Path
    status: str
    reason: str | None
    devices: dict[str, DeviceReport] = field(default_factory=dict)
    duration_s: float = 0.0


def settings_snapshot(protocol: TrialProtocol, extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """Everything that defines how a trial was taken (as QCoDeS's station snapshot)."""
    fields: dict[str, Any] = asdict(protocol) if is_dataclass(protocol) else {}  # type: ignore[arg-type]  # a dataclass protocol's fields, checked by is_dataclass
    proto = {k: v for k, v in fields.items() if not callable(v)}
    return {
        "software": {"name": "afo-gait-instrument", "version": __version__, "python": platform.python_version(),
                     "numpy": np.__version__, "h5py": h5py.__version__, "hdf5": h5py.version.hdf5_version},
        "protocol": {"name": protocol.name, "settings": proto, "condition": protocol.condition()},
        **(extra or {}),
    }


def record_trial(store: SessionStore, session_id: int, protocol: TrialProtocol,
                 devices: dict[str, StreamingDevice], *, operator: str | None = None,
                 trial_number: int | None = None, extra_metadata: dict[str, Any] | None = None,
                 stop: threading.Event | None = None, engine: AcquisitionEngine | None = None,
                 on_event: Any = None) -> TrialOutcome:
    """Set up, record and index one trial.

    A device that loses its link mid-trial: the data on both sides of the hole is kept and the trial
    is marked ``interrupted`` with the device named. A device that refuses a protocol's command (a
    move sent just after an e-stop): the trial ends there, ``interrupted`` with the device's words,
    its data kept. A write failure (disk full): the trial is marked
    ``failed``, the data flushed so far stays readable, and the error is raised.

    :raises RecordingError: the trial file could not be written.
    :raises StoreError: the store could not be written.
    """
    missing = [d for d in protocol.devices if d not in devices]
    if missing:
        raise RecordingError(f"protocol {protocol.name!r} needs device(s) {missing}")
    stop = stop or threading.Event()
    engine = engine or AcquisitionEngine({n: devices[n] for n in protocol.devices})
    engine.open()
    try:
        protocol.prepare(engine.devices)
    except BaseException:
        protocol.shutdown(engine.devices, lambda kind, **fields: log.warning("%s %s", kind, fields))
        raise
    trial_id, path = store.begin_trial(session_id, protocol.name, protocol.condition(),
                                       operator=operator, trial_number=trial_number)
    # the trial file names the operator by the store's code only (the name stays in the store)
    metadata = settings_snapshot(protocol, {"trial_id": trial_id, "operator": store.operator_code(operator),
                                            "trial_number": trial_number,
                                            **(extra_metadata or {})})
    try:
        writer = TrialWriter(path, engine.specs(), metadata)
    except RecordingError as err:
        store.finish_trial(trial_id, "failed", {}, reason=str(err))
        raise
    t0 = time.monotonic()
    refused: DriverError | None = None
    engine.start(writer)
    try:
        def mark(kind: str, **fields: Any) -> None:
            writer.log_event(kind, **fields)
            if on_event is not None:  # live consumers (the GUI's runner) learn the protocol's phases
                on_event(kind, fields)

        try:
            protocol.drive(engine.devices, mark, stop)
        except DriverError as err:  # a device refused a command (after an e-stop, say): the trial ends here
            refused = err
            mark("protocol_ended", error=str(err))
    finally:
        try:
            protocol.shutdown(engine.devices, mark)  # the arm is halted on every path, recorded
        finally:
            reports = engine.stop()
    counts = {n: r.counts() for n, r in reports.items()}
    if engine.recording_error is not None or writer.error is not None:
        failure = writer.error or engine.recording_error
        writer.abort()
        if isinstance(failure, DiskFullError):
            store.release_reserve()  # room for the index to say what happened
        store.finish_trial(trial_id, "failed", counts, reason=str(failure))
        raise failure if isinstance(failure, RecordingError) else RecordingError(str(failure))
    lost_links = {n: r for n, r in reports.items() if any(ConnectionLostError.__name__ in e for e in r.errors)}
    status, reason = "recorded", None
    if stop.is_set():
        status, reason = "interrupted", "stopped by the operator before the protocol ended"
    elif refused is not None:
        status, reason = "interrupted", f"the protocol ended early: {refused}"
    elif lost_links:
        status = "interrupted"
        reason = "; ".join(f"{n}: link lost {sum(ConnectionLostError.__name__ in e for e in r.errors)}× "
                           f"({r.counts()['lost_samples']} samples missing)" for n, r in lost_links.items())
    summary = {"devices": {n: {**r.counts(), "errors": r.errors[:20], "rate_hz": r.stats.get("rate_hz")}
                           for n, r in reports.items()}}
    try:
        writer.close(status, summary)
    except RecordingError as err:
        store.finish_trial(trial_id, "failed", counts, reason=str(err))
        raise
    store.finish_trial(trial_id, status, counts, reason=reason)
    return TrialOutcome(trial_id, path, status, reason, reports, time.monotonic() - t0)
