"""The seeds' own case: why the AADS stiffness misses the known spring (dissertation Table 2.1).

With the spring's own torque–angle curve known (theory from the hook markers, eqs 2.1–2.9), two
extensions of the SOP torque–angle record become identifiable:

- ``coulomb_friction`` at the hinge, constant plus proportional to the spring load,
  (f₀ + μ·S)·tanh(ω/ω_s), which lifts the loading branch and lowers the unloading one;
- ``series_compliance`` of the shell, θ_markers = θ_hinge + c·τ, which stretches the angle axis
  more the stiffer the spring.

The model τ = S(θ − c·τ) + (f₀ + μ·S)·tanh(ω/ω_s) + τ₀ is fitted in the fit window (c by a grid
and a bounded refinement, the rest by least squares). Each extension's gain is the change of the
loading-branch stiffness error against the known spring when its effect is removed from the data.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from ..aads.stiffness import FitError, line_fit
from .causes import FRICTION_SPEED_RAD_S


@dataclass
class StiffnessExplanation:
    """Loading-branch stiffness error (%) against the known spring, raw and with each effect removed."""

    theory_nm_per_deg: float
    error_raw_pct: float
    error_without_friction_pct: float
    error_without_compliance_pct: float
    error_without_both_pct: float
    friction_nm: float
    friction_per_spring_torque: float
    compliance_deg_per_nm: float
    rmse_before_nm: float
    rmse_after_nm: float

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def explain_stiffness_error(angle_deg: np.ndarray, velocity_deg_s: np.ndarray, torque_nm: np.ndarray,
                            spring_torque_nm: np.ndarray, hook_angle_deg: np.ndarray,
                            window_deg: tuple[float, float] = (6.0, 20.0), min_speed_deg_s: float = 2.0) -> StiffnessExplanation:
    """Fit friction and shell compliance against the known spring and measure what each explains.

    :raises FitError: the trial does not cover the window on the loading branch.
    """
    ok = np.isfinite(angle_deg) & np.isfinite(torque_nm) & np.isfinite(spring_torque_nm) & np.isfinite(hook_angle_deg)
    ok &= np.isfinite(velocity_deg_s)
    a, v, tq = angle_deg[ok], velocity_deg_s[ok], torque_nm[ok]
    inside_hook = (hook_angle_deg[ok] >= window_deg[0] - 2) & (hook_angle_deg[ok] <= window_deg[1] + 2)
    spring = np.polyfit(hook_angle_deg[ok][inside_hook], spring_torque_nm[ok][inside_hook], 2)  # S(θ), θ in degrees
    sel_th = (hook_angle_deg[ok] >= window_deg[0]) & (hook_angle_deg[ok] <= window_deg[1])
    k_theory = line_fit(hook_angle_deg[ok][sel_th], spring_torque_nm[ok][sel_th], window_deg).slope_nm_per_deg
    win = (a >= window_deg[0]) & (a <= window_deg[1])
    sign = np.tanh(np.deg2rad(v) / FRICTION_SPEED_RAD_S)

    def solve(c: float) -> tuple[float, np.ndarray, np.ndarray]:
        s = np.polyval(spring, a - c * tq)
        x = np.column_stack([sign, s * sign, np.ones_like(a)])[win]
        coef, *_ = np.linalg.lstsq(x, (tq - s)[win], rcond=None)
        r = (tq - s)[win] - x @ coef
        return float(r @ r), coef, s

    grid = np.linspace(0.0, 0.3, 31)  # °/N·m
    c0 = grid[int(np.argmin([solve(c)[0] for c in grid]))]
    res = minimize_scalar(lambda c: solve(c)[0], bounds=(max(c0 - 0.01, 0.0), c0 + 0.01), method="bounded")
    c = float(res.x)
    rss, (f0, mu, _), s = solve(c)
    friction = (f0 + mu * s) * sign

    def err(angle: np.ndarray, torque: np.ndarray) -> float:
        # the window is taken on the angle at hand: the spring curve is not straight, so the slope
        # must be compared over the same angles as the theory's
        load = (angle >= window_deg[0]) & (angle <= window_deg[1]) & (v > min_speed_deg_s)
        return 100.0 * (line_fit(angle[load], torque[load], window_deg).slope_nm_per_deg / k_theory - 1.0)

    before = tq[win] - np.polyval(spring, a[win])
    return StiffnessExplanation(
        k_theory, err(a, tq), err(a, tq - friction), err(a - c * tq, tq), err(a - c * tq, tq - friction),
        float(f0), float(mu), c, float(np.sqrt(np.mean((before - before.mean()) ** 2))), float(np.sqrt(rss / win.sum())))


__all__ = ["explain_stiffness_error", "StiffnessExplanation", "FitError"]
