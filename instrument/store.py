"""The session store: SQLite (WAL) indexing subjects, sessions, trials and their files.

A store is a folder: ``store.sqlite`` plus ``trials/SESSION/TRIAL.h5``. Subjects are pseudonymous
codes (no name or birth date anywhere). The schema is versioned by ``PRAGMA user_version`` and
migrated forward on open; a store from a newer version is refused with :class:`StoreVersionError`.
Opening a store also recovers trials whose writer died (status ``recording``, writer gone): the
flushed data is kept and the trial is marked ``interrupted``.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import re
import socket
import sqlite3
import threading
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from . import __version__
from .errors import NotFoundError, StoreError, StoreReadOnlyError, StoreVersionError, SubjectCodeError
from .recording import RecoveryReport, recover_trial_file

#: trial states; ``recording`` only while a writer is alive
TRIAL_STATUSES = ("recording", "recorded", "accepted", "rejected", "interrupted", "failed")

#: migration n brings the schema from version n to n + 1
MIGRATIONS: list[str] = [
    # v1: subjects, sessions, trials with one data file each
    """
    CREATE TABLE subjects (
        id INTEGER PRIMARY KEY,
        code TEXT NOT NULL UNIQUE,
        sex TEXT CHECK (sex IN ('female', 'male', 'other', 'unknown')),
        height_m REAL, mass_kg REAL, leg_length_m REAL,
        thigh_length_m REAL, shank_length_m REAL, hip_width_m REAL, foot_length_m REAL,
        thigh_circumference_m REAL, shank_circumference_m REAL,
        created_at REAL NOT NULL
    );
    CREATE TABLE sessions (
        id INTEGER PRIMARY KEY,
        subject_id INTEGER NOT NULL REFERENCES subjects(id),
        started_at REAL NOT NULL,
        operator TEXT, notes TEXT
    );
    CREATE TABLE trials (
        id INTEGER PRIMARY KEY,
        session_id INTEGER NOT NULL REFERENCES sessions(id),
        protocol TEXT NOT NULL,
        condition_json TEXT NOT NULL DEFAULT '{}',
        operator TEXT,
        trial_number INTEGER,
        status TEXT NOT NULL,
        reason TEXT,
        repeated_by INTEGER REFERENCES trials(id),
        file TEXT NOT NULL,
        started_at REAL NOT NULL, ended_at REAL,
        software_version TEXT,
        writer_host TEXT, writer_pid INTEGER
    );
    CREATE INDEX trials_session ON trials(session_id);
    """,
    # v2: files become their own table (a trial may have several: data, exports, plots) and
    # per-device sample counts are indexed so listing a store never opens a data file
    """
    CREATE TABLE trial_files (
        trial_id INTEGER NOT NULL REFERENCES trials(id),
        role TEXT NOT NULL,
        path TEXT NOT NULL,
        PRIMARY KEY (trial_id, role)
    );
    INSERT INTO trial_files (trial_id, role, path) SELECT id, 'data', file FROM trials;
    CREATE TABLE trial_devices (
        trial_id INTEGER NOT NULL REFERENCES trials(id),
        device TEXT NOT NULL,
        samples INTEGER NOT NULL DEFAULT 0,
        lost_samples INTEGER NOT NULL DEFAULT 0,
        gaps INTEGER NOT NULL DEFAULT 0,
        PRIMARY KEY (trial_id, device)
    );
    ALTER TABLE trials DROP COLUMN file;
    """,
    # v3: operators are stored once, by name, and referenced everywhere else (trial files,
    # exports, the trial index) by a code
    """
    CREATE TABLE operators (
        code TEXT PRIMARY KEY,
        name TEXT NOT NULL UNIQUE,
        created_at REAL NOT NULL
    );
    """,
    # v4: analysis results, keyed by a hash of everything that decides them (trials' data,
    # settings, method version), with the inputs (trial ids, file SHA-256) they were made from
    """
    CREATE TABLE analysis_results (
        key TEXT PRIMARY KEY,
        kind TEXT NOT NULL,
        subject_code TEXT,
        label TEXT,
        inputs_json TEXT NOT NULL,
        settings_json TEXT NOT NULL,
        versions_json TEXT NOT NULL,
        result_json TEXT NOT NULL,
        created_at REAL NOT NULL
    );
    CREATE INDEX analysis_results_kind ON analysis_results(kind, subject_code);
    """,
]
SCHEMA_VERSION = len(MIGRATIONS)
#: what a subject code must look like unless ``INSTRUMENT_SUBJECT_CODE_PATTERN`` says otherwise:
#: 1–6 capital letters, an optional hyphen, 1–6 digits (``S01``, ``AFO-12``). A name, an e-mail
#: address or a national identity number does not match, so it can never enter the store.
DEFAULT_SUBJECT_CODE_PATTERN = r"[A-Z]{1,6}-?[0-9]{1,6}"
#: bytes of ballast each writable store keeps, released when the disk fills mid-trial
RESERVE_BYTES = 1 << 20


@dataclass
class Subject:
    """A pseudonymous subject with anthropometrics (SI units; lengths as the dissertation measures them).

    :ivar thigh_length_m: greater trochanter to lateral epicondyle.
    :ivar shank_length_m: fibula head to lateral malleolus.
    :ivar hip_width_m: ASIS to ASIS.
    :ivar foot_length_m: calcaneus to 5th metatarsal tuberosity.
    """

    code: str
    sex: str = "unknown"
    height_m: float | None = None
    mass_kg: float | None = None
    leg_length_m: float | None = None
    thigh_length_m: float | None = None
    shank_length_m: float | None = None
    hip_width_m: float | None = None
    foot_length_m: float | None = None
    thigh_circumference_m: float | None = None
    shank_circumference_m: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class TrialRecord:
    """One row of the trial index."""

    id: int
    session_id: int
    subject_code: str
    protocol: str
    condition: dict[str, Any]
    operator: str | None
    trial_number: int | None
    status: str
    reason: str | None
    repeated_by: int | None
    path: Path
    started_at: float
    ended_at: float | None
    software_version: str | None
    devices: dict[str, dict[str, int]]

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["path"] = str(self.path)
        return d


def default_store_dir() -> Path:
    """The per-user store (``$XDG_DATA_HOME/afo-gait-instrument/store``)."""
    base = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(base) / "afo-gait-instrument" / "store"


class SessionStore:
    """Open (creating if absent) the store in folder ``root``.

    :param read_only: open the database read-only (no recovery, no writes).
    :param recover: recover interrupted trials on open (default True).
    :raises StoreVersionError: the store's schema is newer than this software.
    :raises StoreReadOnlyError: a new store cannot be created, or a write was refused.
    """

    def __init__(self, root: str | Path, *, read_only: bool = False, recover: bool = True,
                 migrations: list[str] | None = None) -> None:
        self.root = Path(root)
        self.read_only = read_only
        self._migrations = MIGRATIONS if migrations is None else migrations
        self.recovered: list[RecoveryReport] = []
        self._write_lock = threading.RLock()
        self._locks: dict[int, TrialLock] = {}
        db = self.root / "store.sqlite"
        try:
            if read_only:
                if not db.exists():
                    raise StoreError(f"{self.root}: no store here (store.sqlite missing)")
                self._db = _connect_read_only(db)
            else:
                try:
                    (self.root / "trials").mkdir(parents=True, exist_ok=True)
                    if not os.access(self.root, os.W_OK):  # a read-only medium (EROFS), even for root
                        raise StoreReadOnlyError(f"{self.root}: the store's folder cannot be written")
                    self._db = sqlite3.connect(db, check_same_thread=False, timeout=10.0)
                    self._db.execute("PRAGMA journal_mode=WAL")
                except (OSError, sqlite3.OperationalError) as err:
                    raise StoreReadOnlyError(f"{self.root}: cannot create or write the store: {err}") from err
            self._db.row_factory = sqlite3.Row
            self._db.execute("PRAGMA foreign_keys=ON")
            self._migrate()
        except sqlite3.DatabaseError as err:  # "file is not a database", "database disk image is malformed"
            raise StoreError(f"{db}: not a readable store database ({err}); the trial files beside it are "
                             "untouched") from err
        if not read_only:
            self._ensure_reserve()
        if recover and not read_only:
            self.recovered = self.recover_interrupted()

    # ------------------------------------------------------------------ schema
    @property
    def schema_version(self) -> int:
        return int(self._db.execute("PRAGMA user_version").fetchone()[0])

    def _migrate(self) -> None:
        current = self.schema_version
        target = len(self._migrations)
        if current > target:
            raise StoreVersionError(
                f"{self.root}: store schema version {current} was written by a newer version of the instrument; "
                f"this version ({__version__}) understands up to {target}. Upgrade the software to open it.")
        if current == target:
            return
        if self.read_only:
            raise StoreReadOnlyError(f"{self.root}: store schema {current} needs migrating to {target}, "
                                     "but it was opened read-only")
        # several processes may open a new store at once: the migration is one IMMEDIATE
        # transaction (one writer at a time) that re-reads the version inside it
        db = self._db
        with self._write_lock:
            try:
                db.execute("BEGIN IMMEDIATE")
                try:
                    current = int(db.execute("PRAGMA user_version").fetchone()[0])
                    for version in range(current, target):
                        for statement in _statements(self._migrations[version]):
                            db.execute(statement)
                        db.execute(f"PRAGMA user_version = {version + 1}")
                    db.execute("COMMIT")
                except BaseException:
                    db.execute("ROLLBACK")
                    raise
            except sqlite3.DatabaseError as err:
                raise StoreError(f"{self.root}: cannot migrate the store schema from {current} to {target}: "
                                 f"{err}") from err

    @contextmanager
    def _write(self) -> Iterator[sqlite3.Connection]:
        if self.read_only:
            raise StoreReadOnlyError(f"{self.root}: store opened read-only")
        try:
            # one connection serves the acquisition threads of every room: a transaction (and the
            # ``lastrowid`` it hands back) must not interleave with another thread's
            with self._write_lock, self._db:
                yield self._db
        except sqlite3.OperationalError as err:
            if "readonly" in str(err) or "read-only" in str(err):
                raise StoreReadOnlyError(f"{self.root}: store is read-only: {err}") from err
            if "disk" in str(err) and "full" in str(err):
                raise StoreError(f"{self.root}: disk full while writing the store index: {err}") from err
            raise StoreError(f"{self.root}: {err}") from err

    # ------------------------------------------------------------------ disk-full reserve
    @property
    def reserve_path(self) -> Path:
        """A ballast file whose space is given back when the disk fills mid-trial."""
        return self.root / ".reserve"

    def _ensure_reserve(self) -> None:
        if self.reserve_path.exists():
            return
        try:
            with open(self.reserve_path, "wb") as fh:
                os.posix_fallocate(fh.fileno(), 0, RESERVE_BYTES)
        except OSError:  # too little room to keep a reserve: nothing to give back later
            self.reserve_path.unlink(missing_ok=True)

    def release_reserve(self) -> bool:
        """Delete the reserve so the trial's status and the index can still be written on a full
        disk; True if there was one. It is made again the next time the store opens."""
        try:
            self.reserve_path.unlink()
            return True
        except FileNotFoundError:
            return False

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> "SessionStore":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ analysis results
    def put_result(self, key: str, kind: str, result: dict[str, Any], *, subject_code: str | None = None,
                   label: str | None = None, inputs: dict[str, Any] | None = None,
                   settings: dict[str, Any] | None = None, replace: bool = False) -> bool:
        """Keep an analysis result under ``key`` (a hash of what decides it); False if the key was
        already stored (a result is written once: a repeated or retried computation adds nothing),
        unless ``replace`` (an operator's explicit recomputation).

        The software versions (this instrument, numpy, scipy, casadi) are recorded with it.
        """
        versions = software_versions()
        with self._write() as db:
            cur = db.execute(
                f"INSERT OR {'REPLACE' if replace else 'IGNORE'} INTO analysis_results (key, kind, subject_code, label, inputs_json, settings_json, "
                "versions_json, result_json, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (key, kind, subject_code, label, json.dumps(inputs or {}, default=str),
                 json.dumps(settings or {}, default=str), json.dumps(versions), json.dumps(result, default=float),
                 time.time()))
            return cur.rowcount == 1

    def result(self, key: str) -> dict[str, Any] | None:
        """The stored result under ``key``, or None."""
        row = self._db.execute("SELECT result_json FROM analysis_results WHERE key = ?", (key,)).fetchone()
        return None if row is None else json.loads(row[0])

    def results(self, kind: str | None = None, subject_code: str | None = None) -> list[dict[str, Any]]:
        """Stored results (with their key, kind, subject, label, inputs, settings and versions), oldest first."""
        sql, args = "SELECT * FROM analysis_results WHERE 1=1", list[str]()
        if kind is not None:
            sql, args = sql + " AND kind = ?", args + [kind]
        if subject_code is not None:
            sql, args = sql + " AND subject_code = ?", args + [subject_code]
        rows = self._db.execute(sql + " ORDER BY created_at, key", args).fetchall()
        return [{"key": r["key"], "kind": r["kind"], "subject_code": r["subject_code"], "label": r["label"],
                 "inputs": json.loads(r["inputs_json"]), "settings": json.loads(r["settings_json"]),
                 "versions": json.loads(r["versions_json"]), "result": json.loads(r["result_json"]),
                 "created_at": r["created_at"]} for r in rows]

    def stale_results(self) -> list[str]:
        """Keys of stored results whose input files changed (SHA-256 differs) or disappeared since."""
        stale = []
        for r in self.results():
            for path, digest in r["inputs"].get("files", {}).items():
                try:
                    if file_sha256(Path(path)) != digest:
                        stale.append(r["key"])
                        break
                except OSError:
                    stale.append(r["key"])
                    break
        return stale

    # ------------------------------------------------------------------ subjects and sessions
    def add_subject(self, subject: Subject) -> int:
        """Insert or update a subject by code; returns its id.

        :raises SubjectCodeError: the code is not a pseudonym (see :func:`check_subject_code`).
        """
        check_subject_code(subject.code)
        d = subject.as_dict()
        cols = [f.name for f in fields(Subject)]
        with self._write() as db:
            db.execute(
                f"INSERT INTO subjects ({', '.join(cols)}, created_at) VALUES ({', '.join('?' * len(cols))}, ?) "
                f"ON CONFLICT(code) DO UPDATE SET {', '.join(f'{c}=excluded.{c}' for c in cols[1:])}",
                [d[c] for c in cols] + [time.time()])
        return int(self._db.execute("SELECT id FROM subjects WHERE code=?", (subject.code,)).fetchone()[0])

    def subject(self, code: str) -> Subject:
        row = self._db.execute("SELECT * FROM subjects WHERE code=?", (code,)).fetchone()
        if row is None:
            raise NotFoundError(f"no subject {code!r} in {self.root}")
        return Subject(**{f.name: row[f.name] for f in fields(Subject)})

    def subjects(self) -> list[Subject]:
        rows = self._db.execute("SELECT * FROM subjects ORDER BY code").fetchall()
        return [Subject(**{f.name: r[f.name] for f in fields(Subject)}) for r in rows]

    def operator_code(self, name: str | None) -> str | None:
        """The code that stands for operator ``name`` outside the store (made on first use: OP01, OP02 …).
        A name that already is one of the store's codes is returned as it is."""
        if not name:
            return None
        row = self._db.execute("SELECT code FROM operators WHERE name=? OR code=?", (name, name)).fetchone()
        if row is not None:
            return str(row[0])
        with self._write() as db:
            n = int(db.execute("SELECT COUNT(*) FROM operators").fetchone()[0])
            code = f"OP{n + 1:02d}"
            db.execute("INSERT INTO operators (code, name, created_at) VALUES (?, ?, ?)", (code, name, time.time()))
        return code

    def operators(self) -> dict[str, str]:
        """Operator code → name (the only place names are kept)."""
        return {r["code"]: r["name"] for r in self._db.execute("SELECT code, name FROM operators ORDER BY code")}

    def new_session(self, subject_code: str, operator: str | None = None, notes: str | None = None) -> int:
        """Start a session for an existing subject; returns the session id (the operator kept by code)."""
        row = self._db.execute("SELECT id FROM subjects WHERE code=?", (subject_code,)).fetchone()
        if row is None:
            raise NotFoundError(f"no subject {subject_code!r} in {self.root}; add it first")
        operator = self.operator_code(operator)
        with self._write() as db:
            cur = db.execute("INSERT INTO sessions (subject_id, started_at, operator, notes) VALUES (?, ?, ?, ?)",
                             (row[0], time.time(), operator, notes))
        return int(cur.lastrowid)  # type: ignore[arg-type]

    def sessions(self) -> list[dict[str, Any]]:
        rows = self._db.execute(
            "SELECT s.id, s.started_at, s.operator, s.notes, sub.code AS subject FROM sessions s "
            "JOIN subjects sub ON sub.id = s.subject_id ORDER BY s.id").fetchall()
        return [dict(r) for r in rows]

    # ------------------------------------------------------------------ trials
    def begin_trial(self, session_id: int, protocol: str, condition: dict[str, Any], *,
                    operator: str | None = None, trial_number: int | None = None) -> tuple[int, Path]:
        """Register a trial being recorded; returns (trial id, path of its data file to create)."""
        rel = Path("trials") / f"session-{session_id:04d}" / f"{protocol}-{uuid.uuid4().hex[:12]}.h5"
        path = self.root / rel
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise StoreReadOnlyError(f"{self.root}: cannot create {path.parent}: {err}") from err
        operator = self.operator_code(operator)
        lock = TrialLock(path)  # held until finish_trial (or this process ends): recovery leaves the file alone
        with self._write() as db:
            cur = db.execute(
                "INSERT INTO trials (session_id, protocol, condition_json, operator, trial_number, status, "
                "started_at, software_version, writer_host, writer_pid) VALUES (?, ?, ?, ?, ?, 'recording', ?, ?, ?, ?)",
                (session_id, protocol, json.dumps(condition), operator, trial_number, time.time(), __version__,
                 socket.gethostname(), os.getpid()))
            trial_id = int(cur.lastrowid)  # type: ignore[arg-type]
            db.execute("INSERT INTO trial_files (trial_id, role, path) VALUES (?, 'data', ?)", (trial_id, str(rel)))
        self._locks[trial_id] = lock
        return trial_id, path

    def finish_trial(self, trial_id: int, status: str, devices: dict[str, dict[str, int]],
                     reason: str | None = None) -> None:
        """Close a trial: final status, end time and per-device counts (samples, lost_samples, gaps)."""
        if status not in TRIAL_STATUSES:
            raise ValueError(f"unknown trial status {status!r}; one of {TRIAL_STATUSES}")
        lock = self._locks.pop(trial_id, None)
        try:
            self._finish_trial(trial_id, status, devices, reason)
        finally:
            if lock is not None:
                lock.release()

    def _finish_trial(self, trial_id: int, status: str, devices: dict[str, dict[str, int]],
                      reason: str | None) -> None:
        with self._write() as db:
            db.execute("UPDATE trials SET status=?, reason=?, ended_at=? WHERE id=?",
                       (status, reason, time.time(), trial_id))
            for name, counts in devices.items():
                db.execute("INSERT OR REPLACE INTO trial_devices (trial_id, device, samples, lost_samples, gaps) "
                           "VALUES (?, ?, ?, ?, ?)", (trial_id, name, int(counts.get("samples", 0)),
                                                      int(counts.get("lost_samples", 0)), int(counts.get("gaps", 0))))

    def set_status(self, trial_id: int, status: str, reason: str | None = None,
                   repeated_by: int | None = None) -> None:
        """Accept or reject a trial (a rejection keeps the data and needs a reason), or link its repeat."""
        if status not in TRIAL_STATUSES or status == "recording":
            raise ValueError(f"cannot set status {status!r}")
        if status == "rejected" and not reason:
            raise ValueError("a rejected trial needs a reason (e.g. 'muscle activation detected')")
        self.trial(trial_id)
        with self._write() as db:
            db.execute("UPDATE trials SET status=?, reason=COALESCE(?, reason), "
                       "repeated_by=COALESCE(?, repeated_by) WHERE id=?", (status, reason, repeated_by, trial_id))

    def add_file(self, trial_id: int, role: str, path: Path) -> None:
        """Index an extra file of a trial (export, plot) by role."""
        rel = os.path.relpath(path, self.root)
        with self._write() as db:
            db.execute("INSERT OR REPLACE INTO trial_files (trial_id, role, path) VALUES (?, ?, ?)", (trial_id, role, rel))

    def trials(self, session_id: int | None = None, protocol: str | None = None) -> list[TrialRecord]:
        sql = ("SELECT t.*, sub.code AS subject_code, f.path AS data_path FROM trials t "
               "JOIN sessions s ON s.id = t.session_id JOIN subjects sub ON sub.id = s.subject_id "
               "LEFT JOIN trial_files f ON f.trial_id = t.id AND f.role = 'data' WHERE 1=1")
        args: list[Any] = []
        if session_id is not None:
            sql += " AND t.session_id=?"
            args.append(session_id)
        if protocol is not None:
            sql += " AND t.protocol=?"
            args.append(protocol)
        rows = self._db.execute(sql + " ORDER BY t.id", args).fetchall()
        counts: dict[int, dict[str, dict[str, int]]] = {}
        for r in self._db.execute("SELECT * FROM trial_devices").fetchall():
            counts.setdefault(r["trial_id"], {})[r["device"]] = {
                "samples": r["samples"], "lost_samples": r["lost_samples"], "gaps": r["gaps"]}
        return [TrialRecord(r["id"], r["session_id"], r["subject_code"], r["protocol"], json.loads(r["condition_json"]),
                            r["operator"], r["trial_number"], r["status"], r["reason"], r["repeated_by"],
                            self.root / r["data_path"], r["started_at"], r["ended_at"], r["software_version"],
                            counts.get(r["id"], {})) for r in rows]

    def trial(self, trial_id: int) -> TrialRecord:
        for t in self.trials():
            if t.id == trial_id:
                return t
        raise NotFoundError(f"no trial {trial_id} in {self.root}")

    # ------------------------------------------------------------------ recovery
    def recover_interrupted(self) -> list[RecoveryReport]:
        """Recover trials left ``recording`` by a writer that no longer runs; mark them ``interrupted``."""
        reports = []
        host = socket.gethostname()
        for t in self.trials():
            if t.status == "failed" and t.path.exists() and _needs_repair(t.path):
                report = recover_trial_file(t.path)
                reports.append(report)
                if report.readable:
                    self.finish_trial(t.id, "failed", {n: {"samples": s} for n, s in report.samples.items()},
                                      reason=f"{t.reason}; data recovered up to the last complete write")
                continue
            if t.status != "recording":
                continue
            alive = TrialLock.held(t.path)
            if alive is None:  # a trial from before writer locks: the host and process id tell
                row = self._db.execute("SELECT writer_host, writer_pid FROM trials WHERE id=?", (t.id,)).fetchone()
                alive = row["writer_host"] != host or _pid_alive(row["writer_pid"])
            if alive:
                continue  # still being written (here, in another container, or on another host)
            report = recover_trial_file(t.path)
            reports.append(report)
            counts = {n: {"samples": s} for n, s in report.samples.items()}
            reason = ("writer stopped before completing the file; data recovered up to its last flush"
                      if report.readable else f"writer stopped; data file unreadable: {report.defect}")
            self.finish_trial(t.id, "interrupted", counts, reason=reason)
            TrialLock.remove_stale(t.path)
        return reports


class TrialLock:
    """An exclusive ``flock`` on ``TRIAL.h5.lock`` for as long as a trial is being written.

    Any process that opens the store respects it, whatever its host or PID namespace: the kernel
    (or NFS's lock manager) releases it when the writer ends, however it ends, so a free lock on
    a trial still marked ``recording`` means its writer is gone.
    """

    def __init__(self, data_path: Path) -> None:
        self.path = TrialLock.path_for(data_path)
        self._fd: int | None = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(self._fd)
            self._fd = None
            raise StoreError(f"{self.path}: trial file is locked by another writer: {err}") from err
        os.write(self._fd, f"{socket.gethostname()} {os.getpid()}\n".encode())

    @staticmethod
    def path_for(data_path: Path) -> Path:
        return data_path.with_name(data_path.name + ".lock")

    def release(self) -> None:
        """Unlock and remove the lock file (the trial is complete)."""
        if self._fd is None:
            return
        self.path.unlink(missing_ok=True)
        fcntl.flock(self._fd, fcntl.LOCK_UN)
        os.close(self._fd)
        self._fd = None

    @staticmethod
    def held(data_path: Path) -> bool | None:
        """True while a writer holds the trial's lock, False when the lock is free, None when the
        trial has no lock file (written before writer locks existed)."""
        lock = TrialLock.path_for(data_path)
        try:
            fd = os.open(lock, os.O_RDONLY)
        except FileNotFoundError:
            return None
        except OSError:
            return True  # cannot tell: never take a file from a writer that may be alive
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        except OSError:
            return True
        else:
            fcntl.flock(fd, fcntl.LOCK_UN)
            return False
        finally:
            os.close(fd)

    @staticmethod
    def remove_stale(data_path: Path) -> None:
        TrialLock.path_for(data_path).unlink(missing_ok=True)


def subject_code_pattern() -> str:
    """The pseudonym pattern in force (``INSTRUMENT_SUBJECT_CODE_PATTERN`` or the default)."""
    return os.environ.get("INSTRUMENT_SUBJECT_CODE_PATTERN") or DEFAULT_SUBJECT_CODE_PATTERN


def check_subject_code(code: str) -> None:
    """Refuse a subject code that is not a pseudonym.

    :raises SubjectCodeError: names the pattern and how to change it.
    """
    pattern = subject_code_pattern()
    if not isinstance(code, str) or re.fullmatch(pattern, code) is None:
        raise SubjectCodeError(
            f"subject code {code!r} is not a pseudonym: codes match {pattern} (e.g. S01); names, e-mail addresses "
            "and identity numbers are never stored (set INSTRUMENT_SUBJECT_CODE_PATTERN to change the pattern)")


def _connect_read_only(db: Path) -> sqlite3.Connection:
    """Read-only connection; on read-only media (where SQLite cannot make the WAL's shared-memory
    file) the database is opened as immutable."""
    conn = sqlite3.connect(f"file:{db}?mode=ro", uri=True, check_same_thread=False)
    try:
        conn.execute("PRAGMA user_version").fetchone()
        return conn
    except sqlite3.OperationalError:
        conn.close()
        return sqlite3.connect(f"file:{db}?immutable=1", uri=True, check_same_thread=False)


def open_store(root: str | Path) -> "SessionStore":
    """Open a store to read it: writable (so interrupted trials are recovered) where possible,
    read-only where the folder or medium cannot be written."""
    try:
        return SessionStore(root)
    except StoreReadOnlyError:
        return SessionStore(root, read_only=True)


def _statements(script: str) -> list[str]:
    """The SQL statements of a migration script, one by one (``executescript`` would commit)."""
    out, buf = [], ""
    for line in script.splitlines(keepends=True):
        buf += line
        if sqlite3.complete_statement(buf):
            if buf.strip().strip(";").strip():
                out.append(buf.strip())
            buf = ""
    if buf.strip():
        out.append(buf.strip())
    return out


def _needs_repair(path: Path) -> bool:
    from .errors import CorruptFileError
    from .recording import read_trial

    try:
        return read_trial(path).status == "recording"
    except CorruptFileError:
        return True


def _pid_alive(pid: int | None) -> bool:
    if not pid:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    # a zombie (killed child not yet reaped) is not a writer
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return True


def file_sha256(path: Path) -> str:
    """SHA-256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def software_versions() -> dict[str, str]:
    """Versions of this instrument and of the numerical libraries its analyses use."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"instrument": __version__}
    for dist in ("numpy", "scipy", "casadi"):
        try:
            out[dist] = version(dist)
        except PackageNotFoundError:
            out[dist] = "absent"
    return out
