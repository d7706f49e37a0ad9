"""Malformed input gets one typed line naming the file, the field and the allowed range; nothing
already recorded is altered. Property-based where the input space is wide (sidecars, CSV bytes)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from analysis.errors import DataFileError, InputError
from analysis.pmp.report import subject_from, trial_from_table
from analysis.trial_csv import MAX_ROWS, TrialTable, read_trial_csv, write_trial_csv
from instrument.cli import main as cli_main


def _knee_csv(path: Path, **sidecar_overrides) -> Path:
    t = np.arange(0.0, 10.0, 0.01)
    table = TrialTable({"time_s": t, "angle_deg": 5.0 * t, "torque_Nm": 0.1 * t},
                       {"kind": "knee", "hip_flexion_deg": 90.0,
                        "subject": {"mass_kg": 75.0, "shank_length_m": 0.42, "foot_length_m": 0.26}})
    table.sidecar.update(sidecar_overrides)
    write_trial_csv(path, table)
    return path


json_values = st.recursive(st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=8),
                           lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner,
                                                                                        max_size=3), max_leaves=8)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.dictionaries(st.sampled_from(["kind", "hip_flexion_deg", "knee_flexion_deg", "subject", "x"]), json_values)
       | json_values)
def test_any_sidecar_is_read_or_refused_with_a_data_file_error(tmp_path: Path, sidecar) -> None:
    path = _knee_csv(tmp_path / "t.csv")
    path.with_suffix(".json").write_text(json.dumps(sidecar, allow_nan=True))
    try:
        table = read_trial_csv(path)
    except DataFileError as err:
        assert str(path.with_suffix(".json")) in str(err) and "\n" not in str(err)
        return
    try:  # what the reader lets through, the fit's own checks take or refuse with one line
        trial_from_table(table)
        subject_from(table.sidecar.get("subject") or {})
    except InputError as err:
        assert "\n" not in str(err)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.binary(max_size=400))
def test_any_bytes_as_a_csv_are_read_or_refused_with_a_data_file_error(tmp_path: Path, blob: bytes) -> None:
    path = tmp_path / "t.csv"
    path.write_bytes(b"time_s,angle_deg,torque_Nm\n" + blob)
    try:
        table = read_trial_csv(path)
    except DataFileError as err:
        assert str(path) in str(err)
        return
    assert np.all(np.diff(table.time_s) > 0) and np.isfinite(table.time_s).all()


@pytest.mark.parametrize("mutate, words", [
    (lambda p: p.write_bytes(p.read_bytes()[:40] + b"\xff\xfe\x00bad" + p.read_bytes()[40:]), "not UTF-8"),
    (lambda p: p.write_text("\n".join(line if i == 0 or i % 10 else "nan" + line[line.index(","):]
                                       for i, line in enumerate(p.read_text().splitlines()))), "rows have no finite time_s"),
    (lambda p: p.write_text(p.read_text().replace("\n0.5,", "\n0.2,", 1)), "time_s must increase"),
    (lambda p: p.with_suffix(".json").write_text("[1, 2]"), "must be a JSON object"),
    (lambda p: p.with_suffix(".json").write_text('{"kind": "knee", "subject": {"mass_kg": "heavy"}}'),
     "subject.mass_kg"),
    (lambda p: p.with_suffix(".json").write_text('{"kind": "knee", "hip_flexion_deg": 400}'), "hip_flexion_deg"),
])
def test_malformed_trial_csvs_are_one_line_data_errors(tmp_path: Path, capsys, mutate, words) -> None:
    path = _knee_csv(tmp_path / "t.csv")
    mutate(path)
    before = path.read_bytes()
    assert cli_main(["analyze", "pmp", str(path), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and words in err[0], err
    assert path.read_bytes() == before


@pytest.mark.parametrize("overrides, words", [
    ({"subject": {"mass_kg": -70.0, "shank_length_m": 0.42, "foot_length_m": 0.26}}, "mass_kg"),
    ({"subject": {"mass_kg": 0.0, "shank_length_m": 0.42, "foot_length_m": 0.26}}, "mass_kg"),
    ({"subject": {"shank_length_m": 0.42, "foot_length_m": 0.26}}, "mass_kg is missing"),
    ({"hip_flexion_deg": None}, "hip_flexion_deg"),
    ({"trial_status": "rejected"}, "rejected trial"),
])
def test_implausible_or_missing_trial_facts_are_refused_not_defaulted(tmp_path: Path, capsys, overrides,
                                                                       words) -> None:
    path = _knee_csv(tmp_path / "t.csv", **overrides)
    assert cli_main(["analyze", "pmp", str(path), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err


def test_a_constant_angle_is_refused(tmp_path: Path) -> None:
    t = np.arange(0.0, 5.0, 0.01)
    table = TrialTable({"time_s": t, "angle_deg": np.full(t.size, 30.0), "torque_Nm": np.zeros(t.size)},
                       {"kind": "knee", "hip_flexion_deg": 90.0})
    with pytest.raises(InputError, match="constant angle"):
        trial_from_table(table)


def test_nan_cells_are_left_out_and_reported(tmp_path: Path) -> None:
    path = _knee_csv(tmp_path / "t.csv")
    lines = path.read_text().splitlines()
    lines[5] = lines[5].split(",")[0] + ",nan,0.0"
    lines[9] = lines[9].split(",")[0] + ",4.0,"
    path.write_text("\n".join(lines) + "\n")
    trial = trial_from_table(read_trial_csv(path))
    assert trial.time_s.size == 1000 - 2 and "2 rows without angle or torque left out" in trial.name


def test_an_oversized_csv_is_refused_before_loading(tmp_path: Path) -> None:
    path = tmp_path / "big.csv"
    with path.open("w") as fh:
        fh.write("time_s,angle_deg,torque_Nm\n")
        fh.write("0,0,0\n" * (MAX_ROWS + 1))
    with pytest.raises(DataFileError, match="data rows"):
        read_trial_csv(path)


def test_a_row_without_a_time_is_left_out_and_counted_not_the_whole_trial(tmp_path: Path) -> None:
    """One corrupt time cell in a long recording costs that row, not the trial (both readers say so)."""
    from analysis.diagnosis import diagnose, from_table

    path = _knee_csv(tmp_path / "t.csv")
    lines = path.read_text().splitlines()
    for row in (17, 400):
        lines[row] = "nan" + lines[row][lines[row].index(","):]
    lines[600] = "," + lines[600].split(",", 1)[1]  # an empty time cell
    path.write_text("\n".join(lines) + "\n")
    table = read_trial_csv(path)
    assert table.rows_without_time == 3 and table.time_s.size == 1000 - 3
    assert "3 rows without a time left out" in trial_from_table(table).name
    result = diagnose(from_table(table))
    assert result.rows_left_out == {"no time": 3}
    assert any("3 row(s) left out (3 no time)" in n for n in result.notes)
    assert result.as_dict()["rows_left_out"] == {"no time": 3}


def test_diagnose_counts_every_row_it_leaves_out_by_reason() -> None:
    from analysis.diagnosis import DiagnosisTrial

    t = np.arange(0.0, 20.0, 0.01)
    angle = np.deg2rad(45.0 - 45.0 * np.cos(2 * np.pi * t / 20.0))
    torque = 5.0 * angle
    t[[3, 50]] = np.nan
    angle[[7, 8, 9]] = np.inf
    torque[[11, 50]] = np.nan  # row 50 has no time either: counted once, as "no time"
    trial = DiagnosisTrial("knee", t, angle, torque)
    assert trial.rows_left_out == {"no time": 2, "angle not finite": 3, "torque not finite": 1}
    assert trial.time_s.size == 2000 - 6
    assert trial.left_out_text().startswith("6 row(s) left out")


@given(st.integers(min_value=0, max_value=300))
@settings(max_examples=15, deadline=None)
def test_more_than_five_percent_of_rows_without_time_is_refused(missing: int) -> None:
    from analysis.diagnosis import DiagnosisTrial

    rng = np.random.default_rng(missing)
    t = np.arange(0.0, 20.0, 0.01)
    angle = np.deg2rad(45.0 - 45.0 * np.cos(2 * np.pi * t / 20.0))
    t[rng.choice(t.size, missing, replace=False)] = np.nan
    if missing > 0.05 * t.size:
        with pytest.raises(InputError, match="rows have no finite time"):
            DiagnosisTrial("knee", t, angle, angle)
    else:
        assert DiagnosisTrial("knee", t, angle, angle).rows_left_out.get("no time", 0) == missing


@pytest.mark.parametrize("kind, moves_deg", [("knee", 0.0), ("knee", 3.0), ("ankle", 1.0), ("afo", 0.5)])
def test_a_trial_whose_angle_does_not_move_is_refused_by_the_diagnosis(kind: str, moves_deg: float) -> None:
    from analysis.diagnosis import DiagnosisTrial, diagnose

    rng = np.random.default_rng(3)
    t = np.arange(0.0, 30.0, 0.01)
    angle = np.deg2rad(10.0 + moves_deg * np.sin(2 * np.pi * t / 10.0) + rng.normal(0, 0.05, t.size))
    trial = DiagnosisTrial(kind, t, angle, rng.normal(0, 0.2, t.size), {"hip_flexion_deg": 90.0})
    with pytest.raises(InputError, match="does not move") as err:
        diagnose(trial)
    assert "\n" not in str(err.value)


@settings(max_examples=100, deadline=None)
@given(st.none() | st.booleans() | st.floats() | st.integers(-5, 5) | st.text(max_size=4))
def test_a_thigh_length_is_taken_when_physiological_and_refused_in_one_line_otherwise(thigh) -> None:
    subject = {"mass_kg": 70.0, "shank_length_m": 0.40, "foot_length_m": 0.26, "thigh_length_m": thigh}
    try:
        s = subject_from(subject)
    except InputError as err:
        assert "thigh_length_m" in str(err) and "\n" not in str(err)
        return
    assert s.thigh_length_m == thigh and (thigh is None or 0.25 <= thigh <= 0.7)
    # without it the thigh's muscles carry adults' spread of proportions; with it, the two tapes'
    assert s.thigh_over_shank_sd() == (0.03 if thigh is None else pytest.approx(0.0025 / thigh))
