"""Recovery: a trial whose writer died is closed with the data it flushed; nothing is thrown away."""

from __future__ import annotations

import socket
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import CorruptFileError
from ..live.recording import RecoveryReport, read_trial, recover_trial_file
from .lock import TrialLock, pid_alive

if TYPE_CHECKING:
    from .index import SessionStore


def recover_interrupted(store: SessionStore) -> list[RecoveryReport]:
    """Recover the trials of ``store`` left ``recording`` by a writer that no longer runs (marked
    ``interrupted``), and failed trials whose file was left incomplete; the data up to the last
    flush is kept."""
    reports = []
    host = socket.gethostname()
    for t in store.trials():
        if t.status == "failed" and t.path.exists() and needs_repair(t.path):
            report = recover_trial_file(t.path)
            reports.append(report)
            if report.readable:
                store.finish_trial(t.id, "failed", {n: {"samples": s} for n, s in report.samples.items()},
                                   reason=f"{t.reason}; data recovered up to the last complete write")
            continue
        if t.status != "recording":
            continue
        alive = TrialLock.held(t.path)
        if alive is None:  # a trial from before writer locks: the host and process id tell
            row = store.index_row("SELECT writer_host, writer_pid FROM trials WHERE id=?", (t.id,)).fetchone()
            alive = row["writer_host"] != host or pid_alive(row["writer_pid"])
        if alive:
            continue  # still being written (here, in another container, or on another host)
        report = recover_trial_file(t.path)
        reports.append(report)
        counts = {n: {"samples": s} for n, s in report.samples.items()}
        reason = ("writer stopped before completing the file; data recovered up to its last flush"
                  if report.readable else f"writer stopped; data file unreadable: {report.defect}")
        store.finish_trial(t.id, "interrupted", counts, reason=reason)
        TrialLock.remove_stale(t.path)
    return reports


def needs_repair(path: Path) -> bool:
    """Whether a trial file was left incomplete (still marked recording, or unreadable)."""
    try:
        return read_trial(path).status == "recording"
    except CorruptFileError:
        return True


__all__ = ["needs_repair", "recover_interrupted"]
