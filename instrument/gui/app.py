"""``instrument gui``: the operator window on the simulated lab or on the lab's devices."""

from __future__ import annotations

import sys
from pathlib import Path

from ..live.sources import HardwareSource
from ..sim.source import SimulatedSource
from ..store import SessionStore, default_store_dir
from .system import check_gui_system


def run(*, simulate: bool, store_dir: Path | None = None, urls: dict[str, str] | None = None,
        subject: str = "SIM01", operator: str = "operator-1", seconds: float | None = None,
        lab_file: Path | None = None) -> int:
    """Open the window; ``seconds`` closes it after that long (smoke runs). Returns the exit code.

    :raises GuiSystemError: the X11 libraries Qt needs are missing (named, with their packages).
    """
    check_gui_system()
    from PySide6 import QtCore, QtWidgets

    from .window import MainWindow

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    source: SimulatedSource | HardwareSource
    if simulate:
        source = SimulatedSource()
    elif lab_file is not None:  # the lab file's devices and envelope, as `instrument record --lab` uses them
        source = HardwareSource.from_lab_file(lab_file)
    else:
        source = HardwareSource(urls or {})
    store = SessionStore(store_dir or default_store_dir())
    limits = source.lab.limits if isinstance(source, HardwareSource) and source.lab is not None else None
    window = MainWindow(store, source, subject_code=subject, operator=operator, limits=limits)
    window.resize(1280, 800)
    window.show()
    if seconds is not None:
        QtCore.QTimer.singleShot(int(seconds * 1000), window.close)
    code = app.exec()
    store.close()
    return int(code)
