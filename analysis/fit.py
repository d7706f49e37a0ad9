"""What every fit in the analysis layer returns about itself, in SciPy's ``OptimizeResult`` names.

A fit is built, solved, and returns a frozen result whatever happened: ``success`` (converged),
``status`` (a :class:`FitStatus`), ``message`` (one line, what happened), ``nit`` (iterations),
``x`` (the estimates, SI, in the order of the result's parameter names) and ``fun`` (the final
cost). A fit that does not converge is a result with ``success=False`` and the last iterate (or
the starting values), never an exception; bad input is an exception (:mod:`analysis.errors`).
"""

from __future__ import annotations

from enum import IntEnum


class FitStatus(IntEnum):
    """How a fit ended (0 is success, as SciPy's ``status``)."""

    CONVERGED = 0
    #: the solver stopped before its tolerance (iteration limit, restoration failure, ...): the last iterate
    NOT_CONVERGED = 1
    #: no start of a multi-start fit converged: the starting values
    NO_START_CONVERGED = 2


__all__ = ["FitStatus"]
