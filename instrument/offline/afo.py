"""``instrument analyze afo``: AADS trials from the store, trial files or C3D files, through the analysis."""

from __future__ import annotations

from collections.abc import Sequence

from analysis.aads.experiment import AadsExperiment, TrialInput, analyze_experiment
from analysis.aads.model import JigModel

from ..kinds.aads import afo_model_diagnosis, trial_input
from ..store import SessionStore, TrialRecord
from .loading import load_trials


def resolve_trials(specs: Sequence[str | TrialRecord], store: SessionStore | None, *, spring: int | None = None,
                   spring_n_per_m: float | None = None, model: JigModel | None = None) -> list[TrialInput]:
    """Turn command-line trial names into inputs: a store trial id, an ``.h5`` trial file or a ``.c3d`` file
    (through :func:`instrument.offline.loading.load_trials`).

    A C3D file carries no experimental factors; ``spring`` (a spring number of the model) or
    ``spring_n_per_m`` supplies the spring for its theoretical stiffness.
    """
    return [t.afo_input(spring=spring, spring_n_per_m=spring_n_per_m, model=model) for t in load_trials(specs, store)]


def analyze_afo(inputs: Sequence[TrialInput], model: JigModel) -> AadsExperiment:
    """Run the AADS analysis over ``inputs``."""
    return analyze_experiment(inputs, model)


__all__ = ["afo_model_diagnosis", "analyze_afo", "resolve_trials", "trial_input"]
