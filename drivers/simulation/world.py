"""The simulated world's physical constants (SI).

The simulators are the world the instrument measures, so they keep their own constants: the
drivers never import the analysis layer, and the models that analyse the simulated data
(:mod:`analysis.constants`) must agree with the world, not share its definition (a test checks
they agree). Each simulator also takes gravity as a parameter.
"""

from __future__ import annotations

#: gravitational acceleration of the simulated lab (m/s²)
GRAVITY_M_S2 = 9.81

__all__ = ["GRAVITY_M_S2"]
