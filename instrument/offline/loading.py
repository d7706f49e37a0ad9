"""One loader for every analysis: store trial ids, instrument trial files (.h5), C3D files and trial CSVs.

``load_trials(specs, store)`` reads each trial once and hands out what an analysis needs: the
``time_s, angle_deg, torque_Nm`` table (knee, ankle, replica trials and CSVs) or the AADS input
(motion and plate data with the spring, operator and trial from the recorded condition, or a
C3D file). The read path is store → table → analysis everywhere: the CLI's ``analyze``, the GUI's
set analysis and the demo.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InstrumentError
from ..kinds.aads import trial_input
from ..store import SessionStore, TrialRecord
from .export import trial_table


@dataclass
class LoadedTrial:
    """One trial as given: ``spec`` (what the operator typed), its store record if any, and the file read once."""

    spec: str
    path: Path
    record: TrialRecord | None = None
    subject: dict[str, Any] | None = None
    _file: Any = field(default=None, repr=False)

    @property
    def kind(self) -> str:
        """``"c3d"``, ``"csv"`` or ``"h5"`` (an instrument trial file, from the store or given directly)."""
        suffix = self.path.suffix.lower()
        return "c3d" if suffix == ".c3d" else ("h5" if suffix in (".h5", ".hdf5") else "csv")

    def file(self) -> Any:
        """The instrument trial file (read once)."""
        if self._file is None:
            from ..live.recording import read_trial

            self._file = read_trial(self.path)
        return self._file

    @property
    def metadata(self) -> dict[str, Any]:
        """The recorded metadata (empty for CSV and C3D)."""
        return self.file().metadata if self.kind == "h5" else {}

    def table(self) -> Any:
        """The ``time_s, angle_deg, torque_Nm`` table with its sidecar (the store's verdict included)."""
        if self.kind == "csv":
            from analysis.trial_csv import read_trial_csv

            return read_trial_csv(self.path)
        if self.kind == "c3d":
            raise InstrumentError(f"{self.spec}: a C3D file has no torque table; analyse it with `analyze afo`")
        table = trial_table(self.file(), self.subject)
        if self.record is not None:
            table.sidecar["trial_status"] = self.record.status  # the index's verdict (accepted, rejected, ...)
        return table

    def afo_input(self, *, spring: int | None = None, spring_n_per_m: float | None = None, model: Any = None) -> Any:
        """The AADS analysis's input; a C3D file carries no factors, so ``spring`` (a number of the jig
        ``model``) or ``spring_n_per_m`` supplies its theoretical stiffness."""
        from analysis.aads.experiment import TrialInput

        if self.kind == "c3d":
            from analysis.c3d import read_c3d

            motion = read_c3d(self.path)
            written = motion.metadata.get("aads_factors", {})  # what the instrument's export wrote, if it did
            spring = spring if spring is not None else written.get("spring")
            k = spring_n_per_m if spring_n_per_m is not None else (
                written.get("spring_n_per_m") if spring == written.get("spring") else None)
            if k is None and spring is not None and model is not None:
                k = model.spring_n_per_m(spring)
            return TrialInput(motion, {"spring": spring, "operator": written.get("operator"),
                                       "trial": written.get("trial")}, k)
        if self.kind != "h5":
            raise InstrumentError(f"{self.spec}: not a trial id, an .h5 trial file or a .c3d file")
        ti = trial_input(self.file())
        if self.record is not None:
            ti.factors["store_trial_id"] = self.record.id
        return ti


def is_store_id(spec: str) -> bool:
    """Whether a trial named on the command line is a store trial id (digits that are not a file)."""
    return spec.isdigit() and not Path(spec).exists()


def load_trials(items: Sequence[str | TrialRecord], store: SessionStore | None) -> list[LoadedTrial]:
    """The trials named by ``items``: store records, or specs as the operator typed them (store trial
    ids, ``.h5``, ``.c3d`` or CSV paths). Each file is read once, when first asked for.

    :raises InstrumentError: a trial id or record without a store, or a store that has no such trial.
    """
    out = []
    for item in items:
        if isinstance(item, TrialRecord) or is_store_id(item):
            if store is None:
                raise InstrumentError(f"trial {item if isinstance(item, str) else item.id}: a trial id needs a "
                                      "session store (--store)")
            rec = item if isinstance(item, TrialRecord) else store.trial(int(item))
            out.append(LoadedTrial(str(rec.id), Path(rec.path), rec, store.subject(rec.subject_code).as_dict()))
        elif Path(item).is_dir():
            raise InstrumentError(f"{item}: a folder, not a trial file; give the trial files in it (e.g. {item}/*.csv)")
        else:
            out.append(LoadedTrial(item, Path(item)))
    return out


__all__ = ["LoadedTrial", "is_store_id", "load_trials"]
