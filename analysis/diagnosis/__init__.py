"""Model-discrepancy diagnosis: what the baseline model of a trial gets wrong, its cause, and what fixing it buys.

``DiagnosisTrial`` (or ``from_table`` of a trial CSV) → ``diagnose`` → ``Diagnosis`` (cause,
parameters with units, RMSE in and out of sample, every candidate's score, ambiguities and the
protocol change that would resolve them) → ``write_diagnosis_plot``.
"""

from .data import DiagnosisTrial, from_table
from .engine import Diagnosis, diagnose, magnitude
from .report import write_diagnosis_plot

__all__ = ["DiagnosisTrial", "from_table", "Diagnosis", "diagnose", "magnitude", "write_diagnosis_plot"]
