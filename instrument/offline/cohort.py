"""A study's passive-parameter fits on Dask: every subject of a store, with bootstrap intervals.

Each solve is one Dask task (:func:`analysis.pmp.cohort.run_fit_task`, pure: plain data in, a
JSON-able result out; the CasADi problem is built inside the worker). By default the tasks run on
an embedded ``LocalCluster`` with one single-threaded worker process per core; ``scheduler``
(``tcp://host:8786``) sends the same tasks to a lab's Dask cluster. A worker that dies has its
tasks re-run elsewhere (Dask's ``allowed-failures``; the task is idempotent), and every result is
written to the session store by this process as it arrives, under its task's key, once
(``INSERT OR IGNORE``): a run that is interrupted resumes from the stored results, and a re-run
with the same trials and settings reads them back instead of solving.

The study: per subject, its knee and ankle trials whose status is ``accepted`` or ``recorded``
(not rejected, interrupted or failed, and not superseded by a repeat), all of them (every repeat).
"""

from __future__ import annotations

import logging
import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from analysis.pmp.cohort import FitTask, bootstrap_trials, coverage, run_fit_task, subject_summary

from .. import kinds
from ..errors import InstrumentError
from ..store import SessionStore, TrialRecord, file_sha256
from .loading import load_trials

log = logging.getLogger(__name__)

#: trial statuses a cohort fit uses
USABLE_STATUSES = ("accepted", "recorded")
#: result kinds in the store
KIND_FIT = "pmp_subject_fit"
KIND_BOOTSTRAP = "pmp_bootstrap_fit"


class ResultSink(Protocol):
    """Where results are kept: the session store, or :class:`MemoryResults`."""

    def result(self, key: str) -> dict[str, Any] | None: ...

    def put_result(self, key: str, kind: str, result: dict[str, Any], *, subject_code: str | None = None,
                   label: str | None = None, inputs: dict[str, Any] | None = None,
                   settings: dict[str, Any] | None = None) -> bool: ...


class MemoryResults:
    """Results kept in memory (benchmarks): the same write-once contract as the store."""

    def __init__(self) -> None:
        self.rows: dict[str, dict[str, Any]] = {}
        self.writes = 0

    def result(self, key: str) -> dict[str, Any] | None:
        return self.rows.get(key)

    def put_result(self, key: str, kind: str, result: dict[str, Any], **_: Any) -> bool:
        self.writes += 1
        if key in self.rows:
            return False
        self.rows[key] = result
        return True


@dataclass
class StudySubject:
    """One subject's fit inputs: the estimator's trials, anthropometrics and where they came from."""

    code: str
    trials: list[Any]
    subject: Any
    inputs: dict[str, Any] = field(default_factory=dict)
    truth: dict[str, float] | None = None
    excluded: list[str] = field(default_factory=list)


@dataclass
class CohortRun:
    """What a cohort run did: the per-subject summaries and the engine's account."""

    summaries: list[dict[str, Any]]
    solves: int
    solved_now: int
    read_back: int
    failed: list[str]
    wall_s: float
    task_seconds: float
    workers: int
    scheduler: str
    coverage: dict[str, Any]
    worker_pids: set[int] = field(default_factory=set)
    #: every AFO set's stiffness analysis (Tables 2.1, 2.2) by AFO name: ``json``, ``text``, ``read_back``
    afo_sets: dict[str, dict[str, Any]] = field(default_factory=dict)
    #: subjects of the store the run left out, with the reason
    left_out: list[str] = field(default_factory=list)


