"""The operator's window: set-up, checklist, live plots, relaxation flags, e-stop, accept or repeat.

Every device call happens off the GUI thread (the ``TrialRunner`` and its command threads); the
window only reads ring buffers and the runner's snapshot on a ``QTimer`` (30 Hz) and calls
``setData`` once per curve per tick (pyqtgraph's scrolling-plot pattern). The emergency stop is a
button and the Esc key; closing the window mid-trial stops the devices and keeps the data.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from analysis.aads.model import default_jig_model
from analysis.trial_csv import SUBJECT_RANGES

from .. import kinds
from ..errors import ProtocolError
from ..kinds.base import Curves, Parameter, SetAnalysis, TrialKind, TrialProtocol
from ..live.acquisition import AcquisitionEngine, device_health_text
from ..live.runner import Checklist, SafetyLimits, TrialRunner, checklist_for
from ..offline.analyses import analyse_set
from ..store import SessionStore, Subject
from .results import ResultsView

REFRESH_HZ = 30.0


class FrameCounter:
    """Timer ticks per second and the longest gap between ticks (ms): the GUI thread's health."""

    def __init__(self) -> None:
        self.ticks = 0
        self.started = time.perf_counter()
        self.last = self.started
        self.max_gap_ms = 0.0

    def tick(self) -> None:
        now = time.perf_counter()
        self.max_gap_ms = max(self.max_gap_ms, (now - self.last) * 1e3)
        self.last = now
        self.ticks += 1

    def fps(self) -> float:
        span = self.last - self.started
        return self.ticks / span if span > 0 else 0.0


