"""The operator GUI (PySide6 + pyqtgraph); the only Qt in the project. Protocols and checks live Qt-free in ``instrument``."""
