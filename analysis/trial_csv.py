"""The trial CSV: ``time_s,angle_deg,torque_Nm[,more channels]`` plus a JSON sidecar of the same name.

Sign convention: angle positive in dorsiflexion (AFO, ankle) or knee flexion; torque is what the
specimen exerts against the bending (a linear spring reads torque = k × angle, k > 0). For knee
and ankle trials the torque includes the weight of the segments distal to the joint; the
dynamometer arm's own weight is already removed. The sidecar holds ``kind`` (afo, knee, ankle,
replica), the fixed joint angles ``hip_flexion_deg``, ``knee_flexion_deg``,
``ankle_dorsiflexion_deg``, and ``subject`` (``mass_kg``, ``height_m``, ``thigh_length_m``,
``shank_length_m``, ...); more keys are allowed.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import DataFileError

REQUIRED = ("time_s", "angle_deg", "torque_Nm")
KINDS = ("afo", "knee", "ankle", "replica")


@dataclass
class TrialTable:
    """Columns of one trial (units in the names) and its sidecar."""

    columns: dict[str, np.ndarray]
    sidecar: dict[str, Any] = field(default_factory=dict)

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

    :raises DataFileError: missing file, missing required column, non-numeric or empty data, bad sidecar.
    """
    path = Path(path)
    if not path.exists():
        raise DataFileError(path, "file does not exist")
    with path.open() as fh:
        header = fh.readline().strip()
    names = [h.strip() for h in header.split(",")]
    missing = [r for r in REQUIRED if r not in names]
    if missing:
        raise DataFileError(path, f"missing column(s) {missing}; header is {names}")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as err:
        raise DataFileError(path, f"non-numeric or ragged data: {err}") from err
    if data.shape[0] == 0:
        raise DataFileError(path, "no data rows")
    if data.shape[1] != len(names):
        raise DataFileError(path, f"{data.shape[1]} columns of data but {len(names)} names in the header")
    sidecar: dict[str, Any] = {}
    sp = sidecar_path(path)
    if sp.exists():
        try:
            sidecar = json.loads(sp.read_text())
        except json.JSONDecodeError as err:
            raise DataFileError(sp, f"sidecar is not valid JSON: {err}") from err
        if "kind" in sidecar and sidecar["kind"] not in KINDS:
            raise DataFileError(sp, f"kind {sidecar['kind']!r} is not one of {KINDS}")
    return TrialTable({n: data[:, i] for i, n in enumerate(names)}, sidecar)
