"""The Results tab: a set's analysis as a headline, a table and its figures, with progress while it runs.

The analysis itself runs on a worker thread (:func:`instrument.offline.analyses.analyse_set`); this
view only shows what it reports: :meth:`ResultsView.busy` when it starts, :meth:`ResultsView.progress`
for each line the fit reports, :meth:`ResultsView.show_analysis` with the finished
:class:`~instrument.kinds.base.SetAnalysis`, or :meth:`ResultsView.failed`.
"""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from ..kinds.base import SetAnalysis


class ResultsView(QtWidgets.QWidget):
    """Headline, busy bar, table of results, the figures (one at a time, chosen by name) and the full text."""

    def __init__(self, parent: QtWidgets.QWidget | None = None) -> None:
        super().__init__(parent)
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        self.headline = QtWidgets.QLabel("No analysis yet: accept a trial and its set is analysed here.")
        self.headline.setWordWrap(True)
        self.headline.setStyleSheet("font-size:14px; font-weight:bold; padding:2px")
        self.headline.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        layout.addWidget(self.headline)
        busy_row = QtWidgets.QHBoxLayout()
        self.busy_bar = QtWidgets.QProgressBar()
        self.busy_bar.setRange(0, 0)  # indeterminate: a fit has no known number of iterations
        self.busy_bar.setMaximumWidth(160)
        self.progress_label = QtWidgets.QLabel("")
        busy_row.addWidget(self.busy_bar)
        busy_row.addWidget(self.progress_label, 1)
        layout.addLayout(busy_row)
        split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal)
        left = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        self.table = QtWidgets.QTableWidget(0, 0)
        self.table.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.verticalHeader().setVisible(False)
        self.table.setAlternatingRowColors(True)
        self.details = QtWidgets.QPlainTextEdit()
        self.details.setReadOnly(True)
        self.details.setStyleSheet("font-family: monospace; font-size:11px")
        left.addWidget(self.table)
        left.addWidget(self.details)
        left.setSizes([300, 160])
        right = QtWidgets.QWidget()
        right_layout = QtWidgets.QVBoxLayout(right)
        right_layout.setContentsMargins(0, 0, 0, 0)
        self.figure_box = QtWidgets.QComboBox()
        self.figure_box.currentIndexChanged.connect(self._show_figure)
        self.figure_label = QtWidgets.QLabel("")
        self.figure_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignTop | QtCore.Qt.AlignmentFlag.AlignHCenter)
        self.figure_scroll = QtWidgets.QScrollArea()
        self.figure_scroll.setWidget(self.figure_label)
        self.figure_scroll.setWidgetResizable(True)
        right_layout.addWidget(self.figure_box)
        right_layout.addWidget(self.figure_scroll, 1)
        split.addWidget(left)
        split.addWidget(right)
        split.setSizes([560, 460])  # proportions: the table whole, the figure at the rest of the width
        split.splitterMoved.connect(lambda *_: self._fit_figure())
        self._pixmap = QtGui.QPixmap()
        layout.addWidget(split, 1)
        self.figures: list[Path] = []
        self.analysis: SetAnalysis | None = None
        self.busy_bar.hide()

    # ------------------------------------------------------------------ states
    def busy(self, message: str) -> None:
        """The analysis started: say what is analysed, show the busy bar, clear the previous result."""
        self.analysis = None
        self.headline.setText(message)
        self.progress_label.setText("")
        self.busy_bar.show()
        self.table.setRowCount(0)
        self.table.setColumnCount(0)
        self.details.setPlainText("")
        self._set_figures([])

    def progress(self, line: str) -> None:
        """One line of what the analysis is doing (an IPOPT iteration, the model-level diagnosis, ...)."""
        self.progress_label.setText(line)

    def failed(self, message: str) -> None:
        """The analysis raised: its first line as the headline, all of it underneath; no table, no figures."""
        self.analysis = None
        self.busy_bar.hide()
        self.progress_label.setText("")
        self.headline.setText(f"analysis failed: {message.splitlines()[0] if message else '?'}")
        self.table.setRowCount(0)
        self.table.setColumnCount(0)
        self.details.setPlainText(message)
        self._set_figures([])

    def show_analysis(self, analysis: SetAnalysis) -> None:
        """The finished analysis: headline, table, figures, details."""
        self.analysis = analysis
        self.busy_bar.hide()
        self.progress_label.setText("")
        self.headline.setText(analysis.headline)
        self.table.setColumnCount(len(analysis.columns))
        self.table.setHorizontalHeaderLabels(list(analysis.columns))
        self.table.setRowCount(len(analysis.rows))
        for i, row in enumerate(analysis.rows):
            for j, cell in enumerate(row):
                item = QtWidgets.QTableWidgetItem(cell)
                if j > 0:
                    item.setTextAlignment(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
                self.table.setItem(i, j, item)
        self.table.resizeColumnsToContents()
        self.details.setPlainText(analysis.details)
        self._set_figures([Path(f) for f in analysis.figures if Path(f).is_file()])

    # ------------------------------------------------------------------ figures
    def _set_figures(self, figures: list[Path]) -> None:
        self.figures = figures
        self.figure_box.blockSignals(True)
        self.figure_box.clear()
        self.figure_box.addItems([f.name for f in figures])
        self.figure_box.blockSignals(False)
        self.figure_box.setVisible(bool(figures))
        self._show_figure(0)

    def _show_figure(self, index: int) -> None:
        if not 0 <= index < len(self.figures):
            self._pixmap = QtGui.QPixmap()
            self.figure_label.setPixmap(self._pixmap)
            self.figure_label.setText("" if self.analysis is None else "no figures for this set")
            return
        self._pixmap = QtGui.QPixmap(str(self.figures[index]))
        self.figure_label.setText("")
        self._fit_figure()

    def _fit_figure(self) -> None:
        """Draw the figure at the view's width (never enlarged): a figure is read whole, not scrolled sideways."""
        if self._pixmap.isNull():
            return
        width = max(self.figure_scroll.viewport().width() - 4, 100)
        shown = self._pixmap if self._pixmap.width() <= width else \
            self._pixmap.scaledToWidth(width, QtCore.Qt.TransformationMode.SmoothTransformation)
        self.figure_label.setPixmap(shown)

    def resizeEvent(self, event: QtGui.QResizeEvent) -> None:  # noqa: N802 - Qt override
        super().resizeEvent(event)
        self._fit_figure()

    def shown_figure(self) -> str:
        """The figure shown now (its file name; empty when none)."""
        i = self.figure_box.currentIndex()
        return self.figures[i].name if 0 <= i < len(self.figures) else ""


__all__ = ["ResultsView"]
