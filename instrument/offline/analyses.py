"""The analysis of a set of accepted trials of one kind, as the operator reads it (Qt-free).

The kind says what its set analysis is (:meth:`TrialKind.analyse_set`); the GUI runs
:func:`analyse_set` on a worker thread after each accepted trial, the same code the CLI's
``analyze`` commands call underneath, and keeps the result in the store with its inputs.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import kinds
from ..errors import StoreReadOnlyError
from ..kinds.base import SetAnalysis, TrialProtocol, live_check_agreement
from ..store import SessionStore, analysis_key, remembered, trial_inputs
from .loading import load_trials


def analyse_set(protocol: TrialProtocol, store_root: Any, trial_id: int, subject: dict[str, float], *,
                progress: Callable[[str], None] | None = None) -> SetAnalysis:
    """The analysis of the set the accepted trial belongs to (its session's accepted trials of this kind).

    Its figures are written under the store's ``figures/`` folder, one folder per analysed set (a read-only
    store: a temporary folder); the same accepted set analysed again is read back with its figures."""
    kind = kinds.get(protocol.name)
    try:
        store = SessionStore(store_root, recover=False)
    except StoreReadOnlyError:  # a read-only medium: analyse, keep nothing
        store = SessionStore(store_root, read_only=True, recover=False)
    try:
        rec = store.trial(trial_id)
        same = [t for t in store.trials(protocol=protocol.name) if t.session_id == rec.session_id
                and t.status == "accepted"]
        settings = {"condition": protocol.condition(), "subject": subject}
        name = f"set_{protocol.name}"
        inputs = trial_inputs(same)  # every trial file hashed once: names the figures' folder and keys the result
        if store.read_only:
            figures_dir = Path(tempfile.mkdtemp(prefix="instrument-figures-"))
        else:
            figures_dir = Path(store.root) / "figures" / f"{name}-{analysis_key(name, inputs, settings)[:12]}"

        def run() -> dict[str, Any]:
            return kind.analyse_set(protocol, load_trials(same, store), subject, figures_dir=figures_dir,
                                    progress=progress).as_dict()

        if store.read_only:
            return SetAnalysis.from_dict(run())
        payload, stored = remembered(store, name, same, settings, run, inputs=inputs)
        if stored and not all(Path(f).is_file() for f in payload.get("figures", ())):  # figures deleted: redraw
            payload, _ = remembered(store, name, same, settings, run, recompute=True, inputs=inputs)
        return SetAnalysis.from_dict(payload)
    finally:
        store.close()


__all__ = ["SetAnalysis", "analyse_set", "live_check_agreement"]