def study_from_store(store: SessionStore, codes: Sequence[str] | None = None,
                     left_out: list[str] | None = None) -> list[StudySubject]:
    """Every subject (or ``codes``) with its usable knee and ankle trials; a subject whose
    anthropometrics are missing or out of range is left out (the reason appended to ``left_out``),
    or, when named in ``codes``, refused.

    :raises InstrumentError: a named subject has no usable trial, or no subject has any.
    """
    from analysis.errors import AnalysisError
    from analysis.pmp.report import subject_from, trial_from_table

    wanted = list(codes) if codes else [s.code for s in store.subjects()]
    out = []
    skipped: list[str] = []
    for code in wanted:
        passive = kinds.names_feeding(kinds.PASSIVE_PARAMETERS)
        records = [t for t in store.trials() if t.subject_code == code and t.protocol in passive]
        usable = [t for t in records if t.status in USABLE_STATUSES and t.repeated_by is None]
        excluded = [f"trial {t.id} ({t.protocol}): {t.status}" + (f", repeated by {t.repeated_by}"
                                                                   if t.repeated_by else "")
                    for t in records if t not in usable]
        if not usable:
            if codes:
                raise InstrumentError(f"subject {code}: no accepted or recorded knee/ankle trial in the store")
            continue
        loaded = load_trials(usable, store)
        trials = []
        for lt in loaded:
            try:
                trials.append(trial_from_table(lt.table()))
            except AnalysisError as err:
                excluded.append(f"trial {lt.spec}: {err}")
        if not trials:
            continue
        try:
            subject = subject_from(store.subject(code).as_dict())
        except AnalysisError as err:  # missing or absurd anthropometrics: the subject is left out, and said so
            if codes:
                raise InstrumentError(f"subject {code}: {err}") from err
            skipped.append(f"subject {code}: {err}")
            continue
        truth = loaded[0].metadata.get("study_truth") if loaded else None
        out.append(StudySubject(code, trials, subject,
                                {"trial_ids": [t.id for t in usable],
                                 "files": {str(t.path): file_sha256(Path(t.path)) for t in usable}},
                                truth, excluded))
    if not out:
        raise InstrumentError(f"{store.root}: no subject with usable knee or ankle trials"
                              + (f" ({'; '.join(skipped)})" if skipped else ""))
    if skipped:
        log.warning("cohort leaves out %s", "; ".join(skipped))
    if left_out is not None:
        left_out.extend(skipped)
    return out


def local_client(scheduler: str | None = None, workers: int | None = None) -> tuple[Any, Any, int]:
    """(client, the LocalCluster or None, workers): a lab scheduler's client, or an embedded LocalCluster."""
    from distributed import Client, LocalCluster

    for name in ("distributed", "bokeh", "tornado"):  # the engine's chatter is not the operator's
        logging.getLogger(name).setLevel(logging.ERROR)
    if scheduler:
        client = Client(scheduler)
        return client, None, len(client.scheduler_info().get("workers", {}))
    n = workers or os.cpu_count() or 1
    with warnings.catch_warnings():  # the health endpoint moves to a free port when 8787 is taken: fine
        warnings.filterwarnings("ignore", message="Port .* is already in use")
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
    return Client(cluster), cluster, n


