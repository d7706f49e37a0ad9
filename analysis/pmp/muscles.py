"""Passive joint moments of the eleven leg muscles from their paths and the DeGroote–Fregly curves (SI).

Each muscle is a fibre at constant thickness (pennation: l_M sin α = l_opt sin α₀) in series with
its tendon. Knee muscles have rigid tendons (l_T = l_s); the calf muscles (soleus, gasmed,
gaslat) have compliant tendons whose length follows from the fibre–tendon equilibrium of
eq 3.2, f_pas(l̃_M, ε₀)·cos α = f_T(l̃_T, ε_T0). A muscle's force along its path times its
moment arm (r = −∂L/∂q) gives its moment toward positive joint angle; the passive elastic
elements are conservative, so the joint moment is also −∂U/∂q of their stored energy, which the
tests use as an independent check.

Parameters per muscle (``MuscleParameters``): tendon slack length (m), passive fibre strain ε₀,
tendon strain ε_T0. Subject scaling multiplies the generic lengths (path, optimal fibre length,
tendon slack length) by the ratio of the subject's segment length to the generic one, as
OpenSim's scaling does for muscles on one segment pair. A thigh scaled unlike the shank
(``thigh_over_shank`` ≠ 1) scales each muscle by its own factor, the shank's times
1 + f_thigh·(thigh_over_shank − 1), f_thigh the fraction of its path length that follows the thigh's
scale (:func:`analysis.pmp.geometry.segment_fractions`: OpenSim's ``Model.scale`` per segment, the mean
over seated poses; the vasti 0.83–0.84, the hamstrings 0.89–0.99, the calf 0–0.04).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .curves import passive_fiber_force, tendon_force
from .geometry import MUSCLES, MusclePath, load_paths, model_segment_lengths_m, segment_fractions

COMPLIANT = ("soleus", "gasmed", "gaslat")


@dataclass
class MuscleParameters:
    """The estimated parameters of one muscle."""

    tendon_slack_length_m: float
    passive_strain: float = 0.6     # ε₀ (DeGroote–Fregly default; the leg takes its model's value)
    tendon_strain: float = 0.049    # ε_T0 (DeGroote–Fregly default; the leg takes its model's value)


@dataclass
class LegMuscles:
    """The eleven muscles of one (scaled) leg."""

    paths: dict[str, MusclePath] = field(default_factory=load_paths)
    length_scale: float = 1.0
    params: dict[str, MuscleParameters] = field(default_factory=dict)
    #: the thigh's scale over the shank's (1: the leg scaled by one factor, ``length_scale``)
    thigh_over_shank: float = 1.0
    #: path Taylor coefficients already computed for this leg (model.path_taylor), by trial geometry and anchors
    path_cache: dict[tuple[Any, ...], Any] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        for m in MUSCLES:
            p = self.paths[m]
            self.params.setdefault(m, MuscleParameters(p.tendon_slack_length_m * self.muscle_scale(m),
                                                       p.passive_strain, p.tendon_strain))

    def muscle_scale(self, m: str) -> float:
        """The factor on muscle ``m``'s generic path, optimal fibre and tendon slack lengths."""
        if self.thigh_over_shank == 1.0:
            return self.length_scale
        return self.length_scale * (1.0 + segment_fractions()[m]["thigh"] * (self.thigh_over_shank - 1.0))

    def rescaled(self, factor: float, thigh_factor: float = 1.0) -> LegMuscles:
        """The same subject's parameters on paths ``factor`` times as long (a shank measured that much longer),
        the thigh's relative scale times ``thigh_factor``: path lengths, optimal fibre lengths and moment arms
        scale, the tendon parameters stay."""
        return LegMuscles(paths=self.paths, length_scale=self.length_scale * factor, params=dict(self.params),
                          thigh_over_shank=self.thigh_over_shank * thigh_factor)

    def optimal_fiber_length_m(self, m: str) -> float:
        return self.paths[m].optimal_fiber_length_m * self.muscle_scale(m)

    def path_length_m(self, m: str, **q: Any) -> Any:
        return self.paths[m].length_m(**q) * self.muscle_scale(m)

    def moment_arm_m(self, m: str, joint: str, **q: Any) -> Any:
        return self.paths[m].moment_arm_m(joint, **q) * self.muscle_scale(m)

    def fiber_state(self, m: str, path_length_m: float) -> tuple[float, float, float]:
        """(fibre length m, pennation rad, tendon force N) at one path length (numpy; equilibrium for the calf)."""
        p, par = self.paths[m], self.params[m]
        lo = self.optimal_fiber_length_m(m)
        h = lo * np.sin(p.pennation_at_optimal_rad)
        ls = par.tendon_slack_length_m

        def fibre(l_t: float) -> tuple[float, float]:
            along = max(path_length_m - l_t, 1e-9)
            lm = float(np.sqrt(along**2 + h**2))
            return lm, float(np.arcsin(h / lm))

        if m not in COMPLIANT:
            lm, alpha = fibre(ls)
            force = p.max_isometric_force_n * float(passive_fiber_force(lm / lo, par.passive_strain)) * np.cos(alpha)
            return lm, alpha, force

        def residual(l_t: float) -> float:
            lm, alpha = fibre(l_t)
            return (float(passive_fiber_force(lm / lo, par.passive_strain)) * np.cos(alpha)
                    - float(tendon_force(l_t / ls, par.tendon_strain)))

        hi = min(path_length_m - 1e-6, ls * (1.0 + 10.0 * par.tendon_strain))
        if residual(ls) <= 0:  # the fibre pulls less than a slack tendon can carry: tendon at slack
            l_t = ls
        elif hi <= ls or residual(hi) > 0:  # the tendon as long as the path allows (force beyond the curve's use)
            l_t = max(hi, ls)
        else:
            l_t = brentq(residual, ls, hi, xtol=1e-14, rtol=1e-14)
        lm, alpha = fibre(l_t)
        return lm, alpha, p.max_isometric_force_n * float(tendon_force(l_t / ls, par.tendon_strain))

    def force_n(self, m: str, **q: float) -> float:
        """Passive force along the path (N) at joint angles ``q`` (rad)."""
        return max(self.fiber_state(m, float(self.path_length_m(m, **q)))[2], 0.0)

    def joint_moment_nm(self, joint: str, **q: float) -> float:
        """Passive moment of all muscles about ``joint`` toward positive angle (N·m)."""
        return float(sum(float(self.moment_arm_m(m, joint, **q)) * self.force_n(m, **q) for m in MUSCLES
                         if joint in self.paths[m].joints))


def thigh_over_shank_for_subject(thigh_length_m: float | None, shank_length_m: float) -> float:
    """The thigh's scale over the shank's for a subject (each measured over the generic model's, hip to knee
    and knee to ankle joint centres); 1 when the thigh was not measured."""
    if thigh_length_m is None:
        return 1.0
    generic = model_segment_lengths_m()
    return (thigh_length_m / generic["thigh_length_m"]) / (shank_length_m / generic["shank_length_m"])


def scale_for_subject(shank_length_m: float, generic_shank_length_m: float | None = None) -> float:
    """Length scale of the leg muscles for a subject, as OpenSim's scale tool: the subject's
    measured shank length (knee joint centre, at the fibula head, to ankle joint centre, at the
    lateral malleolus; m) over the same distance in the generic model (Rajagopal 2016: 0.3965 m,
    read from the ``.osim`` by ``tools/fit_muscle_paths.py``). One factor scales every muscle's
    path, optimal fibre length and tendon slack length."""
    reference = generic_shank_length_m if generic_shank_length_m is not None else \
        model_segment_lengths_m()["shank_length_m"]
    return shank_length_m / reference
