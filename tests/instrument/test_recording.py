"""Trial files: round trip, gaps, SIGKILL recovery, disk full, corrupted files."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from drivers.blocks import DynamometerBlock, ForcePlateBlock
from instrument.errors import CorruptFileError
from instrument.live.recording import DeviceSpec, TrialWriter, read_trial, recover_trial_file
from instrument.store import SessionStore, Subject

ROOT = Path(__file__).resolve().parents[2]


def plate_block(start: int, n: int = 16) -> dict[str, np.ndarray]:
    c = np.arange(start, start + n, dtype=np.int64)
    return {"counter": c, "time_s": c / 1000.0, "force_n": np.column_stack([c, -c, c * 0.5]).astype(float),
            "moment_nm": np.zeros((n, 3)), "cop_m": np.zeros((n, 2)), "free_moment_nm": np.zeros(n),
            "trigger": (c % 1000 == 0).astype(np.uint8)}


def test_round_trip_keeps_every_sample_and_records_gaps(tmp_path: Path) -> None:
    w = TrialWriter(tmp_path / "t.h5", {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {"serial": "X1"})},
                    {"protocol": {"name": "aads"}}, flush_interval_s=0.05)
    starts = [0, 16, 32, 60, 76, 200]  # gaps after 47 (12 lost) and after 91 (108 lost)
    for s in starts:
        w.append("force_plate", plate_block(s))
    w.log_event("note", text="operator pushed twice")
    w.close(summary={"ok": True})
    t = read_trial(tmp_path / "t.h5")
    d = t.devices["force_plate"]
    assert t.status == "recorded" and d.identity == {"serial": "X1"}
    assert d.samples == 16 * len(starts)
    assert d.gaps.tolist() == [[47, 60], [91, 200]] and d.lost_samples == 12 + 108
    np.testing.assert_array_equal(d.channels["force_n"][:, 0], d.channels["counter"].astype(float))
    assert t.events[0]["text"] == "operator pushed twice" and t.summary["ok"] is True


WRITER_SCRIPT = textwrap.dedent("""
    import sys, time, numpy as np
    sys.path.insert(0, {root!r})
    from instrument.store import SessionStore, Subject
    from instrument.live.recording import TrialWriter, DeviceSpec
    from drivers.blocks import DynamometerBlock
    store = SessionStore({store!r})
    store.add_subject(Subject("S01"))
    session = store.new_session("S01")
    trial_id, path = store.begin_trial(session, "knee", {{"hip_flexion_deg": 90}})
    w = TrialWriter(path, {{"dynamometer": DeviceSpec(DynamometerBlock.LAYOUT, {{}})}}, {{"protocol": {{"name": "knee"}}}},
                    flush_interval_s=0.1)
    n = 0
    while True:
        c = np.arange(n, n + 10)
        w.append("dynamometer", {{"counter": c, "time_s": c / 100, "torque_nm": c * 0.1, "position_rad": c * 1e-3,
                                  "velocity_rad_s": np.zeros(10), "state": np.ones(10, np.uint8)}})
        n += 10
        if n == 300:
            print("flushed-300", flush=True)
        time.sleep(0.01)
