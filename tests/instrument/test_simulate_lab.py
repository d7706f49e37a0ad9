"""The simulated lab as its own process: a lab file whose devices answer from another process exactly as
real ones do (the CiA 402 drive through an slcan adapter on a pty, Modbus RTU and the plate over TCP, LSL)."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import can
import pytest

from drivers.simulation.slcan_pty import decode, encode
from instrument.cli import main


def test_slcan_lines_round_trip() -> None:
    msg = can.Message(arbitration_id=0x190, data=bytes([1, 2, 0xAB]), is_extended_id=False)
    assert encode(msg) == b"t19030102AB\r"
    back = decode(b"t19030102AB")
    assert back is not None and back.arbitration_id == 0x190 and bytes(back.data) == bytes([1, 2, 0xAB])
    ext = decode(b"T1234567820102")
    assert ext is not None and ext.is_extended_id and ext.arbitration_id == 0x12345678
    for bad in (b"t19", b"t1903zz", b"t1909" + b"00" * 9, b"x", b""):
        assert decode(bad) is None


def test_another_process_s_simulated_lab_answers_through_its_lab_file(tmp_path: Path,
                                                                        capsys: pytest.CaptureFixture[str]) -> None:
    lab_file = tmp_path / "lab.toml"
    server = subprocess.Popen([sys.executable, "-m", "instrument", "simulate-lab", "--lab-file", str(lab_file),
                               "--seconds", "60"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 40.0
        while not lab_file.exists() and server.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
        assert lab_file.exists(), server.stdout.read() if server.poll() is not None and server.stdout else "no lab file"
        text = lab_file.read_text(encoding="utf-8")
        assert 'dynamometer = "canopen://slcan//dev/pts/' in text and "[streams]" in text
        assert main(["devices", "--lab", str(lab_file)]) == 0
        lines = capsys.readouterr().out.splitlines()
    finally:
        server.terminate()
        server.wait(20)
    assert [ln.split()[0] for ln in lines] == ["dynamometer", "force_plate", "torque_sensor", "goniometer", "emg"]
    assert all("answers:" in ln for ln in lines), lines
    assert "CiA 402 (CANopen), limits ROM -35..95°" in lines[0]
    assert "hip_flexion (degrees)" in lines[3] and "rectus_femoris (V)" in lines[4]


def test_the_demo_repeats_a_replica_trial_whose_hold_lost_its_readings(tmp_path: Path,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """A host stalled past the transmitter's history loses a hold (counted): the demo records the trial again, as an
    operator would, and fits the pooled holds."""
    from instrument.kinds import replica
    from instrument.kinds.replica import ReplicaProtocol
    from instrument.sim import demo
    from instrument.sim.lab_day import SUBJECT, record_repeat
    from instrument.store import SessionStore

    with SessionStore(tmp_path / "store") as store:
        store.add_subject(SUBJECT)
        first = record_repeat(store, ReplicaProtocol(hold_s=0.5), seed=9, note="the day's replica trial")
    assert first.status == "recorded"
    real = replica.holds_short_of_readings
    # the first trial's hold at 8° taken as lost (a stall cannot be made on demand); with the repeat it is pooled
    monkeypatch.setattr(replica, "holds_short_of_readings",
                        lambda tables, share=0.5: [8.0] if len(tables) == 1 else real(tables, share))
    result, ok = demo.replica_leg(tmp_path)
    assert ok and {"VASINT.stiffness_n_per_m", "RECFEM.stiffness_n_per_m"} <= set(result["determined"])
    with SessionStore(tmp_path / "store", read_only=True) as store:
        assert [t.protocol for t in store.trials()] == ["replica", "replica"]
