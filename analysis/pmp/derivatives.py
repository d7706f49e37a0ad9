"""The collocation problem's derivatives for IPOPT, made per collocation point and assembled.

Every nonlinear term of :func:`analysis.pmp.problem.build_problem`'s problem is one small point function (a
trial's dynamics and the calf tendons' equilibrium at one collocation point), mapped over the trial's points;
everything around it (Hermite–Simpson conditions, bounds, the tracking cost, the priors) is linear in the point
function's outputs and at most quadratic in the decision variables. CasADi's own derivatives of the expanded
problem differentiate the whole expression graph (≈ 100,000 nodes for six trials): making them was ≈ 3 s of a
3.4 s fit. Here the point function is differentiated once per trial, its Jacobian and (one triangle of) its
Hessian are mapped over the points and assembled by the chain rule, the sums through one constant sparse matrix
per result (the assembly is linear in the parts):

    J_g = ∂g̃/∂x + Σ_trials B · blockdiag(∂w/∂z) · D
    ∇²L = σ ∇²f + ∇²_x(λᵀ g̃) + Σ_trials Dᵀ · blockdiag(∇²_z (μᵀ w)) · D,    μ = Bᵀ λ

with w the point outputs (a column per point), z its differentiable inputs (z = D x: linear in the decision
variables), g̃ the constraints with the point outputs as symbols and B = ∂g̃/∂w. When B is not constant or a point
input is not linear in the decision variables (the problem is not of this form; both checked symbolically)
CasADi's own derivatives are used. Either way the derivatives are the same to rounding.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class PointCall:
    """One trial's point function mapped over its collocation points: the function, its differentiable inputs
    (each ``n × points``, as passed to the map), the inputs it is not differentiated by (path coefficients:
    constants or parameters) and its outputs (each ``m × points``) as they appear in the problem."""

    function: Any
    inputs: tuple[Any, ...]
    fixed: tuple[Any, ...]
    outputs: tuple[Any, ...]


def _blocks(ca: Any, mapped: Any, points: int, block: Any) -> Any:
    """The map's horizontally concatenated blocks (each of sparsity ``block``) as a block-diagonal matrix."""
    pattern = ca.kron(ca.DM(ca.Sparsity.diag(points), 1.0), ca.DM(block, 1.0)).sparsity()
    return ca.sparsity_cast(mapped, pattern)


