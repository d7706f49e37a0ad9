"""Acquisition engine with the simulators: ring buffers, a vanishing device, alignment."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np

from analysis.timebase import align, resample
from drivers.simulation.faults import FaultConfig
from instrument.kinds.aads import AadsProtocol
from instrument.live.acquisition import RingBuffer
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.sim.simulate import lab_config_for, simulated_devices
from instrument.store import SessionStore, Subject


def test_ring_buffer_wraps_and_a_slow_reader_never_blocks_the_writer() -> None:
    ring = RingBuffer({"counter": ((), "i8"), "time_s": ((), "f8"), "force_n": ((3,), "f8")}, capacity=100)
    stop = threading.Event()
    reads = []

    def slow_reader() -> None:
        while not stop.is_set():
            reads.append(ring.latest(50))
            time.sleep(0.02)

    t = threading.Thread(target=slow_reader)
    t.start()
    for k in range(2000):
        c = np.arange(k * 7, k * 7 + 7)
        ring.write({"counter": c, "time_s": c / 1e3, "force_n": np.repeat(c[:, None], 3, 1).astype(float)})
    stop.set()
    t.join()
    assert ring.total == 14000 and len(reads) >= 1  # every write landed while the reader was busy
    last = ring.latest()
    np.testing.assert_array_equal(last["counter"], np.arange(14000 - 100, 14000))
    for r in reads:  # every snapshot is consecutive samples, oldest first
        assert (np.diff(r["counter"]) == 1).all()


def test_resample_never_bridges_a_gap() -> None:
    t = np.concatenate([np.arange(0, 1, 0.01), np.arange(1.5, 2, 0.01)])
    grid = np.arange(0, 2, 0.005)
    v = resample(t, np.sin(t), grid, max_gap_s=0.025)
    inside_gap = (grid > 0.99) & (grid < 1.5)
    assert np.isnan(v[inside_gap]).all()
    ok = ~np.isnan(v)
    np.testing.assert_allclose(v[ok], np.sin(grid[ok]), atol=2e-5)
    grid2, out = align({"a": (t, t, 100.0), "b": (np.arange(0, 2, 0.001), np.arange(0, 2, 0.001), 1000.0)}, 100.0)
    assert np.isnan(out["a"][(grid2 > 1.0) & (grid2 < 1.5)]).all()
    np.testing.assert_allclose(out["b"], grid2, atol=1e-9)


def test_device_vanishing_mid_trial_keeps_the_data_and_marks_the_trial(tmp_path: Path) -> None:
    store = SessionStore(tmp_path)
    store.add_subject(Subject("S01"))
    session = store.new_session("S01")
    proto = AadsProtocol(spring=1, duration_s=3.0)
    cfg = lab_config_for(proto)
    cfg.plate_faults = FaultConfig(disconnect_after_s=1.0, reconnect_after_s=0.6)
    with simulated_devices(proto, cfg) as (_, devices):
        out = record_trial(store, session, proto, devices)
    assert out.status == "interrupted" and "force_plate: link lost" in (out.reason or "")
    trial = read_trial(out.path)
    fp = trial.devices["force_plate"]
    assert fp.samples > 1500  # before and after the hole
    assert len(fp.gaps) >= 1 and fp.lost_samples >= 400  # the hole is recorded, not papered over
    assert trial.devices["mocap"].samples > 250
    assert any(e["kind"] == "device_error" and e["device"] == "force_plate" for e in trial.events)
    assert store.trial(out.trial_id).status == "interrupted"


def test_the_health_line_tells_unanswered_polls_from_bad_frames() -> None:
    from drivers import DeviceStats
    from instrument.live.acquisition import device_health_text

    st = DeviceStats(samples=101, gaps=2, lost_samples=3, first_time_s=0.0, last_time_s=1.0)
    assert device_health_text("torque_sensor", "connected", st) == "torque_sensor: connected, 100 Hz, 2 gaps, 3 lost"
    st.poll_timeouts, st.crc_errors, st.malformed_frames = 2, 1, 0
    assert device_health_text("torque_sensor", "connected", st).endswith("3 lost, 2 unanswered polls, 1 bad frames")
    st.command_retries = 1  # a START whose reply was lost: sent again, and the operator is told
    assert device_health_text("torque_sensor", "connected", st).endswith(
        "1 bad frames, 1 commands answered only when sent again")
    assert device_health_text("mocap", "closed", DeviceStats()) == "mocap: closed"
