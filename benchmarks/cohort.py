"""Cohort analysis on Dask: scaling with workers, the engine's overhead, and accuracy against a simulated study's truth.

A simulated study (``instrument.sim.study``: subjects with drawn anthropometrics and muscle
parameters; six sweeps each at the protocol's 5°/s, recorded through the drivers into a store)
is fitted with ``bootstrap`` refits per subject:

* with a LocalCluster of 1 and of 2 worker processes (wall time of each, their ratio);
* in a plain loop in this process (the same solves, no engine) on ``loop_subjects`` of the
  subjects, against the 1-worker engine on the same subjects: the engine's overhead;
* the 95 % intervals of the determined parameters against the truth (coverage, errors);
* an interrupted run (stopped after a few results) resumed from the store, and a worker
  killed mid-run: no result lost or duplicated.

Keys: ``subjects``, ``solves``, ``wall_s_1_worker``, ``wall_s_2_workers``, ``scaling_ratio``,
``engine_overhead_pct``, ``coverage_95``, ``max_error_determined_pct``, ``resume_after_kill_ok``,
``worker_kill_ok``, ``seconds_per_solve``, ``solves_per_core_minute``.
"""

from __future__ import annotations

import os
import signal
import tempfile
import time
from pathlib import Path
from typing import Any

from instrument.offline.cohort import MemoryResults, StudySubject, run_cohort, study_from_store
from instrument.sim.study import record_study
from instrument.store import SessionStore


def _plain_loop(study: list[StudySubject], bootstrap: int, intervals: int) -> tuple[float, int]:
    """The same solves as the engine makes, called one after another in this process."""
    from analysis.pmp.cohort import FitTask, bootstrap_trials, run_fit_task

    started = time.perf_counter()
    n = 0
    for s in study:
        main = run_fit_task(FitTask(s.code, 0, s.trials, s.subject, intervals, None, s.inputs))
        n += 1
        if not main["success"]:
            continue
        for b in range(1, bootstrap + 1):
            trials = bootstrap_trials(s.trials, main["fitted_torque_nm"], b)
            run_fit_task(FitTask(s.code, b, trials, s.subject, intervals, main["parameters"], s.inputs))
            n += 1
    return time.perf_counter() - started, n


def _client(workers: int) -> tuple[Any, Any]:
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster), cluster


def _interrupted_then_resumed(study: list[StudySubject], root: Path, intervals: int) -> bool:
    """Stop a run after 3 results (as a killed process would), resume it: every result once."""
    store = SessionStore(root)

    def stop(done: int, running: int, failed: int, total: int) -> None:
        if done >= 3:
            raise KeyboardInterrupt

    try:
        run_cohort(study, store, bootstrap=3, intervals=intervals, workers=2, progress=stop)
    except KeyboardInterrupt:
        pass
    kept = len(store.results())
    resumed = run_cohort(study, store, bootstrap=3, intervals=intervals, workers=2)
    keys = [r["key"] for r in store.results()]
    store.close()
    return (resumed.read_back == kept and resumed.solved_now == resumed.solves - kept
            and len(keys) == len(set(keys)) == resumed.solves and not resumed.failed)


