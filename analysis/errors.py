"""One exception hierarchy for the analysis package.

``AnalysisError``
 ├── ``InputError``        input data unusable (also a ``ValueError``): missing markers, no force plate, NaNs
 │    └── ``DataFileError`` a file that cannot be read; names the file and the defect
 └── ``FitError``          an estimator could not produce a trustworthy number (e.g. no frames in the fit window)
"""

from __future__ import annotations

from pathlib import Path


class AnalysisError(Exception):
    """Base class of every analysis error."""


class InputError(AnalysisError, ValueError):
    """The input data cannot be analysed as asked."""


class DataFileError(InputError):
    """A file that cannot be read.

    :param path: the file.
    :param defect: what is wrong with it.
    """

    def __init__(self, path: str | Path, defect: str) -> None:
        self.path = Path(path)
        self.defect = defect
        super().__init__(f"{self.path}: {defect}")


class FitError(AnalysisError):
    """An estimator cannot give a number the data supports."""
