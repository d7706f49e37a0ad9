"""One exception hierarchy for the application layer.

``InstrumentError``
 ├── ``StoreError``               the session store cannot do what was asked
 │    ├── ``StoreVersionError``   the store was written by a newer version (schema too new)
 │    ├── ``StoreReadOnlyError``  the store's folder or database cannot be written
 │    ├── ``NotFoundError``       no such subject, session or trial
 │    └── ``SubjectCodeError``    a subject code that is not a pseudonym (also a ``ValueError``)
 ├── ``RecordingError``           a trial file could not be written or read
 │    ├── ``DiskFullError``       the disk (or file-size limit) is full; data up to the last flush is kept
 │    ├── ``ExportError``         the trial cannot be exported in the format asked for
 │    └── ``CorruptFileError``    a data file (trial, C3D, CSV) is unreadable; names the file and the defect
 │                                (also the analysis layer's ``DataFileError``: one class for one defect)
 └── ``ProtocolError``            a trial protocol cannot run as configured
"""

from __future__ import annotations

from analysis.errors import DataFileError


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


class ExportError(RecordingError):
    """The trial cannot be exported in the format asked for (or has no data for its table)."""


class CorruptFileError(RecordingError, DataFileError):
    """A data file is unreadable: ``path`` and ``defect`` as the analysis layer's :class:`DataFileError`
    (it is one, so a reader of either layer catches it)."""


class ProtocolError(InstrumentError, ValueError):
    """A trial protocol cannot run as configured (bad condition, missing device)."""