def _worker_killed(study: list[StudySubject], intervals: int) -> bool:
    client, cluster = _client(2)
    killed: list[int] = []

    def kill(done: int, running: int, failed: int, total: int) -> None:
        if done >= 1 and not killed:
            pid = next(iter(client.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    sink = MemoryResults()
    try:
        run = run_cohort(study, sink, bootstrap=3, intervals=intervals, client=client, progress=kill)
    finally:
        client.close()
        cluster.close()
    return bool(killed) and not run.failed and len(sink.rows) == sink.writes == run.solves


def run(quick: bool = False) -> dict[str, Any]:
    subjects = 4 if quick else 10
    bootstrap = 6 if quick else 20
    loop_subjects = 2 if quick else 3
    speed = 15.0 if quick else 5.0
    intervals = 12
    root = Path(tempfile.mkdtemp(prefix="cohort-bench-"))
    t0 = time.perf_counter()
    store = record_study(root / "study", subjects, speed_deg_s=speed, progress=lambda m: None)
    study = study_from_store(store)
    store.close()
    record_s = time.perf_counter() - t0
    print(f"recorded {subjects} subjects x {sum(len(s.trials) for s in study) // subjects} trials in "
          f"{record_s:.0f} s", flush=True)

    runs = {}
    for workers in (1, 2):
        r = run_cohort(study, MemoryResults(), bootstrap=bootstrap, intervals=intervals, workers=workers)
        runs[workers] = r
        print(f"{workers} worker(s): {r.solves} solves in {r.wall_s:.1f} s", flush=True)
    subset = study[:loop_subjects]
    loop_s, loop_n = _plain_loop(subset, bootstrap, intervals)
    engine_subset = run_cohort(subset, MemoryResults(), bootstrap=bootstrap, intervals=intervals, workers=1)
    print(f"plain loop: {loop_n} solves in {loop_s:.1f} s; engine (1 worker) on the same: "
          f"{engine_subset.wall_s:.1f} s", flush=True)
    resume_ok = _interrupted_then_resumed(study[:2], root / "resume", intervals)
    kill_ok = _worker_killed(study[:2], intervals)
    cov = runs[2].coverage
    wall1, wall2 = runs[1].wall_s, runs[2].wall_s
    per_solve = loop_s / max(loop_n, 1)
    solves_per_core_minute = 60.0 / per_solve
    per_subject = 1 + bootstrap
    result = {
        "subjects": subjects, "trials_per_subject": sum(len(s.trials) for s in study) / subjects,
        "bootstrap_per_subject": bootstrap, "solves": runs[2].solves, "collocation_intervals": intervals,
        "sweep_speed_deg_s": speed, "record_s": record_s,
        "wall_s_1_worker": wall1, "wall_s_2_workers": wall2, "scaling_ratio": wall1 / wall2,
        "plain_loop_s": loop_s, "plain_loop_solves": loop_n, "engine_1_worker_same_solves_s": engine_subset.wall_s,
        "engine_task_seconds_same_solves": engine_subset.task_seconds,
        "engine_overhead_pct": 100.0 * (engine_subset.wall_s - loop_s) / loop_s,
        "seconds_per_solve": per_solve, "solves_per_core_minute": solves_per_core_minute,
        "subject_fits_per_core_minute": solves_per_core_minute / per_subject,
        "extrapolated_100_subjects_200_bootstrap_64_cores_min": 100 * 201 / (solves_per_core_minute * 64),
        "coverage_95": cov["coverage_95"], "determined_with_truth": cov["determined_with_truth"],
        "max_error_determined_pct": cov["max_error_determined_pct"],
        "median_error_determined_pct": cov["median_error_determined_pct"],
        "resume_after_kill_ok": resume_ok, "worker_kill_ok": kill_ok,
        "failed_solves": runs[1].failed + runs[2].failed,
        "misfit_ratio_per_subject": {s["subject_code"]: s["misfit_ratio"] for s in runs[2].summaries},
        "determined_per_subject": {s["subject_code"]: [n for n, r in s["parameters"].items() if r["determined"]]
                                   for s in runs[2].summaries},
        "cpu_count": os.cpu_count(),
    }
    print(f"{'measure':<44} value")
    for k in ("subjects", "solves", "wall_s_1_worker", "wall_s_2_workers", "scaling_ratio", "engine_overhead_pct",
              "seconds_per_solve", "subject_fits_per_core_minute", "coverage_95", "determined_with_truth",
              "max_error_determined_pct", "resume_after_kill_ok", "worker_kill_ok"):
        v = result[k]
        print(f"{k:<44} {v:.3f}" if isinstance(v, float) else f"{k:<44} {v}")
    return result
