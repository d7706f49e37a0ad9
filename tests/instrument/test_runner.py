"""The Qt-free trial runner: limits refuse a protocol, the relaxation check marks a burst, e-stop ends a trial."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from instrument.errors import ProtocolError
from instrument.kinds.ankle import AnkleProtocol
from instrument.kinds.knee import KneeProtocol
from instrument.kinds.replica import ReplicaProtocol
from instrument.live.recording import read_trial
from instrument.live.runner import Checklist, SafetyLimits, TrialRunner, checklist_for
from instrument.live.sources import HardwareSource
from instrument.sim.source import SimulatedSource
from instrument.store import SessionStore, Subject


@pytest.fixture
def store(tmp_path: Path):
    s = SessionStore(tmp_path / "store")
    s.add_subject(Subject("R1", mass_kg=75.0))
    yield s
    s.close()


def test_limits_refuse_a_protocol_outside_them() -> None:
    limits = SafetyLimits(rom_deg=(0.0, 60.0), max_speed_deg_s=10.0)
    assert limits.violations(KneeProtocol(end_deg=90.0))  # leaves the ROM
    assert limits.violations(KneeProtocol(end_deg=50.0, speed_deg_s=20.0))  # too fast
    assert not limits.violations(KneeProtocol(end_deg=50.0))
    with pytest.raises(ProtocolError, match="range of motion"):
        TrialRunner(None, 0, KneeProtocol(end_deg=90.0), {"dynamometer": None}, limits=limits)  # type: ignore[arg-type]  # the limits are checked before any device is used


def test_checklists_name_the_set_up_of_each_protocol() -> None:
    knee = checklist_for(KneeProtocol(hip_flexion_deg=55.0))
    assert any("hip at 55°" in i for i in knee) and any("gravity" in i for i in knee)
    assert any("aligned" in i for i in checklist_for(AnkleProtocol(knee_flexion_deg=45.0)))
    c = Checklist(checklist_for(ReplicaProtocol()))
    assert not c.complete
    for i in range(len(c.items)):
        c.confirm(i)
    assert c.complete and not c.missing()


@pytest.mark.parametrize("seed", [0, 1])
def test_burst_is_flagged_at_its_angle_and_rejection_keeps_the_data(store: SessionStore, seed: int) -> None:
    rng = np.random.default_rng(seed)
    amplitude = float(rng.uniform(2.0, 5.0)) * (1 if seed % 2 == 0 else -1)
    delay = float(rng.uniform(1.0, 1.5))  # 10–15° into a 30° sweep, past the warm-up
    source = SimulatedSource(seed=seed)
    proto = KneeProtocol(end_deg=30.0, speed_deg_s=10.0)
    with source.devices(proto) as devices:
        runner = TrialRunner(store, store.new_session("R1"), proto, devices, extra_metadata=source.metadata())
        runner.start()
        assert runner.sweep_started.wait(20.0)
        source.inject_burst(amplitude, delay_s=delay)
        assert runner.wait(30.0)
    snap = runner.snapshot()
    assert snap.phase == "done" and snap.alarms
    reason = runner.suggested_rejection()
    assert reason is not None and "activation" in reason
    import re

    into = float(re.search(r"\(([0-9.]+) s into the trial", reason).group(1))  # type: ignore[union-attr]  # the reason was asserted to contain it
    assert 1.0 < into < 30.0, reason  # time in the trial, never the host's clock
    runner.reject(reason)
    rec = store.trial(snap.outcome.trial_id)
    assert rec.status == "rejected" and rec.reason == reason
    trial = read_trial(rec.path)
    assert trial.devices["dynamometer"].samples > 100
    events = [e for e in trial.events if e["kind"] == "activation"]
    assert events
    # the flag marks where in the sweep it happened: inside the sweep, after the burst began
    assert 8.0 <= events[0]["angle_deg"] <= 30.0
    assert events[0]["time_s"] >= snap.alarms[0].time_s - 1e-9


def test_relaxed_trial_is_not_flagged_and_can_be_accepted(store: SessionStore) -> None:
    source = SimulatedSource(seed=5)
    proto = AnkleProtocol(knee_flexion_deg=45.0, speed_deg_s=10.0)
    with source.devices(proto) as devices:
        runner = TrialRunner(store, store.new_session("R1"), proto, devices)
        runner.start()
        assert runner.wait(40.0)
    assert runner.snapshot().alarms == [] and runner.suggested_rejection() is None
    runner.accept()
    assert store.trial(runner.snapshot().outcome.trial_id).status == "accepted"


def test_verdict_before_the_end_is_refused_and_missing_urls_are_named(store: SessionStore) -> None:
    runner = TrialRunner(store, store.new_session("R1"), KneeProtocol(), {"dynamometer": None})  # type: ignore[dict-item]  # a missing device, on purpose
    with pytest.raises(ProtocolError, match="not finished"):
        runner.accept()
    with pytest.raises(ProtocolError, match="dynamometer"):
        with HardwareSource({}).devices(KneeProtocol()):
            pass


def test_aads_zeroes_the_plate_with_the_afo_lifted_and_runs_force_guided_without_markers(store: SessionStore) -> None:
    from drivers.simulation.aads_jig import AadsJig
    from instrument.kinds.aads import AadsProtocol

    assert AadsProtocol.devices == ("force_plate", "mocap")
    proto = AadsProtocol(spring=1, duration_s=3.0, live_markers=False, afo="test AFO")
    assert proto.devices == ("force_plate",) and AadsProtocol.devices == ("force_plate", "mocap")
    source = SimulatedSource(seed=2)
    with source.devices(proto) as devices:
        assert set(devices) == {"force_plate"}
        runner = TrialRunner(store, store.new_session("R1"), proto, devices)
        runner.start()
        assert runner.wait(30.0)
    snap = runner.snapshot()
    assert snap.phase == "done" and runner.suggested_rejection() is None  # no loop to judge without markers
    rec = store.trial(snap.outcome.trial_id)
    assert rec.condition["plate_zeroed_unloaded"] and rec.condition["afo"] == "test AFO"
    fz = read_trial(rec.path).devices["force_plate"].channels["force_n"][:, 2]
    geo = AadsJig().geometry
    weight = (geo.foot_mass_kg + geo.shank_mass_kg) * 9.81
    # zeroed with nothing on the plate, it reads at least the AFO's weight (plus the operator's push)
    assert np.percentile(fz, 5) > 0.9 * weight


def test_a_bend_past_the_stop_is_in_the_trials_record(store: SessionStore) -> None:
    """The live AADS loop's 'past the stop' goes into the trial file as an event (not only on screen)."""
    from instrument.kinds.aads import AadsProtocol

    source = SimulatedSource(seed=3)
    peaks, marked = [], []
    for operator in (2,):  # the simulated operator who bends hardest (to 25° with this seed)
        proto = AadsProtocol(spring=1, operator=operator, duration_s=12.0)
        with source.devices(proto) as devices:
            runner = TrialRunner(store, store.new_session("R1"), proto, devices)
            runner.start()
            assert runner.wait(60.0)
        snap = runner.snapshot()
        events = [e for e in read_trial(store.trial(snap.outcome.trial_id).path).events if e["kind"] == "past_stop"]
        peaks.append(snap.aads_peak_deg)
        marked.append(bool(events))
        assert bool(events) == bool(snap.aads_past_stop)  # flagged live exactly when recorded
        if events:
            assert events[0]["peak_deg"] > events[0]["stop_deg"] == proto.stop_deg
    assert all(marked), f"the simulated bend did not pass the stop (peaks {peaks})"