def run_cohort(study: list[StudySubject], results: ResultSink, *, bootstrap: int = 20, intervals: int = 12,
               seed: int = 0, scheduler: str | None = None, workers: int | None = None,
               progress: Callable[[int, int, int, int], None] | None = None,
               client: Any = None, extension: str | None = None) -> CohortRun:
    """Fit every subject of ``study`` and its ``bootstrap`` resamples on Dask; results kept in ``results``.

    :param extension: a model extension fitted beside every subject's muscles, or
        :data:`analysis.pmp.cohort.DIAGNOSED` (each subject's model-level diagnosis chooses; its resamples are
        fitted with what it named); None: the muscle model alone.

    :param progress: called as ``progress(done, running, failed, total)`` after every task.
    :param client: an existing ``distributed.Client`` (tests); otherwise one is made (and closed).
    """
    from distributed import as_completed

    started = time.perf_counter()
    settings: dict[str, Any] = {"intervals": intervals, "bootstrap": bootstrap, "seed": seed}
    if extension:
        settings["extension"] = extension
    total = len(study) * (1 + bootstrap)
    own = client is None
    cluster = None
    if own:
        client, cluster, n_workers = local_client(scheduler, workers)
    else:
        n_workers = len(client.scheduler_info().get("workers", {}))
    done = failed_n = read_back = solved = 0
    failed: list[str] = []
    task_seconds = 0.0
    pids: set[int] = set()
    mains: dict[str, dict[str, Any]] = {}
    boots: dict[str, list[dict[str, Any]]] = {s.code: [] for s in study}
    by_code = {s.code: s for s in study}
    running = as_completed(with_results=False)
    meta: dict[str, tuple[FitTask, str]] = {}

    def tick() -> None:
        if progress is not None:
            progress(done, running.count(), failed_n, total)

    def submit(task: FitTask, kind: str) -> None:
        nonlocal done, read_back
        stored = results.result(task.key)
        if stored is not None:
            read_back += 1
            done += 1
            accept(task, kind, stored)
            return
        fut = client.submit(run_fit_task, task, key=f"{kind}-{task.key}", retries=2, pure=False)
        meta[fut.key] = (task, kind)
        running.add(fut)

    def accept(task: FitTask, kind: str, result: dict[str, Any]) -> None:
        nonlocal total
        if kind == KIND_FIT and not result["success"]:
            total -= bootstrap  # no resample of a fit that did not converge
        if kind == KIND_FIT:
            mains[task.subject_code] = result
            if result["success"]:
                s = by_code[task.subject_code]
                for b in range(1, bootstrap + 1):
                    trials = bootstrap_trials(s.trials, result["fitted_torque_nm"], b, seed=seed)
                    submit(FitTask(s.code, b, trials, s.subject, intervals, result["parameters"], s.inputs,
                                   result.get("extension")), KIND_BOOTSTRAP)
        else:
            boots[task.subject_code].append(result)
        tick()

    try:
        for s in study:
            submit(FitTask(s.code, 0, s.trials, s.subject, intervals, None, s.inputs, extension), KIND_FIT)
        for fut in running:
            task, kind = meta.pop(fut.key)
            try:
                result = fut.result()
            except Exception as err:
                failed_n += 1
                done += 1
                failed.append(f"{task.subject_code} replicate {task.replicate}: {type(err).__name__}: {err}")
                if kind == KIND_FIT:
                    total -= bootstrap
                tick()
                continue
            finally:
                fut.release()
            done += 1
            solved += 1
            task_seconds += float(result.get("task_seconds", 0.0))
            pids.add(int(result.get("worker_pid", 0)))
            results.put_result(task.key, kind, result, subject_code=task.subject_code,
                               label=f"replicate {task.replicate}", inputs=task.inputs, settings=settings)
            accept(task, kind, result)
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()
    summaries = [subject_summary(mains[s.code], boots[s.code], s.truth) for s in study if s.code in mains]
    for summ in summaries:
        member = by_code[summ["subject_code"]]
        summ["excluded_trials"] = member.excluded
        summ["inputs"] = member.inputs
        summ["subject"] = {"mass_kg": member.subject.mass_kg, "shank_length_m": member.subject.shank_length_m,
                           "foot_length_m": member.subject.foot_length_m,
                           "thigh_length_m": member.subject.thigh_length_m}
    return CohortRun(summaries, total, solved, read_back, failed, time.perf_counter() - started, task_seconds,
                     n_workers, scheduler or f"LocalCluster({n_workers} processes)", coverage(summaries), pids)


def engine_account(run: CohortRun, subjects: int) -> dict[str, Any]:
    """The engine's account of a run, as the report and the JSON state it."""
    return {"subjects": subjects, "solves": run.solves, "solved_now": run.solved_now, "read_back": run.read_back,
            "failed": run.failed, "wall_s": run.wall_s, "task_seconds": run.task_seconds, "workers": run.workers,
            "scheduler": run.scheduler, "coverage": run.coverage, "left_out": run.left_out}


