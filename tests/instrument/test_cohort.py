"""The cohort engine on Dask: results kept once in the store, read back, invalidated by a changed
trial, and neither lost nor duplicated when a worker is killed or the run is interrupted."""

from __future__ import annotations

import os
import signal
import sqlite3
import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from analysis.pmp.estimator import PmpTrial, Subject
from analysis.pmp.muscles import LegMuscles
from instrument.cli import main
from instrument.offline.cohort import KIND_BOOTSTRAP, KIND_FIT, StudySubject, run_cohort
from instrument.store import SessionStore

pytestmark = pytest.mark.timeout(600)


def _subject(code: str, seed: int) -> StudySubject:
    """Two short knee sweeps from the generic muscles (a cheap fit: the engine is under test here)."""
    rng = np.random.default_rng(seed)
    leg, subject = LegMuscles(), Subject()
    trials = []
    for hip in (55.0, 15.0):
        t = np.arange(0.0, 16.0, 0.4)
        q = np.deg2rad(10.0 + 5.0 * t)
        fixed = {"hip": np.deg2rad(hip), "ankle": 0.0}
        moment = np.array([leg.joint_moment_nm("knee", hip=fixed["hip"], knee=x, ankle=0.0) for x in q])
        u = -(moment + subject.gravity_moment_nm("knee", q, fixed)) + rng.normal(0.0, 0.3, t.size)
        trials.append(PmpTrial("knee", fixed, t, q, np.full(t.size, np.deg2rad(5.0)), u, f"knee hip {hip:g}"))
    return StudySubject(code, trials, subject, {"trial_ids": [seed]})


@pytest.fixture(scope="module")
def client() -> Any:
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def _rows(store: SessionStore) -> list[tuple[str, str]]:
    return [(r["key"], r["kind"]) for r in store.results()]


def test_results_are_stored_once_and_read_back(tmp_path: Path, client: Any) -> None:
    store = SessionStore(tmp_path)
    study = [_subject("S01", 1), _subject("S02", 2)]
    first = run_cohort(study, store, bootstrap=2, intervals=4, client=client)
    assert (first.solves, first.solved_now, first.read_back, first.failed) == (6, 6, 0, [])
    rows = _rows(store)
    assert len(rows) == len({k for k, _ in rows}) == 6
    assert sorted(k for _, k in rows) == [KIND_BOOTSTRAP] * 4 + [KIND_FIT] * 2
    stored = store.results(kind=KIND_FIT, subject_code="S01")[0]
    assert stored["inputs"] == {"trial_ids": [1]} and stored["settings"]["bootstrap"] == 2
    assert set(stored["versions"]) >= {"instrument", "numpy", "scipy", "casadi"}
    again = run_cohort(study, store, bootstrap=2, intervals=4, client=client)
    assert (again.solved_now, again.read_back) == (0, 6)
    assert [s["parameters"] for s in again.summaries] == [s["parameters"] for s in first.summaries]
    # one changed sample of S02's data: S02 is solved again (new keys), S01 is read back
    study[1].trials[0].torque_nm[5] += 0.5
    changed = run_cohort(study, store, bootstrap=2, intervals=4, client=client)
    assert (changed.solved_now, changed.read_back) == (3, 3)
    assert len(_rows(store)) == 9
    store.close()


def test_a_killed_worker_loses_and_duplicates_nothing(tmp_path: Path, client: Any) -> None:
    store = SessionStore(tmp_path)
    study = [_subject(f"S{i:02d}", 10 + i) for i in range(3)]
    killed: list[int] = []
    lock = threading.Lock()

    def kill_one(done: int, running: int, failed: int, total: int) -> None:
        with lock:
            if done >= 1 and not killed and running:
                pids = client.run(os.getpid)  # {worker address: pid}
                busy = [a for a, tasks in client.processing().items() if tasks]
                pid = pids[busy[0]] if busy else next(iter(pids.values()))
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)

    run = run_cohort(study, store, bootstrap=3, intervals=4, client=client, progress=kill_one)
    assert killed, "no worker was killed: the test did not test anything"
    assert run.failed == [] and run.solves == 12
    keys = [k for k, _ in _rows(store)]
    assert len(keys) == len(set(keys)) == 12
    assert {s["subject_code"] for s in run.summaries} == {"S00", "S01", "S02"}
    assert all(s["parameters"]["recfem.tendon_slack_length_m"]["bootstrap_n"] == 3 for s in run.summaries)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts the killed worker for the next test
    store.close()


