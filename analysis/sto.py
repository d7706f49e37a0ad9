"""OpenSim Storage files (``.sto``, ``.mot``): a short header, ``endheader``, then tab-separated columns."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import DataFileError


def write_sto(path: str | Path, columns: dict[str, np.ndarray], *, name: str = "", in_degrees: bool = True) -> None:
    """Write ``columns`` (the first must be ``time``) as an OpenSim storage file (version 1)."""
    path = Path(path)
    names = list(columns)
    if not names or names[0] != "time":
        raise ValueError("the first column of a storage file must be 'time'")
    data = np.column_stack([np.asarray(columns[k], dtype=float) for k in names])
    header = (f"{name or path.stem}\nversion=1\nnRows={data.shape[0]}\nnColumns={data.shape[1]}\n"
              f"inDegrees={'yes' if in_degrees else 'no'}\nendheader\n" + "\t".join(names))
    np.savetxt(path, data, delimiter="\t", header=header, comments="", fmt="%.12g")


def read_sto(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """Read a storage file: (columns, header key/values).

    :raises DataFileError: no ``endheader``, row count differing from ``nRows``, or bad numbers.
    """
    path = Path(path)
    if not path.exists():
        raise DataFileError(path, "file does not exist")
    lines = path.read_text().splitlines()
    try:
        end = next(i for i, ln in enumerate(lines) if ln.strip().lower() == "endheader")
    except StopIteration:
        raise DataFileError(path, "no 'endheader' line: not an OpenSim storage file") from None
    header = dict(ln.split("=", 1) for ln in lines[:end] if "=" in ln)
    names = lines[end + 1].split("\t")
    try:
        data = np.loadtxt(lines[end + 2:], delimiter="\t", ndmin=2)
    except ValueError as err:
        raise DataFileError(path, f"bad numbers in the data: {err}") from err
    if "nRows" in header and int(header["nRows"]) != data.shape[0]:
        raise DataFileError(path, f"header says {header['nRows']} rows, file has {data.shape[0]} (truncated?)")
    if data.shape[1] != len(names):
        raise DataFileError(path, f"{len(names)} column names but {data.shape[1]} columns")
    return {n: data[:, i] for i, n in enumerate(names)}, header
