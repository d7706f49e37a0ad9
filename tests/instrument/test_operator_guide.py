"""The operator guide's screenshots are taken by this test: each protocol's set-up screen, a knee sweep with
the subject relaxed, and the alarm banner after an activation. Offscreen in CI (the images checked for
content); ``INSTRUMENT_DOCS_SCREENSHOTS=docs/img`` under Xvfb (``QT_QPA_PLATFORM=xcb``) writes the guide's
images from a real X server. Every image the guide names must exist."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

pytest.importorskip("pytestqt")
from PySide6 import QtCore

from instrument import kinds
from instrument.gui.window import MainWindow
from instrument.sim.source import SimulatedSource
from instrument.store import SessionStore

from .test_gui import non_blank

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_every_image_the_operator_guide_names_exists() -> None:
    text = (DOCS / "operator.md").read_text(encoding="utf-8")
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(images) >= len(kinds.KINDS) + 2
    for image in images:
        assert (DOCS / image).is_file(), image


def test_operator_guide_screenshots(qtbot, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]  # qtbot is pytest-qt's
    out = Path(os.environ.get("INSTRUMENT_DOCS_SCREENSHOTS") or tmp_path)
    out.mkdir(parents=True, exist_ok=True)
    store = SessionStore(tmp_path / "store")
    window = MainWindow(store, SimulatedSource(seed=5), subject_code="DOC01")
    window.resize(1366, 768)
    qtbot.addWidget(window)
    window.show()
    window.set_subject(75.0, 0.42, 0.26)
    shots = []
    try:
        for i, kind in enumerate(kinds.KINDS):
            window.protocol_box.setCurrentIndex(i)
            window.confirm_checklist()
            QtCore.QCoreApplication.processEvents()
            shots.append(out / f"operator-setup-{kind.name}.png")
            assert window.grab().save(str(shots[-1]))
        window.protocol_box.setCurrentIndex([k.name for k in kinds.KINDS].index("knee"))
        window.set_field("end_deg", 40.0)
        window.set_field("speed_deg_s", 10.0)
        window.confirm_checklist()
        qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: window.runner is not None and window.runner.sweep_started.is_set(), timeout=30000)
        qtbot.waitUntil(lambda: window.relaxed_label.text() == "subject: relaxed", timeout=10000)
        qtbot.wait(1500)
        shots.append(out / "operator-knee-sweep.png")
        assert window.grab().save(str(shots[-1]))
        window.source.inject_burst(4.0, delay_s=0.5)
        qtbot.waitUntil(lambda: window.banner.isVisible(), timeout=15000)
        qtbot.waitUntil(lambda: window.runner.snapshot().phase in ("done", "failed"), timeout=60000)
        qtbot.wait(300)
        shots.append(out / "operator-knee-alarm.png")
        assert window.grab().save(str(shots[-1]))
        qtbot.mouseClick(window.banner_button, QtCore.Qt.MouseButton.LeftButton)
        qtbot.mouseClick(window.repeat_button, QtCore.Qt.MouseButton.LeftButton)
        # an AADS trial accepted: the Results tab with the spring's table and the torque–angle figure
        window.protocol_box.setCurrentIndex([k.name for k in kinds.KINDS].index("aads"))
        window.confirm_checklist()
        assert window.start_button.isEnabled()
        qtbot.mouseClick(window.start_button, QtCore.Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: window.runner is not None and window.runner.snapshot().phase in ("done", "failed"),
                        timeout=60000)
        qtbot.waitUntil(lambda: window.accept_button.isEnabled(), timeout=5000)
        qtbot.mouseClick(window.accept_button, QtCore.Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: window.analysis_text != "", timeout=60000)
        if window.banner.isVisible():  # the simulated operator may bend past the stop: flagged, acknowledged
            qtbot.mouseClick(window.banner_button, QtCore.Qt.MouseButton.LeftButton)
        window.tabs.setCurrentIndex(1)
        QtCore.QCoreApplication.processEvents()
        assert window.results.table.rowCount() == 1 and window.results.shown_figure() == "torque_angle.png"
        shots.append(out / "operator-results-aads.png")
        assert window.grab().save(str(shots[-1]))
    finally:
        window.close()
        store.close()
    for shot in shots:
        assert non_blank(shot), shot
