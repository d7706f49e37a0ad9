"""``instrument analyze afo`` on recorded trials and on C3D files, end to end."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from analysis.c3d import write_c3d
from drivers.simulation.aads_jig import AfoProperties
from instrument.cli import main
from instrument.kinds.aads import AadsProtocol
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.sim.simulate import simulated_devices, simulation_metadata, synthesize_aads_trial
from instrument.store import SessionStore, Subject

IDEAL = AfoProperties(hinge_friction_nm=0.0, hinge_friction_coeff=0.0, shell_stiffness_nm_per_deg=1e9)


def test_recorded_trial_through_the_devices_gives_the_simulators_torque(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01", mass_kg=75.0))
    session = store.new_session("S01")
    proto = AadsProtocol(spring=2, operator=1, trial=3, duration_s=4.5)
    with simulated_devices(proto) as (lab, devices):
        out = record_trial(store, session, proto, devices, extra_metadata=simulation_metadata(lab))
        jig = lab.jig
        # the simulated operator began one pass of bends on the protocol's cue, at this plate counter
        bends_from_s = lab.force_plate.bend_origin / lab.force_plate.rate_hz
        last_s = (round(jig.profile.duration_s * lab.force_plate.rate_hz) - 1) / lab.force_plate.rate_hz
    store.close()
    trial = read_trial(out.path)
    assert main(["analyze", "afo", str(out.trial_id), "--store", str(tmp_path / "store"),
                 "--out", str(tmp_path / "report"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    row = report["trials"][0]
    assert (row["spring"], row["operator"], row["trial"], row["store_trial_id"]) == (2, 1, 3, out.trial_id)
    assert row["sop_vs_bottom_up_max_nm"] < 1e-9 and row["marker_fit_accepted"]
    # the torque the analysis finds is the torque the jig simulator applied at those instants
    from instrument.kinds.aads import aads_table

    table = aads_table(trial)
    t_abs = table.time_s + trial.devices["mocap"].channels["time_s"][0] - trial.metadata["simulation"]["jig_time_origin_s"]
    state = jig.state(np.clip(t_abs - bends_from_s, 0.0, last_s))  # one pass, at rest before and after
    inside = (table.angle_deg > 6) & (table.angle_deg < 20)
    assert inside.sum() > 50
    err = table.torque_nm[inside] - state.afo_torque_nm[inside]
    assert np.sqrt(np.mean(err**2)) < 0.15, np.sqrt(np.mean(err**2))
    assert (tmp_path / "report" / "torque_angle.png").stat().st_size > 10_000
    assert (tmp_path / "report" / "sop_vs_theory.png").exists()
    # the analysis is kept in the store with its inputs; the same trials again are read back, identical
    with SessionStore(tmp_path / "store") as s:
        kept = s.results(kind="afo_set")
    assert len(kept) == 1 and kept[0]["inputs"]["trial_ids"] == [out.trial_id]
    assert list(kept[0]["inputs"]["files"]) == [str(out.path)]
    assert main(["analyze", "afo", str(out.trial_id), "--store", str(tmp_path / "store"), "--json"]) == 0
    again = capsys.readouterr()
    assert json.loads(again.out) == report and "read back from the store" in again.err
    assert main(["analyze", "afo", str(out.trial_id), "--store", str(tmp_path / "store"), "--recompute",
                 "--out", str(tmp_path / "report2"), "--json"]) == 0
    assert "read back" not in capsys.readouterr().err and (tmp_path / "report2" / "torque_angle.png").exists()
    # its C3D export carries the spring, operator and trial: another lab re-analyses it without flags
    assert main(["export", "--store", str(tmp_path / "store"), str(out.trial_id), "--format", "c3d",
                 "-o", str(tmp_path / "t.c3d")]) == 0
    import ezc3d

    params = ezc3d.c3d(str(tmp_path / "t.c3d"))["parameters"]
    assert list(params["FORCE_PLATFORM"]["TYPE"]["value"]) == [2]
    assert [int(params["AADS"][k]["value"][0]) for k in ("SPRING", "OPERATOR", "TRIAL")] == [2, 1, 3]
    capsys.readouterr()
    assert main(["analyze", "afo", str(tmp_path / "t.c3d"), "--out", str(tmp_path / "r3"), "--json"]) == 0
    c3d_row = json.loads(capsys.readouterr().out)["trials"][0]
    assert (c3d_row["spring"], c3d_row["operator"], c3d_row["trial"]) == (2, 1, 3)
    assert c3d_row["stiffness_nm_per_deg"] == pytest.approx(row["stiffness_nm_per_deg"], rel=0.02)


def test_c3d_files_from_another_lab(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    files = []
    truths = []
    for op in (1, 4):
        motion, truth = synthesize_aads_trial(1, op, 1, afo=IDEAL)
        files.append(tmp_path / f"op{op}.c3d")
        write_c3d(files[-1], motion)
        truths.append(truth["theoretical_stiffness_nm_per_deg"])
    assert main(["analyze", "afo", *map(str, files), "--spring", "1", "--out", str(tmp_path / "r")]) == 0
    text = capsys.readouterr().out
    assert "Table 2.1" in text and "no ANOVA" in text  # a C3D carries no operator or trial numbers
    report = json.loads((tmp_path / "r" / "afo_report.json").read_text())
    for row, k in zip(report["trials"], truths):
        assert abs(row["stiffness_nm_per_deg"] / k - 1) < 0.015
        assert abs(row["theoretical_stiffness_nm_per_deg"] / k - 1) < 0.01
    # a lab's own model file changes what is reported
    (tmp_path / "jig.json").write_text(json.dumps({"stiffness": {"reported_branch": "both", "fit_window_deg": [7, 19]}}))
    assert main(["analyze", "afo", str(files[0]), "--spring", "1", "--model", str(tmp_path / "jig.json"),
                 "--out", str(tmp_path / "r3"), "--json"]) == 0
    row = json.loads(capsys.readouterr().out)["trials"][0]
    assert row["sop"]["reported_branch"] == "both"
    assert row["stiffness_nm_per_deg"] == row["sop"]["fits"]["both"]["slope_nm_per_deg"]
    assert row["sop"]["fits"]["both"]["span_deg"] <= 12.0
    # a C3D without force-plate data: a clear error naming the file, exit status 1
    import ezc3d
    c = ezc3d.c3d()
    c["parameters"]["POINT"]["RATE"]["value"] = [100.0]
    c["parameters"]["POINT"]["LABELS"]["value"] = ["RTOE1"]
    c["data"]["points"] = np.ones((4, 1, 50))
    c.write(str(tmp_path / "markers-only.c3d"))
    assert main(["analyze", "afo", str(tmp_path / "markers-only.c3d"), "--out", str(tmp_path / "r2")]) == 1
    assert "markers-only.c3d: no force platform" in capsys.readouterr().err
    assert main(["analyze", "afo", str(tmp_path / "nothing.txt")]) == 1


def test_analyze_afo_diagnoses_the_afo_model_across_trials(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """``--diagnose-model`` names what the spring model misses in one AFO's trials from another lab's
    C3D files (springs and operators in the files): the jig's hinge friction and 12.5 N·m/° shell."""
    afo = AfoProperties(hinge_friction_nm=0.2, hinge_friction_coeff=0.06, shell_stiffness_nm_per_deg=12.5)
    files = []
    for spring in (1, 2, 3):
        motion, _ = synthesize_aads_trial(spring, 3, 1, seed=7, afo=afo)
        files.append(tmp_path / f"spring{spring}.c3d")
        write_c3d(files[-1], motion, factors={"spring": spring, "operator": 3, "trial": 1})
    assert main(["analyze", "afo", *map(str, files), "--out", str(tmp_path / "r"), "--diagnose-model", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["model_diagnosis"]
    assert set(d["named"]) == {"hinge_friction", "shell_compliance"}, d["message"]
    pair = next(c for c in d["candidates"] if set(c["names"]) == set(d["named"]))
    assert abs(pair["parameters"]["compliance_deg_per_Nm"] * 12.5 - 1.0) < 0.15
    assert abs(pair["parameters"]["friction_per_spring_torque"] / 0.06 - 1.0) < 0.15
    # two trials are too few to leave one out: said, not crashed
    assert main(["analyze", "afo", *map(str, files[:2]), "--out", str(tmp_path / "r2"), "--diagnose-model"]) == 0
    assert "AFO model-level diagnosis not run: the AFO model-level diagnosis needs at least 3 trials" in \
        capsys.readouterr().out
