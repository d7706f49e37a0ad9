"""``instrument demo`` runs the simulated lab end to end through the real drivers."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from instrument import kinds
from instrument.cli import main

#: the demo's run (4–6 min on a loaded 2-core host) is set up inside whichever of these tests comes first
pytestmark = pytest.mark.timeout(900)


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """One run of the whole demo (3 min 58 s alone on this 2-core machine, longer loaded), shared by the tests."""
    import contextlib
    import io

    out = tmp_path_factory.mktemp("demo")
    text, progress = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(text), contextlib.redirect_stderr(progress):
        code = main(["demo", "--seconds", "1.5", "--out", str(out)])
    assert code == 0, text.getvalue()[-3000:] + progress.getvalue()[-2000:]
    (out / "stdout.txt").write_text(text.getvalue())  # the story alone, for the tests that read it
    # the story on stdout, every detail in the report file, progress and this host's measurements on stderr
    return out, text.getvalue() + progress.getvalue() + (out / "demo_report.txt").read_text()


def test_the_demo_tells_a_short_story_with_its_figures(demo_run: tuple[Path, str]) -> None:
    out, _ = demo_run
    story = (out / "stdout.txt").read_text().splitlines()
    assert len(story) <= 80
    assert [ln[:5] for ln in story if ln.startswith("[")] == [f"[{k}/8]" for k in range(1, 9)]
    text = "\n".join(story)
    for figure in ("torque_angle.png", "pmp_fit.png", "pmp_parameters.png", "demo_report.txt"):
        assert figure in text
    assert "holds it" not in text and "IPOPT" not in text  # the detail is in the report file


def test_demo_streams_every_device(demo_run: tuple[Path, str]) -> None:
    tmp_path, printed = demo_run
    report = json.loads((tmp_path / "demo.json").read_text())
    rows = {r["device"]: r for r in report["clean"]}
    assert set(rows) == {"force_plate", "dynamometer", "torque_sensor"}
    for r in rows.values():
        assert r["samples"] > 0 and r["crc_errors"] == 0
    # streamed devices lose nothing on a clean link; a polled one may time out a poll on a loaded host,
    # which is counted and reported, never hidden
    assert rows["force_plate"]["lost_samples"] == 0 and rows["dynamometer"]["lost_samples"] == 0
    drill = {r["device"]: r for r in report["fault_drill"]}
    assert sum(r["crc_errors"] for r in drill.values()) > 0
    assert "Fault drill" in printed and "bad frames were counted" in printed and "PROBLEM" not in printed
    # stdout holds what the seeds determine; this host's rates, counts and latencies go to stderr
    results = (tmp_path / "stdout.txt").read_text() + (tmp_path / "demo_report.txt").read_text()
    assert "rate Hz" not in results and "e-stop reached the dynamometer in" not in results
    assert "rate Hz" in printed and "every sample arrived" in results


def test_demo_records_a_lab_day_into_a_store(demo_run: tuple[Path, str]) -> None:
    tmp_path, printed = demo_run
    report = json.loads((tmp_path / "demo.json").read_text())
    protocols = [r["protocol"] for r in report["lab_day"]]
    assert sorted(protocols) == sorted(["aads"] * 3 + ["knee"] * 3 + ["ankle"] * 3 + ["replica"])
    assert all(r["status"] == "recorded" for r in report["lab_day"])
    assert main(["sessions", "--store", str(tmp_path / "store"), "--json"]) == 0
    assert (tmp_path / "exports").is_dir() and len(list((tmp_path / "exports").glob("*.c3d"))) == 1
    afo = report["afo"]
    table = {r["spring"]: r for r in afo["table_2_1"]}
    assert sorted(table) == [1, 2, 3] and all(r["trials"] == 20 for r in table.values())
    # the dissertation's pattern from hinge friction and shell compliance: softest over, stiffest under
    assert table[1]["percent_difference"] > 0 > table[3]["percent_difference"]
    anova = {r["source"]: r for r in afo["table_2_2"]}
    assert (anova["Model"]["df"], anova["Residual"]["df"], anova["Total"]["df"]) == (15, 44, 59)
    assert anova["Spring"]["p"] < 1e-6
    assert len(afo["recorded"]) == 3 and all(r["sop_vs_bottom_up_max_nm"] < 1e-9 for r in afo["recorded"])
    assert (tmp_path / "afo" / "torque_angle.png").exists()
    # the AFO model-level diagnosis names the jig's hinge friction and shell compliance (10 N·m/°)
    afo_model = afo["model_diagnosis"]
    assert set(afo_model["named"]) == {"hinge_friction", "shell_compliance"}
    pair = next(c for c in afo_model["candidates"] if set(c["names"]) == set(afo_model["named"]))
    assert pair["heldout_ratio"] < 0.5 and abs(pair["parameters"]["compliance_deg_per_Nm"] / 0.1 - 1.0) < 0.15
    explained = {r["spring"]: r for r in afo["explained"]}
    for r in explained.values():  # friction and shell compliance together explain the stiffness error
        assert abs(r["error_without_both_pct"]) < 1.0
    assert explained[1]["error_raw_pct"] > 0 > explained[3]["error_raw_pct"]
    assert {d["protocol"] for d in report["diagnosis"]} == {"aads", "knee", "ankle", "replica"}
    assert all("cause" in d and "candidates" in d for d in report["diagnosis"])
    for d in report["diagnosis"]:  # a second effect is printed on the trial's line, not only in the JSON
        for a in d["also"]:
            assert f"→ {d['cause']}" in printed and f" + {a['cause']} " in printed
    # the knee and ankle trials' subject has OpenSim's limit forces at its swept ends: the truth is printed
    # beside the finding, and a stop named there sits within the limit force's onset and transition
    for d in report["diagnosis"]:
        assert (d["simulated_truth"] is not None) == (d["protocol"] in ("knee", "ankle")), d["protocol"]
        if d["protocol"] in ("knee", "ankle"):
            assert f"the simulated subject: {d['simulated_truth']}" in printed
            if d["cause"] == "hard_stop":
                onset = {"knee": 80.0, "ankle": 10.0}[d["protocol"]]  # demo_subject.json's upper limits
                assert onset <= d["parameters"]["stop_angle_deg"] <= onset + 5.0
    pmp = report["pmp"]
    assert "parameters" in pmp and pmp["identifiability"]["undetermined"]  # the report says what is free
    assert len(pmp["forward_dynamics"]) == 6  # knee at hip 90/55/15°, ankle at knee 0/45/90°
    # the subject's moments are OpenSim's, with structures and muscles the estimator lacks: the model-level
    # diagnosis names the end-range structures, the extended model fits, and what it determines holds the truth.
    # A torque offset may be named beside them: the simulated leg's damping (0.3 N·m·s/rad) is a constant
    # 0.08 N·m against each one-way sweep at 15 °/s
    first, *second = pmp["model_diagnosis"]["cause"].split("+")
    assert first == "end_range_structures" and set(second) <= {"torque_offset"}, pmp["model_diagnosis"]["cause"]
    # no repeats: each candidate judged by predicting held-out time blocks of every trial
    assert pmp["model_diagnosis"]["folds"] == [f"blocks {k}" for k in range(1, 5)]
    assert pmp["extended"]["misfit_ratio"] < pmp["extended"]["plain_misfit_ratio"] / 3
    assert pmp["against_truth"] and all(c["held"] for c in pmp["against_truth"])
    # soleus beside the ankle's end-range structures and the muscles the estimator lacks there is told from them by
    # the extension's shape only: left open and said when the structures' shape uncertainty reaches it (its interval
    # within the family missed the truth on such subjects), else determined with an interval that holds the truth
    held = {c["parameter"] for c in pmp["against_truth"] if c["held"]}
    soleus = "soleus.tendon_slack_length_m"
    assert soleus in pmp["identifiability"]["shape_limited"] or soleus in held, pmp["identifiability"]["determined"]
    assert "recfem.tendon_slack_length_m" in held  # the two-joint muscle, told from the knee's structures by the hip
    replica = report["replica"]  # the rig's springs through the real Modbus driver, against the simulator's truth
    assert {"VASINT.stiffness_n_per_m", "RECFEM.stiffness_n_per_m"} <= set(replica["determined"])
    assert all(abs(replica["error_pct"][n]) < 3.5 for n in replica["determined"])
    assert (tmp_path / "replica" / "replica_fit.png").exists()
    drill = report["operator_drill"]  # the GUI's runner: burst flagged and rejected, relaxed accepted, e-stop
    assert len(drill["burst"]["alarms"]) == 1 and drill["burst"]["status"] == "rejected"  # one burst, one flag
    assert drill["relaxed"]["status"] == "accepted" and not drill["relaxed"]["alarms"]
    assert drill["estop"]["status"] == "rejected" and drill["estop"]["estop_latency_ms"] is not None
    assert drill["gui_screens"] == [f"{i}-{k.name}.png" for i, k in enumerate(kinds.KINDS)]


def test_the_loader_gives_store_trials_their_subject_and_the_index_verdict(demo_run: tuple[Path, str]) -> None:
    from instrument.offline.loading import load_trials
    from instrument.store import SessionStore

    store = SessionStore(demo_run[0] / "store", read_only=True)
    try:
        knee = [r for r in store.trials() if r.protocol == "knee"][:1]
        (loaded,) = load_trials(knee, store)
        assert loaded.kind == "h5" and loaded.subject and loaded.subject.get("mass_kg")
        table = loaded.table()
        assert table.sidecar["trial_status"] == knee[0].status
        assert loaded.file() is loaded.file()  # read once
        by_id = load_trials([str(knee[0].id)], store)[0]
        assert by_id.record is not None and by_id.record.id == knee[0].id
        aads = [r for r in store.trials() if r.protocol == "aads"][:1]
        ti = load_trials(aads, store)[0].afo_input()
        assert ti.factors["store_trial_id"] == aads[0].id and ti.factors["spring"] is not None
    finally:
        store.close()


def test_the_demo_runs_the_cohort_and_remembers_every_analysis(demo_run: tuple[Path, str],
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    from instrument.store import SessionStore

    out, printed = demo_run
    cohort = json.loads((out / "demo.json").read_text())["cohort"]
    assert cohort["engine"]["solves"] == 4 and cohort["engine"]["failed"] == []
    assert cohort["rerun_read_back"] == 4  # the re-run solved nothing: every result came from the store
    assert (out / "cohort" / "cohort_parameters.png").exists() and (out / "cohort" / "table_3_3.csv").exists()
    assert "lab day: 10/10 trials recorded" in printed and "IPOPT iteration" in printed  # progress, on stderr
    with SessionStore(out / "store") as store:
        kinds = {r["kind"] for r in store.results()}
        knee = [t for t in store.trials() if t.protocol == "knee"][0]
    assert {"pmp_subject_fit", "pmp_bootstrap_fit", "afo_set"} <= kinds
    # a store trial's diagnosis is kept too, and read back the second time; the limb's and the arm's
    # inertia are known (the subject comes with the store id), so they are not reported as a cause
    capsys.readouterr()
    args = ["diagnose", str(knee.id), "--store", str(out / "store"), "--json"]
    assert main(args) == 0
    first = capsys.readouterr()
    assert main(args) == 0
    second = capsys.readouterr()
    assert json.loads(second.out) == json.loads(first.out) and "read back from the store" in second.err
    assert json.loads(first.out)["cause"] != "inertia"