def derivative_functions(opti: Any, calls: list[PointCall]) -> dict[str, Any] | None:
    """IPOPT's ``jac_g`` and ``hess_lag`` (nlpsol options) for ``opti``'s problem, or None when the problem's
    constraints are not linear in the point outputs with constant coefficients or a point input is not linear in
    the decision variables."""
    import casadi as ca

    if not calls:
        return None
    x, p, f, g = opti.x, opti.p, opti.f, opti.g
    # the constraints with each trial's point outputs replaced by one symbol (outputs stacked by rows)
    w_mx = [ca.MX.sym("w", sum(o.size1() for o in c.outputs), c.outputs[0].size2()) for c in calls]
    originals, replacements = [], []
    for c, w in zip(calls, w_mx, strict=True):
        row = 0
        for o in c.outputs:
            originals.append(o)
            replacements.append(w[row:row + o.size1(), :])
            row += o.size1()
    g_tilde = ca.graph_substitute([g], originals, replacements)[0]
    outer = ca.Function("outer", [x, p, *w_mx], [g_tilde, f]).expand()
    xs, ps = ca.SX.sym("x", x.sparsity()), ca.SX.sym("p", p.sparsity())
    w_sx = [ca.SX.sym("w", w.sparsity()) for w in w_mx]
    gs, fs = outer(xs, ps, *w_sx)
    w_flat = ca.vertcat(*[ca.vec(w) for w in w_sx])
    b = ca.jacobian(gs, w_flat)
    if ca.depends_on(b, ca.vertcat(xs, ps, w_flat)):
        return None
    b_dm = ca.DM(ca.Function("b0", [xs, ps], [b])(0, 0))
    lam_f_sx, lam_g_sx = ca.SX.sym("lam_f"), ca.SX.sym("lam_g", gs.sparsity())
    outer_jac = ca.Function("outer_jac", [xs, ps], [ca.jacobian(gs, xs)])
    outer_hess = ca.Function("outer_hess", [xs, ps, lam_f_sx, lam_g_sx],
                             [ca.triu(ca.hessian(lam_f_sx * fs + ca.dot(lam_g_sx, gs), xs)[0])])
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.sparsity())
    jac_parts, hess_parts = [outer_jac(x, p)], [outer_hess(x, p, lam_f, lam_g)]
    # the same sums with symbols for the parts: linear in them, so each result's nonzeros are a constant sparse
    # matrix times the parts' nonzeros (one product per evaluation instead of a chain of sparse products)
    jac_sum = jac_sym = ca.SX.sym("j", jac_parts[0].sparsity())
    hess_sum = hess_sym = ca.SX.sym("h", hess_parts[0].sparsity())
    jac_syms, hess_syms = [jac_sym], [hess_sym]
    offset = 0
    w_values: list[Any] = []  # each trial's point outputs (n_w × points), evaluated beside their Jacobian
    for c in calls:
        fn, points = c.function, c.inputs[0].size2()
        sizes = [i.size1() for i in c.inputs]
        n_z, n_w = sum(sizes), sum(o.size1() for o in c.outputs)
        z = ca.SX.sym("z", n_z)
        fixed = [ca.SX.sym("c", fn.size1_in(len(sizes) + k), 1) for k in range(len(c.fixed))]
        parts, at = [], 0
        for s in sizes:
            parts.append(z[at:at + s])
            at += s
        w = ca.vertcat(*fn(*parts, *fixed))
        mu = ca.SX.sym("mu", n_w)
        jac_z = ca.jacobian(w, z)
        hess_z = ca.triu(ca.hessian(ca.dot(mu, w), z)[0])  # one triangle: half the point Hessian's work
        jac_pt = ca.Function("jac_pt", [z, *fixed], [w, jac_z])  # the outputs too: g from them, not evaluated again
        hess_pt = ca.Function("hess_pt", [z, mu, *fixed], [hess_z])
        z_cols = ca.vertcat(*c.inputs)  # n_z × points
        # D = ∂vec(Z)/∂x: the inputs are linear in the decision variables (checked)
        d_sx = ca.Function("dz", [x, p], [ca.jacobian(ca.vec(z_cols), x)]).expand()(xs, ps)
        if ca.depends_on(d_sx, ca.vertcat(xs, ps)):
            return None
        d = ca.DM(ca.Function("d0", [xs, ps], [d_sx])(0, 0))
        b_t = b_dm[:, offset:offset + n_w * points]
        offset += n_w * points
        w_cols, jac_map = jac_pt.map(points)(z_cols, *c.fixed)
        hess_map = hess_pt.map(points)(z_cols, ca.reshape(ca.mtimes(b_t.T, lam_g), n_w, points), *c.fixed)
        w_values.append(w_cols)
        jac_parts.append(jac_map)
        hess_parts.append(hess_map)
        jac_syms.append(ca.SX.sym("j", jac_map.sparsity()))
        hess_syms.append(ca.SX.sym("h", hess_map.sparsity()))
        jac_sum = jac_sum + ca.mtimes(b_t, ca.mtimes(_blocks(ca, jac_syms[-1], points, jac_z.sparsity()), d))
        upper = _blocks(ca, hess_syms[-1], points, hess_z.sparsity())
        full = upper + upper.T - ca.diag(ca.diag(upper))
        hess_sum = hess_sum + ca.triu(ca.mtimes(d.T, ca.mtimes(full, d)))
    jac = _linear_map(ca, jac_sum, jac_syms, jac_parts)
    hess = _linear_map(ca, hess_sum, hess_syms, hess_parts)
    g_from_outputs = outer(x, p, *w_values)[0]
    return {"jac_g": ca.Function("nlp_jac_g", [x, p], [g_from_outputs, jac]),
            "hess_lag": ca.Function("nlp_hess_l", [x, p, lam_f, lam_g], [hess])}


def _linear_map(ca: Any, total: Any, symbols: list[Any], parts: list[Any]) -> Any:
    """``total`` (SX, linear in ``symbols``' nonzeros) with each symbol replaced by its part (MX of the same
    sparsity): its nonzeros as a constant sparse matrix times the parts' nonzeros."""
    stacked = ca.vertcat(*[s.nz[:] for s in symbols])
    matrix = ca.evalf(ca.jacobian(total.nz[:], stacked))
    return ca.MX(total.sparsity(), ca.mtimes(matrix, ca.vertcat(*[part.nz[:] for part in parts])))
