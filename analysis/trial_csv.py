"""The trial CSV: ``time_s,angle_deg,torque_Nm[,more channels]`` plus a JSON sidecar of the same name.

Sign convention (the one place it is defined): angle positive in dorsiflexion (AFO, ankle) or
knee flexion; ``torque_Nm`` is the torque applied to the specimen toward positive angle — by the
dynamometer, the operator or the sensor — which is what the specimen resists with (a linear
spring reads torque = k × angle, k > 0). For a passive limb moved slowly it is
−(M_muscles + M_gravity), the estimator's control u. For knee and ankle trials it includes the
weight of the segments distal to the joint; the dynamometer arm's own weight is already removed. The sidecar holds ``kind``
(afo, knee, ankle,
replica), the fixed joint angles ``hip_flexion_deg``, ``knee_flexion_deg``,
``ankle_dorsiflexion_deg``, and ``subject`` (``mass_kg``, ``height_m``, ``thigh_length_m``,
``shank_length_m``, ...); more keys are allowed.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import DataFileError

REQUIRED = ("time_s", "angle_deg", "torque_Nm")
KINDS = ("afo", "knee", "ankle", "replica")
#: the angle range each kind's protocol covers (deg): AFO bends to the 21° stop, knee flexion 0–90°,
#: ankle 15° dorsiflexion to 30° plantarflexion, the replica leg's holds 0–90°
NOMINAL_RANGE_DEG: dict[str, tuple[float, float]] = {"afo": (0.0, 21.0), "knee": (0.0, 90.0), "ankle": (-30.0, 15.0),
                                                     "replica": (0.0, 90.0)}
#: the most rows a trial CSV may have (33 min at 1 kHz); larger files are refused before loading
MAX_ROWS = 2_000_000
#: the largest fraction of rows without a finite time a trial may have: such rows (a corrupt line in a
#: long recording) are left out and counted; past this the time base itself is not trusted
MAX_ROWS_WITHOUT_TIME_FRACTION = 0.05
#: allowed range of each sidecar number: fixed joint angles (deg) and subject anthropometrics (SI)
SIDECAR_RANGES: dict[str, tuple[float, float]] = {
    "hip_flexion_deg": (-30.0, 130.0), "knee_flexion_deg": (-10.0, 150.0), "ankle_dorsiflexion_deg": (-60.0, 45.0),
}
SUBJECT_RANGES: dict[str, tuple[float, float]] = {
    "mass_kg": (20.0, 250.0), "height_m": (1.0, 2.3), "leg_length_m": (0.5, 1.3), "thigh_length_m": (0.25, 0.7),
    "shank_length_m": (0.25, 0.6), "hip_width_m": (0.15, 0.5), "foot_length_m": (0.12, 0.35),
    "thigh_circumference_m": (0.25, 1.2), "shank_circumference_m": (0.15, 0.8),
}


@dataclass
class TrialTable:
    """Columns of one trial (units in the names) and its sidecar."""

    columns: dict[str, np.ndarray]
    sidecar: dict[str, Any] = field(default_factory=dict)
    #: rows of the file left out because their time was missing or not finite (counted, not silent)
    rows_without_time: int = 0

    @property
    def time_s(self) -> np.ndarray:
        return self.columns["time_s"]

    @property
    def angle_deg(self) -> np.ndarray:
        return self.columns["angle_deg"]

    @property
    def torque_nm(self) -> np.ndarray:
        return self.columns["torque_Nm"]


def sidecar_path(csv_path: str | Path) -> Path:
    return Path(csv_path).with_suffix(".json")


def write_trial_csv(path: str | Path, table: TrialTable) -> None:
    """Write ``path`` (CSV, full float precision) and its ``.json`` sidecar."""
    path = Path(path)
    names = list(REQUIRED) + [k for k in table.columns if k not in REQUIRED]
    data = np.column_stack([np.asarray(table.columns[k], dtype=float) for k in names])
    np.savetxt(path, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    sidecar_path(path).write_text(json.dumps(table.sidecar, indent=2, default=float))


def read_trial_csv(path: str | Path) -> TrialTable:
    """Read a trial CSV and its sidecar (if present).

    Cells of the data columns may be empty or NaN (a dropped sample). A row whose time is empty or
    not finite is left out and counted in ``rows_without_time`` (one corrupt line in a long
    recording must not lose the rest); the times that remain must strictly increase.

    :raises DataFileError: missing or oversized file, not UTF-8, missing required column,
        non-numeric or empty data, more than :data:`MAX_ROWS_WITHOUT_TIME_FRACTION` of the rows
        without a time, time not increasing, bad sidecar (names the field and its allowed range).
    """
    path = Path(path)
    if not path.exists():
        raise DataFileError(path, "file does not exist")
    rows = _count_lines(path) - 1
    if rows > MAX_ROWS:
        raise DataFileError(path, f"{rows} data rows; a trial CSV has at most {MAX_ROWS} (split or resample it)")
    try:
        with path.open(encoding="utf-8") as fh:
            header = fh.readline().strip()
        names = [h.strip() for h in header.split(",")]
        missing = [r for r in REQUIRED if r not in names]
        if missing:
            raise DataFileError(path, f"missing column(s) {missing}; header is {names}")
        with warnings.catch_warnings():  # "input contained no data" is our own error below
            warnings.simplefilter("ignore", UserWarning)
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, encoding="utf-8",
                              converters=lambda text: float(text) if text.strip() else np.nan)
    except UnicodeDecodeError as err:
        raise DataFileError(path, f"not UTF-8 text (byte {err.start}): is it a trial CSV?") from err
    except ValueError as err:
        raise DataFileError(path, f"non-numeric or ragged data: {str(err).splitlines()[0]}") from err
    if data.shape[0] == 0:
        raise DataFileError(path, "no data rows")
    if data.shape[1] != len(names):
        raise DataFileError(path, f"{data.shape[1]} columns of data but {len(names)} names in the header")
    time = data[:, names.index("time_s")]
    timed = np.isfinite(time)
    missing_time = int(data.shape[0] - timed.sum())
    if missing_time > MAX_ROWS_WITHOUT_TIME_FRACTION * data.shape[0]:
        first = int(np.flatnonzero(~timed)[0])
        raise DataFileError(path, f"{missing_time} of {data.shape[0]} rows have no finite time_s (first: row "
                                  f"{first + 2}); at most {MAX_ROWS_WITHOUT_TIME_FRACTION:.0%} may be left out")
    line_of = np.flatnonzero(timed) + 2  # file line numbers of the kept rows (the header is line 1)
    if missing_time:
        data, time = data[timed], time[timed]
    steps = np.diff(time)
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0])
        raise DataFileError(path, f"time_s must increase: row {line_of[k + 1]} ({time[k + 1]:g} s) does not follow row "
                                  f"{line_of[k]} ({time[k]:g} s) (duplicated or out-of-order time)")
    sidecar: dict[str, Any] = {}
    sp = sidecar_path(path)
    if sp.exists():
        try:
            sidecar = json.loads(sp.read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            raise DataFileError(sp, f"sidecar is not valid JSON: {err}") from err
        validate_sidecar(sidecar, sp)
    return TrialTable({n: data[:, i] for i, n in enumerate(names)}, sidecar, missing_time)


def validate_sidecar(sidecar: Any, path: str | Path) -> None:
    """Check a sidecar's schema: an object; ``kind`` one of :data:`KINDS`; fixed angles and the
    subject's numbers finite and inside :data:`SIDECAR_RANGES` / :data:`SUBJECT_RANGES`.

    :raises DataFileError: names the field, its value and the allowed range.
    """
    if not isinstance(sidecar, dict):
        raise DataFileError(path, f"sidecar must be a JSON object, not a {type(sidecar).__name__}")
    if "kind" in sidecar and sidecar["kind"] not in KINDS:
        raise DataFileError(path, f"kind {sidecar['kind']!r} is not one of {KINDS}")
    for key, (lo, hi) in SIDECAR_RANGES.items():
        if sidecar.get(key) is not None:
            _check_number(path, key, sidecar[key], lo, hi, "°")
    subject = sidecar.get("subject")
    if subject is None:
        return
    if not isinstance(subject, dict):
        raise DataFileError(path, f"subject must be a JSON object, not a {type(subject).__name__}")
    for key, (lo, hi) in SUBJECT_RANGES.items():
        if subject.get(key) is not None:
            _check_number(path, f"subject.{key}", subject[key], lo, hi, key.rsplit("_", 1)[-1])


def _check_number(path: str | Path, field_name: str, value: Any, lo: float, hi: float, unit: str) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not lo <= value <= hi:
        raise DataFileError(path, f"{field_name} = {value!r} is outside the allowed range {lo:g}..{hi:g} {unit}")


def _count_lines(path: Path) -> int:
    """Lines in ``path``, counted in 1 MiB blocks (bounded memory)."""
    lines, last = 0, b"\n"
    with path.open("rb") as fh:
        while block := fh.read(1 << 20):
            lines += block.count(b"\n")
            last = block[-1:]
    return lines + (last != b"\n")
