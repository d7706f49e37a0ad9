"""Cohort analysis on Dask: scaling with workers, the engine's overhead, and accuracy against a simulated study's truth.

A simulated study whose subjects' passive moments OpenSim made (:func:`opensim_draws`: Rajagopal 2016's
muscles with perturbed parameters, :mod:`benchmarks.opensim_truth` in a subprocess, never the estimator's
own muscle model), one variant per subject in turn from :data:`VARIANTS` (the realistic ones of
``pmp_realistic``: compliant knee tendons with tone, end-range structures, unmodelled muscles, a tape error on
the shank, the fixed joints' set angles off), six sweeps each at the protocol's speed recorded through the
drivers into a store (``instrument.sim.study``), is fitted (the plain muscle model, as ``analyze cohort``
does) with ``bootstrap`` refits per subject:

* with a LocalCluster of 1 and of 2 worker processes (wall time of each, their ratio);
* in a plain loop in this process (the same solves, no engine) on ``loop_subjects`` of the
  subjects, against the 1-worker engine on the same subjects: the engine's overhead;
* the 95 % intervals of the determined parameters against the truth (coverage, errors), over all
  subjects and per variant;
* an interrupted run (stopped after a few results) resumed from the store, and a worker
  killed mid-run: no result lost or duplicated.

Keys: ``subjects``, ``solves``, ``wall_s_1_worker``, ``wall_s_2_workers``, ``scaling_ratio``,
``engine_overhead_pct``, ``coverage_95``, ``max_error_determined_pct``, ``resume_after_kill_ok``,
``worker_kill_ok``, ``seconds_per_solve``, ``solves_per_core_minute``, ``truth_source``, ``variant_per_subject``,
``by_variant`` (per variant: determined parameters with truth, coverage, worst error, median misfit ratio).
"""

from __future__ import annotations

import os
import signal
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline

from instrument.kinds.ankle import AnkleProtocol
from instrument.kinds.isokinetic import IsokineticProtocol
from instrument.kinds.knee import KneeProtocol
from instrument.offline.cohort import MemoryResults, StudySubject, run_cohort, study_from_store
from instrument.sim.study import StudyDraw, record_study
from instrument.store import SessionStore, Subject

#: the variant of subject i is VARIANTS[i % len(VARIANTS)] (as ``pmp_realistic``'s, one mismatch each)
VARIANTS = ("matched", "compliant_tone", "end_range", "unmodelled_muscles", "tape", "set_angle")
#: seeds of the truth's draws (pmp_realistic's development and measured seeds are 900–13999, 15000–17509 and
#: 50000–50502). 20000 until the twelfth stop, whose rerun there showed a tape-error subject outside its interval
#: (the cohort's intervals lacked the measured inputs' share); the fix is measured on fresh subjects
COHORT_SEED_BASE = 21000
FOOT_M = 0.26
#: OpenSim's poses every this many degrees over each sweep's range ±3°, a cubic spline between (deg)
POSE_STEP_DEG = 1.0


def _sweep_key(proto: IsokineticProtocol) -> tuple[str, float]:
    return proto.joint, round(float(proto.set_angle_deg), 3)


def opensim_draw(index: int, seed: int) -> StudyDraw:
    """Subject ``index``: parameters drawn around Rajagopal 2016's, passive moments from OpenSim with the
    subject's variant hidden, a moment table per protocol sweep (knee at hip 90/55/15°, ankle at knee 0/45/90°)."""
    from .opensim_truth import draw_truth, generic_parameters, model_path, remembered_opensim
    from .pmp_opensim import SHANK_M
    from .pmp_realistic import THIGH_M, _limit_forces

    variant = VARIANTS[index % len(VARIANTS)]
    rng = np.random.default_rng([seed, index])
    truth = draw_truth(int(rng.integers(2**31)), generic_parameters())
    protos: list[IsokineticProtocol] = [KneeProtocol(hip_flexion_deg=h) for h in (90.0, 55.0, 15.0)]
    protos += [AnkleProtocol(knee_flexion_deg=k) for k in (0.0, 45.0, 90.0)]
    errors_deg = rng.uniform(-3.0, 3.0, len(protos)) if variant == "set_angle" else np.zeros(len(protos))
    poses, grids = [], []
    for proto, err in zip(protos, errors_deg):
        lo, hi = sorted((proto.start_deg, proto.end_deg))
        grid = np.arange(lo - 3.0, hi + 3.0 + 1e-9, POSE_STEP_DEG)
        grids.append(grid)
        fixed = proto.fixed_angles_deg()
        at = {"hip": fixed.get("hip_flexion_deg", 0.0), "knee": fixed.get("knee_flexion_deg", 0.0),
              "ankle": fixed.get("ankle_dorsiflexion_deg", 0.0)}
        at["hip" if proto.joint == "knee" else "knee"] += float(err)  # the fixed joint truly sits there
        for d in grid:
            poses.append({k: float(np.radians(d if k == proto.joint else v)) for k, v in at.items()})
    answer = remembered_opensim({"model": str(model_path()), "parameters": truth, "poses": poses,
                                 "compliant_knee_tendons": variant == "compliant_tone",
                                 "activation": 0.01 if variant == "compliant_tone" else 0.0,
                                 "limit_forces": _limit_forces(rng) if variant == "end_range" else {},
                                 "unmodelled_muscles": variant == "unmodelled_muscles"})
    tables: dict[tuple[str, float], tuple[np.ndarray, np.ndarray]] = {}
    first = 0
    for proto, grid in zip(protos, grids):
        moments = np.asarray(answer["moments_nm"][proto.joint][first:first + grid.size], dtype=float)
        first += grid.size
        fine = np.arange(grid[0], grid[-1] + 1e-9, 0.1)
        tables[_sweep_key(proto)] = (fine, CubicSpline(grid, moments)(fine))
    tape_m = float(rng.uniform(-0.005, 0.005)) if variant == "tape" else 0.0
    mass = float(rng.uniform(60.0, 90.0))
    # the thigh measured too (the model's hip to knee; in the tape variant within ±5 mm, like the shank)
    thigh_m = THIGH_M + (float(rng.uniform(-0.005, 0.005)) if variant == "tape" else 0.0)
    subject = Subject(f"OS{index + 1:02d}", "unknown", None, mass, None, thigh_m, SHANK_M + tape_m, None, FOOT_M)
    flat = {f"{m}.{what}": float(v) for m, row in truth.items() for what, v in row.items()}
    return StudyDraw(subject, flat, lambda proto: tables[_sweep_key(proto)], variant=variant, true_shank_length_m=SHANK_M)


