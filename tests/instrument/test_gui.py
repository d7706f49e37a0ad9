"""The operator window, offscreen, driving each protocol end to end against the simulators (pytest-qt)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtCore, QtGui

from drivers.dynamometer.protocol import State
from instrument import kinds
from instrument.gui.window import MainWindow
from instrument.live.recording import read_trial
from instrument.sim.source import SimulatedSource
from instrument.store import SessionStore


def non_blank(path: Path) -> bool:
    """A screenshot with real content: many distinct colours, not one flat fill."""
    img = QtGui.QImage(str(path))
    if img.isNull() or img.width() < 200:
        return False
    px = np.array([img.pixel(x, y) for x in range(0, img.width(), 7) for y in range(0, img.height(), 7)])
    return len(np.unique(px)) > 20


@pytest.fixture
def window(qtbot, tmp_path: Path):
    store = SessionStore(tmp_path / "store")
    source = SimulatedSource(seed=3)
    w = MainWindow(store, source, subject_code="GUI01")
    w.resize(1280, 800)
    qtbot.addWidget(w)
    w.show()
    w.set_subject(75.0, 0.42, 0.26)
    yield w
    w.close()
    store.close()


def run_to_end(qtbot, w: MainWindow, timeout_s: float = 60.0) -> None:
    qtbot.waitUntil(lambda: w.runner is not None and w.runner.snapshot().phase in ("done", "failed"),
                    timeout=int(timeout_s * 1000))
    qtbot.waitUntil(lambda: w.verdict.text().startswith(("Trial finished", "Trial failed")), timeout=5000)


def test_every_screen_renders(window: MainWindow, tmp_path: Path) -> None:
    for i, name in enumerate(k.title for k in kinds.KINDS):
        window.protocol_box.setCurrentIndex(i)
        QtCore.QCoreApplication.processEvents()
        shot = tmp_path / f"screen-{i}-{name.split()[0].lower()}.png"
        assert window.grab().save(str(shot))
        assert non_blank(shot), shot
        # the checklist gates the start button
        assert not window.start_button.isEnabled()
        window.confirm_checklist()
        assert window.start_button.isEnabled()


def test_knee_trial_flags_a_burst_is_repeated_then_accepted(qtbot, window: MainWindow, tmp_path: Path) -> None:
    window.protocol_box.setCurrentIndex(1)
    window.set_field("end_deg", 30.0)
    window.set_field("speed_deg_s", 10.0)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: window.runner is not None and window.runner.sweep_started.is_set(), timeout=20000)
    qtbot.waitUntil(lambda: window.relaxed_label.text() == "subject: relaxed", timeout=5000)
    window.source.inject_burst(4.0, delay_s=1.5)  # at 15° of 30°: past the detector warm-up
    qtbot.waitUntil(lambda: window.relaxed_label.text().startswith("subject: ACTIVE"), timeout=10000)
    run_to_end(qtbot, window)
    snap = window.runner.snapshot()
    assert snap.alarms, "a 4 N·m burst must be flagged"
    assert "activation" in window.verdict.text().lower() or "Suggest repeat" in window.verdict.text()
    shot = tmp_path / "knee-activation.png"
    window.grab().save(str(shot))
    assert non_blank(shot)
    first = snap.outcome.trial_id
    qtbot.mouseClick(window.repeat_button, QtCore.Qt.MouseButton.LeftButton)
    rec = window.store.trial(first)
    assert rec.status == "rejected" and "activation" in rec.reason
    assert read_trial(rec.path).devices["dynamometer"].samples > 100  # a rejected trial keeps its data
    events = [e["kind"] for e in read_trial(rec.path).events]
    assert "activation" in events
    # repeat the same condition, relaxed this time: the checklist is confirmed again first, and the
    # activation's banner stays (Start disabled) until the operator acknowledges it
    assert not window.start_button.isEnabled()
    window.confirm_checklist()
    assert window.banner.isVisible() and "ACTIVATION at" in window.banner_text.text()
    assert not window.start_button.isEnabled()
    qtbot.mouseClick(window.banner_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.banner.isVisible() and window.start_button.isEnabled()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    run_to_end(qtbot, window)
    assert not window.runner.snapshot().alarms
    qtbot.mouseClick(window.accept_button, QtCore.Qt.MouseButton.LeftButton)
    second = window.runner.snapshot().outcome.trial_id
    assert window.store.trial(second).status == "accepted"
    qtbot.waitUntil(lambda: window.analysis_text != "", timeout=120000)  # the set's fit, in the background
    # the set's fit (or, honestly, that IPOPT did not converge on one short sweep) and its diagnosis
    assert ("fit:" in window.analysis_text or "did not converge" in window.analysis_text)
    assert "diagnosis" in window.analysis_text and "analysis failed" not in window.analysis_text
    assert window.results.table.rowCount() >= 1 and "diagnosis.png" in [f.name for f in window.results.figures]


def test_escape_is_an_emergency_stop_that_reaches_the_dynamometer(qtbot, window: MainWindow) -> None:
    window.protocol_box.setCurrentIndex(2)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: window.runner is not None and window.runner.sweep_started.is_set(), timeout=20000)
    lab = window.source.lab
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Escape)
    qtbot.waitUntil(lambda: lab.dynamometer.state == State.ESTOP, timeout=2000)
    run_to_end(qtbot, window)
    snap = window.runner.snapshot()
    assert snap.emergency_stop_s is not None and snap.estop_confirmed_s is not None
    rec = window.store.trial(snap.outcome.trial_id)
    assert rec.status == "interrupted"
    assert "emergency_stop" in [e["kind"] for e in read_trial(rec.path).events]
    assert "emergency stop" in (window.runner.suggested_rejection() or "")
    assert window.banner.isVisible() and "EMERGENCY STOP confirmed by the dynamometer" in window.banner_text.text()
    qtbot.waitUntil(lambda: not window.checklist.complete, timeout=5000)  # the e-stop's end unticks the checklist
    assert not window.start_button.isEnabled()


def test_aads_trial_draws_the_loop_and_checks_the_fit_window(qtbot, window: MainWindow, tmp_path: Path) -> None:
    window.protocol_box.setCurrentIndex(0)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    run_to_end(qtbot, window)
    snap = window.runner.snapshot()
    assert snap.aads_angle_deg.size > 100 and snap.aads_covers_window
    x, y = window.curve_a.getData()
    assert x is not None and len(x) > 100  # the loop is on screen
    shot = tmp_path / "aads-loop.png"
    window.grab().save(str(shot))
    assert non_blank(shot)
    qtbot.mouseClick(window.accept_button, QtCore.Qt.MouseButton.LeftButton)
    # the Results view says it is computing (its answer arrives through the event loop, not before)
    assert not window.results.busy_bar.isHidden() and "analysing the accepted aads" in window.results.headline.text()
    qtbot.waitUntil(lambda: window.analysis_text != "", timeout=60000)
    assert "N·m/°" in window.analysis_text and "failed" not in window.analysis_text
    results = window.results
    assert results.busy_bar.isHidden() and results.table.rowCount() == 1 and results.table.columnCount() == 6
    assert results.table.item(0, 3).text() == "one trial"  # not "± 0.000"
    assert results.shown_figure() == "torque_angle.png" and not results.figure_label.pixmap().isNull()
    assert window.field_value("trial") == 2  # the next trial number is offered
    window._refresh()  # after a normal trial no device is reported lost (closed ones say "closed")
    assert "DISCONNECTED" not in window.health.text(), window.health.text()


def test_replica_trial_and_closing_mid_trial_keeps_the_data(qtbot, window: MainWindow) -> None:
    window.protocol_box.setCurrentIndex(3)
    window.set_field("hold_s", 0.4)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    run_to_end(qtbot, window)
    qtbot.mouseClick(window.accept_button, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: window.analysis_text != "", timeout=60000)
    assert "VASINT" in window.analysis_text
    # a knee trial, closed mid-sweep: the dynamometer is stopped and the recording kept
    window.protocol_box.setCurrentIndex(1)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: window.runner is not None and window.runner.sweep_started.is_set(), timeout=20000)
    runner = window.runner
    window.close()
    snap = runner.snapshot()
    assert snap.phase == "done" and snap.emergency_stop_s is not None, snap.error
    rec = window.store.trial(snap.outcome.trial_id)
    assert rec.status == "interrupted"
    assert read_trial(rec.path).devices["dynamometer"].samples > 50


def test_an_unconfirmed_emergency_stop_raises_a_modal_alarm_and_blocks_accept(qtbot, window: MainWindow,
                                                                              tmp_path: Path) -> None:
    window.protocol_box.setCurrentIndex(2)
    window.confirm_checklist()
    qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: window.runner is not None and window.runner.sweep_started.is_set(), timeout=20000)
    lab = window.source.lab
    lab.dynamometer.lose_estop_frames = 1000  # no e-stop frame reaches the device
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Escape)
    qtbot.waitUntil(lambda: window.estop_alarm is not None and window.estop_alarm.isVisible(), timeout=10000)
    assert window.estop_alarm.isModal() and "NOT CONFIRMED" in window.estop_alarm.windowTitle()
    run_to_end(qtbot, window)
    assert lab.dynamometer.state != State.MOVING  # halted by command instead
    assert not window.accept_button.isEnabled() and window.repeat_button.isEnabled()
    rec = window.store.trial(window.runner.snapshot().outcome.trial_id)
    assert rec.status == "interrupted" and "did not confirm" in (rec.reason or "")
    shot = tmp_path / "estop-alarm.png"
    window.estop_alarm.grab().save(str(shot))
    window.estop_alarm.accept()


def test_subject_is_saved_validated_and_updated(window: MainWindow) -> None:
    window.protocol_box.setCurrentIndex(1)  # knee: needs anthropometrics
    window.confirm_checklist()
    window.set_subject(0.0, 0.42, 0.26)
    assert window.mass_spin.text() == "required"  # not entered is shown as such, never as 0.00 kg
    assert not window.start_button.isEnabled()
    assert not window.save_subject() and "mass kg 0 outside 20..250" in window.subject_label.text()
    window.set_subject(75.0, 0.42, 0.26)
    assert window.start_button.isEnabled() and window.save_subject()
    assert window.store.subject("GUI01").mass_kg == 75.0
    window.set_subject(81.5, 0.44, 0.27)  # edited later: the store follows, nothing stays at the first entry
    assert window.save_subject()
    saved = window.store.subject("GUI01")
    assert (saved.mass_kg, saved.shank_length_m, saved.foot_length_m) == (81.5, 0.44, 0.27)
    assert saved.thigh_length_m is None and window.thigh_spin.text() == "optional"  # not asked for
    window.set_subject(81.5, 0.44, 0.27, 0.75)
    assert not window.save_subject() and "thigh length m 0.75 outside 0.25..0.7" in window.subject_label.text()
    window.set_subject(81.5, 0.44, 0.27, 0.45)  # scales the thigh's muscles in the set analyses
    assert window.save_subject() and window.store.subject("GUI01").thigh_length_m == 0.45
    window.set_subject(81.5, 0.44, 0.27)  # cleared again: the store follows
    assert window.save_subject() and window.store.subject("GUI01").thigh_length_m is None


def test_arm_entries_reach_the_protocol_and_its_checklist(window: MainWindow) -> None:
    window.protocol_box.setCurrentIndex(2)  # ankle
    window.set_field("arm_mass_kg", 2.5)
    window.set_field("arm_com_m", 0.3)
    proto = window.protocol()
    assert (proto.arm_mass_kg, proto.arm_com_m) == (2.5, 0.3)
    items = [window.check_list.item(i).text() for i in range(window.check_list.count())]
    assert any("2.5 kg at 0.3 m" in t for t in items), items


def test_a_long_result_gets_its_own_tab_and_leaves_the_plots_alone(window: MainWindow, tmp_path: Path) -> None:
    from instrument.kinds.base import SetAnalysis

    window.protocol_box.setCurrentIndex(1)
    QtCore.QCoreApplication.processEvents()
    before = window.plots.height()
    rows = tuple((f"muscle{i}.tendon_slack_length_m", "0.3", f"0.3{i}", "[0.29, 0.31]") for i in range(40))
    window._show_analysis(SetAnalysis("40 of 40 parameters determined", ("quantity", "generic", "estimate",
                                                                         "95 % interval"), rows,
                                      details="\n".join(f"line {i}" for i in range(200))))
    QtCore.QCoreApplication.processEvents()
    assert window.plots.height() == before
    assert window.tabs.tabText(1) == "Results (new)"
    assert window.results.table.rowCount() == 40 and window.results.table.item(39, 2).text() == "0.339"
    assert window.results.details.toPlainText().count("\n") == 199
    # a failure is one line on top, its whole text underneath; the plots keep their size
    window._show_analysis("AnalysisError: " + "\n".join(f"traceback line {i}" for i in range(40)))
    QtCore.QCoreApplication.processEvents()
    assert window.plots.height() == before
    assert window.results.headline.text() == "analysis failed: AnalysisError: traceback line 0"
    assert window.results.table.rowCount() == 0 and "traceback line 39" in window.results.details.toPlainText()
    window.tabs.setCurrentIndex(1)
    QtCore.QCoreApplication.processEvents()
    assert window.grab().save(str(tmp_path / "results-tab.png")) and non_blank(tmp_path / "results-tab.png")


def test_the_checklist_follows_the_settings(window: MainWindow) -> None:
    """A ticked item must describe the settings that will run: any change unticks and rewrites the list."""
    window.protocol_box.setCurrentIndex(1)
    window.confirm_checklist()
    assert window.start_button.isEnabled()
    window.set_field("hip_flexion_deg", 55.0)
    items = [window.check_list.item(i).text() for i in range(window.check_list.count())]
    assert not window.start_button.isEnabled() and any("hip at 55°" in t for t in items)
    window.protocol_box.setCurrentIndex(0)
    window.confirm_checklist()
    window.set_field("spring", 3)
    items = [window.check_list.item(i).text() for i in range(window.check_list.count())]
    assert not window.start_button.isEnabled() and any("spring 3 fitted" in t for t in items)


def test_keyboard_space_starts_only_when_ready_and_ctrl_q_closes(qtbot, window: MainWindow) -> None:
    window.protocol_box.setCurrentIndex(3)  # replica
    window.start_shortcut.activated.emit()
    assert window.runner is None and window._trial_thread is None  # checklist not confirmed: nothing starts
    window.quit_shortcut.activated.emit()
    qtbot.waitUntil(lambda: not window.isVisible(), timeout=5000)
