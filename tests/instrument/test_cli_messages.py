"""What the command line says: read-only commands never create a store, times in ISO 8601, errors that name the file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from instrument.cli import build_parser, main
from instrument.kinds.knee import KneeProtocol
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.sim.simulate import lab_config_for, simulated_devices, simulation_metadata
from instrument.store import SessionStore, Subject


@pytest.mark.parametrize("command", [["sessions"], ["export", "1", "--format", "csv", "-o", "x.csv"],
                                     ["analyze", "pmp", "1"], ["diagnose", "1"]])
def test_a_reading_command_on_a_missing_store_is_one_line_and_creates_nothing(
        tmp_path: Path, command: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "typo"
    assert main([*command, "--store", str(missing)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {missing}: no store here (store.sqlite missing); check --store, or record a trial first"]
    assert not missing.exists()


@pytest.fixture(scope="module")
def one_knee_trial(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("cli") / "store"
    store = SessionStore(root)
    store.add_subject(Subject("S01", mass_kg=75.0, shank_length_m=0.40, foot_length_m=0.26))
    proto = KneeProtocol(end_deg=10.0, speed_deg_s=20.0)
    with simulated_devices(proto, lab_config_for(proto, seed=4)) as (lab, devices):
        record_trial(store, store.new_session("S01"), proto, devices, extra_metadata=simulation_metadata(lab))
    store.close()
    return root


def test_sessions_names_the_store_and_prints_no_reprs(one_knee_trial: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sessions", "--store", str(one_knee_trial)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"store {one_knee_trial}")
    assert "None" not in out and "{" not in out and "hip_flexion_deg 90" in out
    assert main(["sessions", "--store", str(one_knee_trial), "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    assert listing["trials"][0]["started_at"].endswith("+00:00") and "T" in listing["sessions"][0]["started_at"]


def test_an_export_into_a_missing_folder_names_it(one_knee_trial: Path, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "no" / "such" / "folder" / "t.csv"
    assert main(["export", "1", "--store", str(one_knee_trial), "--format", "csv", "-o", str(target)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"its folder {target.parent} does not exist" in err[0] and "Errno" not in err[0]


def test_the_trial_file_keeps_no_host_name(one_knee_trial: Path) -> None:
    with SessionStore(one_knee_trial, read_only=True) as store:
        meta = read_trial(store.trials()[0].path).metadata
    assert "host" not in meta


def test_the_fastest_sweep_the_envelope_allows_is_accepted_as_written() -> None:
    args = build_parser().parse_args(["record", "--simulate", "--protocol", "knee", "--speed", "30"])
    assert args.speed == 30.0  # the option is --speed


def test_a_csv_without_its_sidecar_says_so(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    csv = tmp_path / "knee.csv"
    csv.write_text("time_s,angle_deg,torque_Nm\n" + "".join(f"{i * 0.1:.1f},{i:.1f},{0.1 * i:.2f}\n" for i in range(50)))
    assert main(["analyze", "pmp", str(csv), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sidecar" in err[0] and "None" not in err[0]


@pytest.mark.parametrize("command", [["analyze", "pmp"], ["diagnose"], ["analyze", "afo"]])
def test_a_folder_given_for_a_trial_file_is_named_without_an_errno(command: list[str], tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*command, str(tmp_path), "--out", str(tmp_path / "out")] if command[0] == "analyze"
                else [*command, str(tmp_path)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(tmp_path) in err[0] and "folder" in err[0] and "Errno" not in err[0]
