"""Session store: migrations, version guard, read-only, statuses, anthropometrics."""

from __future__ import annotations

import os
import sqlite3
from pathlib import Path

import pytest

from instrument.errors import NotFoundError, StoreReadOnlyError, StoreVersionError
from instrument.store import MIGRATIONS, SCHEMA_VERSION, SessionStore, Subject


def test_store_written_by_version_1_opens_in_the_current_version(tmp_path: Path) -> None:
    old = SessionStore(tmp_path, migrations=MIGRATIONS[:1], recover=False)  # the schema version 1 wrote
    assert old.schema_version == 1
    old._db.execute("INSERT INTO subjects (code, sex, mass_kg, created_at) VALUES ('P07', 'female', 61.5, 0)")
    old._db.execute("INSERT INTO sessions (subject_id, started_at) VALUES (1, 0)")
    old._db.execute("INSERT INTO trials (session_id, protocol, status, file, started_at) "
                    "VALUES (1, 'knee', 'accepted', 'trials/session-0001/knee-1.h5', 0)")
    old._db.commit()
    old.close()
    new = SessionStore(tmp_path)
    assert new.schema_version == SCHEMA_VERSION == 4  # v2 files table, v3 operators, v4 analysis results
    (trial,) = new.trials()
    assert trial.status == "accepted" and trial.path == tmp_path / "trials/session-0001/knee-1.h5"
    assert new.subject("P07").mass_kg == 61.5


def test_store_from_a_newer_version_is_refused_clearly(tmp_path: Path) -> None:
    SessionStore(tmp_path).close()
    db = sqlite3.connect(tmp_path / "store.sqlite")
    db.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 3}")
    db.commit()
    db.close()
    with pytest.raises(StoreVersionError, match=rf"newer version .* understands up to {SCHEMA_VERSION}"):
        SessionStore(tmp_path)


def test_read_only_store_refuses_writes_and_keeps_trials(tmp_path: Path) -> None:
    s = SessionStore(tmp_path)
    s.add_subject(Subject("S01", "male", 1.80, 80.0, 0.95, 0.43, 0.41, 0.26, 0.19, 0.55, 0.38))
    sid = s.new_session("S01")
    s.begin_trial(sid, "knee", {"hip_flexion_deg": 90})
    s.close()
    ro = SessionStore(tmp_path, read_only=True)
    with pytest.raises(StoreReadOnlyError):
        ro.new_session("S01")
    assert len(ro.trials()) == 1 and ro.subject("S01").shank_length_m == 0.41


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores directory permissions")
def test_store_in_a_read_only_folder(tmp_path: Path) -> None:
    tmp_path.chmod(0o555)
    try:
        with pytest.raises(StoreReadOnlyError):
            SessionStore(tmp_path / "new")
    finally:
        tmp_path.chmod(0o755)


def test_statuses_reasons_and_repeats(tmp_path: Path) -> None:
    s = SessionStore(tmp_path)
    s.add_subject(Subject("S01"))
    sid = s.new_session("S01", operator="op2")
    a, _ = s.begin_trial(sid, "ankle", {"knee_flexion_deg": 0})
    b, _ = s.begin_trial(sid, "ankle", {"knee_flexion_deg": 0})
    s.finish_trial(a, "recorded", {"dynamometer": {"samples": 1000, "lost_samples": 2, "gaps": 1}})
    with pytest.raises(ValueError, match="needs a reason"):
        s.set_status(a, "rejected")
    s.set_status(a, "rejected", reason="muscle activation detected at 12.3 s", repeated_by=b)
    t = s.trial(a)
    assert (t.status, t.repeated_by, t.devices["dynamometer"]["lost_samples"]) == ("rejected", b, 2)
    assert "activation" in (t.reason or "")
    with pytest.raises(NotFoundError):
        s.trial(999)
    with pytest.raises(NotFoundError):
        s.new_session("nobody")


def test_subjects_need_no_identifying_fields() -> None:
    names = set(Subject.__dataclass_fields__)
    assert not names & {"name", "first_name", "last_name", "birth_date", "date_of_birth"}


def test_trials_begun_from_many_threads_get_their_own_ids_and_files(tmp_path: Path) -> None:
    """The lab day records rooms in parallel through one store: ids and file rows must not cross."""
    import threading

    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01"))
    session = store.new_session("S01")
    got: list[tuple[int, Path]] = []
    lock = threading.Lock()

    def room() -> None:
        for _ in range(25):
            out = store.begin_trial(session, "knee", {})
            with lock:
                got.append(out)

    threads = [threading.Thread(target=room) for _ in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ids = [i for i, _ in got]
    assert len(set(ids)) == 150
    for trial_id, path in got:
        assert Path(store.trial(trial_id).path) == path