""")


def test_sigkill_mid_recording_is_recovered_as_interrupted(tmp_path: Path) -> None:
    store_dir = tmp_path / "store"
    proc = subprocess.Popen([sys.executable, "-c", WRITER_SCRIPT.format(root=str(ROOT), store=str(store_dir))],
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "flushed-300"
    time.sleep(0.5)  # several more flushes
    proc.send_signal(signal.SIGKILL)
    proc.wait(5)
    store = SessionStore(store_dir)
    assert len(store.recovered) == 1 and store.recovered[0].readable
    (trial,) = store.trials()
    assert trial.status == "interrupted" and "last flush" in (trial.reason or "")
    samples = trial.devices["dynamometer"]["samples"]
    assert samples >= 300
    t = read_trial(trial.path)  # the file is clean now: opens without SWMR
    assert t.status == "interrupted"
    torque = t.devices["dynamometer"].channels["torque_nm"]
    np.testing.assert_allclose(torque, np.arange(samples) * 0.1)
    assert SessionStore(store_dir).recovered == []  # recovered once, not again


DISK_FULL_SCRIPT = textwrap.dedent("""
    import resource, signal, sys, numpy as np
    sys.path.insert(0, {root!r})
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    from instrument.store import SessionStore
    from instrument.live.recording import TrialWriter, DeviceSpec
    from instrument.errors import DiskFullError
    from drivers.blocks import ForcePlateBlock
    store = SessionStore({store!r})
    session = store.new_session("S01")
    trial_id, path = store.begin_trial(session, "aads", {{}})
    resource.setrlimit(resource.RLIMIT_FSIZE, (3_000_000, 3_000_000))  # a 3 MB disk for the data files
    w = TrialWriter(path, {{"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {{}})}}, {{}}, flush_interval_s=0.02)
    n = 0
    try:
        for k in range(4000):
            c = np.arange(n, n + 100); n += 100
            w.append("force_plate", {{"counter": c, "time_s": c / 1e3, "force_n": np.ones((100, 3)),
                                      "moment_nm": np.ones((100, 3)), "cop_m": np.ones((100, 2)),
                                      "free_moment_nm": np.ones(100), "trigger": np.zeros(100, np.uint8)}})
            import time; time.sleep(0.002)
        w.close()
        print("no-error")
    except DiskFullError as err:
        w.abort()
        store.finish_trial(trial_id, "failed", {{}}, reason=str(err))
        print("DiskFullError:", err)
""")


def test_disk_full_is_a_clear_error_and_earlier_trials_stay_intact(tmp_path: Path) -> None:
    store_dir = tmp_path / "store"
    store = SessionStore(store_dir)
    store.add_subject(Subject("S01"))
    session = store.new_session("S01")
    tid, path = store.begin_trial(session, "aads", {})
    w = TrialWriter(path, {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {})}, {})
    w.append("force_plate", plate_block(0, 500))
    w.close()
    store.finish_trial(tid, "recorded", {"force_plate": {"samples": 500}})
    store.close()
    out = subprocess.run([sys.executable, "-c", DISK_FULL_SCRIPT.format(root=str(ROOT), store=str(store_dir))],
                         capture_output=True, text=True, timeout=60)
    assert "DiskFullError:" in out.stdout, out.stdout + out.stderr
    assert "data up to the last flush is kept" in out.stdout
    assert out.returncode == 0, out.stderr[-2000:]  # no crash at exit (HDF5 once retried its writes: SIGSEGV)
    store = SessionStore(store_dir)  # opening repairs the failed trial's file (the disk has room again)
    first, second = store.trials()
    assert first.status == "recorded" and read_trial(first.path).devices["force_plate"].samples == 500
    assert second.status == "failed" and "write failed" in (second.reason or "") and "recovered" in second.reason
    part = read_trial(second.path).devices["force_plate"]  # what was written before the disk filled
    assert part.samples > 1000
    np.testing.assert_array_equal(part.channels["counter"], np.arange(part.samples))
    assert (part.channels["force_n"] == 1.0).all(), "rows past the end of the file must be cut, not zero-filled"


def test_corrupted_and_truncated_files_name_the_file_and_the_defect(tmp_path: Path) -> None:
    good = tmp_path / "good.h5"
    w = TrialWriter(good, {"force_plate": DeviceSpec(ForcePlateBlock.LAYOUT, {})}, {})
    w.append("force_plate", plate_block(0, 5000))
    w.close()
    truncated = tmp_path / "truncated.h5"
    truncated.write_bytes(good.read_bytes()[:2000])
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(os.urandom(4096))
    empty = tmp_path / "empty.h5"
    empty.write_bytes(b"")
    for path, words in ((truncated, "truncated"), (garbage, "not a readable HDF5"), (empty, "empty"),
                        (tmp_path / "missing.h5", "does not exist")):
        with pytest.raises(CorruptFileError) as info:
            read_trial(path)
        assert str(path) in str(info.value) and words in str(info.value)
    report = recover_trial_file(garbage)
    assert not report.readable and garbage.exists()  # never deleted
    import h5py
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = [1, 2, 3]
    with pytest.raises(CorruptFileError, match="not an instrument trial"):
        read_trial(tmp_path / "other.h5")


def test_metadata_snapshot_is_json_with_numpy_values(tmp_path: Path) -> None:
    meta = {"calibration": np.eye(6), "zero_v": np.float32(0.5), "software": {"version": "x"}}
    w = TrialWriter(tmp_path / "m.h5", {"dynamometer": DeviceSpec(DynamometerBlock.LAYOUT, {"limits": {"a": 1}})}, meta)
    w.close()
    t = read_trial(tmp_path / "m.h5")
    assert np.allclose(t.metadata["calibration"], np.eye(6)) and t.metadata["zero_v"] == 0.5
    assert json.loads(json.dumps(t.metadata)) == t.metadata


CLI_DISK_FULL = textwrap.dedent("""
    import resource, signal, sys
    sys.path.insert(0, {root!r})
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (1_200_000, 1_200_000))  # the data file outgrows it mid-trial
    from instrument.cli import main
    sys.exit(main(["record", "--simulate", "--protocol", "aads", "--store", {store!r}]))
""")


def test_record_on_a_full_disk_exits_with_one_line_and_keeps_what_reached_the_disk(tmp_path: Path) -> None:
    store_dir = tmp_path / "store"
    out = subprocess.run([sys.executable, "-c", CLI_DISK_FULL.format(root=str(ROOT), store=str(store_dir))],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 1, (out.returncode, out.stderr[-2000:])
    last = out.stderr.strip().splitlines()[-1]
    assert last.startswith("error:") and "disk full" in last and "Traceback" not in out.stderr
    store = SessionStore(store_dir, recover=False)
    (trial,) = store.trials()
    assert trial.status == "failed" and "disk full" in (trial.reason or "")
    data = read_trial(trial.path)  # readable at once, before any recovery
    plate = data.devices["force_plate"]
    assert plate.samples > 0
    np.testing.assert_array_equal(np.diff(plate.channels["counter"]), 1)
    assert np.isfinite(plate.channels["force_n"]).all() and (plate.channels["time_s"] > 0).all()
    store.close()
