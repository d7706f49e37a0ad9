"""Exports: sto/csv/c3d round trips preserve values and units; bad files give clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from analysis.c3d import read_c3d, write_c3d
from analysis.errors import DataFileError
from analysis.motion import MotionTrial
from analysis.sto import read_sto, write_sto
from analysis.trial_csv import TrialTable, read_trial_csv, write_trial_csv
from instrument import kinds
from instrument.kinds.aads import AadsProtocol
from instrument.kinds.knee import KneeProtocol
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.offline.export import export_trial
from instrument.sim.simulate import simulated_devices, simulation_metadata
from instrument.store import SessionStore, Subject


def synthetic_motion(seed: int = 0) -> MotionTrial:
    rng = np.random.default_rng(seed)
    n, k = 40, 400
    force = np.column_stack([rng.normal(0, 20, k), rng.normal(0, 10, k), 80 + 60 * rng.random(k)])
    cop = np.column_stack([rng.normal(0, 0.05, k), rng.normal(0, 0.03, k), np.zeros(k)])
    # markers where a foot's are, moving by millimetres between frames (a lab's data; 0.2 m jumps are refused)
    markers = rng.normal(0, 0.2, (1, 4, 3)) + np.cumsum(rng.normal(0, 0.002, (n, 4, 3)), axis=0)
    return MotionTrial(np.arange(n) / 100, markers, ["RTOE1", "RHEE", "RMMAL", "RLMAL"],
                       np.arange(k) / 1000, force, cop, rng.normal(0, 0.5, k))


def test_c3d_round_trip_preserves_markers_forces_cop_and_free_moment(tmp_path: Path) -> None:
    m = synthetic_motion()
    write_c3d(tmp_path / "t.c3d", m)
    r = read_c3d(tmp_path / "t.c3d")
    assert r.marker_labels == m.marker_labels
    np.testing.assert_allclose(r.markers_m, m.markers_m, atol=1e-7)        # m (written in mm, float32)
    np.testing.assert_allclose(r.force_n, m.force_n, atol=2e-5)            # N
    np.testing.assert_allclose(r.cop_m, m.cop_m, atol=1e-7)                # m
    np.testing.assert_allclose(r.free_moment_nm, m.free_moment_nm, atol=1e-6)  # N·m
    np.testing.assert_allclose(r.plate_time_s, m.plate_time_s, atol=1e-12)


def test_c3d_bad_inputs(tmp_path: Path) -> None:
    (tmp_path / "junk.c3d").write_bytes(b"\x02\x50" + bytes(600))
    with pytest.raises(DataFileError, match="junk.c3d"):
        read_c3d(tmp_path / "junk.c3d")
    good = tmp_path / "good.c3d"
    write_c3d(good, synthetic_motion())
    (tmp_path / "cut.c3d").write_bytes(good.read_bytes()[:1500])
    with pytest.raises(DataFileError, match="cut.c3d"):
        read_c3d(tmp_path / "cut.c3d")
    # a damaged float (its exponent byte flipped) in the marker data: refused, not analysed (C3D has no checksum)
    import struct

    raw = bytearray(good.read_bytes())
    data_start = (struct.unpack_from("<H", raw, 16)[0] - 1) * 512  # header word 9: the data's first block
    raw[data_start + 10 * (len(synthetic_motion().marker_labels) * 16 + 6 * 10 * 4) + 3] = 0x7E  # x of frame 10
    (tmp_path / "flipped.c3d").write_bytes(bytes(raw))
    with pytest.raises(DataFileError, match="flipped.c3d: corrupt data: marker"):
        read_c3d(tmp_path / "flipped.c3d")
    blob = good.read_bytes()  # half a file reads as a shorter, plausible trial unless the header is checked
    (tmp_path / "half.c3d").write_bytes(blob[:len(blob) // 2])
    with pytest.raises(DataFileError, match="truncated: the header declares"):
        read_c3d(tmp_path / "half.c3d")
    import ezc3d
    c = ezc3d.c3d()
    c["parameters"]["POINT"]["RATE"]["value"] = [100.0]
    c["parameters"]["POINT"]["LABELS"]["value"] = ["A"]
    c["data"]["points"] = np.ones((4, 1, 5))
    c.write(str(tmp_path / "noplate.c3d"))
    with pytest.raises(DataFileError, match="no force platform"):
        read_c3d(tmp_path / "noplate.c3d")
    assert read_c3d(tmp_path / "noplate.c3d", require_plate=False).markers_m.shape == (5, 1, 3)


def test_sto_and_csv_round_trips(tmp_path: Path) -> None:
    t = np.linspace(0, 18, 1801)
    cols = {"time": t, "knee_angle_r": 5 * t, "knee_angle_r_moment": np.sin(t) * 12.345678901}
    write_sto(tmp_path / "k.sto", cols)
    back, header = read_sto(tmp_path / "k.sto")
    assert header["inDegrees"] == "yes" and header["nRows"] == "1801"
    for k in cols:
        np.testing.assert_allclose(back[k], cols[k], rtol=1e-11, atol=1e-12)
    table = TrialTable({"time_s": t, "angle_deg": 5 * t, "torque_Nm": np.cos(t), "velocity_deg_s": np.full_like(t, 5)},
                       {"kind": "knee", "hip_flexion_deg": 90.0, "subject": {"mass_kg": 75.0}})
    write_trial_csv(tmp_path / "k.csv", table)
    r = read_trial_csv(tmp_path / "k.csv")
    assert r.sidecar == table.sidecar
    for k, v in table.columns.items():
        np.testing.assert_array_equal(r.columns[k], v)  # 17 significant digits: exact
    text = (tmp_path / "k.sto").read_text().splitlines()
    (tmp_path / "cut.sto").write_text("\n".join(text[:100]))
    with pytest.raises(DataFileError, match="truncated"):
        read_sto(tmp_path / "cut.sto")
    (tmp_path / "bad.csv").write_text("time_s,torque_Nm\n0,1\n")
    with pytest.raises(DataFileError, match="angle_deg"):
        read_trial_csv(tmp_path / "bad.csv")


def test_arm_weight_compensation_signs() -> None:
    # knee: arm horizontal at 0° pulls toward flexion; hanging at 90° it pulls nowhere
    np.testing.assert_allclose(kinds.get("knee").arm_gravity_nm(np.array([0.0, 90.0]), 2.0, 0.25, {}), [4.905, 0.0], atol=1e-12)
    # ankle, knee at 90°: footplate horizontal at 0° dorsiflexion, gravity plantarflexes
    assert kinds.get("ankle").arm_gravity_nm(np.array([0.0]), 2.0, 0.25, {"knee_flexion_deg": 90.0})[0] == pytest.approx(-4.905)


def test_recorded_trials_export_with_the_documented_conventions(tmp_path: Path) -> None:
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01", mass_kg=75.0))
    session = store.new_session("S01")
    knee = KneeProtocol(end_deg=12.0, speed_deg_s=10.0)
    with simulated_devices(knee) as (lab, devices):
        out = record_trial(store, session, knee, devices, extra_metadata=simulation_metadata(lab))
        leg = lab.config.leg
    trial = read_trial(out.path)
    files = export_trial(trial, "csv", tmp_path / "knee.csv", {"mass_kg": 75.0})
    table = read_trial_csv(files[0])
    assert table.sidecar["kind"] == "knee" and table.sidecar["hip_flexion_deg"] == 90.0
    at_speed = np.abs(table.columns["velocity_deg_s"] - 10.0) < 0.05
    steady = at_speed & np.roll(at_speed, 1) & np.roll(at_speed, -1)  # not the sample the ramp ends on
    # torque against flexion = passive + limb weight (arm weight removed), plus damping while moving
    expected = -(leg.passive_moment_nm(table.angle_deg) + leg.gravity_moment_nm(table.angle_deg, include_arm=False))
    expected += leg.damping_nm_s_per_rad * np.deg2rad(10.0)
    assert steady.sum() > 50
    err = table.torque_nm[steady] - expected[steady]
    assert np.abs(err).max() < 0.4 and abs(err.mean()) < 0.1  # 0.05 N·m noise; one 10 ms sample ≈ 0.25 N·m here
    # the same trial as C3D, as a Vicon lab keeps a dynamometer: analog channels with units, marks as events
    import ezc3d

    export_trial(trial, "c3d", tmp_path / "knee.c3d")
    c = ezc3d.c3d(str(tmp_path / "knee.c3d"))
    p = c["parameters"]
    assert p["ANALOG"]["LABELS"]["value"] == ["Torque", "TorqueLimb", "Angle", "Velocity"]
    assert p["ANALOG"]["UNITS"]["value"] == ["Nm", "Nm", "deg", "deg/s"]
    assert p["ANALOG"]["RATE"]["value"][0] == pytest.approx(100.0)
    analog = c["data"]["analogs"][0]
    dyno = trial.devices["dynamometer"].channels
    assert analog.shape[1] == int(dyno["counter"][-1] - dyno["counter"][0] + 1)
    assert np.allclose(analog[2, :len(dyno["position_rad"])][:50], np.rad2deg(dyno["position_rad"][:50]), atol=1e-4)
    assert p["DYNAMOMETER"]["HIP_FLEXION_DEG"]["value"][0] == 90.0 and p["DYNAMOMETER"]["JOINT"]["value"] == ["knee"]
    assert {"sweep_start", "sweep_end"} <= set(p["EVENT"]["LABELS"]["value"])
    aads = AadsProtocol(spring=3, duration_s=1.5)
    with simulated_devices(aads) as (lab, devices):
        out = record_trial(store, session, aads, devices)
    trial = read_trial(out.path)
    files = export_trial(trial, "csv", tmp_path / "a.csv")
    afo = read_trial_csv(files[0])
    assert afo.sidecar["kind"] == "afo" and afo.sidecar["stiffness"]["spring_n_per_m"] == 25200.0
    # the CSV carries the static-optimisation torque; the foot free body gives the same numbers
    assert np.allclose(afo.torque_nm, afo.columns["bottom_up_torque_Nm"], atol=1e-9)
    export_trial(trial, "c3d", tmp_path / "a.c3d")
    c3d = read_c3d(tmp_path / "a.c3d")
    fp = trial.devices["force_plate"].channels
    assert c3d.marker_labels[:4] == ["RTOE1", "RTOE5", "RMCUN", "RHEE"]
    assert abs(np.nanmean(c3d.force_n[:, 2]) - np.mean(fp["force_n"][:, 2])) < 2.0
    export_trial(trial, "sto", tmp_path / "a.mot")
    cols, _ = read_sto(tmp_path / "a.mot")
    assert "ground_force_vz" in cols and abs(np.mean(cols["ground_force_vz"]) - np.mean(fp["force_n"][:, 2])) < 2.0


def _replica_table(tmp_path: Path, name: str) -> TrialTable:
    """One seeded replica trial (0.3 s holds) recorded through the Modbus driver and exported."""
    from instrument.kinds.replica import ReplicaProtocol
    from instrument.offline.export import trial_table
    from instrument.sim.simulate import lab_config_for

    store = SessionStore(tmp_path / name)
    store.add_subject(Subject("S01", mass_kg=75.0))
    session = store.new_session("S01")
    proto = ReplicaProtocol(hold_s=0.3, angles_deg=(0.0, 24.0, 48.0, 72.0))
    with simulated_devices(proto, lab_config_for(proto, seed=11)) as (lab, devices):
        out = record_trial(store, session, proto, devices, extra_metadata=simulation_metadata(lab))
    assert out.status == "recorded"
    return trial_table(read_trial(out.path))


def test_a_replica_trial_reads_the_same_conversions_whatever_the_hosts_timing(tmp_path: Path) -> None:
    """The lab's transmitter numbers its conversions: each hold is marked by its first and last device
    sample, so two recordings of the same seed hold the same samples with the same values (the
    host's polls land differently every run). A conversion no poll read is counted, not hidden."""
    a, b = _replica_table(tmp_path, "a"), _replica_table(tmp_path, "b")
    per_hold = 19  # 0.3 s holds, the middle 60 %: conversions 6 to 24 of the hold at 100 Hz
    for t in (a, b):
        # a loaded host may miss conversions (a stall past the transmitter's 8-conversion history); each is counted,
        # per hold too
        missed = t.sidecar["hold_conversions_missed"]
        assert 0 <= missed < 4 * per_hold and t.torque_nm.size + missed == 4 * per_hold
        readings = t.sidecar["hold_readings"]
        assert [r[0] for r in readings] == [0.0, 24.0, 48.0, 72.0] and all(r[2] == per_hold for r in readings)
        assert sum(r[2] - r[1] for r in readings) == missed
    # the same conversion (time in the device's clock) carries the same value in both recordings
    ta, tb = np.round(a.columns["time_s"] * 100).astype(int), np.round(b.columns["time_s"] * 100).astype(int)
    common, ia, ib = np.intersect1d(ta + 10_000 * a.angle_deg.astype(int), tb + 10_000 * b.angle_deg.astype(int),
                                    return_indices=True)
    assert common.size >= 4 * per_hold - 8
    assert np.array_equal(a.torque_nm[ia], b.torque_nm[ib])
    if a.sidecar["hold_conversions_missed"] == b.sidecar["hold_conversions_missed"] == 0:
        assert np.array_equal(a.torque_nm, b.torque_nm) and np.array_equal(a.columns["time_s"], b.columns["time_s"])
