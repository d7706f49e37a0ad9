"""Analysis results remembered in the session store: a re-run with the same inputs is read back.

A result is keyed by a SHA-256 of its kind, the SHA-256 of every input trial file, the settings
and the instrument's version: the same trials and settings give the same key (read back, not
recomputed); a changed trial file gives a new key (recomputed), and the old result is listed by
:meth:`ResultsIndex.stale_results`.
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .. import __version__
from .hashing import file_sha256, software_versions
from .records import TrialRecord

if TYPE_CHECKING:
    from .index import SessionStore


class ResultsIndex:
    """The store's analysis results: kept once per key with their inputs, settings and software versions."""

    _db: sqlite3.Connection

    def _write(self) -> AbstractContextManager[sqlite3.Connection]:
        raise NotImplementedError

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
                f"INSERT OR {'REPLACE' if replace else 'IGNORE'} INTO analysis_results (key, kind, subject_code, label, "
                "inputs_json, settings_json, "
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


def trial_inputs(records: Sequence[TrialRecord]) -> dict[str, Any]:
    """The inputs of an analysis of store trials: their ids and the SHA-256 of their files."""
    return {"trial_ids": [r.id for r in records], "files": {str(r.path): file_sha256(Path(r.path)) for r in records}}


def analysis_key(kind: str, inputs: dict[str, Any], settings: dict[str, Any]) -> str:
    """SHA-256 of what decides an analysis's result (not where its files are)."""
    h = hashlib.sha256()
    h.update(f"{kind}|{__version__}|".encode())
    h.update("|".join(sorted(inputs.get("files", {}).values())).encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    return h.hexdigest()


def remembered(store: SessionStore, kind: str, records: Sequence[TrialRecord], settings: dict[str, Any],
               compute: Callable[[], dict[str, Any]], *, recompute: bool = False,
               inputs: dict[str, Any] | None = None) -> tuple[dict[str, Any], bool]:
    """The analysis's JSON-able result: read back from the store when it holds one for these
    inputs and settings (True), otherwise computed by ``compute()`` and kept (False). ``inputs``:
    :func:`trial_inputs` of ``records`` when the caller has it already (each trial file is hashed once)."""
    inputs = inputs if inputs is not None else trial_inputs(records)
    key = analysis_key(kind, inputs, settings)
    if not recompute:
        stored = store.result(key)
        if stored is not None:
            return stored, True
    result = compute()
    subjects = sorted({r.subject_code for r in records})
    store.put_result(key, kind, result, subject_code=subjects[0] if len(subjects) == 1 else None,
                     label=f"trials {','.join(str(r.id) for r in records)}", inputs=inputs, settings=settings,
                     replace=recompute)
    return result, False


__all__ = ["ResultsIndex", "analysis_key", "remembered", "trial_inputs"]
