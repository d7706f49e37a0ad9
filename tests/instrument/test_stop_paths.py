"""Every path that ends an isokinetic trial leaves the arm halted, and the trial says how.

Paths: the operator's Stop, the emergency stop (delivered, one frame lost, every frame lost), a
limit breach, and an error inside the protocol. Assertions are on the device's state, the
telemetry and the trial's events (counts, order, content), never on wall-clock rates.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from drivers.dynamometer.protocol import State
from instrument.kinds.knee import KneeProtocol
from instrument.live.recording import read_trial
from instrument.live.runner import ESTOP_RESENDS, SafetyLimits, TrialRunner
from instrument.sim.source import SimulatedSource
from instrument.store import SessionStore, Subject


@pytest.fixture
def store(tmp_path: Path):
    s = SessionStore(tmp_path / "store")
    s.add_subject(Subject("S01", mass_kg=75.0))
    yield s
    s.close()


def _kinds(path: Path) -> list[str]:
    return [e["kind"] for e in read_trial(path).events]


def _final_velocity(path: Path) -> float:
    """The arm's velocity (°/s) in the trial's last telemetry sample."""
    d = read_trial(path).devices["dynamometer"].channels
    return float(np.rad2deg(d["velocity_rad_s"][-1]))


def _run(store: SessionStore, stop_how, *, lose_estop_frames: int = 0, limits: SafetyLimits | None = None):
    source = SimulatedSource(seed=11)
    proto = KneeProtocol(end_deg=60.0, speed_deg_s=20.0)
    with source.devices(proto) as devices:
        sim = source.lab.dynamometer  # type: ignore[union-attr]  # inside the source's trial the lab is set
        sim.lose_estop_frames = lose_estop_frames
        runner = TrialRunner(store, store.new_session("S01"), proto, devices, limits=limits)
        runner.start()
        assert runner.sweep_started.wait(20.0)
        assert runner.stop_event.wait(0.5) is False  # mid-sweep
        stop_how(runner, sim)
        assert runner.wait(30.0)
        final_state, moving_at_end = sim.state, sim.state == State.MOVING
        lost = sim.estop_frames_lost
    snap = runner.snapshot()
    assert snap.phase == "done", snap.error
    return snap, final_state, moving_at_end, lost


def test_operator_stop_halts_the_arm(store: SessionStore) -> None:
    snap, state, moving, _ = _run(store, lambda r, sim: r.request_stop())
    assert not moving and state == State.HOLDING
    path = store.trial(snap.outcome.trial_id).path
    kinds = _kinds(path)
    assert "halted" in kinds and "sweep_end" in kinds and kinds.index("sweep_end") < kinds.index("halted")
    assert _final_velocity(path) == 0.0
    assert store.trial(snap.outcome.trial_id).status == "interrupted"


def test_emergency_stop_is_confirmed_by_the_device(store: SessionStore) -> None:
    snap, state, _, lost = _run(store, lambda r, sim: r.emergency_stop("test"))
    assert state == State.ESTOP and lost == 0
    assert snap.estop_confirmed_s is not None and snap.estop_unconfirmed is None
    kinds = _kinds(store.trial(snap.outcome.trial_id).path)
    assert kinds.count("emergency_stop_resent") == 0 and "emergency_stop_confirmed" in kinds


def test_a_lost_estop_frame_is_sent_again_and_confirmed(store: SessionStore) -> None:
    snap, state, _, lost = _run(store, lambda r, sim: r.emergency_stop("test"), lose_estop_frames=1)
    assert lost == 1 and state == State.ESTOP
    assert snap.estop_confirmed_s is not None and snap.estop_unconfirmed is None
    kinds = _kinds(store.trial(snap.outcome.trial_id).path)
    assert kinds.count("emergency_stop_resent") >= 1
    assert kinds.index("emergency_stop") < kinds.index("emergency_stop_resent") < kinds.index("emergency_stop_confirmed")


def test_an_estop_that_never_arrives_halts_by_command_and_alarms(store: SessionStore) -> None:
    snap, state, moving, lost = _run(store, lambda r, sim: r.emergency_stop("test"), lose_estop_frames=1000)
    assert lost == 1 + ESTOP_RESENDS
    assert not moving and state in (State.HOLDING, State.FAULT)
    assert snap.estop_unconfirmed is not None and "did not confirm" in snap.estop_unconfirmed
    rec = store.trial(snap.outcome.trial_id)
    assert rec.status == "interrupted" and "did not confirm" in (rec.reason or "")
    kinds = _kinds(rec.path)
    assert "emergency_stop_unconfirmed" in kinds and "halted" in kinds and "heartbeat_withdrawn" in kinds
    assert _final_velocity(rec.path) == 0.0


def test_a_limit_breach_stops_the_arm(store: SessionStore) -> None:
    # the sweep goes to 60°, the runner's envelope ends at 40° (+2° tolerance): the stream breaches it
    limits = SafetyLimits(rom_deg=(-5.0, 65.0))

    def narrow(runner: TrialRunner, sim) -> None:
        object.__setattr__(runner.limits, "rom_deg", (-5.0, 30.0))

    snap, state, _, _ = _run(store, narrow, limits=limits)
    assert snap.limit_breaches and state == State.ESTOP
    assert snap.estop_confirmed_s is not None


def test_the_device_enforces_a_rom_narrowed_mid_move(store: SessionStore) -> None:
    def narrow(runner: TrialRunner, sim) -> None:
        sim.rom_deg = (sim.rom_deg[0], sim.position_deg + 2.0)

    snap, state, _, _ = _run(store, narrow)
    assert state == State.FAULT
    path = store.trial(snap.outcome.trial_id).path
    pos = np.rad2deg(read_trial(path).devices["dynamometer"].channels["position_rad"])
    assert pos.max() < 60.0 - 5.0  # stopped at the narrowed stop, far from the sweep's end


def test_an_estop_just_before_the_protocols_next_move_ends_the_trial_with_its_data(store: SessionStore) -> None:
    # the race a closing window met: the e-stop goes out between the sweep's start mark and its move command;
    # the driver refuses the move, and the trial ends interrupted with the device's words, nothing lost
    from instrument.live.session import record_trial

    source = SimulatedSource(seed=12)
    proto = KneeProtocol(end_deg=60.0, speed_deg_s=20.0)
    with source.devices(proto) as devices:
        sim = source.lab.dynamometer  # type: ignore[union-attr]  # inside the source's trial the lab is set
        dyno = devices["dynamometer"]

        def on_event(kind: str, fields: dict) -> None:
            if kind == "sweep_start":
                dyno.emergency_stop()  # type: ignore[attr-defined]  # the knee protocol's device is a Dynamometer

        outcome = record_trial(store, store.new_session("S01"), proto, devices, on_event=on_event)
        assert sim.state == State.ESTOP
    rec = store.trial(outcome.trial_id)
    assert rec.status == "interrupted" and "emergency stop" in (rec.reason or "")
    kinds = _kinds(rec.path)
    assert kinds.index("sweep_start") < kinds.index("protocol_ended") < kinds.index("halted")
    assert read_trial(rec.path).devices["dynamometer"].samples > 10
