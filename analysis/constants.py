"""Physical constants, defined once for the whole instrument (SI).

The benchmarks' independent generators (``benchmarks/diagnosis_truth.py``, ``benchmarks/opensim_truth.py``)
keep their own on purpose: they must share nothing with the code they test.
"""

from __future__ import annotations

#: gravitational acceleration used by every model and simulator (m/s²)
GRAVITY_M_S2 = 9.81

__all__ = ["GRAVITY_M_S2"]
