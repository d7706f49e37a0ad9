"""Crash-safe trial files: append-only HDF5 (h5py) in SWMR mode, flushed and fsynced every 0.25 s.

Why HDF5: one self-describing file per trial that MATLAB, Python and R labs already read; chunked,
resizable datasets append without rewriting; SWMR (single-writer/multiple-reader) orders metadata
writes so that a file whose writer was killed still opens (read-only, SWMR) with every sample up
to the last flush. Recovery copies such a file into a clean one and marks it ``interrupted``.

Layout of a trial file (format ``afo-gait-trial`` version 1)::

    /                     attrs: format, format_version, metadata (JSON snapshot), status, summary (JSON)
    /devices/NAME/        attrs: identity (JSON: device, calibration, zero offsets, settings)
        counter, time_s, <channels...>   one row per sample, SI units in the names
        gaps              (k, 2) int64: (last counter before, first counter after) each gap
    /events               (k,) JSON strings: device errors, protocol marks, operator notes
"""

from __future__ import annotations

import errno
import json
import logging
import os
import queue
import re
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from drivers import StreamingDevice

from ..errors import CorruptFileError, DiskFullError, RecordingError

log = logging.getLogger(__name__)

FORMAT = "afo-gait-trial"
FORMAT_VERSION = 1
EVENT_DTYPE = h5py.string_dtype("utf-8", 1024)
#: free space a recovery needs beyond two copies of the file (bytes)
RECOVERY_HEADROOM_BYTES = 1 << 20
#: rows per HDF5 chunk: about 4 s of force plate, 40 s of dynamometer
CHUNK_ROWS = 4096

Layout = dict[str, tuple[tuple[int, ...], str]]


@dataclass
class DeviceSpec:
    """What a trial file needs to know of a device before the first sample arrives."""

    layout: Layout
    identity: dict[str, Any] = field(default_factory=dict)


@dataclass
class WriterStats:
    """Counts of a :class:`TrialWriter` (flush intervals in host seconds)."""

    samples: dict[str, int] = field(default_factory=dict)
    gaps: dict[str, int] = field(default_factory=dict)
    flushes: int = 0
    max_flush_interval_s: float = 0.0
    write_cpu_s: float = 0.0


def _is_disk_full(err: BaseException) -> bool:
    if isinstance(err, OSError) and err.errno in (errno.ENOSPC, errno.EFBIG, errno.EDQUOT):
        return True
    text = str(err).lower()
    return any(s in text for s in ("no space", "file too large", "disk quota", "errno = 27", "errno = 28"))


