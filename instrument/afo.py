"""``instrument analyze afo``: AADS trials from the store, trial files or C3D files, through the analysis."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from analysis.aads.experiment import AadsExperiment, TrialInput, analyze_experiment
from analysis.aads.model import JigModel

from .errors import InstrumentError
from .motion import motion_trial
from .recording import read_trial
from .store import SessionStore


def _factors_from_metadata(metadata: dict[str, Any]) -> tuple[dict[str, Any], float | None]:
    proto = metadata.get("protocol", {})
    if proto.get("name") != "aads":
        raise InstrumentError(f"not an AADS trial (protocol {proto.get('name')!r})")
    cond = proto.get("condition", {})
    return ({k: cond.get(k) for k in ("spring", "operator", "trial")}, cond.get("spring_n_per_m"))


def trial_input(trial: Any) -> TrialInput:
    """An instrument trial file (read), with its spring, operator and trial from the recorded condition."""
    factors, k = _factors_from_metadata(trial.metadata)
    return TrialInput(motion_trial(trial), factors, k)


def trial_input_from_file(path: Path) -> TrialInput:
    """An instrument trial file (.h5), with its spring, operator and trial from the recorded condition."""
    return trial_input(read_trial(path))


def resolve_trials(specs: Sequence[str], store: SessionStore | None, *, spring: int | None = None,
                   spring_n_per_m: float | None = None, model: JigModel | None = None) -> list[TrialInput]:
    """Turn command-line trial names into inputs: a store trial id, an ``.h5`` trial file or a ``.c3d`` file
    (through :func:`instrument.loading.load_trials`).

    A C3D file carries no experimental factors; ``spring`` (a spring number of the model) or
    ``spring_n_per_m`` supplies the spring for its theoretical stiffness.
    """
    from .loading import load_trials

    return [t.afo_input(spring=spring, spring_n_per_m=spring_n_per_m, model=model) for t in load_trials(specs, store)]


def analyze_afo(inputs: Sequence[TrialInput], model: JigModel) -> AadsExperiment:
    """Run the AADS analysis over ``inputs``."""
    return analyze_experiment(inputs, model)


def afo_model_diagnosis(experiment: AadsExperiment, window_deg: tuple[float, float]) -> tuple[dict[str, Any] | None, str]:
    """The AFO model-level diagnosis of an analysed set (one AFO's trials, each left out once):
    (its JSON, or ``None`` when it cannot run; its text, or one line saying why not)."""
    from analysis.diagnosis.aads_model import AfoTrialData, diagnose_afo_model
    from analysis.errors import AnalysisError

    with_theory = [r for r in experiment.results if r.theory is not None]
    try:
        d = diagnose_afo_model([AfoTrialData.from_result(r, Path(r.source).name) for r in with_theory],
                               window_deg=window_deg)
    except AnalysisError as err:
        return None, f"AFO model-level diagnosis not run: {err}"
    return d.as_dict(), d.text()
