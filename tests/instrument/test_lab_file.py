"""The lab file: devices by URL and the subject's envelope; probing what answers; recording without the GUI."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from drivers.simulation.lab import SimulatedLab
from instrument.cli import main
from instrument.kinds.knee import KneeProtocol
from instrument.live.lab import LabFile, LabFileError, probe
from instrument.sim.simulate import lab_config_for
from instrument.store import SessionStore, Subject


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
        # Other tests publish "instrument-dynamometer" outlets too (on the same host, in parallel workers):
        # wait for this store's outlet by its source id, not for the first outlet of that name.
        predicate = "name='instrument-dynamometer' and starts-with(source_id, 'instrument:store-')"
        seen.extend(i.source_id() for i in pylsl.resolve_bypred(predicate, minimum=1, timeout=8.0))

    listener = threading.Thread(target=listen)
    listener.start()
    code = main(["record", "--protocol", "knee", "--lab", str(path), "--end", "20", "--speed", "20",
                 "--store", str(tmp_path / "store"), "--subject", "S01"])
    listener.join()
    assert code == 0
    assert any(s.startswith("instrument:store-") and s.endswith(":dynamometer") for s in seen), seen


def test_lab_streams_are_recorded_beside_the_devices_emg_flags_a_burst_and_the_goniometer_gives_the_hip(
        tmp_path: Path) -> None:
    pytest.importorskip("pylsl")
    import os
    import time

    from analysis.pmp.report import trial_from_table
    from drivers.simulation.lsl_outlets import emg, goniometer
    from instrument import kinds
    from instrument.live.recording import read_trial
    from instrument.live.runner import TrialRunner
    from instrument.live.sources import HardwareSource

    tag = f"{os.getpid()}-{time.monotonic_ns()}"
    proto = KneeProtocol(end_deg=20.0, speed_deg_s=10.0, hip_flexion_deg=55.0)
    sim = SimulatedLab(lab_config_for(proto, seed=6))
    gon, emg_sender = goniometer(f"gon-{tag}", hip_deg=52.0, seed=2), emg(f"emg-{tag}", seed=4)
    try:
        path = write_lab(tmp_path / "lab.toml", {"dynamometer": sim.urls["dynamometer"]},
                         limits=f'[streams]\nemg = "lsl://?source_id=emg-{tag}"\n'
                                f'goniometer = "lsl://?source_id=gon-{tag}"\n')
        source = HardwareSource.from_lab_file(path)
        assert source.lab is not None and set(source.lab.streams) == {"emg", "goniometer"}
        with SessionStore(tmp_path / "store") as store, source.devices(proto) as devices:
            store.add_subject(Subject("S01", mass_kg=75.0))
            runner = TrialRunner(store, store.new_session("S01"), proto, devices, limits=source.lab.limits)
            runner.start()
            assert runner.sweep_started.wait(20.0), runner.snapshot().error
            emg_sender.burst_after(0.5)  # the subject tenses half a second into the sweep
            assert runner.wait(30.0)
            snap = runner.snapshot()
            trial = read_trial(store.trial(snap.outcome.trial_id).path)
            why = runner.suggested_rejection()
    finally:
        gon.close()
        emg_sender.close()
        sim.close()
    assert {"dynamometer", "emg", "goniometer"} <= set(trial.devices)
    assert trial.devices["emg"].channels["values"].shape[1] == 4 and trial.devices["emg"].identity["labels"][0] == \
        "rectus_femoris"
    assert len(trial.devices["goniometer"].channels["time_s"]) > 100
    assert [a.source.split()[:2] for a in snap.alarms] == [["emg", "rectus_femoris"]]
    assert why is not None and "emg rectus_femoris" in why
    table = kinds.get("knee").table(trial)
    assert table.sidecar["hip_flexion_deg"] == 55.0 and table.sidecar["hip_flexion_measured_by"] == "goniometer"
    assert table.sidecar["hip_flexion_measured_deg"] == pytest.approx(52.0, abs=0.1)
    assert trial_from_table(table).fixed_rad["hip"] == pytest.approx(math.radians(table.sidecar["hip_flexion_measured_deg"]))
