"""The DeGroote–Fregly passive curves against OpenSim's own DeGrooteFregly2016Muscle (agreement to 1e-9)."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.pmp.curves import (
    active_fiber_force,
    passive_fiber_force,
    passive_fiber_stiffness,
    tendon_force,
    tendon_length_from_force,
    tendon_stiffness,
)
from tests.opensim_reference import run_opensim

FIBER = np.linspace(0.2, 1.9, 400)
FIBER_STRAINS = (0.3, 0.6, 0.9)
TENDON_STRAINS = (0.02, 0.049, 0.1)
FORCES = np.linspace(0.0, 1.2, 50)


@pytest.fixture(scope="module")
def reference() -> dict:
    return run_opensim(f"""
        m = osim.DeGrooteFregly2016Muscle()
        out = {{"fiber": {{}}, "tendon": {{}}}}
        out["active"] = [m.calcActiveForceLengthMultiplier(x) for x in {FIBER.tolist()}]
        for e in {list(FIBER_STRAINS)}:
            m.set_passive_fiber_strain_at_one_norm_force(e)
            xs = {FIBER.tolist()}
            out["fiber"][str(e)] = [[m.calcPassiveForceMultiplier(x) for x in xs],
                                    [m.calcPassiveForceMultiplierDerivative(x) for x in xs]]
        for e in {list(TENDON_STRAINS)}:
            m.set_tendon_strain_at_one_norm_force(e)
            xs = [0.98 + i * (0.02 + 1.5 * e) / 399 for i in range(400)]
            out["tendon"][str(e)] = [xs, [m.calcTendonForceMultiplier(x) for x in xs],
                                     [m.calcTendonForceMultiplierDerivative(x) for x in xs],
                                     [m.calcTendonForceLengthInverseCurve(f) for f in {FORCES.tolist()}]]
        print(json.dumps(out))
    """)


@pytest.mark.parametrize("strain", FIBER_STRAINS)
def test_passive_fiber_curve_matches_opensim(reference: dict, strain: float) -> None:
    ref, dref = (np.array(v) for v in reference["fiber"][str(strain)])
    np.testing.assert_allclose(passive_fiber_force(FIBER, strain), ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(passive_fiber_stiffness(FIBER, strain), dref, rtol=1e-9, atol=1e-12)


def test_active_force_length_curve_matches_opensim(reference: dict) -> None:
    """The tonic-activation extension's isometric active curve, against OpenSim's own (DeGroote et al. 2016, eq S2)."""
    np.testing.assert_allclose(active_fiber_force(FIBER), np.array(reference["active"]), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("strain", TENDON_STRAINS)
def test_tendon_curve_matches_opensim(reference: dict, strain: float) -> None:
    xs, ref, dref, inv = (np.array(v) for v in reference["tendon"][str(strain)])
    np.testing.assert_allclose(tendon_force(xs, strain), ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(tendon_stiffness(xs, strain), dref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(tendon_length_from_force(FORCES, strain), inv, rtol=1e-9)


def test_casadi_expressions_are_the_same_curves() -> None:
    import casadi as ca

    x, e = ca.SX.sym("x"), ca.SX.sym("e")
    f = ca.Function("f", [x, e], [passive_fiber_force(x, e), tendon_force(x, e), ca.jacobian(tendon_force(x, e), x)])
    for lm, eps in ((1.3, 0.6), (1.03, 0.049)):
        a, b, c = (float(v) for v in f(lm, eps))
        assert a == pytest.approx(passive_fiber_force(lm, eps), rel=1e-12)
        assert b == pytest.approx(tendon_force(lm, eps), rel=1e-12)
        assert c == pytest.approx(tendon_stiffness(lm, eps), rel=1e-12)  # exact derivative, not a difference
