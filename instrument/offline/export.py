"""Export a recorded trial: OpenSim ``.sto``/``.mot``, the trial CSV with its JSON sidecar, and C3D.

Sign conventions are the trial CSV's (:mod:`analysis.trial_csv`). What a trial's table is, is its
kind's (:meth:`instrument.kinds.base.TrialKind.table`): for dynamometer trials the isokinetic sweep
with the arm's weight removed, for replica-leg trials the samples inside each hold, for AADS
trials the AFO torque from static optimisation against the hinge angle.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from analysis.sto import write_sto
from analysis.trial_csv import TrialTable, write_trial_csv

from .. import kinds
from ..errors import ExportError, ProtocolError
from ..live.recording import TrialFile

FORMATS = ("sto", "csv", "c3d")


def trial_table(trial: TrialFile, subject: dict[str, Any] | None = None) -> TrialTable:
    """The trial as ``time_s, angle_deg, torque_Nm`` columns with its sidecar (its kind's table).

    :raises ExportError: the trial's kind is unknown, or the trial holds no data for its table.
    """
    name = trial.metadata["protocol"]["name"]
    try:
        kind = kinds.get(name)
    except ProtocolError:
        raise ExportError(f"{trial.path}: no table export for {name!r} trials") from None
    return kind.table(trial, subject)


def export_targets(fmt: str, out: str | Path) -> list[Path]:
    """The files an export of ``fmt`` to ``out`` writes (a CSV brings its JSON sidecar)."""
    out = Path(out)
    return [out, out.with_suffix(".json")] if fmt == "csv" else [out]


def check_export_targets(fmt: str, out: str | Path, *, store_root: Path | None, inputs: list[Path]) -> None:
    """Refuse an export that would write inside the store or over one of its own inputs.

    :raises ExportError: names the file and why.
    """
    targets = [t.resolve() for t in export_targets(fmt, out)]
    if len(set(targets)) != len(targets):
        raise ExportError(f"{out}: a {fmt} export writes {Path(out).with_suffix('.json').name} beside it; "
                          "choose a name that does not end in .json")
    root = store_root.resolve() if store_root is not None else None
    sources = {p.resolve() for p in inputs}
    for t in targets:
        if t in sources:
            raise ExportError(f"{t}: is an input of this export; exports never overwrite their inputs")
        if root is not None and (t == root or root in t.parents):
            raise ExportError(f"{t}: is inside the store {root}; exports are written outside it")


def export_trial(trial: TrialFile, fmt: str, out: str | Path, subject: dict[str, Any] | None = None) -> list[Path]:
    """Write ``trial`` as ``fmt`` to ``out``; returns the files written.

    :raises ExportError: unknown format, or this trial has no such export.
    """
    out = Path(out)
    if fmt not in FORMATS:
        raise ExportError(f"unknown export format {fmt!r}; one of {FORMATS}")
    kind = kinds.get(trial.metadata["protocol"]["name"])
    if fmt == "c3d":
        kind.write_c3d(trial, out)
        return [out]
    if fmt == "sto":
        cols, in_degrees = kind.sto_columns(trial, subject)
        write_sto(out, cols, name=f"{kind.name} trial {trial.path.stem}", in_degrees=in_degrees)
        return [out]
    write_trial_csv(out, trial_table(trial, subject))
    return [out, out.with_suffix(".json")]


__all__ = ["FORMATS", "ExportError", "check_export_targets", "export_targets", "export_trial", "trial_table"]