def afo_sets(store: SessionStore) -> dict[str, list[TrialRecord]]:
    """The study's AADS sets: usable AADS trials grouped by the AFO tested (its name in the condition)."""
    sets: dict[str, list[TrialRecord]] = {}
    for t in (t for t in store.trials() if t.protocol in kinds.names_feeding(kinds.AFO_STIFFNESS)):
        if t.status in USABLE_STATUSES and t.repeated_by is None and t.condition.get("live_markers", True):
            sets.setdefault(str(t.condition.get("afo") or "unnamed AFO"), []).append(t)
    return sets


def analyze_afo_sets(store: SessionStore) -> dict[str, dict[str, Any]]:
    """Every AFO set's stiffness (Tables 2.1 and 2.2), each remembered in the store like any analysis."""
    from analysis.aads.model import load_jig_model

    from ..store import remembered
    from .afo import analyze_afo, resolve_trials

    model = load_jig_model()
    out = {}
    for afo, records in afo_sets(store).items():
        def compute(records: list[TrialRecord] = records) -> dict[str, Any]:
            exp = analyze_afo(resolve_trials(records, store, model=model), model)
            return {"json": exp.as_dict(), "text": exp.text()}

        if store.read_only:
            out[afo] = {**compute(), "read_back": False}
        else:
            payload, read_back = remembered(store, "afo_set", records, {"spring": None, "spring_n_per_m": None},
                                            compute)
            out[afo] = {**payload, "read_back": read_back}
    return out


def analyze_cohort(store: SessionStore, out_dir: Path, *, codes: Sequence[str] | None = None, bootstrap: int = 20,
                   intervals: int = 12, seed: int = 0, scheduler: str | None = None, workers: int | None = None,
                   progress: Callable[[int, int, int, int], None] | None = None,
                   client: Any = None, extension: str | None = None) -> tuple[CohortRun, list[Path]]:
    """The cohort analysis of a store: fits (on Dask, results kept in the store) and the report files.
    ``extension``: see :func:`run_cohort`.

    ``client``: a ``distributed.Client`` to use (and leave open), e.g. for several runs on one cluster.
    """
    from analysis.pmp.cohort_report import write_cohort

    afo = analyze_afo_sets(store) if not codes else {}
    left_out: list[str] = []
    study = study_from_store(store, codes, left_out) if codes or any(
        t.protocol in kinds.names_feeding(kinds.PASSIVE_PARAMETERS) for t in store.trials()) else []
    run = run_cohort(study, store, bootstrap=bootstrap, intervals=intervals, seed=seed, scheduler=scheduler,
                     workers=workers, progress=progress, client=client, extension=extension) \
        if study else CohortRun([], 0, 0, 0, [], 0.0, 0.0, 0, "none", {})
    run.afo_sets = afo
    run.left_out = left_out
    if not study and not afo:
        raise InstrumentError(f"{store.root}: no subject with usable knee or ankle trials and no AADS set")
    files = write_cohort(out_dir, run.summaries, engine_account(run, len(study)),
                         {"afo_sets": {k: v["json"] for k, v in afo.items()}})
    return run, files


def progress_printer(stream: Any = None, every: int = 1) -> Callable[[int, int, int, int], None]:
    """A one-line progress bar: tasks done, running, failed (rewritten in place on a terminal)."""
    stream = stream or sys.stdout
    tty = bool(getattr(stream, "isatty", lambda: False)())
    last = {"done": -1}

    def show(done: int, running: int, failed: int, total: int) -> None:
        if not tty and done != total and done - last["done"] < every:
            return
        last["done"] = done
        width = 30
        filled = int(width * done / max(total, 1))
        line = (f"[{'#' * filled}{'.' * (width - filled)}] {done}/{total} solves done, "
                f"{running} waiting or running, {failed} failed")
        stream.write(("\r" + line) if tty else line + "\n")
        if tty and done == total:
            stream.write("\n")
        stream.flush()

    return show


def default_every(total: int) -> int:
    """Progress lines for a log: about twenty per run."""
    return max(1, math.ceil(total / 20))
