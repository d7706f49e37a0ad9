"""A simulated study given its subjects: each subject's own moment table reaches the simulated dynamometer
through the drivers, the sweeps start where that table allows, and the truth and where it came from ride in
the trials' metadata (for validation only)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from instrument.kinds.isokinetic import IsokineticProtocol
from instrument.offline.loading import load_trials
from instrument.sim.study import SWEEP_TORQUE_LIMIT_NM, StudyDraw, record_study
from instrument.store import Subject


def _table(proto: IsokineticProtocol) -> tuple[np.ndarray, np.ndarray]:
    """A subject no muscle model made: the knee at hip 90° resists with 150 N·m below 30° of flexion (a
    tight hamstring a dynamometer cannot straighten), 5 N·m elsewhere; the ankle a linear spring."""
    lo, hi = sorted((proto.start_deg, proto.end_deg))
    deg = np.arange(lo - 3.0, hi + 3.0 + 1e-9, 0.1)
    if proto.joint == "knee":
        tight = proto.set_angle_deg == 90.0
        nm = np.where(tight & (deg < 30.0), 150.0, 5.0)
    else:
        nm = -0.5 * deg
    return deg, nm


def test_a_study_records_the_subjects_it_is_given_with_their_tables_and_truth(tmp_path: Path) -> None:
    subject = Subject("TAB01", "unknown", None, 70.0, None, None, 0.40, None, 0.26)
    draw = StudyDraw(subject, {"soleus.tendon_slack_length_m": 0.25}, _table, variant="step table",
                     true_shank_length_m=0.395)
    store = record_study(tmp_path / "study", 1, speed_deg_s=30.0, progress=lambda m: None, draws=[draw])
    try:
        trials = load_trials(store.trials(), store)
        assert [s.code for s in store.subjects()] == ["TAB01"]
        assert store.subjects()[0].shank_length_m == 0.40  # as the lab entered it, not the body's
        assert len(trials) == 6
        for trial in trials:
            assert trial.metadata["study_truth"] == {"soleus.tendon_slack_length_m": 0.25}
            assert trial.metadata["study_truth_variant"] == "step table"
        protocols = [(t.metadata["protocol"]["name"], t.metadata["protocol"]["settings"]) for t in trials]
        starts = {(name, s["hip_flexion_deg"] if name == "knee" else s["knee_flexion_deg"]): s["start_deg"]
                  for name, s in protocols}
        # the knee at hip 90° starts 1° past where the table first falls within the dynamometer's limit
        assert 150.0 > SWEEP_TORQUE_LIMIT_NM
        assert starts[("knee", 90.0)] == pytest.approx(31.0)
        assert starts[("knee", 55.0)] == pytest.approx(1.0) and starts[("knee", 15.0)] == pytest.approx(1.0)
    finally:
        store.close()
