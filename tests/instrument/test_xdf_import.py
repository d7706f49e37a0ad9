"""LabRecorder XDF files as trials: the instrument's outlets back into its devices, other streams as stream
devices, the goniometer's hip in the passive fit; damaged files refused in one line, nothing written."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip("pyxdf")

from drivers.blocks import DynamometerBlock
from instrument import kinds
from instrument.cli import main
from instrument.live.lsl import MANUFACTURER, channel_labels
from instrument.live.recording import read_trial
from instrument.store import SessionStore

from .xdf_writer import XdfStream, write_xdf

RATE_HZ = 100.0


def _streams(drop: slice | None = None) -> list[XdfStream]:
    """A 0→40° knee sweep at 5°/s from the dynamometer's outlet, a goniometer (hip 52°) and two EMG channels."""
    t = 1000.0 + np.arange(int(9.0 * RATE_HZ)) / RATE_HZ
    angle = np.deg2rad(np.clip(5.0 * (t - t[0] - 0.5), 0.0, 40.0))
    velocity = np.gradient(angle, t)
    torque = 2.0 + 8.0 * angle**2 + 0.01 * np.random.default_rng(1).standard_normal(t.size)
    columns = {"counter": np.arange(t.size), "torque_nm": torque, "position_rad": angle, "velocity_rad_s": velocity,
               "state": np.ones(t.size)}
    labels = channel_labels(DynamometerBlock.LAYOUT)
    dyno = np.column_stack([columns[src] for _, _, src in labels])
    keep = np.ones(t.size, bool)
    if drop is not None:
        keep[drop] = False
    tg = 1000.0 + np.arange(int(9.0 * 148.148)) / 148.148
    te = 1000.0 + np.arange(int(9.0 * 1000)) / 1000.0
    return [XdfStream("instrument-dynamometer", "Kinetics", [lab for lab, _, _ in labels],
                      [u for _, u, _ in labels], RATE_HZ, t[keep], dyno[keep], manufacturer=MANUFACTURER,
                      source_id="instrument:demo:dynamometer"),
            XdfStream("Goniometer", "Angle", ["hip_flexion", "knee_flexion"], ["degrees", "degrees"], 148.148, tg,
                      np.column_stack([np.full(tg.size, 52.0), np.rad2deg(np.interp(tg, t, angle))])),
            XdfStream("EMG", "EMG", ["rectus_femoris", "biceps_femoris"], ["V", "V"], 1000.0, te,
                      5e-6 * np.random.default_rng(2).standard_normal((te.size, 2)))]


def _import(tmp_path: Path, xdf: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(["import-xdf", str(xdf), "--protocol", "knee", "--hip", "55", "--store", str(tmp_path / "store"),
                 "--subject", "S07"])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_an_xdf_file_becomes_a_knee_trial_with_its_streams(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xdf = write_xdf(tmp_path / "session.xdf", _streams(drop=slice(300, 305)))
    code, out, err = _import(tmp_path, xdf, capsys)
    assert code == 0, err
    assert "imported from session.xdf" in out and "dynamometer: 895 samples, 5 lost" in out
    with SessionStore(tmp_path / "store", read_only=True) as store:
        (record,) = store.trials()
        trial = read_trial(record.path)
    assert record.protocol == "knee" and record.condition["hip_flexion_deg"] == 55.0
    assert set(trial.devices) == {"dynamometer", "goniometer", "emg"}
    dyno = trial.devices["dynamometer"].channels
    assert len(dyno["counter"]) == 895 and int(np.max(np.diff(dyno["counter"]))) == 6  # the dropped rows: a gap
    assert np.rad2deg(dyno["position_rad"]).max() == pytest.approx(40.0)
    assert trial.devices["emg"].identity["labels"] == ["rectus_femoris", "biceps_femoris"]
    assert trial.metadata["imported_from"]["file"] == "session.xdf"
    table = kinds.get("knee").table(trial)
    assert table.sidecar["hip_flexion_measured_deg"] == pytest.approx(52.0)
    assert table.sidecar["hip_flexion_measured_by"] == "goniometer"
    assert float(np.max(table.angle_deg)) == pytest.approx(40.0, abs=0.5)
    assert math.isfinite(float(np.mean(table.torque_nm)))


def test_a_damaged_or_incomplete_xdf_file_is_refused_and_nothing_is_written(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    good = write_xdf(tmp_path / "good.xdf", _streams()).read_bytes()
    (tmp_path / "bad.xdf").write_bytes(b"XDX:" + good[4:])
    code, _, err = _import(tmp_path, tmp_path / "bad.xdf", capsys)
    assert code == 1 and "bad.xdf: not a readable XDF file" in err and len(err.strip().splitlines()) == 1
    no_dyno = write_xdf(tmp_path / "emg_only.xdf", _streams()[1:])
    code, _, err = _import(tmp_path, no_dyno, capsys)
    assert code == 1 and "no dynamometer stream" in err and "a knee trial needs it" in err
    assert not (tmp_path / "store").exists() or not SessionStore(tmp_path / "store", read_only=True).trials()


_GOOD: list[bytes] = []


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.floats(0.0, 1.0), value=st.integers(0, 255))
def test_a_bit_flipped_xdf_file_is_read_or_refused_in_one_typed_line(tmp_path: Path, where: float, value: int) -> None:
    from instrument.offline.xdf import XdfImportError, read_xdf

    if not _GOOD:
        _GOOD.append(write_xdf(tmp_path / "good.xdf", _streams()).read_bytes())
    data = bytearray(_GOOD[0])
    data[4 + int(where * (len(data) - 5))] = value
    path = tmp_path / "flipped.xdf"
    path.write_bytes(bytes(data))
    try:
        devices = read_xdf(path)
    except XdfImportError as err:
        assert str(err).startswith(str(path)) and "\n" not in str(err)
    else:
        assert devices and all(len(ch["time_s"]) == len(ch["counter"]) for _, ch in devices.values())


def test_a_stream_whose_time_stamp_is_not_finite_is_refused_in_one_line(tmp_path: Path) -> None:
    from instrument.offline.xdf import XdfImportError, read_xdf

    streams = _streams()
    emg = streams[2]
    emg.time_s = emg.time_s.copy()
    emg.time_s[500] = np.nan
    path = write_xdf(tmp_path / "nan_stamp.xdf", streams)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # refused before any cast of a NaN
        with pytest.raises(XdfImportError, match="'EMG'.*time stamp is NaN or infinite") as info:
            read_xdf(path)
    assert "\n" not in str(info.value)