def opensim_draws(subjects: int, seed: int = COHORT_SEED_BASE) -> list[StudyDraw]:
    """``subjects`` :func:`opensim_draw` subjects, two OpenSim processes at a time."""
    with ThreadPoolExecutor(max_workers=2) as pool:
        return list(pool.map(lambda i: opensim_draw(i, seed), range(subjects)))


def by_variant(summaries: list[dict[str, Any]], variant_of: dict[str, str]) -> dict[str, dict[str, Any]]:
    """Per variant: determined parameters with truth, how many intervals hold it, the worst error, the misfit."""
    out: dict[str, dict[str, Any]] = {}
    for v in dict.fromkeys(variant_of.values()):
        rows = [r for s in summaries if variant_of.get(s["subject_code"]) == v for r in s["parameters"].values()
                if r.get("determined") and "covered" in r]
        misfit = [s["misfit_ratio"] for s in summaries if variant_of.get(s["subject_code"]) == v
                  and s["misfit_ratio"] is not None]
        out[v] = {"subjects": sum(1 for c in variant_of.values() if c == v), "determined_with_truth": len(rows),
                  "covered": sum(bool(r["covered"]) for r in rows),
                  "coverage_95": float(np.mean([r["covered"] for r in rows])) if rows else None,
                  "max_error_determined_pct": float(max(abs(r["error_pct"]) for r in rows)) if rows else None,
                  "median_misfit_ratio": float(np.median(misfit)) if misfit else None}
    return out


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
    subjects = 6 if quick else 12
    bootstrap = 6 if quick else 10
    loop_subjects = 2 if quick else 3
    speed = 15.0 if quick else 5.0
    intervals = 12
    root = Path(tempfile.mkdtemp(prefix="cohort-bench-"))
    t0 = time.perf_counter()
    draws = opensim_draws(subjects)
    truth_s = time.perf_counter() - t0
    variant_of = {d.subject.code: d.variant for d in draws}
    print(f"OpenSim made {subjects} subjects' passive moments in {truth_s:.0f} s", flush=True)
    t0 = time.perf_counter()
    store = record_study(root / "study", subjects, speed_deg_s=speed, progress=lambda m: None, draws=draws)
    study = study_from_store(store)
    store.close()
    record_s = time.perf_counter() - t0
    print(f"recorded {subjects} subjects, {sum(len(s.trials) for s in study)} trials in {record_s:.0f} s", flush=True)

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
        "sweep_speed_deg_s": speed, "record_s": record_s, "truth_s": truth_s,
        "truth_source": "OpenSim (Rajagopal 2016, DeGrooteFregly2016Muscle) in a subprocess",
        "variant_per_subject": variant_of, "by_variant": by_variant(runs[2].summaries, variant_of),
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
        "trials_per_subject_recorded": {s.code: len(s.trials) for s in study},
        "cpu_count": os.cpu_count(),
    }
    print(f"{'measure':<44} value")
    for k in ("subjects", "solves", "wall_s_1_worker", "wall_s_2_workers", "scaling_ratio", "engine_overhead_pct",
              "seconds_per_solve", "subject_fits_per_core_minute", "coverage_95", "determined_with_truth",
              "max_error_determined_pct", "resume_after_kill_ok", "worker_kill_ok"):
        v = result[k]
        print(f"{k:<44} {v:.3f}" if isinstance(v, float) else f"{k:<44} {v}")
    print(f"{'variant':<20}{'subjects':>9}{'determined':>11}{'covered':>8}{'worst %':>9}{'misfit':>8}")
    for v, row in result["by_variant"].items():
        worst = row["max_error_determined_pct"]
        print(f"{v:<20}{row['subjects']:>9}{row['determined_with_truth']:>11}{row['covered']:>8}"
              f"{'—' if worst is None else f'{worst:.2f}':>9}{row['median_misfit_ratio'] or float('nan'):>8.2f}")
    return result
