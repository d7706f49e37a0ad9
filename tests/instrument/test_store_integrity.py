"""The store under concurrent and hostile use: writer locks, atomic migrations, exports that never
overwrite an input, a corrupt index, and the command line's one-line errors."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from drivers.blocks import ForcePlateBlock
from instrument.cli import main as cli_main
from instrument.errors import StoreError
from instrument.live.recording import DeviceSpec, TrialWriter, read_trial
from instrument.store import SessionStore, Subject, TrialLock

ROOT = Path(__file__).resolve().parents[2]


def _plate(c0: int, n: int) -> dict[str, np.ndarray]:
    c = np.arange(c0, c0 + n)
    return {"counter": c, "time_s": c / 1e3, "force_n": np.ones((n, 3)), "moment_nm": np.ones((n, 3)),
            "cop_m": np.ones((n, 2)), "free_moment_nm": np.ones(n), "trigger": np.zeros(n, np.uint8)}


def test_a_live_writer_on_another_host_is_never_recovered(tmp_path: Path) -> None:
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01"))
    tid, path = store.begin_trial(store.new_session("S01"), "aads", {})
    w = TrialWriter(path, {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {})}, {}, flush_interval_s=0.02)
    w.append("force_plate", _plate(0, 300))
    # the index says another host wrote it (a PID this process cannot see, as from another container)
    with store._write() as db:
        db.execute("UPDATE trials SET writer_host='elsewhere', writer_pid=999999 WHERE id=?", (tid,))
    other = SessionStore(tmp_path / "store")  # a second opener while the trial is being recorded
    assert other.recovered == [] and other.trial(tid).status == "recording"
    other.close()
    w.append("force_plate", _plate(300, 300))
    w.close()
    store.finish_trial(tid, "recorded", {"force_plate": {"samples": 600}})
    assert not TrialLock.path_for(path).exists()
    assert read_trial(path).devices["force_plate"].samples == 600
    store.close()


KILLED_WRITER = textwrap.dedent("""
    import os, sys, numpy as np
    sys.path.insert(0, {root!r})
    from instrument.store import SessionStore
    from instrument.live.recording import TrialWriter, DeviceSpec
    from drivers.blocks import ForcePlateBlock
    store = SessionStore({store!r})
    tid, path = store.begin_trial(store.new_session("S01"), "aads", {{}})
    with store._write() as db:
        db.execute("UPDATE trials SET writer_host='elsewhere' WHERE id=?", (tid,))
    w = TrialWriter(path, {{"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {{}})}}, {{}})
    c = np.arange(200)
    w.append("force_plate", {{"counter": c, "time_s": c / 1e3, "force_n": np.ones((200, 3)),
                              "moment_nm": np.ones((200, 3)), "cop_m": np.ones((200, 2)),
                              "free_moment_nm": np.ones(200), "trigger": np.zeros(200, np.uint8)}})
    import time; time.sleep(0.6)
    os.kill(os.getpid(), 9)
""")


def test_a_dead_writer_on_another_host_is_recovered_by_its_free_lock(tmp_path: Path) -> None:
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01"))
    store.close()
    subprocess.run([sys.executable, "-c", KILLED_WRITER.format(root=str(ROOT), store=str(tmp_path / "store"))],
                   timeout=60)
    store = SessionStore(tmp_path / "store")
    (trial,) = store.trials()
    assert trial.status == "interrupted" and len(store.recovered) == 1
    assert read_trial(trial.path).devices["force_plate"].samples == 200
    assert not TrialLock.path_for(trial.path).exists()
    store.close()


CREATE_STORE = textwrap.dedent("""
    import sys
    sys.path.insert(0, {root!r})
    from instrument.store import SessionStore
    SessionStore({store!r}).close()
    print("ok")
""")


def test_processes_creating_one_store_at_once_all_succeed(tmp_path: Path) -> None:
    for k in range(4):
        target = str(tmp_path / f"store{k}")
        procs = [subprocess.Popen([sys.executable, "-c", CREATE_STORE.format(root=str(ROOT), store=target)],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(3)]
        results = [p.communicate(timeout=120) for p in procs]
        assert [p.returncode for p in procs] == [0, 0, 0], [r[1][-500:] for r in results]
        with SessionStore(target) as s:
            assert s.schema_version == len(__import__("instrument.store", fromlist=["MIGRATIONS"]).MIGRATIONS)


@pytest.fixture
def recorded(tmp_path: Path):
    store_dir = tmp_path / "store"
    store = SessionStore(store_dir)
    store.add_subject(Subject("S01", mass_kg=70.0, shank_length_m=0.42))
    tid, path = store.begin_trial(store.new_session("S01"), "knee", {"joint": "knee"})
    w = TrialWriter(path, {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {})}, {"protocol": {"name": "knee"}})
    w.append("force_plate", _plate(0, 100))
    w.close()
    store.finish_trial(tid, "recorded", {})
    store.close()
    return store_dir, tid, path


def _bytes(*paths: Path) -> list[bytes]:
    return [p.read_bytes() for p in paths]


@pytest.mark.parametrize("target", ["data", "index", "inside", "sidecar_clash"])
def test_export_never_writes_over_an_input_or_inside_the_store(recorded, tmp_path: Path, capsys, target) -> None:
    store_dir, tid, path = recorded
    out = {"data": path, "index": store_dir / "store.sqlite", "inside": store_dir / "trials" / "x.csv",
           "sidecar_clash": tmp_path / "x.json"}[target]
    before = _bytes(path, store_dir / "store.sqlite")
    code = cli_main(["export", "--store", str(store_dir), str(tid), "--format", "csv", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and err[0].startswith("error:")
    assert _bytes(path, store_dir / "store.sqlite") == before
    assert target == "data" or target == "index" or not out.exists()


def test_a_corrupt_index_is_one_typed_line_and_the_trials_stay(recorded, capsys) -> None:
    store_dir, _, path = recorded
    (store_dir / "store.sqlite-wal").unlink(missing_ok=True)
    (store_dir / "store.sqlite").write_bytes(b"this is not a database" * 100)
    before = path.read_bytes()
    with pytest.raises(StoreError, match="not a readable store database"):
        SessionStore(store_dir)
    assert cli_main(["sessions", "--store", str(store_dir)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "store.sqlite" in err[0] and "not a readable store database" in err[0]
    assert path.read_bytes() == before


def test_a_read_only_opening_lists_a_store_it_cannot_write(recorded, monkeypatch, capsys) -> None:
    store_dir, tid, _ = recorded
    import instrument.store as store_module

    real = store_module.SessionStore

    def refuse_writes(root, *, read_only=False, **kw):
        if not read_only:
            raise store_module.StoreReadOnlyError(f"{root}: read-only file system")
        return real(root, read_only=True, **kw)

    monkeypatch.setattr(store_module, "SessionStore", refuse_writes)
    assert cli_main(["sessions", "--store", str(store_dir)]) == 0
    assert f"{tid:>5}" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [
    ["record", "--simulate", "--protocol", "knee", "--speed", "-5"],
    ["record", "--simulate", "--protocol", "knee", "--speed", "nan"],
    ["record", "--simulate", "--protocol", "knee", "--speed", "500"],
    ["record", "--simulate", "--protocol", "replica", "--hold", "inf"],
])
def test_out_of_range_record_arguments_are_usage_errors(argv, tmp_path: Path, capsys) -> None:
    with pytest.raises(SystemExit) as info:
        cli_main(argv + ["--store", str(tmp_path / "s")])
    assert info.value.code == 2
    assert "outside" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


@pytest.mark.parametrize("offset", [0, 700, 2048, -600])
def test_a_bit_flipped_trial_file_is_one_line_and_stays_as_it_was(recorded, tmp_path: Path, capsys,
                                                                   offset: int) -> None:
    store_dir, tid, path = recorded
    blob = bytearray(path.read_bytes())
    for k in range(64):  # a burst of flipped bits
        blob[offset + k] ^= 0xA5
    path.write_bytes(bytes(blob))
    code = cli_main(["export", "--store", str(store_dir), str(tid), "--format", "csv", "-o", str(tmp_path / "x.csv")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code in (0, 1) and (code == 0 or (len(err) == 1 and err[0].startswith("error:")))
    assert path.read_bytes() == bytes(blob)


def test_a_store_on_read_only_media_lists_and_exports(recorded, tmp_path: Path, capsys) -> None:
    """A real read-only mount (bind, ro) where this host allows one (root); skipped elsewhere."""
    import os
    import subprocess as sp

    store_dir, tid, _ = recorded
    mnt = tmp_path / "ro"
    mnt.mkdir()
    if os.geteuid() != 0 or sp.run(["mount", "--bind", str(store_dir), str(mnt)], capture_output=True).returncode:
        pytest.skip("needs root and mount to make read-only media")
    try:
        if sp.run(["mount", "-o", "remount,bind,ro", str(mnt)], capture_output=True).returncode:
            pytest.skip("cannot remount read-only here")
        assert cli_main(["sessions", "--store", str(mnt)]) == 0
        out = tmp_path / "export.csv"
        # a knee trial without dynamometer data: the export itself refuses, but as a data error
        code = cli_main(["export", "--store", str(mnt), str(tid), "--format", "csv", "-o", str(out)])
        err = capsys.readouterr().err
        assert code == 1 and "read-only" not in err and "readonly" not in err, err
    finally:  # a lazy unmount if a handle is still open, so no mount outlives the test
        if sp.run(["umount", str(mnt)], capture_output=True).returncode:
            sp.run(["umount", "-l", str(mnt)], capture_output=True)