class TrialWriter:
    """Appends blocks to one trial file from a writer thread; callers never wait on the disk.

    :param path: the ``.h5`` file to create (must not exist).
    :param devices: device name → :class:`DeviceSpec`.
    :param metadata: JSON-serialisable snapshot stored with the data (protocol, condition, operator,
        software version, settings).
    :param flush_interval_s: flush + fsync period; at most about twice this much data is at risk.
    """

    def __init__(self, path: str | Path, devices: dict[str, DeviceSpec], metadata: dict[str, Any],
                 flush_interval_s: float = 0.25) -> None:
        self.path = Path(path)
        self.flush_interval_s = flush_interval_s
        self.stats = WriterStats(samples={n: 0 for n in devices}, gaps={n: 0 for n in devices})
        self._queue: queue.SimpleQueue[tuple[str, Any] | None] = queue.SimpleQueue()
        self._last_counter = {n: -1 for n in devices}
        self._error: RecordingError | None = None
        self._closed = False
        try:
            self._file = h5py.File(self.path, "w-", libver="latest")
            f = self._file
            f.attrs["format"] = FORMAT
            f.attrs["format_version"] = FORMAT_VERSION
            f.attrs["metadata"] = json.dumps(metadata, default=_json_default)
            f.attrs["status"] = "recording"
            f.attrs["summary"] = "{}"
            grp = f.create_group("devices")
            self._datasets: dict[str, dict[str, h5py.Dataset]] = {}
            for name, spec in devices.items():
                g = grp.create_group(name)
                g.attrs["identity"] = json.dumps(spec.identity, default=_json_default)
                ds = {}
                for channel, (shape, dtype) in spec.layout.items():
                    ds[channel] = g.create_dataset(channel, shape=(0, *shape), maxshape=(None, *shape),
                                                   chunks=(CHUNK_ROWS, *shape) if shape else (CHUNK_ROWS,),
                                                   dtype=dtype)
                ds["gaps"] = g.create_dataset("gaps", shape=(0, 2), maxshape=(None, 2), chunks=(256, 2), dtype="i8")
                self._datasets[name] = ds
            self._events = f.create_dataset("events", shape=(0,), maxshape=(None,), chunks=(64,), dtype=EVENT_DTYPE)
            f.swmr_mode = True
            self._sync()
        except OSError as err:
            raise (DiskFullError if _is_disk_full(err) else RecordingError)(
                f"{self.path}: cannot create trial file: {err}") from err
        self._last_flush = time.monotonic()
        self._thread = threading.Thread(target=self._run, name=f"writer-{self.path.stem}", daemon=True)
        self._thread.start()

    # ------------------------------------------------------------------ producer side
    @property
    def error(self) -> RecordingError | None:
        """The write error that stopped the writer, if any (data up to the last flush is kept)."""
        return self._error

    def append(self, device: str, channels: dict[str, np.ndarray]) -> None:
        """Queue one block of ``device`` (channel name → array, as ``SampleBlock.channels()``).

        :raises RecordingError: the writer has stopped on an earlier error.
        """
        if self._error is not None:
            raise self._error
        if self._closed:
            raise RecordingError(f"{self.path}: trial already closed")
        self._queue.put(("block", (device, channels)))

    def log_event(self, kind: str, **fields: Any) -> None:
        """Queue an event (device error, protocol mark, operator note) with the host time."""
        if self._error is None and not self._closed:
            self._queue.put(("event", {"kind": kind, "time_s": time.monotonic(), **fields}))

    def close(self, status: str = "recorded", summary: dict[str, Any] | None = None) -> None:
        """Write everything queued, then mark the file ``status`` with ``summary``.

        :raises RecordingError: the file could not be completed (the data already flushed stays readable).
        """
        if self._closed:
            return
        self._closed = True
        self._queue.put(None)
        self._thread.join()
        if self._error is not None:
            raise self._error
        self._datasets.clear()
        f: h5py.File | None = self._file
        try:
            assert f is not None  # finish() runs once, on an open file
            f.close()
            f = h5py.File(self.path, "r+")
            f.attrs["status"] = status
            f.attrs["summary"] = json.dumps({**(summary or {}), "writer": _stats_dict(self.stats)},
                                            default=_json_default)
            f.close()
            f = None
            _fsync_path(self.path)
        except (OSError, RuntimeError) as err:
            if f is not None:
                _detach_and_close(f, self.path)
            raise (DiskFullError if _is_disk_full(err) else RecordingError)(
                f"{self.path}: cannot complete trial file: {str(err).splitlines()[0][:160]}") from err

    def abort(self) -> None:
        """Stop the writer without completing the file (used when the process must exit now)."""
        if not self._closed:
            self._closed = True
            self._queue.put(None)
            self._thread.join()
        self._datasets.clear()
        try:
            self._file.close()
        except Exception:
            pass

    def _detach_file(self) -> None:
        """After a failed write: make sure HDF5 never writes this file again, then close it."""
        _detach_and_close(self._file, self.path, before_close=self._datasets.clear)

    # ------------------------------------------------------------------ writer thread
    def _run(self) -> None:
        pending: dict[str, list[dict[str, np.ndarray]]] = {}
        events: list[dict[str, Any]] = []
        done = False
        while not done:
            timeout = max(0.0, self._last_flush + self.flush_interval_s - time.monotonic())
            try:
                item = self._queue.get(timeout=timeout)
                while item is not None:
                    kind, payload = item
                    if kind == "block":
                        pending.setdefault(payload[0], []).append(payload[1])
                    else:
                        events.append(payload)
                    item = self._queue.get_nowait()
                done = True
            except queue.Empty:
                pass
            if done or time.monotonic() - self._last_flush >= self.flush_interval_s:
                if self._error is None:
                    try:
                        self._write(pending, events)
                    except Exception as err:
                        full = _is_disk_full(err)
                        why = "disk full (no space left on device)" if full else str(err).splitlines()[0][:160]
                        self._error = (DiskFullError if full else RecordingError)(
                            f"{self.path}: write failed after {sum(self.stats.samples.values())} samples, "
                            f"data up to the last flush is kept: {why}")
                        log.error("%s", self._error)
                        self._detach_file()
                pending, events = {}, []

    def _write(self, pending: dict[str, list[dict[str, np.ndarray]]], events: list[dict[str, Any]]) -> None:
        cpu0 = time.thread_time()
        for name, blocks in pending.items():
            ds = self._datasets[name]
            counters = np.concatenate([b["counter"] for b in blocks])
            n0 = ds["counter"].shape[0]
            for channel, dset in ds.items():
                if channel == "gaps":
                    continue
                data = np.concatenate([b[channel] for b in blocks])
                dset.resize(n0 + data.shape[0], axis=0)
                dset[n0:] = data
            steps = np.diff(np.concatenate([[self._last_counter[name]], counters]))
            # a gap is a plausible forward jump; larger ones are counter resyncs (reported as events)
            jumps = np.flatnonzero((steps > 1) & (steps <= StreamingDevice.max_counter_jump))
            if self._last_counter[name] < 0:
                jumps = jumps[jumps > 0]
            if jumps.size:
                prev = np.concatenate([[self._last_counter[name]], counters])[jumps]
                gaps = np.column_stack([prev, counters[jumps]])
                g = ds["gaps"]
                g.resize(g.shape[0] + len(gaps), axis=0)
                g[-len(gaps):] = gaps
                self.stats.gaps[name] += len(gaps)
            self._last_counter[name] = int(counters[-1])
            self.stats.samples[name] += int(counters.size)
        if events:
            e = self._events
            e.resize(e.shape[0] + len(events), axis=0)
            e[-len(events):] = [json.dumps(ev, default=_json_default)[:1000] for ev in events]
        self._sync()
        now = time.monotonic()
        self.stats.max_flush_interval_s = max(self.stats.max_flush_interval_s, now - self._last_flush)
        self._last_flush = now
        self.stats.flushes += 1
        self.stats.write_cpu_s += time.thread_time() - cpu0

    def _sync(self) -> None:
        self._file.flush()
        os.fsync(self._file.id.get_vfd_handle())


