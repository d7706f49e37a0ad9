"""``instrument analyze afo``: AADS trials from the store, trial files or C3D files, through the analysis."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from analysis.aads.experiment import AadsExperiment, TrialInput, analyze_experiment
from analysis.aads.model import JigModel
from analysis.c3d import read_c3d

from .errors import InstrumentError
from .export import motion_trial
from .recording import read_trial
from .store import SessionStore


def _factors_from_metadata(metadata: dict[str, Any]) -> tuple[dict[str, Any], float | None]:
    proto = metadata.get("protocol", {})
    if proto.get("name") != "aads":
        raise InstrumentError(f"not an AADS trial (protocol {proto.get('name')!r})")
    cond = proto.get("condition", {})
    return ({k: cond.get(k) for k in ("spring", "operator", "trial")}, cond.get("spring_n_per_m"))


def trial_input_from_file(path: Path) -> TrialInput:
    """An instrument trial file (.h5), with its spring, operator and trial from the recorded condition."""
    trial = read_trial(path)
    factors, k = _factors_from_metadata(trial.metadata)
    return TrialInput(motion_trial(trial), factors, k)


def resolve_trials(specs: Sequence[str], store: SessionStore | None, *, spring: int | None = None,
                   spring_n_per_m: float | None = None, model: JigModel | None = None) -> list[TrialInput]:
    """Turn command-line trial names into inputs: a store trial id, an ``.h5`` trial file or a ``.c3d`` file.

    A C3D file carries no experimental factors; ``spring`` (a spring number of the model) or
    ``spring_n_per_m`` supplies the spring for its theoretical stiffness.
    """
    out: list[TrialInput] = []
    for spec in specs:
        path = Path(spec)
        if spec.isdigit() and not path.exists():
            if store is None:
                raise InstrumentError(f"trial {spec}: a trial id needs a session store (--store)")
            rec = store.trial(int(spec))
            ti = trial_input_from_file(Path(rec.path))
            ti.factors["store_trial_id"] = rec.id
            out.append(ti)
        elif path.suffix.lower() == ".c3d":
            motion = read_c3d(path)
            k = spring_n_per_m
            if k is None and spring is not None and model is not None:
                k = model.spring_n_per_m(spring)
            out.append(TrialInput(motion, {"spring": spring, "operator": None, "trial": None}, k))
        elif path.suffix.lower() in (".h5", ".hdf5"):
            out.append(trial_input_from_file(path))
        else:
            raise InstrumentError(f"{spec}: not a trial id, an .h5 trial file or a .c3d file")
    return out


def analyze_afo(inputs: Sequence[TrialInput], model: JigModel) -> AadsExperiment:
    """Run the AADS analysis over ``inputs``."""
    return analyze_experiment(inputs, model)