def test_an_interrupted_run_resumes_from_the_stored_results(tmp_path: Path, client: Any) -> None:
    store = SessionStore(tmp_path)
    study = [_subject("S01", 21), _subject("S02", 22)]

    def interrupt(done: int, running: int, failed: int, total: int) -> None:
        if done >= 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_cohort(study, store, bootstrap=2, intervals=4, client=client, progress=interrupt)
    kept = len(_rows(store))
    assert 3 <= kept < 6
    resumed = run_cohort(study, store, bootstrap=2, intervals=4, client=client)
    assert resumed.read_back == kept and resumed.solved_now == 6 - kept
    keys = [k for k, _ in _rows(store)]
    assert len(keys) == len(set(keys)) == 6
    with sqlite3.connect(tmp_path / "store.sqlite") as db:  # the table's key forbids a second copy
        with pytest.raises(sqlite3.IntegrityError):
            db.execute("INSERT INTO analysis_results (key, kind, inputs_json, settings_json, versions_json, "
                       "result_json, created_at) VALUES (?, 'x', '{}', '{}', '{}', '{}', 0)", (keys[0],))
    store.close()


def test_a_changed_trial_file_marks_its_results_stale(tmp_path: Path) -> None:
    store = SessionStore(tmp_path)
    data = tmp_path / "trial.h5"
    data.write_bytes(b"recorded samples")
    from instrument.store import file_sha256

    assert store.put_result("k1", "pmp_subject_fit", {"x": 1}, inputs={"files": {str(data): file_sha256(data)}})
    assert not store.put_result("k1", "pmp_subject_fit", {"x": 2})  # written once
    assert store.result("k1") == {"x": 1} and store.stale_results() == []
    data.write_bytes(b"recorded samples, edited")
    assert store.stale_results() == ["k1"]
    data.unlink()
    assert store.stale_results() == ["k1"]
    store.close()


def test_cli_refuses_a_bootstrap_without_spread_and_an_empty_store(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "cohort", "--store", str(tmp_path), "--bootstrap", "1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--bootstrap must be at least 2" in err[0]
    assert main(["analyze", "cohort", "--store", str(tmp_path), "--bootstrap", "2", "--workers", "1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no subject with usable knee or ankle trials" in err[0]
    assert main(["analyze", "cohort", "--store", str(tmp_path), "--extension", "friction"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no model extension 'friction'" in err[0]


def test_the_same_run_goes_to_a_lab_cluster_by_its_scheduler_address(tmp_path: Path, client: Any) -> None:
    store = SessionStore(tmp_path)
    run = run_cohort([_subject("S01", 31)], store, bootstrap=2, intervals=4, scheduler=client.scheduler.address)
    assert run.scheduler == client.scheduler.address and run.workers == 2
    assert (run.solved_now, run.failed) == (3, []) and len(_rows(store)) == 3
    assert client.status == "running"  # the lab's cluster is left running for its other users
    store.close()


def test_a_subject_without_anthropometrics_is_left_out_and_said_so(tmp_path: Path) -> None:
    from instrument.errors import InstrumentError
    from instrument.kinds.knee import KneeProtocol
    from instrument.live.session import record_trial
    from instrument.offline.cohort import study_from_store
    from instrument.sim.simulate import simulated_devices
    from instrument.store import Subject

    store = SessionStore(tmp_path)
    store.add_subject(Subject("S01", mass_kg=75.0, shank_length_m=0.42, foot_length_m=0.26))
    store.add_subject(Subject("S02", mass_kg=None, shank_length_m=0.42, foot_length_m=0.26))
    for code in ("S01", "S02"):
        proto = KneeProtocol(end_deg=12.0, speed_deg_s=20.0, settle_s=0.1)  # short: the fit is not run here
        with simulated_devices(proto) as (_, devices):
            record_trial(store, store.new_session(code), proto, devices)
    left_out: list[str] = []
    study = study_from_store(store, left_out=left_out)
    assert [s.code for s in study] == ["S01"] and len(study[0].trials) == 1
    assert len(left_out) == 1 and left_out[0].startswith("subject S02:") and "mass_kg is missing" in left_out[0]
    with pytest.raises(InstrumentError, match="subject S02: .*mass_kg is missing"):
        study_from_store(store, ["S02"])
    store.close()