class MainWindow(QtWidgets.QMainWindow):
    """One operator, one subject, one session; trials recorded into ``store`` from ``source``'s devices."""

    analysis_ready = QtCore.Signal(object)  # a SetAnalysis, or the error's text
    analysis_progress = QtCore.Signal(str)

    def __init__(self, store: SessionStore, source: Any, *, subject_code: str = "SIM01", operator: str = "operator-1",
                 limits: SafetyLimits | None = None) -> None:
        super().__init__()
        self.store, self.source, self.operator = store, source, operator
        self.limits = limits or SafetyLimits()
        self.runner: TrialRunner | None = None
        self.checklist = Checklist([])
        self.monitor_engine: AcquisitionEngine | None = None
        self._trial_thread: threading.Thread | None = None
        self._setup_error: str | None = None
        self._closing = threading.Event()
        self._session_id: int | None = None
        self._subject_code = subject_code
        self._last_verdict: str | None = None
        self.estop_alarm: QtWidgets.QMessageBox | None = None
        self.frames = FrameCounter()
        self._monitor_axes = False  # monitor view's fixed time axes set up
        self.analysis_text = ""
        self.setWindowTitle("AFO & passive-muscle lab instrument" + (" — SIMULATION" if source.simulated else ""))
        self._build()
        self.analysis_ready.connect(self._show_analysis)
        self.analysis_progress.connect(self.results.progress)
        self.timer = QtCore.QTimer(self)
        self.timer.timeout.connect(self._refresh)
        self.timer.start(int(1000 / REFRESH_HZ))
        self._on_protocol_changed(0)

    # ------------------------------------------------------------------ layout
    def _build(self) -> None:
        central = QtWidgets.QWidget()
        self.setCentralWidget(central)
        root = QtWidgets.QHBoxLayout(central)
        side = QtWidgets.QVBoxLayout()
        root.addLayout(side, 0)

        self.protocol_box = QtWidgets.QComboBox()
        self.protocol_box.addItems([k.title for k in kinds.KINDS])
        self.protocol_box.currentIndexChanged.connect(self._on_protocol_changed)
        side.addWidget(QtWidgets.QLabel("<b>Protocol</b>"))
        side.addWidget(self.protocol_box)

        # the form: one field per parameter of any kind (generated from the kinds), shown for the kinds
        # that have it; a kind's buttons (actions) below its fields
        form = QtWidgets.QFormLayout()
        self.fields: dict[str, QtWidgets.QWidget] = {}
        self.rows: dict[str, list[QtWidgets.QWidget]] = {}
        for p in kinds.all_parameters():
            w = self._field_for(p)
            lab = QtWidgets.QLabel("" if p.value_type is bool else p.label)
            form.addRow(lab, w)
            self.fields[p.name] = w
            self.rows[p.name] = [lab, w]
        live = self.fields.get("live_markers")
        if isinstance(live, QtWidgets.QCheckBox):
            live.setChecked(bool(getattr(self.source, "live_markers", True)))
        # the checklist names the settings (hip angle, spring, arm weight): any change rebuilds it, unticked
        for w in self.fields.values():
            for signal in ("currentIndexChanged", "valueChanged", "toggled", "textChanged"):
                if hasattr(w, signal):
                    getattr(w, signal).connect(self._reset_checklist)
                    break
        self.action_rows: dict[str, list[QtWidgets.QWidget]] = {}
        for k in kinds.KINDS:
            for action in k.actions:
                button, note = QtWidgets.QPushButton(action.label), QtWidgets.QLabel("")
                button.clicked.connect(lambda _=False, act=action, out=note: self._run_action(act, out))
                form.addRow(button, note)
                self.action_rows.setdefault(k.name, []).extend([button, note])
        side.addLayout(form)

        side.addWidget(QtWidgets.QLabel("<b>Subject</b>"))
        subj = QtWidgets.QFormLayout()
        self.mass_spin = QtWidgets.QDoubleSpinBox(minimum=0.0, maximum=250.0, value=0.0, suffix=" kg")
        self.shank_spin = QtWidgets.QDoubleSpinBox(minimum=0.0, maximum=0.8, value=0.0, decimals=3, suffix=" m")
        self.foot_spin = QtWidgets.QDoubleSpinBox(minimum=0.0, maximum=0.5, value=0.0, decimals=3, suffix=" m")
        # the thigh (hip to knee joint centre) scales the thigh's muscles; without it they follow the shank
        self.thigh_spin = QtWidgets.QDoubleSpinBox(minimum=0.0, maximum=0.8, value=0.0, decimals=3, suffix=" m")
        for label, w in (("Mass", self.mass_spin), ("Shank length", self.shank_spin), ("Foot length", self.foot_spin),
                         ("Thigh length", self.thigh_spin)):
            w.setSpecialValueText("optional" if w is self.thigh_spin else "required")  # 0: not entered
            subj.addRow(label, w)
            w.valueChanged.connect(self._update_buttons)
            w.valueChanged.connect(lambda *_: self._draw_band() if hasattr(self, "band_lo") else None)
        self.subject_button = QtWidgets.QPushButton("Save subject")
        self.subject_button.clicked.connect(self.save_subject)
        self.subject_label = QtWidgets.QLabel("")
        self.subject_label.setWordWrap(True)
        subj.addRow(self.subject_button, self.subject_label)
        side.addLayout(subj)

        side.addWidget(QtWidgets.QLabel("<b>Before the trial</b>"))
        self.check_list = QtWidgets.QListWidget()
        self.check_list.setWordWrap(True)  # an item's whole text, however narrow the window
        self.check_list.itemChanged.connect(self._on_check)
        side.addWidget(self.check_list, 1)

        lim = self.limits
        self.limits_label = QtWidgets.QLabel(
            f"Limits: ROM {lim.rom_deg[0]:g}…{lim.rom_deg[1]:g}°, speed ≤ {lim.max_speed_deg_s:g}°/s, "
            f"torque ≤ {lim.max_torque_nm:g} N·m")
        self.limits_label.setWordWrap(True)
        side.addWidget(self.limits_label)

        buttons = QtWidgets.QGridLayout()
        self.start_button = QtWidgets.QPushButton("Start trial")
        self.stop_button = QtWidgets.QPushButton("Stop")
        self.accept_button = QtWidgets.QPushButton("Accept")
        self.repeat_button = QtWidgets.QPushButton("Reject && repeat")
        self.estop_button = QtWidgets.QPushButton("EMERGENCY STOP (Esc)")
        self.estop_button.setStyleSheet("background:#c00; color:white; font-weight:bold; padding:10px")
        self.start_button.clicked.connect(self.start_trial)
        self.stop_button.clicked.connect(self.stop_trial)
        self.accept_button.clicked.connect(self.accept_trial)
        self.repeat_button.clicked.connect(self.repeat_trial)
        self.estop_button.clicked.connect(self.emergency_stop)
        buttons.addWidget(self.start_button, 0, 0)
        buttons.addWidget(self.stop_button, 0, 1)
        buttons.addWidget(self.accept_button, 1, 0)
        buttons.addWidget(self.repeat_button, 1, 1)
        buttons.addWidget(self.estop_button, 2, 0, 1, 2)
        side.addLayout(buttons)
        self.estop_shortcut = QtGui.QShortcut(QtGui.QKeySequence(QtCore.Qt.Key.Key_Escape), self)
        self.estop_shortcut.setContext(QtCore.Qt.ShortcutContext.ApplicationShortcut)
        self.estop_shortcut.activated.connect(self.emergency_stop)
        self.quit_shortcut = QtGui.QShortcut(QtGui.QKeySequence("Ctrl+Q"), self)
        self.quit_shortcut.activated.connect(self.close)  # closing mid-trial stops the devices, keeps the data
        self.start_shortcut = QtGui.QShortcut(QtGui.QKeySequence(QtCore.Qt.Key.Key_Space), self)
        self.start_shortcut.activated.connect(self._start_if_ready)

        main = QtWidgets.QVBoxLayout()
        root.addLayout(main, 1)
        # the alarm banner: an e-stop, an activation, a limit breach or a bend past the stop stays on screen
        # (and Start stays disabled) until the operator acknowledges it
        self.banner = QtWidgets.QFrame()
        self.banner.setStyleSheet("background:#c00; color:white; font-weight:bold; font-size:15px")
        banner_row = QtWidgets.QHBoxLayout(self.banner)
        self.banner_text = QtWidgets.QLabel("")
        self.banner_text.setWordWrap(True)
        self.banner_button = QtWidgets.QPushButton("Acknowledge")
        self.banner_button.setStyleSheet("background:white; color:#c00; font-weight:bold; padding:6px")
        self.banner_button.clicked.connect(self.acknowledge_alarms)
        banner_row.addWidget(self.banner_text, 1)
        banner_row.addWidget(self.banner_button, 0)
        self.banner.hide()
        main.addWidget(self.banner)
        self._banner_lines: list[str] = []
        self._banner_seen: set[str] = set()
        # relaxed / active: what the relaxation checks say of the subject during a sweep
        self.relaxed_label = QtWidgets.QLabel("subject: —")
        self.relaxed_label.setStyleSheet("font-size:14px; font-weight:bold; padding:4px; color:#666")
        main.addWidget(self.relaxed_label)
        self.instructions = QtWidgets.QLabel("")
        self.instructions.setWordWrap(True)
        self.instructions.setStyleSheet("font-size:14px; padding:4px")
        main.addWidget(self.instructions)
        self.plots = pg.GraphicsLayoutWidget()
        # repaint only what changed (the curves), not the axes' text every frame
        self.plots.setViewportUpdateMode(QtWidgets.QGraphicsView.ViewportUpdateMode.SmartViewportUpdate)
        # live plots and the set's analysis on their own tabs: a long result never squeezes the plots
        self.tabs = QtWidgets.QTabWidget()
        self.tabs.addTab(self.plots, "Live")
        self.results = ResultsView()
        self.tabs.addTab(self.results, "Results")
        main.addWidget(self.tabs, 1)
        self.plot_a = self.plots.addPlot(row=0, col=0)
        self.plot_b = self.plots.addPlot(row=1, col=0)
        for p in (self.plot_a, self.plot_b):
            p.showGrid(x=True, y=True, alpha=0.3)
            p.setClipToView(True)
            p.setDownsampling(mode="peak")
        self.curve_a = self.plot_a.plot(pen=pg.mkPen("#1f77b4", width=1))  # width 1: thick pens are slow in Qt raster
        self.curve_b = self.plot_b.plot(pen=pg.mkPen("#ff7f0e", width=1))
        self.curve_c = self.plot_a.plot(pen=pg.mkPen("#2ca02c", width=1))  # monitor: the replica torque sensor
        # the expected band of a kind that has one (a relaxed subject's torque against angle)
        self.band_lo = pg.PlotDataItem(pen=pg.mkPen((120, 200, 120, 160), width=1))
        self.band_hi = pg.PlotDataItem(pen=pg.mkPen((120, 200, 120, 160), width=1))
        self.band_fill = pg.FillBetweenItem(self.band_lo, self.band_hi, brush=pg.mkBrush(80, 180, 80, 50))
        for item in (self.band_fill, self.band_lo, self.band_hi):
            self.plot_a.addItem(item)
        self.alarm_points = pg.ScatterPlotItem(size=14, brush=pg.mkBrush(220, 0, 0, 200), symbol="x")
        self.plot_a.addItem(self.alarm_points)
        self._curves = Curves()  # what a kind's live view draws on
        self._curves.a, self._curves.b, self._curves.c = self.curve_a, self.curve_b, self.curve_c
        self._curves.alarms = self.alarm_points
        jig = default_jig_model()  # the fit window and the hinge stop the AADS analysis uses
        self.window_region = pg.LinearRegionItem(values=jig.fit_window_deg, movable=False, brush=pg.mkBrush(0, 160, 0, 40))
        self.stop_line = pg.InfiniteLine(pos=jig.stop_deg, angle=90, pen=pg.mkPen("r", style=QtCore.Qt.PenStyle.DashLine))
        self.verdict = QtWidgets.QLabel("")
        self.verdict.setWordWrap(True)
        main.addWidget(self.verdict)
        self.health = QtWidgets.QLabel("devices: idle")
        self.statusBar().addPermanentWidget(self.health, 1)

    # ------------------------------------------------------------------ protocol set-up
    @staticmethod
    def _field_for(p: Parameter) -> QtWidgets.QWidget:
        """The form's field for a parameter: a list of its choices, a check box, a text line or a spin box."""
        if p.value_type is bool:
            box = QtWidgets.QCheckBox(p.label)
            box.setChecked(bool(p.default))
            box.setToolTip(p.help)
            return box
        if p.choices:
            combo = QtWidgets.QComboBox()
            for c in p.choices:
                combo.addItem(p.text_of(c), c)
            combo.setCurrentIndex(p.choices.index(p.default))
            combo.setToolTip(p.help)
            return combo
        if p.value_type is str:
            edit = QtWidgets.QLineEdit(str(p.default))
            edit.setToolTip(p.help)
            return edit
        spin: QtWidgets.QSpinBox | QtWidgets.QDoubleSpinBox
        if p.value_type is int:
            spin = QtWidgets.QSpinBox(minimum=int(p.low or 0), maximum=int(p.high or 999))
        else:
            spin = QtWidgets.QDoubleSpinBox(minimum=p.low or 0.0, maximum=p.high or 1e6,
                                            decimals=3 if p.unit == "m" else 2)
        spin.setValue(p.default)
        if p.unit:
            spin.setSuffix(f" {p.unit}")
        spin.setToolTip(p.help)
        return spin

    def field_value(self, name: str) -> Any:
        """The value the operator entered for parameter ``name``."""
        w = self.fields[name]
        if isinstance(w, QtWidgets.QCheckBox):
            return w.isChecked()
        if isinstance(w, QtWidgets.QComboBox):
            return w.currentData()
        if isinstance(w, QtWidgets.QLineEdit):
            return w.text()
        return w.value()  # type: ignore[attr-defined]  # a spin box

    def set_field(self, name: str, value: Any) -> None:
        """Enter ``value`` for parameter ``name`` (as the operator would)."""
        w = self.fields[name]
        if isinstance(w, QtWidgets.QCheckBox):
            w.setChecked(bool(value))
        elif isinstance(w, QtWidgets.QComboBox):
            w.setCurrentIndex(w.findData(value))
        elif isinstance(w, QtWidgets.QLineEdit):
            w.setText(str(value))
        else:
            w.setValue(value)  # type: ignore[attr-defined]  # a spin box

    def kind(self) -> TrialKind:
        """The trial kind chosen in the form."""
        return kinds.KINDS[self.protocol_box.currentIndex()]

    def protocol(self) -> TrialProtocol:
        """The protocol the form describes."""
        kind = self.kind()
        return kind.protocol(**{p.name: self.field_value(p.name) for p in kind.parameters})

    def _run_action(self, action: Any, note: QtWidgets.QLabel) -> None:
        values, line = action.run({p.name: self.field_value(p.name) for p in self.kind().parameters})
        for name, value in values.items():
            self.set_field(name, value)
        note.setText(line)

    def _on_protocol_changed(self, index: int) -> None:
        kind = self.kind()
        mine = {p.name for p in kind.parameters}
        for name, widgets in self.rows.items():
            for w in widgets:
                w.setVisible(name in mine)
        for owner, widgets in self.action_rows.items():
            for w in widgets:
                w.setVisible(owner == kind.name)
        self._reset_checklist()
        self._set_plot_mode(kind)
        self.instructions.setText(kind.instructions())
        self._update_buttons()

    def _reset_checklist(self, *_: object) -> None:
        """Rebuild the checklist from the form's current settings, every item unticked (and Start with it)."""
        try:
            protocol = self.protocol()
        except ProtocolError as err:  # a setting the kind refuses: nothing can start until it is fixed
            self.verdict.setText(f"Cannot use these settings: {err}")
            protocol = None
        self.checklist = Checklist(checklist_for(protocol) if protocol is not None else ["fix the settings above"])
        self.check_list.blockSignals(True)
        self.check_list.clear()
        for text in self.checklist.items:
            item = QtWidgets.QListWidgetItem(text)
            item.setFlags(item.flags() | QtCore.Qt.ItemFlag.ItemIsUserCheckable)
            item.setCheckState(QtCore.Qt.CheckState.Unchecked)
            self.check_list.addItem(item)
        self.check_list.blockSignals(False)
        if hasattr(self, "band_lo"):
            self._draw_band()  # the band follows the settings (hip angle, arm weight)
        if hasattr(self, "start_button"):
            self._update_buttons()

    def _on_check(self, item: QtWidgets.QListWidgetItem) -> None:
        self.checklist.confirm(self.check_list.row(item), item.checkState() == QtCore.Qt.CheckState.Checked)
        self._update_buttons()

    def confirm_checklist(self) -> None:
        """Tick every item (as the operator does, one by one)."""
        for i in range(self.check_list.count()):
            self.check_list.item(i).setCheckState(QtCore.Qt.CheckState.Checked)

    def set_subject(self, mass_kg: float, shank_length_m: float, foot_length_m: float,
                    thigh_length_m: float | None = None) -> None:
        self.mass_spin.setValue(mass_kg)
        self.shank_spin.setValue(shank_length_m)
        self.foot_spin.setValue(foot_length_m)
        self.thigh_spin.setValue(thigh_length_m or 0.0)

    def _subject_entries(self) -> dict[str, float]:
        """The entered anthropometrics (m, kg); the thigh only when entered (it is optional)."""
        out = {"mass_kg": self.mass_spin.value(), "shank_length_m": self.shank_spin.value(),
               "foot_length_m": self.foot_spin.value()}
        if self.thigh_spin.value() > 0:
            out["thigh_length_m"] = self.thigh_spin.value()
        return out

    def subject_problems(self) -> list[str]:
        """What is missing or outside the physiological range in the subject's entries (empty: fine)."""
        out = []
        for key, value in self._subject_entries().items():
            lo, hi = SUBJECT_RANGES[key]
            if not lo <= value <= hi:
                out.append(f"{key.replace('_', ' ')} {value:g} outside {lo:g}..{hi:g}")
        return out

    def save_subject(self) -> bool:
        """Store the entered anthropometrics on the subject (created or updated, by code), if valid."""
        problems = self.subject_problems()
        if problems:
            self.subject_label.setText("not saved: " + "; ".join(problems))
            return False
        try:
            old = self.store.subject(self._subject_code).as_dict()
        except Exception:
            old = {"code": self._subject_code}
        # a thigh cleared in the form clears the saved one (the form is what the operator sees)
        self.store.add_subject(Subject(**{**old, "thigh_length_m": None, **self._subject_entries()}))
        self.subject_label.setText(f"{self._subject_code} saved")
        return True

    def _anthropometrics_ok(self) -> bool:
        return not self.subject_problems()

    def _set_plot_mode(self, kind: TrialKind) -> None:
        for item in (self.window_region, self.stop_line):
            if item.scene() is not None:
                self.plot_a.removeItem(item)
        view = kind.view
        self.plot_a.setLabels(left=view.a_labels[0], bottom=view.a_labels[1])
        self.plot_b.setLabels(left=view.b_labels[0], bottom=view.b_labels[1])
        if view.marks_fit_window:
            self.plot_a.addItem(self.window_region)
            self.plot_a.addItem(self.stop_line)
        self.curve_a.setData([], [])
        self.curve_b.setData([], [])
        self.curve_c.setData([], [])
        self.alarm_points.setData([], [])
        self._draw_band()

    def _draw_band(self) -> None:
        """The kind's expected band for the current settings and subject (cleared where there is none)."""
        view = self.kind().view
        band = None
        if view.band is not None:
            try:
                band = view.band(self.protocol(), self._subject_entries())
            except (ProtocolError, ValueError):
                band = None  # settings the protocol refuses: no band until they are valid
        if band is None:
            self.band_lo.setData([], [])
            self.band_hi.setData([], [])
        else:
            x, lo, hi = band
            self.band_lo.setData(x, lo)
            self.band_hi.setData(x, hi)

    def _update_buttons(self) -> None:
        running = (self.runner is not None and self.runner.snapshot().phase == "running") or (
            self._trial_thread is not None and self._trial_thread.is_alive() and self.runner is None)
        finished = self.runner is not None and self.runner.snapshot().phase in ("done", "failed") and \
            self._last_verdict is None
        needs_subject = self.kind().needs_anthropometrics
        ready = self.checklist.complete and (self._anthropometrics_ok() or not needs_subject)
        self.start_button.setEnabled(ready and not running and not finished and not self.banner_raised)
        self.stop_button.setEnabled(running)
        snap = self.runner.snapshot() if self.runner is not None else None
        # a trial that ended by an emergency stop is not accepted: it is repeated
        self.accept_button.setEnabled(finished and snap is not None and snap.outcome is not None
                                      and snap.emergency_stop_s is None)
        self.repeat_button.setEnabled(finished)
        self.protocol_box.setEnabled(not running)

    # ------------------------------------------------------------------ trial control
    def _session(self) -> int:
        if self._session_id is None:
            if not (self._anthropometrics_ok() and self.save_subject()):  # entries kept only when valid
                try:
                    self.store.subject(self._subject_code)
                except Exception:
                    self.store.add_subject(Subject(self._subject_code))
            self._session_id = self.store.new_session(self._subject_code, self.operator, notes="gui")
        return self._session_id

    def start_trial(self) -> None:
        """Start a trial; the devices are opened, run and closed on a trial thread, never on this one."""
        if self.banner_raised:
            self.verdict.setText("Acknowledge the alarm first (the red banner).")
            return
        if not self.checklist.complete:
            self.verdict.setText("Confirm the checklist first: " + "; ".join(self.checklist.missing()))
            return
        if (self.runner is not None and self.runner.snapshot().phase == "running") or (
                self.runner is None and self._trial_thread is not None and self._trial_thread.is_alive()):
            return  # a trial is running or opening its devices
        protocol = self.protocol()
        problems = self.limits.violations(protocol)
        if problems:
            self.verdict.setText("Cannot start: " + "; ".join(problems))
            return
        session = self._session()
        self.runner = None
        self._setup_error = None
        self._last_verdict = None
        self.estop_alarm = None
        self._banner_seen.clear()  # the new trial's alarms are its own
        self._set_plot_mode(kinds.get(protocol.name))
        # the previous trial's devices may still be closing: the new trial thread waits for that
        self._trial_thread = threading.Thread(target=self._run_trial, args=(protocol, session, self._trial_thread),
                                              daemon=True, name="gui-trial")
        self._trial_thread.start()
        self.verdict.setText(f"Opening the devices for {protocol.name} … (about {protocol.expected_duration_s():.0f} s)")
        self._update_buttons()

    def _run_trial(self, protocol: TrialProtocol, session: int, previous: threading.Thread | None) -> None:
        """Trial thread: wait for the previous trial's devices to close, open these, record, close them."""
        if previous is not None:
            previous.join()
        try:
            with self.source.devices(protocol) as devices:
                runner = TrialRunner(self.store, session, protocol, devices, operator=self.operator,
                                     trial_number=getattr(protocol, "trial", None),
                                     extra_metadata=self.source.metadata(), limits=self.limits)
                runner.start()
                self.runner = runner
                while not runner.wait(0.2):
                    if self._closing.is_set() and runner.snapshot().phase == "running":
                        runner.request_stop()
        except Exception as err:
            self._setup_error = f"{type(err).__name__}: {err}"

    def stop_trial(self) -> None:
        if self.runner is not None:
            self.runner.request_stop()

    def _start_if_ready(self) -> None:
        """Space: start the trial when the Start button would (checklist complete, nothing running)."""
        if self.start_button.isEnabled():
            self.start_trial()

    def emergency_stop(self) -> None:
        """Stop the dynamometer at once (command thread), mark the trial and end it."""
        if self.runner is not None and self.runner.snapshot().phase == "running":
            self.runner.emergency_stop("operator: e-stop")
            self.verdict.setText("EMERGENCY STOP sent to the dynamometer; the trial's data is kept.")

    def accept_trial(self) -> None:
        if self.runner is None:
            return
        self.runner.accept()
        self._last_verdict = "accepted"
        outcome = self.runner.snapshot().outcome
        self.verdict.setText(f"Trial {outcome.trial_id if outcome is not None else '?'} accepted.")
        self._analyse_in_background(self.runner)
        self._next_trial_number()
        self._reset_checklist()  # every trial starts from an unticked checklist
        self._update_buttons()

    def repeat_trial(self) -> None:
        if self.runner is None:
            return
        reason = self.runner.suggested_rejection() or "operator asked for a repeat"
        if self.runner.snapshot().outcome is not None:
            self.runner.reject(reason)
        self._last_verdict = "rejected"
        self.verdict.setText(f"Rejected ({reason}); data kept. Confirm the checklist again to repeat the same condition.")
        self._reset_checklist()
        self._update_buttons()

    def _next_trial_number(self) -> None:
        """Offer the next trial number, for kinds that number their trials."""
        trial = next((p for p in self.kind().parameters if p.name == "trial"), None)
        if trial is not None and trial.high is not None and self.field_value("trial") < trial.high:
            self.set_field("trial", self.field_value("trial") + 1)

    # ------------------------------------------------------------------ background analysis
    def _analyse_in_background(self, runner: TrialRunner) -> None:
        outcome = runner.snapshot().outcome
        if outcome is None:
            return
        protocol, store_root = runner.protocol, self.store.root
        subject = self._subject_entries()
        self.results.busy(f"analysing the accepted {protocol.name} trials of this session "
                          f"(trial {outcome.trial_id} is the newest) …")

        def work() -> None:
            try:
                result: SetAnalysis | str = analyse_set(protocol, store_root, outcome.trial_id, subject,
                                                        progress=self.analysis_progress.emit)
            except Exception as err:
                result = f"{type(err).__name__}: {err}"
            self.analysis_ready.emit(result)

        self.tabs.setTabText(1, "Results (analysing …)")
        threading.Thread(target=work, name="set-analysis", daemon=True).start()

    def _show_analysis(self, result: SetAnalysis | str) -> None:
        if isinstance(result, SetAnalysis):
            self.analysis_text = result.as_text()
            self.results.show_analysis(result)
        else:
            self.analysis_text = f"analysis failed: {result}"
            self.results.failed(result)
        self.tabs.setTabText(1, "Results (new)")

    # ------------------------------------------------------------------ refresh (timer)
    def _refresh(self) -> None:
        self.frames.tick()
        runner = self.runner
        engine = runner.engine if runner is not None else self.monitor_engine
        if engine is not None:
            self._plot(engine, runner)
            self._health(engine)
        if self._setup_error is not None and runner is None:
            self.verdict.setText(f"Cannot start: {self._setup_error}")
            self._setup_error = None
            self._update_buttons()
        if runner is not None:
            snap = runner.snapshot()
            self._alarms_to_banner(snap)
            self._relaxed_indicator(snap, runner)
            if snap.estop_unconfirmed is not None and self.estop_alarm is None:
                self._raise_estop_alarm(snap.estop_unconfirmed)
            if snap.phase in ("done", "failed") and self._last_verdict is None and not self.verdict.text().startswith(
                    ("Trial finished", "Trial failed")):
                why = runner.suggested_rejection()
                if snap.phase == "failed":
                    self.verdict.setText(f"Trial failed: {snap.error}. Data recorded so far is kept.")
                else:
                    self.verdict.setText(f"Trial finished ({snap.outcome.status if snap.outcome else '?'}). "
                                         + (f"Suggest repeat: {why}." if why else "Accept, or reject and repeat."))
                self._reset_checklist()  # any end (done, e-stop, failure) unticks it: the next trial is confirmed anew
                self._update_buttons()
            elif snap.phase == "running" and snap.alarms:
                a = snap.alarms[-1]
                self.verdict.setText(f"ACTIVATION flagged at {a.angle_deg:.1f}° ({a.what()}): "
                                     "the trial will be offered for repeat.")
            elif snap.phase == "running" and (hint := runner.protocol.live_hint(snap)):
                self.verdict.setText(hint)
            elif snap.phase == "running" and not self.verdict.text().startswith(("Recording", "EMERGENCY")):
                self.verdict.setText(f"Recording {runner.protocol.name} …")

    # ------------------------------------------------------------------ alarms the operator acknowledges
    @property
    def banner_raised(self) -> bool:
        """True while an alarm is on the banner, unacknowledged."""
        return bool(self._banner_lines)

    def raise_alarm(self, key: str, text: str) -> None:
        """Put ``text`` on the banner (once per ``key``: an alarm is raised once, however often it is seen)."""
        if key in self._banner_seen:
            return
        self._banner_seen.add(key)
        self._banner_lines.append(text)
        shown = self._banner_lines[-3:]
        more = len(self._banner_lines) - len(shown)
        self.banner_text.setText("\n".join(shown) + (f"\n(+{more} earlier)" if more else ""))
        self.banner.show()
        self._update_buttons()

    def acknowledge_alarms(self) -> None:
        """The operator has seen the alarms: the banner goes; Start is possible again."""
        self._banner_lines.clear()
        self.banner.hide()
        self._update_buttons()

    def _alarms_to_banner(self, snap: Any) -> None:
        if snap.emergency_stop_s is not None:
            state = ("confirmed by the dynamometer" if snap.estop_confirmed_s is not None else
                     "NOT CONFIRMED: " + snap.estop_unconfirmed if snap.estop_unconfirmed else "sent")
            self.raise_alarm(f"estop-{snap.emergency_stop_s}-{state[:9]}", f"EMERGENCY STOP {state}")
        for k, a in enumerate(snap.alarms):
            self.raise_alarm(f"activation-{k}", f"ACTIVATION at {a.angle_deg:.1f}° ({a.what()})")
        for k, breach in enumerate(snap.limit_breaches):
            self.raise_alarm(f"limit-{k}", f"LIMIT BREACHED: {breach}")
        if snap.aads_past_stop:
            self.raise_alarm("past-stop", f"BEND PAST THE STOP: peak {snap.aads_peak_deg:.1f}° (the fit window "
                                          "ends before it; the trial's record says so)")

    def _relaxed_indicator(self, snap: Any, runner: TrialRunner) -> None:
        """RELAXED (green) while a monitored sweep runs without an alarm in the last second, ACTIVE (red)
        after one; a dash when nothing is being checked."""
        watched = runner.relaxation_watch is not None or bool(runner.emg_monitors)
        if snap.phase != "running" or not watched or not runner.sweep_started.is_set():
            self.relaxed_label.setText("subject: —")
            self.relaxed_label.setStyleSheet("font-size:14px; font-weight:bold; padding:4px; color:#666")
            return
        recent = [a for a in snap.alarms if time.monotonic() - a.time_s < 1.0]
        if recent:
            self.relaxed_label.setText(f"subject: ACTIVE ({recent[-1].what()})")
            self.relaxed_label.setStyleSheet("font-size:14px; font-weight:bold; padding:4px; color:white; "
                                             "background:#c00")
        else:
            self.relaxed_label.setText("subject: relaxed")
            self.relaxed_label.setStyleSheet("font-size:14px; font-weight:bold; padding:4px; color:white; "
                                             "background:#2a2")

    def _raise_estop_alarm(self, why: str) -> None:
        """A modal alarm the operator must acknowledge: the device did not confirm the e-stop."""
        box = QtWidgets.QMessageBox(self)
        box.setIcon(QtWidgets.QMessageBox.Icon.Critical)
        box.setWindowTitle("EMERGENCY STOP NOT CONFIRMED")
        box.setText(f"{why}.\nThe arm was halted by command and the host heartbeat withdrawn, so the device's "
                    "watchdog stops it. Check the subject and the dynamometer now; use the device's own "
                    "hardware stop if the arm still moves. The trial is marked.")
        box.setStandardButtons(QtWidgets.QMessageBox.StandardButton.Ok)
        box.setModal(True)
        self.estop_alarm = box
        self.verdict.setText("EMERGENCY STOP NOT CONFIRMED by the dynamometer: " + why)
        box.open()

    def _plot(self, engine: AcquisitionEngine, runner: TrialRunner | None) -> None:
        rings = engine.rings
        if runner is None:
            self._plot_monitor(rings)
            return
        if runner.protocol.name != self.kind().name:
            return  # the form shows another kind now: its axes are not this trial's, its plots stay cleared
        kinds.get(runner.protocol.name).view.draw(self._curves, rings, runner.snapshot())

    def _plot_monitor(self, rings: dict[str, Any]) -> None:
        """Every device streaming, nothing recorded: dynamometer and sensor torque, plate Fz (last 10 s).

        The time axes are fixed (−10…0 s, the newest sample at 0), so the axes are not redrawn
        every frame as the data scrolls: axis text is most of a frame's cost."""
        if not self._monitor_axes:
            for p in (self.plot_a, self.plot_b):
                p.setXRange(-10.0, 0.0, padding=0)
                p.disableAutoRange(axis="x")
            self._monitor_axes = True
        if "dynamometer" in rings:
            d = rings["dynamometer"].latest(1000)
            if len(d["time_s"]):
                self.curve_a.setData(d["time_s"] - d["time_s"][-1], d["torque_nm"])
        if "torque_sensor" in rings:
            d = rings["torque_sensor"].latest(5000)
            if len(d["time_s"]):
                self.curve_c.setData(d["time_s"] - d["time_s"][-1], d["torque_nm"])
        if "force_plate" in rings:
            f = rings["force_plate"].latest(10000)
            if len(f["time_s"]):
                # 1 kHz for 10 s: every 10th sample is more than the 1280-pixel trace can show
                self.curve_b.setData(f["time_s"][::10] - f["time_s"][-1], f["force_n"][::10, 2])

    def _health(self, engine: AcquisitionEngine) -> None:
        parts = []
        for name, dev in engine.devices.items():
            # a device the trial closed on purpose is "closed"; only a lost link is shouted
            state = "closed" if dev.closed else ("connected" if dev.connected else "DISCONNECTED")
            parts.append(device_health_text(name, state, dev.stats))
        parts.append(f"GUI {self.frames.fps():.0f} fps")
        self.health.setText(" | ".join(parts))

    # ------------------------------------------------------------------ closing
    def closeEvent(self, event: QtGui.QCloseEvent) -> None:  # noqa: N802 - Qt override
        """Mid-trial: stop the dynamometer and end the recording (its data stays), then close the devices."""
        runner = self.runner
        self._closing.set()
        if runner is not None and runner.snapshot().phase == "running":
            if "dynamometer" in runner.devices:
                runner.emergency_stop("window closed during the trial")
            else:
                runner.request_stop()
        if self._trial_thread is not None:
            self._trial_thread.join(15.0)  # the window is going: let the trial file close cleanly
        self.timer.stop()
        if self.monitor_engine is not None:
            self.monitor_engine.stop()
            self.monitor_engine.close()
        super().closeEvent(event)


__all__ = ["FrameCounter", "MainWindow", "analyse_set"]