# ---------------------------------------------------------------------- reading
@dataclass
class DeviceData:
    """One device's channels in a trial file (SI units in the channel names)."""

    name: str
    identity: dict[str, Any]
    channels: dict[str, np.ndarray]
    gaps: np.ndarray

    @property
    def samples(self) -> int:
        return int(self.channels["counter"].shape[0])

    @property
    def lost_samples(self) -> int:
        return int((self.gaps[:, 1] - self.gaps[:, 0] - 1).sum()) if len(self.gaps) else 0


@dataclass
class TrialFile:
    """Everything in one trial file."""

    path: Path
    status: str
    metadata: dict[str, Any]
    summary: dict[str, Any]
    devices: dict[str, DeviceData]
    events: list[dict[str, Any]]
    warnings: list[str] = field(default_factory=list)


def _open_for_read(path: Path) -> tuple[h5py.File, bool]:
    if not path.exists():
        raise CorruptFileError(path, "file does not exist")
    if path.stat().st_size == 0:
        raise CorruptFileError(path, "file is empty (0 bytes)")
    try:
        return h5py.File(path, "r"), False
    except OSError as err:
        if "already open for write" in str(err) or "consistency flags" in str(err):
            try:
                return h5py.File(path, "r", swmr=True, libver="latest"), True
            except OSError as err2:
                raise CorruptFileError(path, f"writer was interrupted and the file cannot be opened: {err2}") from err2
        raise CorruptFileError(path, f"not a readable HDF5 file (truncated or not a trial?): {err}") from err


