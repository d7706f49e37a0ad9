"""Passive muscle-tendon parameters from isokinetic trials by direct collocation: the names, in one place.

The estimator is split along its seams: the model (:mod:`analysis.pmp.model`: trials, subject,
free parameters, the muscles' moment), the fit (:mod:`analysis.pmp.problem`: build → solve →
a frozen result) and what the fit determined (:mod:`analysis.pmp.identifiability`).
"""

from __future__ import annotations

from .identifiability import MISFIT_LIMIT, MODEL_ERROR_RMS_NM, autocorrelation_time, identifiability, smoothed
from .model import (
    MEASUREMENT_SD,
    SLACK_BOUNDS,
    ParameterSet,
    PmpTrial,
    Subject,
    eliminate_tendons,
    free_parameters,
    moment_function,
    muscles_moment,
)
from .problem import PRIOR_RELATIVE_SD, PRIOR_WEIGHT, SIGMA_Q_RAD, SIGMA_U_NM, SIGMA_V_RAD_S, PmpResult, estimate

__all__ = ["MEASUREMENT_SD", "MISFIT_LIMIT", "MODEL_ERROR_RMS_NM", "PRIOR_RELATIVE_SD", "PRIOR_WEIGHT", "SIGMA_Q_RAD",
           "SIGMA_U_NM", "SIGMA_V_RAD_S", "SLACK_BOUNDS", "ParameterSet", "PmpResult", "PmpTrial", "Subject",
           "autocorrelation_time", "eliminate_tendons", "estimate", "free_parameters", "identifiability",
           "moment_function", "muscles_moment", "smoothed"]
