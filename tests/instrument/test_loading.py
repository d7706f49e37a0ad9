"""One loader: store ids, .h5 files, CSVs and C3D files become what each analysis needs, each read once."""

from __future__ import annotations

from pathlib import Path

import pytest

from instrument.errors import InstrumentError
from instrument.offline.loading import load_trials


def test_a_trial_id_needs_a_store_and_a_csv_is_a_table(tmp_path: Path) -> None:
    with pytest.raises(InstrumentError, match="needs a session store"):
        load_trials(["7"], None)
    import numpy as np

    from analysis.trial_csv import TrialTable, write_trial_csv

    t = np.linspace(0.0, 10.0, 200)
    csv = tmp_path / "knee.csv"
    write_trial_csv(csv, TrialTable({"time_s": t, "angle_deg": 9.0 * t, "torque_Nm": 0.5 * t},
                                    {"kind": "knee", "subject": {"mass_kg": 70.0}}))
    (loaded,) = load_trials([str(csv)], None)
    assert loaded.kind == "csv" and loaded.metadata == {} and loaded.record is None
    table = loaded.table()
    assert table.time_s.size == 200 and table.sidecar["kind"] == "knee"
    with pytest.raises(InstrumentError, match="not a trial id"):
        loaded.afo_input()
