"""The analysis of a set of accepted trials of one kind, as text for the operator (Qt-free).

The kind says what its set analysis is (:meth:`TrialKind.analyse_set`); the GUI runs
:func:`analyse_set` on a worker thread after each accepted trial, the same code the CLI's
``analyze`` commands call underneath, and keeps the result in the store with its inputs.
"""

from __future__ import annotations

from typing import Any

from .. import kinds
from ..errors import StoreReadOnlyError
from ..kinds.base import TrialProtocol, live_check_agreement
from ..store import SessionStore, remembered
from .loading import load_trials


def analyse_set(protocol: TrialProtocol, store_root: Any, trial_id: int, subject: dict[str, float]) -> str:
    """The analysis of the set the accepted trial belongs to (its session's accepted trials of this kind), as text."""
    kind = kinds.get(protocol.name)
    try:
        store = SessionStore(store_root, recover=False)
    except StoreReadOnlyError:  # a read-only medium: analyse, keep nothing
        store = SessionStore(store_root, read_only=True, recover=False)
    try:
        rec = store.trial(trial_id)
        same = [t for t in store.trials(protocol=protocol.name) if t.session_id == rec.session_id
                and t.status == "accepted"]
        # kept in the store with its inputs; the same accepted set analysed again is read back
        def run() -> str:
            return kind.analyse_set(protocol, load_trials(same, store), subject)

        if store.read_only:
            return run()
        payload, _ = remembered(store, f"set_{protocol.name}", same, {"condition": protocol.condition(),
                                                                        "subject": subject},
                                lambda: {"text": run()})
        return str(payload["text"])
    finally:
        store.close()


__all__ = ["analyse_set", "live_check_agreement"]
