"""The session store: SQLite (WAL) indexing subjects, sessions, trials and their files.

A store is a folder: ``store.sqlite`` plus ``trials/SESSION/TRIAL.h5``. Subjects are pseudonymous
codes (no name or birth date anywhere). The schema is versioned by ``PRAGMA user_version`` and
migrated forward on open; a store from a newer version is refused with :class:`StoreVersionError`.
Opening a store also recovers trials whose writer died (status ``recording``, writer gone): the
flushed data is kept and the trial is marked ``interrupted``.
"""

from __future__ import annotations

import json
import os
import socket
import sqlite3
import threading
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import fields
from pathlib import Path
from typing import Any

from .. import __version__
from ..errors import NotFoundError, StoreError, StoreReadOnlyError, StoreVersionError
from ..live.recording import RecoveryReport
from .lock import TrialLock
from .records import Subject, TrialRecord, check_subject_code
from .recovery import recover_interrupted
from .reserve import DiskReserve
from .results import ResultsIndex
from .schema import MIGRATIONS, TRIAL_STATUSES, statements


def default_store_dir() -> Path:
    """The per-user store (``$XDG_DATA_HOME/afo-gait-instrument/store``)."""
    base = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(base) / "afo-gait-instrument" / "store"


#: how long (s) opening a store waits for another process that holds its database (creating or converting it)
OPEN_TIMEOUT_S = 10.0


def _write_ahead_log(db: sqlite3.Connection) -> None:
    """Put ``db`` in write-ahead-log mode, waiting up to :data:`OPEN_TIMEOUT_S` while another process converts or
    creates the same new database: the conversion can answer "database is locked" at once, without the connection's
    busy wait (of three processes creating one store at once, one failed so in a fresh-clone CI run at d4352e6:
    tests/instrument/test_store_integrity.py)."""
    deadline = time.monotonic() + OPEN_TIMEOUT_S
    while True:
        try:
            db.execute("PRAGMA journal_mode=WAL")
            return
        except sqlite3.OperationalError as err:
            if "locked" not in str(err) or time.monotonic() >= deadline:
                raise
            time.sleep(0.05)


class SessionStore(ResultsIndex):
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
                    self._db = sqlite3.connect(db, check_same_thread=False, timeout=OPEN_TIMEOUT_S)
                    _write_ahead_log(self._db)
                except (OSError, sqlite3.OperationalError) as err:
                    raise StoreReadOnlyError(f"{self.root}: cannot create or write the store: {err}") from err
            self._db.row_factory = sqlite3.Row
            self._db.execute("PRAGMA foreign_keys=ON")
            self._migrate()
        except sqlite3.DatabaseError as err:  # "file is not a database", "database disk image is malformed"
            raise StoreError(f"{db}: not a readable store database ({err}); the trial files beside it are "
                             "untouched") from err
        self._reserve = DiskReserve(self.root / ".reserve")
        if not read_only:
            self._reserve.ensure()
        if recover and not read_only:
            self.recovered = self.recover_interrupted()

    # ------------------------------------------------------------------ schema
    @property
    def schema_version(self) -> int:
        return int(self._db.execute("PRAGMA user_version").fetchone()[0])

    def recover_interrupted(self) -> list[RecoveryReport]:
        """Recover trials left ``recording`` by a writer that no longer runs; mark them ``interrupted``."""
        return recover_interrupted(self)

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
                        for statement in statements(self._migrations[version]):
                            db.execute(statement)
                        db.execute(f"PRAGMA user_version = {version + 1}")
                    db.execute("COMMIT")
                except BaseException:
                    db.execute("ROLLBACK")
                    raise
            except sqlite3.DatabaseError as err:
                raise StoreError(f"{self.root}: cannot migrate the store schema from {current} to {target}: "
                                 f"{err}") from err

    @contextmanager  # type: ignore[override]  # the generator form of ResultsIndex._write
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
        return self._reserve.path

    def release_reserve(self) -> bool:
        """Delete the reserve so the trial's status and the index can still be written on a full
        disk; True if there was one. It is made again the next time the store opens."""
        return self._reserve.release()

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> SessionStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

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
        assert cur.lastrowid is not None  # an INSERT sets it
        return int(cur.lastrowid)

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
            assert cur.lastrowid is not None  # an INSERT sets it
            trial_id = int(cur.lastrowid)
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

    def index_row(self, sql: str, args: tuple[Any, ...] = ()) -> Any:
        """A read of the index (for the store's own helpers: recovery)."""
        return self._db.execute(sql, args)


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


def open_store(root: str | Path) -> SessionStore:
    """Open a store to read it: writable (so interrupted trials are recovered) where possible,
    read-only where the folder or medium cannot be written."""
    try:
        return SessionStore(root)
    except StoreReadOnlyError:
        return SessionStore(root, read_only=True)


__all__ = ["SessionStore", "default_store_dir", "open_store"]
