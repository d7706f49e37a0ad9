"""Analysis results remembered in the session store: a re-run with the same inputs is read back.

A result is keyed by a SHA-256 of its kind, the SHA-256 of every input trial file, the settings
and the instrument's version: the same trials and settings give the same key (read back, not
recomputed); a changed trial file gives a new key (recomputed), and the old result is listed by
:meth:`instrument.store.SessionStore.stale_results`.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from . import __version__
from .store import SessionStore, TrialRecord, file_sha256


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
               compute: Callable[[], dict[str, Any]], *, recompute: bool = False) -> tuple[dict[str, Any], bool]:
    """The analysis's JSON-able result: read back from the store when it holds one for these
    inputs and settings (True), otherwise computed by ``compute()`` and kept (False)."""
    inputs = trial_inputs(records)
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


__all__ = ["analysis_key", "remembered", "trial_inputs"]