def read_trial(path: str | Path) -> TrialFile:
    """Read a trial file, including one whose writer was killed (status then reads ``recording``) or
    whose disk filled mid-write (the file ends before HDF5's recorded end: rows past the real end
    are cut, never read as zeros).

    :raises CorruptFileError: missing, empty, truncated beyond repair, not HDF5, or not an instrument trial.
    """
    path = Path(path)
    try:
        return _read_trial(path, path, cut=False)
    except CorruptFileError as err:
        m = re.search(r"stored_eof = (\d+)", err.defect)
        if m is None:
            raise
    with tempfile.TemporaryDirectory() as tmp:  # a sparse padded copy: HDF5 will not open a short file
        padded = Path(tmp) / path.name
        try:
            shutil.copyfile(path, padded)
            os.truncate(padded, int(m.group(1)))
        except OSError as err2:
            raise CorruptFileError(path, f"file ends before its recorded end and cannot be padded to read it: "
                                         f"{err2}") from err2
        try:
            trial = _read_trial(padded, path, cut=True)
        except CorruptFileError as err3:
            raise CorruptFileError(path, f"truncated file ({path.stat().st_size} of {m.group(1)} bytes) whose "
                                         f"structure is damaged: {err3.defect}") from err3
    trial.warnings.append("the file ends before its recorded end (the disk filled); rows past the end are cut")
    return trial


def _read_trial(open_path: Path, path: Path, *, cut: bool) -> TrialFile:
    real_size = path.stat().st_size if path.exists() else 0
    f, interrupted = _open_for_read(open_path)
    warnings: list[str] = []
    try:
        try:
            fmt, version = f.attrs.get("format"), int(f.attrs.get("format_version", 0))
        except (KeyError, ValueError, OSError, RuntimeError) as err:
            raise CorruptFileError(path, f"damaged trial header: {str(err).splitlines()[0]}") from err
        if fmt != FORMAT:
            raise CorruptFileError(path, f"not an instrument trial file (format attribute {fmt!r})")
        if version > FORMAT_VERSION:
            raise CorruptFileError(path, f"trial format version {version} is newer than this software ({FORMAT_VERSION})")
        try:
            metadata = json.loads(f.attrs["metadata"])
            summary = json.loads(f.attrs.get("summary", "{}"))
            status = str(f.attrs.get("status", "recording"))
            devices: dict[str, DeviceData] = {}
            for name, g in f["devices"].items():
                if interrupted or cut:  # rows whose chunks never reached the disk are cut, never read as zeros
                    rows = min(_valid_rows(d, real_size) for k, d in g.items() if k != "gaps")
                    channels = {k: v[:rows] for k, v in g.items() if k != "gaps"}
                else:
                    channels = {k: v[()] for k, v in g.items() if k != "gaps"}
                n = min(a.shape[0] for a in channels.values())
                if any(a.shape[0] != n for a in channels.values()):
                    warnings.append(f"{name}: channels of unequal length after an interruption; cut to {n} samples")
                    channels = {k: v[:n] for k, v in channels.items()}
                devices[name] = DeviceData(name, json.loads(g.attrs["identity"]), channels, g["gaps"][()])
            events = []
            for text in f["events"].asstr()[()]:
                try:
                    events.append(json.loads(text))
                except ValueError:  # an event whose chunk never reached the disk reads back empty
                    warnings.append("an event was lost in an interrupted write")
        except (KeyError, ValueError, OSError, RuntimeError) as err:
            raise CorruptFileError(path, f"damaged trial structure: {str(err).splitlines()[0]}") from err
    finally:
        f.close()
    if interrupted and status == "recording":
        warnings.append("the writer was interrupted; data up to its last flush")
    return TrialFile(path, status, metadata, summary, devices, events, warnings)


@dataclass
class RecoveryReport:
    """What :func:`recover_trial_file` found and did."""

    path: Path
    samples: dict[str, int]
    seconds: float
    readable: bool
    defect: str = ""


def _valid_rows(dset: h5py.Dataset, real_size: int) -> int:
    """Rows of ``dset`` whose chunks were all written and lie wholly inside the first ``real_size`` bytes.

    A chunk never allocated (the write failed first) would read back as fill values: it ends the valid rows.
    """
    rows = dset.shape[0]
    if not dset.chunks:
        return rows
    step = dset.chunks[0]
    good = set()
    for i in range(dset.id.get_num_chunks()):
        info = dset.id.get_chunk_info(i)
        if info.byte_offset is not None and info.byte_offset + info.size <= real_size:
            good.add(info.chunk_offset[0])
    start = 0
    while start < rows and start in good:
        start += step
    return min(rows, start)


