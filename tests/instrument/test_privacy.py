"""Privacy: subject codes are pseudonyms by pattern, operators are codes outside the store, exports
carry no absolute paths or host names."""

from __future__ import annotations

import json
import platform
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from instrument.cli import main as cli_main
from instrument.errors import SubjectCodeError
from instrument.kinds.knee import KneeProtocol
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.sim.simulate import simulated_devices
from instrument.store import SessionStore, Subject, check_subject_code


@pytest.mark.parametrize("code", ["John Smith", "jane.doe@example.org", "123-45-6789", "AB1234567", "", "S01 ",
                                  "Müller01", "s01"])
def test_identifying_subject_codes_are_refused(tmp_path: Path, code: str) -> None:
    with SessionStore(tmp_path / "store") as store:
        with pytest.raises(SubjectCodeError, match="not a pseudonym"):
            store.add_subject(Subject(code))
        assert store.subjects() == []


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=20))
def test_an_accepted_code_never_holds_a_space_an_at_sign_or_seven_digits(code: str) -> None:
    try:
        check_subject_code(code)
    except SubjectCodeError:
        return
    assert " " not in code and "@" not in code and not any(code[i:i + 7].isdigit() for i in range(len(code) - 6))


def test_the_pattern_is_configurable(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("INSTRUMENT_SUBJECT_CODE_PATTERN", r"P[0-9]{3}")
    with SessionStore(tmp_path / "store") as store:
        store.add_subject(Subject("P007"))
        with pytest.raises(SubjectCodeError):
            store.add_subject(Subject("S01"))


def test_operator_names_stay_in_the_store_and_exports_carry_no_host_or_path(tmp_path: Path, capsys) -> None:
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01", mass_kg=70.0))
    session = store.new_session("S01", "Dr Jane Example")
    proto = KneeProtocol(end_deg=8.0, speed_deg_s=10.0)
    with simulated_devices(proto) as (_, devices):
        out = record_trial(store, session, proto, devices, operator="Dr Jane Example")
    assert store.operators() == {"OP01": "Dr Jane Example"}
    assert store.trial(out.trial_id).operator == "OP01"
    raw = out.path.read_bytes()
    assert b"Jane" not in raw and read_trial(out.path).metadata["operator"] == "OP01"
    store.close()
    csv = tmp_path / "export" / "knee.csv"
    csv.parent.mkdir()
    assert cli_main(["export", "--store", str(tmp_path / "store"), str(out.trial_id), "--format", "csv",
                     "-o", str(csv)]) == 0
    capsys.readouterr()
    for f in (csv, csv.with_suffix(".json")):
        text = f.read_text()
        assert "Jane" not in text and str(tmp_path) not in text and platform.node() not in text
    assert json.loads(csv.with_suffix(".json").read_text())["source"] == out.path.name
