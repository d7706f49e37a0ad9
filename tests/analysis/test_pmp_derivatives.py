"""The collocation problem's derivatives assembled per point (:mod:`analysis.pmp.derivatives`) are CasADi's own."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from analysis.pmp.derivatives import derivative_functions
from analysis.pmp.model_diagnosis import get_extension
from analysis.pmp.problem import build_problem, estimate
from analysis.pmp.synthetic import simulated_subject


def _reference(opti: Any) -> tuple[Any, Any]:
    """CasADi's own constraint Jacobian and Lagrangian Hessian of ``opti``'s problem (expanded)."""
    import casadi as ca

    x, p, f, g = opti.x, opti.p, opti.f, opti.g
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.sparsity())
    jac = ca.Function("jac_ref", [x, p], [ca.jacobian(g, x)]).expand()
    hess = ca.Function("hess_ref", [x, p, lam_f, lam_g],
                       [ca.triu(ca.hessian(lam_f * f + ca.dot(lam_g, g), x)[0])]).expand()
    return jac, hess


@pytest.mark.parametrize("extension", [None, "end_range_structures+tonic_activation", "knee_tendon_compliance",
                                       "axis_misalignment"])
def test_assembled_jacobian_and_hessian_equal_casadis_own(extension: str | None) -> None:
    """Knee and ankle trials (the calf's tendon equilibrium as constraints, the set angles fitted, path
    coefficients as parameters when an extension turns the joint): at random points and multipliers every entry
    of the assembled constraint Jacobian and Lagrangian Hessian equals CasADi's derivative of the same problem."""
    import casadi as ca

    _, trials, subject = simulated_subject(3, ("knee", "ankle"))
    problem = build_problem([trials[0], trials[4]], subject, intervals=4,
                            extension=get_extension(extension) if extension else None)
    opti = problem.opti
    ours = derivative_functions(opti, problem.point_calls)
    assert ours is not None
    jac_ref, hess_ref = _reference(opti)
    rng = np.random.default_rng(7)
    x0 = np.asarray(ca.DM(opti.value(opti.x, opti.initial()))).ravel()
    p0 = np.asarray(ca.DM(opti.value(opti.p, opti.value_parameters()))).ravel()
    g_ref = ca.Function("g_ref", [opti.x, opti.p], [opti.g])
    for _ in range(3):
        x = x0 * (1 + 0.02 * rng.standard_normal(x0.size))
        lam_f, lam_g = rng.uniform(0.5, 2.0), rng.standard_normal(opti.ng)
        g_ours, j_ours = ours["jac_g"](x, p0)
        np.testing.assert_allclose(ca.DM(j_ours).full(), ca.DM(jac_ref(x, p0)).full(), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(ca.DM(g_ours).full(), ca.DM(g_ref(x, p0)).full(), rtol=1e-12, atol=1e-12)
        h_ours = ca.DM(ours["hess_lag"](x, p0, lam_f, lam_g)).full()
        h_ref = ca.DM(hess_ref(x, p0, lam_f, lam_g)).full()
        np.testing.assert_allclose(h_ours, h_ref, rtol=1e-9, atol=1e-9 * max(1.0, float(np.abs(h_ref).max())))


def test_a_fit_with_the_assembled_derivatives_is_the_fit_with_casadis(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same problem solved with either set of derivatives: the same iterations and estimates to rounding."""
    import analysis.pmp.problem as pr

    _, trials, subject = simulated_subject(5, ("knee",))
    ours = estimate(trials, subject, intervals=6)
    monkeypatch.setattr(pr, "derivative_functions", lambda opti, calls: None)  # CasADi's own of the expanded problem
    theirs = estimate(trials, subject, intervals=6)
    assert ours.success and theirs.success and ours.nit == theirs.nit
    np.testing.assert_allclose(ours.x, theirs.x, rtol=1e-8)
    assert ours.objective == pytest.approx(theirs.objective, rel=1e-10)
