"""The lab file: devices by URL and the subject's envelope; probing what answers; recording without the GUI."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from drivers.simulation.lab import SimulatedLab
from instrument.cli import main
from instrument.kinds.knee import KneeProtocol
from instrument.live.lab import LabFile, LabFileError, probe
from instrument.sim.simulate import lab_config_for
from instrument.store import SessionStore


def write_lab(path: Path, urls: dict[str, str], limits: str = "") -> Path:
    devices = "\n".join(f'{k} = "{v}"' for k, v in urls.items())
    path.write_text(f"[devices]\n{devices}\n\n[limits]\nrom_deg = [-10.0, 95.0]\nmax_speed_deg_s = 25.0\n"
                    f"max_torque_nm = 120.0\n{limits}\n[probe]\nseconds = 0.4\n", encoding="utf-8")
    return path


@pytest.fixture
def knee_lab():
    proto = KneeProtocol(end_deg=20.0, speed_deg_s=20.0)
    lab = SimulatedLab(lab_config_for(proto, seed=5))
    try:
        yield lab, proto
    finally:
        lab.close()


def test_every_device_of_the_lab_answers_and_the_dynamometer_reports_the_lab_envelope(
        knee_lab, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lab, _ = knee_lab
    path = write_lab(tmp_path / "lab.toml", {k: lab.urls[k] for k in ("dynamometer", "force_plate", "torque_sensor")})
    assert main(["devices", "--lab", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [ln.split()[0] for ln in lines] == ["dynamometer", "force_plate", "torque_sensor"]
    assert all("answers:" in ln for ln in lines)
    assert "limits ROM -10..95° speed ≤ 25°/s torque ≤ 120 N·m" in lines[0]


def test_a_trial_is_recorded_on_the_lab_devices_with_progress(knee_lab, tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    lab, _ = knee_lab
    path = write_lab(tmp_path / "lab.toml", {"dynamometer": lab.urls["dynamometer"]})
    store_dir = tmp_path / "store"
    code = main(["record", "--protocol", "knee", "--lab", str(path), "--end", "20", "--speed", "20",
                 "--store", str(store_dir), "--subject", "S01"])
    captured = capsys.readouterr()
    out = captured.out
    assert code == 0, out + captured.err
    assert "answers:" in out and " s of about " in out and "recorded" in out
    with SessionStore(store_dir, read_only=True) as store:
        (trial,) = store.trials()
        assert trial.protocol == "knee" and trial.status == "recorded"
        assert trial.condition["end_deg"] == 20.0


def test_a_silent_device_refuses_the_trial_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_lab(tmp_path / "lab.toml", {"dynamometer": "virtual://nobody-listens-here?rate=100"})
    assert main(["devices", "--lab", str(path)]) == 1
    assert "NO ANSWER" in capsys.readouterr().out
    code = main(["record", "--protocol", "knee", "--lab", str(path), "--store", str(tmp_path / "store")])
    err = capsys.readouterr().err
    assert code == 1 and err.startswith("error: not recording: dynamometer") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "store").exists()  # nothing was started


@pytest.mark.parametrize(("text", "message"), [
    ("this is not toml [", "not a TOML lab file"),
    ("[limits]\nmax_torque_nm = 100\n", "no [devices] table"),
    ('[devices]\nmotor = "virtual://x"\n', "motor: no such device kind"),
    ('[devices]\ndynamometer = 3\n', "is not a device URL"),
    ('[devices]\ndynamometer = "virtual://x"\n[limits]\nmax_torque_nm = 400\n', "may only narrow"),
    ('[devices]\ndynamometer = "virtual://x"\n[limits]\nrom_deg = [0, "x"]\n', "must hold numbers"),
])
def test_a_bad_lab_file_is_named_in_one_line(tmp_path: Path, text: str, message: str,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "lab.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LabFileError, match=re.escape(message)):
        LabFile.load(path)
    assert main(["devices", "--lab", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and len(err.strip().splitlines()) == 1


def test_the_lab_envelope_reaches_the_driver(knee_lab, tmp_path: Path) -> None:
    """A command outside the lab's envelope is refused by the driver, before any frame is sent."""
    from drivers.errors import LimitViolationError

    lab, _ = knee_lab
    lab_file = LabFile.load(write_lab(tmp_path / "lab.toml", {"dynamometer": lab.urls["dynamometer"]}))
    (p,) = probe(lab_file)
    assert p.answered, p.problem
    dyno = lab_file.open("dynamometer")
    with pytest.raises(LimitViolationError):
        dyno.set_passive_isokinetic(0.5)  # 28.6°/s > the lab's 25°/s
    dyno.close()


def test_the_lab_file_can_publish_the_trial_as_lab_streaming_layer_outlets(knee_lab, tmp_path: Path) -> None:
    """``[lsl] publish = true``: the recorded trial's dynamometer stream is an LSL outlet while it runs."""
    pylsl = pytest.importorskip("pylsl")
    import threading

    lab, _ = knee_lab
    path = write_lab(tmp_path / "lab.toml", {"dynamometer": lab.urls["dynamometer"]}, limits="[lsl]\npublish = true\n")
    assert LabFile.load(path).lsl_publish
    seen: list[str] = []

    def listen() -> None:
        seen.extend(i.source_id() for i in pylsl.resolve_byprop("name", "instrument-dynamometer", timeout=8.0))

    listener = threading.Thread(target=listen)
    listener.start()
    code = main(["record", "--protocol", "knee", "--lab", str(path), "--end", "20", "--speed", "20",
                 "--store", str(tmp_path / "store"), "--subject", "S01"])
    listener.join()
    assert code == 0
    assert any(s.startswith("instrument:store-") and s.endswith(":dynamometer") for s in seen), seen
