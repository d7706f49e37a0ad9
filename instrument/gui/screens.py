"""The operator window's screens as PNG files, one per trial kind (offscreen: the demo and the docs)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from PySide6 import QtCore, QtWidgets

from .. import kinds
from ..store import SessionStore
from .window import MainWindow

#: the window's size on the saved screens (pixels)
SCREEN_SIZE = (1280, 800)


def save_screens(store_root: Path, out: Path, source: Any) -> list[Path]:
    """Open the window on a store at ``store_root`` with ``source``'s devices, save one screen per
    kind (``{index}-{kind}.png``) into ``out`` and close it; returns the files, in the form's order."""

    def relay(mode: QtCore.QtMsgType, context: QtCore.QMessageLogContext, message: str) -> None:
        if "propagateSizeHints" not in message:  # the offscreen platform's note on every window
            print(message, file=sys.stderr)

    previous = QtCore.qInstallMessageHandler(relay)
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    store = SessionStore(store_root)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    try:
        window = MainWindow(store, source)
        window.resize(*SCREEN_SIZE)
        window.show()
        for i, kind in enumerate(kinds.KINDS):
            window.protocol_box.setCurrentIndex(i)
            app.processEvents()
            path = out / f"{i}-{kind.name}.png"
            window.grab().save(str(path))
            files.append(path)
        window.close()
    finally:
        store.close()
        QtCore.QCoreApplication.processEvents()
        QtCore.qInstallMessageHandler(previous)
    return files


__all__ = ["SCREEN_SIZE", "save_screens"]
