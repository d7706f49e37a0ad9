"""The operator's set analysis (what the GUI shows after each accepted trial), on trials recorded through the drivers."""

from __future__ import annotations

from pathlib import Path

import pytest

from instrument.kinds.knee import KneeProtocol
from instrument.live.session import record_trial
from instrument.offline.analyses import analyse_set
from instrument.sim.lab_day import SUBJECT
from instrument.sim.simulate import lab_config_for, simulated_devices
from instrument.store import SessionStore


@pytest.mark.timeout(600)
def test_a_knee_set_is_analysed_into_a_table_and_figures_kept_in_the_store(tmp_path: Path) -> None:
    """Two accepted knee trials (hip 90 and 15°): the fit's table, its figures in the store, the newest
    trial's diagnosis; the same set asked again is read back. (From three trials the set analysis adds the
    model-level diagnosis: the same ``analyse`` call as the demo's, whose test holds its finding.)"""
    store = SessionStore(tmp_path / "store")
    store.add_subject(SUBJECT)
    session = store.new_session(SUBJECT.code, operator="op")
    ids = []
    for i, hip in enumerate((90.0, 15.0)):
        proto = KneeProtocol(hip_flexion_deg=hip, speed_deg_s=15.0)
        with simulated_devices(proto, lab_config_for(proto, seed=i)) as (_, devices):
            outcome = record_trial(store, session, proto, devices, operator="op", trial_number=1)
        store.set_status(outcome.trial_id, "accepted")
        ids.append(outcome.trial_id)
    subject = SUBJECT.as_dict()
    store.close()
    result = analyse_set(KneeProtocol(hip_flexion_deg=15.0), tmp_path / "store", ids[1], subject)
    assert result.headline.startswith("2 accepted knee trials: ")
    # the figures of the set: the fit, the parameters, the newest trial's diagnosis; drawn, in the store
    assert [Path(f).name for f in result.figures] == ["pmp_fit.png", "pmp_parameters.png", "diagnosis.png"]
    assert all(Path(f).is_file() and Path(f).is_relative_to(tmp_path / "store" / "figures") for f in result.figures)
    assert result.columns == ("quantity", "generic", "estimate", "95 % interval") and result.rows
    assert sum(r[0].startswith("forward dynamics") for r in result.rows) == 2
    assert "diagnosis:" in result.details and "model-level" not in result.details  # two trials: not yet
    # asked again: read back from the store (figures included), not refitted
    again = analyse_set(KneeProtocol(hip_flexion_deg=15.0), tmp_path / "store", ids[1], subject)
    assert again == result
    for f in result.figures:
        Path(f).unlink()
    redrawn = analyse_set(KneeProtocol(hip_flexion_deg=15.0), tmp_path / "store", ids[1], subject)
    assert all(Path(f).is_file() for f in redrawn.figures)  # figures deleted since: the set is analysed again


def test_an_activation_the_live_check_let_through_is_explained_not_contradicted() -> None:
    """A relaxed-looking knee trial with a small burst (3–5× the noise, under the live check's 1 N·m):
    the set analysis names it and says why the live check raised no alarm; a clean trial gets no such line."""
    from analysis.diagnosis import diagnose
    from benchmarks.diagnosis import as_trial
    from benchmarks.diagnosis_truth import generate
    from instrument.offline.analyses import live_check_agreement

    g = generate("knee", ("activation_burst",), 1000)  # independent generator: Riener & Edrich moments
    d = diagnose(as_trial(g))
    assert d.cause == "activation_burst"
    line = live_check_agreement(d)
    assert g.effects["activation_burst"] < 1.0
    assert "accepted" in line and "below the 1 N·m the live relaxation check catches" in line
    start = g.details["burst_start_s"]
    assert f"{d.parameters['burst_start_s']:.1f}" in line and abs(d.parameters["burst_start_s"] - start) < 1.0
    # a clean trial: seed 501 (seed 500, used before the thirty-fifth stop, is one where the isolated-burst test fires at
    # its 1 % family-wise level by chance: a 0.6 N·m window of 0.15 s at z 4.63 against a level of 4.61)
    assert live_check_agreement(diagnose(as_trial(generate("knee", (), 501)))) == ""


@pytest.mark.timeout(600)
def test_an_aads_set_of_three_springs_gets_the_afo_model_level_diagnosis(tmp_path: Path) -> None:
    """After the third accepted AADS trial of the session's AFO, the set analysis diagnoses the AFO
    model across its springs (the simulated AFO has hinge friction and a compliant shell)."""
    from instrument.kinds.aads import AadsProtocol
    from instrument.store import Subject

    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("AFO1", mass_kg=70.0))
    session = store.new_session("AFO1", operator="op")
    ids = []
    for spring in (1, 2, 3):
        proto = AadsProtocol(spring=spring, operator=3, trial=1, duration_s=6.0)
        with simulated_devices(proto, lab_config_for(proto, seed=spring)) as (_, devices):
            outcome = record_trial(store, session, proto, devices, operator="op", trial_number=1)
        store.set_status(outcome.trial_id, "accepted")
        ids.append(outcome.trial_id)
        if spring == 2:  # two trials: not yet, and said so
            store.close()
            text = analyse_set(AadsProtocol(spring=2), tmp_path / "store", ids[1], {"mass_kg": 70.0}).as_text()
            assert "AFO model-level diagnosis: from 3 accepted trials of this AFO (has 2)" in text
            store = SessionStore(tmp_path / "store")
    store.close()
    result = analyse_set(AadsProtocol(spring=3), tmp_path / "store", ids[2], {"mass_kg": 70.0})
    text = result.as_text()
    assert result.headline.startswith("spring 3: ") and "N·m/° from 1 accepted trial (fit 6–20°)" in result.headline
    # one row per spring; a single trial has no spread, and says so instead of "± 0.000"
    assert [r[:2] for r in result.rows] == [("1", "1"), ("2", "1"), ("3", "1")]
    assert all(r[3] == "one trial" for r in result.rows)
    assert [Path(f).name for f in result.figures] == ["torque_angle.png", "sop_vs_theory.png"]
    assert "AFO model-level diagnosis (held-out across 3 trials): hinge_friction" in text, text
