"""One exception hierarchy for the application layer.

``InstrumentError``
 ├── ``StoreError``               the session store cannot do what was asked
 │    ├── ``StoreVersionError``   the store was written by a newer version (schema too new)
 │    ├── ``StoreReadOnlyError``  the store's folder or database cannot be written
 │    ├── ``NotFoundError``       no such subject, session or trial
 │    └── ``SubjectCodeError``    a subject code that is not a pseudonym (also a ``ValueError``)
 ├── ``RecordingError``           a trial file could not be written or read
 │    ├── ``DiskFullError``       the disk (or file-size limit) is full; data up to the last flush is kept
 │    └── ``CorruptFileError``    a data file (trial, C3D, CSV) is unreadable; names the file and the defect
 └── ``ProtocolError``            a trial protocol cannot run as configured
"""

from __future__ import annotations

from pathlib import Path


class InstrumentError(Exception):
    """Base class of every application-layer error."""


class StoreError(InstrumentError):
    """The session store cannot do what was asked."""


class StoreVersionError(StoreError):
    """The store's schema is newer than this software understands."""


class StoreReadOnlyError(StoreError):
    """The store cannot be written (read-only folder, file or medium)."""


class NotFoundError(StoreError, KeyError):
    """No such subject, session or trial."""

    def __str__(self) -> str:  # KeyError quotes its message; keep it readable
        return str(self.args[0]) if self.args else ""


class SubjectCodeError(StoreError, ValueError):
    """A subject code that does not match the store's pseudonym pattern."""


class RecordingError(InstrumentError):
    """A trial file could not be written or read."""


class DiskFullError(RecordingError, OSError):
    """No space (or file-size limit) left while recording; everything up to the last flush is on disk."""


class CorruptFileError(RecordingError):
    """A data file is unreadable.

    :param path: the file.
    :param defect: what is wrong with it.
    """

    def __init__(self, path: str | Path, defect: str) -> None:
        self.path = Path(path)
        self.defect = defect
        super().__init__(f"{self.path}: {defect}")


class ProtocolError(InstrumentError, ValueError):
    """A trial protocol cannot run as configured (bad condition, missing device)."""
