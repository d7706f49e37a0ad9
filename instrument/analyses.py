"""Which analysis runs on a set of accepted trials of one kind, as text for the operator (Qt-free).

``SET_ANALYSES`` is keyed by the trial kind (the protocol's ``name``); the GUI runs
:func:`analyse_set` on a worker thread after each accepted trial, the same code the CLI's
``analyze`` commands call underneath.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .errors import StoreReadOnlyError
from .protocols import TrialProtocol
from .store import SessionStore, TrialRecord


def _aads_set(protocol: Any, store: SessionStore, same: list[TrialRecord], subject: dict[str, float]) -> str:
    if not protocol.live_markers:
        return ("force-guided AADS trial recorded; its stiffness needs the markers: export the C3D from the "
                "motion-capture system and run `instrument analyze afo FILE.c3d`.")
    from analysis.aads.model import load_jig_model

    from .afo import afo_model_diagnosis, analyze_afo, resolve_trials

    model = load_jig_model()
    every = analyze_afo(resolve_trials([str(t.id) for t in same], store, model=model), model)
    k = [r.stiffness_nm_per_deg for r in every.results if r.factors.get("spring") == protocol.spring]
    line = (f"spring {protocol.spring}: {len(k)} accepted trial(s), stiffness "
            f"{np.nanmean(k):.3f} ± {np.nanstd(k):.3f} N·m/° (fit {model.fit_window_deg[0]:g}–{model.fit_window_deg[1]:g}°)")
    # the session's AFO, all its springs: what its spring model misses, once a trial can be left out
    if len(every.results) < 3:
        return line + f"\nAFO model-level diagnosis: from 3 accepted trials of this AFO (has {len(every.results)})"
    return line + "\n" + afo_model_diagnosis(every, model.fit_window_deg)[1]


def _tables(store: SessionStore, same: list[TrialRecord]) -> list[Any]:
    from .loading import records_as_loaded

    return [t.table() for t in records_as_loaded(store, same)]


def live_check_agreement(diagnosis: Any) -> str:
    """What the operator needs when the offline diagnosis names an activation on an accepted trial,
    which the live relaxation check let through: the two checks' sizes, so they do not contradict
    each other on screen ("" when the diagnosis names no activation)."""
    from .relaxation import LIVE_DETECTION_FLOOR_NM

    named = [(diagnosis.cause, diagnosis.parameters)] + [(a["cause"], a["parameters"]) for a in diagnosis.also]
    burst = next((p for c, p in named if c == "activation_burst"), None)
    if burst is None:
        return ""
    amplitude = abs(float(burst["burst_amplitude_Nm"]))
    start, duration = float(burst["burst_start_s"]), float(burst["burst_duration_s"])
    if amplitude < LIVE_DETECTION_FLOOR_NM:
        why = (f"below the {LIVE_DETECTION_FLOOR_NM:g} N·m the live relaxation check catches, so it raised no alarm "
               "while the diagnosis, fitting the whole trial, can see it")
    else:
        why = "large enough for the live relaxation check: if it raised no alarm, the operator accepted the trial over it"
    return (f"\n  the trial was accepted, yet the diagnosis fits an activation of {amplitude:.2f} N·m at "
            f"{start:.1f}–{start + duration:.1f} s into the trial: {why}. Look at the torque there; repeat the "
            "trial if the subject was not relaxed, or the passive fit includes it")


def _diagnosis_line(tables: list[Any]) -> str:
    from analysis.diagnosis import diagnose, from_table

    if not tables:
        return ""
    d = diagnose(from_table(tables[-1]))
    return "\ndiagnosis: " + d.text().splitlines()[0] + live_check_agreement(d)


def _replica_set(protocol: Any, store: SessionStore, same: list[TrialRecord], subject: dict[str, float]) -> str:
    from analysis.pmp.replica import text

    from .loading import records_as_loaded
    from .replica import analyze_replica

    loaded = records_as_loaded(store, same)
    tables = [t.table() for t in loaded]
    result, truth, _ = analyze_replica(tables, [t.metadata for t in loaded], None, None)
    return text(result, truth) + _diagnosis_line(tables)


def _passive_set(protocol: Any, store: SessionStore, same: list[TrialRecord], subject: dict[str, float]) -> str:
    from analysis.errors import AnalysisError
    from analysis.pmp.model_diagnosis import folds_of
    from analysis.pmp.report import analyse, subject_from, text, trial_from_table

    tables = _tables(store, same)
    try:  # a fit that does not converge says so in its own text (success=False)
        trials = [trial_from_table(t) for t in tables]
        # the model-level diagnosis (damping, a limb-mass error, an offset, ... fitted inside the
        # estimator, each judged by predicting a left-out condition) once the set allows it: repeats,
        # or three conditions (the knee at hip 90/55/15°)
        model = len(trials) >= 3 and len(folds_of(trials)) >= 2
        report = analyse(trials, subject_from(subject), intervals=16, diagnose_model=model, model_intervals=12,
                         model_candidates=list(MODEL_CANDIDATES) if model else None)
        fitted = text(report)
    except AnalysisError as err:  # missing anthropometrics, a rejected trial, ...: say so, show the diagnosis
        fitted = f"passive parameters not fitted: {err}"
    return fitted + _diagnosis_line(tables)


#: the model-level diagnosis's candidates in the operator's set analysis (as the demo runs them)
MODEL_CANDIDATES = ("end_range_structures", "limb_mass_error", "torque_offset")

#: the analysis of a set of accepted trials, per trial kind
SET_ANALYSES: dict[str, Callable[[Any, SessionStore, list[TrialRecord], dict[str, float]], str]] = {
    "aads": _aads_set, "knee": _passive_set, "ankle": _passive_set, "replica": _replica_set}


def analyse_set(protocol: TrialProtocol, store_root: Any, trial_id: int, subject: dict[str, float]) -> str:
    """The analysis of the set the accepted trial belongs to (its session's accepted trials of this kind), as text."""
    from .results import remembered

    try:
        store = SessionStore(store_root, recover=False)
    except StoreReadOnlyError:  # a read-only medium: analyse, keep nothing
        store = SessionStore(store_root, read_only=True, recover=False)
    try:
        rec = store.trial(trial_id)
        same = [t for t in store.trials(protocol=protocol.name) if t.session_id == rec.session_id
                and t.status == "accepted"]
        # kept in the store with its inputs; the same accepted set analysed again is read back
        if store.read_only:
            return SET_ANALYSES[protocol.name](protocol, store, same, subject)
        payload, _ = remembered(store, f"set_{protocol.name}", same, {"condition": protocol.condition(),
                                                                        "subject": subject},
                                lambda: {"text": SET_ANALYSES[protocol.name](protocol, store, same, subject)})
        return str(payload["text"])
    finally:
        store.close()


__all__ = ["SET_ANALYSES", "analyse_set", "live_check_agreement"]