def recover_trial_file(path: str | Path) -> RecoveryReport:
    """Make an interrupted trial file clean: copy what its writer flushed into a new file, status ``interrupted``.

    Handles a writer killed mid-trial (SWMR file left open) and a disk that filled mid-write (the
    file ends before HDF5's recorded end): rows whose chunks lie past the real end of the file
    are cut, never returned as zeros. The original bytes of a damaged file are kept beside it as
    ``*.damaged``. A file that cannot be read at all is left untouched and reported (``readable`` False).
    """
    path = Path(path)
    t0 = time.perf_counter()
    work, real_size = path, path.stat().st_size if path.exists() else 0
    free = shutil.disk_usage(path.parent).free if path.parent.exists() else 0
    if free < 2 * real_size + RECOVERY_HEADROOM_BYTES:
        # a copy that fills the disk would fail half-way (and HDF5 retries its writes at exit)
        return RecoveryReport(path, {}, time.perf_counter() - t0, False,
                              f"not enough free space to recover ({free} bytes free, {real_size}-byte file); "
                              "the file is kept as it is")
    try:
        _open_for_read(path)[0].close()
    except CorruptFileError as err:
        m = re.search(r"stored_eof = (\d+)", err.defect)
        if m is None:
            return RecoveryReport(path, {}, time.perf_counter() - t0, False, err.defect)
        work = path.with_suffix(".padded")
        shutil.copyfile(path, work)
        with open(work, "r+b") as fh:
            fh.truncate(int(m.group(1)))
    tmp = path.with_suffix(".recovering")
    samples: dict[str, int] = {}
    try:
        with h5py.File(work, "r", swmr=True, libver="latest") as src, h5py.File(tmp, "w", libver="latest") as dst:
            for key, value in src.attrs.items():
                dst.attrs[key] = value
            for key in src:
                src.copy(src[key], dst, name=key)
            for name, g in src["devices"].items():
                rows = min(_valid_rows(d, real_size) for k, d in g.items() if k != "gaps")
                samples[name] = rows
                for channel in dst["devices"][name]:
                    if channel != "gaps" and dst["devices"][name][channel].shape[0] != rows:
                        dst["devices"][name][channel].resize(rows, axis=0)
            dst.attrs["status"] = "interrupted"
            dst.attrs["summary"] = json.dumps({"recovered_at": time.time(), "samples": samples})
    except (OSError, KeyError) as err:
        tmp.unlink(missing_ok=True)
        return RecoveryReport(path, {}, time.perf_counter() - t0, False, f"cannot recover: {err}")
    finally:
        if work != path:
            work.unlink(missing_ok=True)
    _fsync_path(tmp)
    if work != path:
        os.replace(path, path.with_suffix(".damaged"))
    os.replace(tmp, path)
    return RecoveryReport(path, samples, time.perf_counter() - t0, True)


def _detach_and_close(f: h5py.File, path: Path, before_close: Callable[[], None] | None = None) -> None:
    """Close ``f`` after a failed write without HDF5 ever writing to the file again.

    HDF5 keeps the metadata it could not flush and retries at close and again at interpreter
    exit, where a second failure crashed the process (SIGSEGV) and left a half-written file.
    Pointing the file's descriptor at ``/dev/null`` lets those writes succeed harmlessly: the
    file on disk stays as the last successful flush left it (SWMR-readable; recovery copies it
    into a clean file once there is room).
    """
    try:
        fd = f.id.get_vfd_handle()
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, fd)
        finally:
            os.close(null)
    except Exception:
        log.exception("%s: could not detach the file after a write error", path)
    if before_close is not None:  # handles to the file's objects go only now: closing them writes too
        before_close()
    try:
        f.close()
    except Exception:
        pass


def _fsync_path(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _stats_dict(stats: WriterStats) -> dict[str, Any]:
    return {"samples": stats.samples, "gaps": stats.gaps, "flushes": stats.flushes,
            "max_flush_interval_s": stats.max_flush_interval_s, "write_cpu_s": stats.write_cpu_s}


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.integer, np.floating)):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    if hasattr(obj, "as_dict"):
        return obj.as_dict()
    return repr(obj)


def concat_channels(blocks: Iterable[dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """Concatenate channel dicts of consecutive blocks."""
    blocks = list(blocks)
    return {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]} if blocks else {}
