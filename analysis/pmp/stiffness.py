"""Representative stiffnesses from the estimated strains (dissertation eqs 3.11–3.16), in SI units.

Tendon (eq 3.11): K̄_T(l̃) = d f_T/d l̃_T = c₁ m e^{m(l̃ − c₂)}. Its value is c₁·m = 0.2 m at the slack
length and (1 + c₃)·m = 1.2 m at the strain of one normalised force. The dissertation's eq 3.12
writes m for the first point, so its eq 3.13 averages to 1.1 m (K_T = 1.97 F/(ε_T0 L_s)). The
curve itself averages to 0.7 m. Both are offered: ``convention="dissertation"`` reproduces its
numbers for comparison, ``"curve"`` (the default) is the curve's own average.

Muscle (eqs 3.14–3.16): K̄_P = (k/ε₀) f_pas, 0 at l̃_min and k/ε₀ at 1 + ε₀; the average 2/ε₀ (k = 4)
gives K_P = (2/ε₀)·F_max/L_opt.
"""

from __future__ import annotations

import math
from typing import Any

from .curves import C1, C3, K_PE, tendon_exponent

CALF_TENDONS = ("soleus", "gasmed", "gaslat")


def tendon_stiffness_n_per_m(max_isometric_force_n: float, tendon_slack_length_m: float, strain_at_one: float,
                             convention: str = "curve") -> float:
    """Representative tendon stiffness (N/m) between the slack length and the strain of one normalised force."""
    m = float(tendon_exponent(strain_at_one))
    if convention == "curve":
        mean_norm = 0.5 * (C1 * m + (1.0 + C3) * m)
    elif convention == "dissertation":
        mean_norm = 0.5 * (m + (1.0 + C3) * m)
    else:
        raise ValueError("convention must be 'curve' or 'dissertation'")
    return max_isometric_force_n / tendon_slack_length_m * mean_norm


def muscle_stiffness_n_per_m(max_isometric_force_n: float, optimal_fiber_length_m: float, passive_strain: float) -> float:
    """Representative passive fibre stiffness (N/m), eq 3.16: (k/(2 ε₀)) F_max / L_opt."""
    return K_PE / (2.0 * passive_strain) * max_isometric_force_n / optimal_fiber_length_m


#: the keys of :func:`representative_values`, with the parameter each is made from
FIGURE_QUANTITIES = {"slack_per_shank": "tendon_slack_length_m", "tendon_kN_per_m": "tendon_strain",
                     "muscle_N_per_m": "passive_strain"}


def representative_values(leg: Any, values: dict[str, float], shank_length_m: float) -> dict[str, dict[str, float]]:
    """Figures 3.15–3.17's quantities per muscle from parameter values (``"muscle.what"`` → value):
    slack length per shank length, tendon stiffness (kN/m; eq 3.13) and muscle stiffness (N/m; eq
    3.16). ``leg`` (an :class:`analysis.pmp.muscles.LegMuscles`) gives the maximal forces, optimal
    fibre lengths and, for a tendon whose slack length is not among ``values``, the leg's own."""
    out: dict[str, dict[str, float]] = {k: {} for k in FIGURE_QUANTITIES}
    for name, v in values.items():
        m, what = name.split(".")
        force = leg.paths[m].max_isometric_force_n
        if what == "tendon_slack_length_m":
            out["slack_per_shank"][m] = v / shank_length_m
        elif what == "tendon_strain":
            ls = values.get(f"{m}.tendon_slack_length_m", leg.params[m].tendon_slack_length_m)
            out["tendon_kN_per_m"][m] = tendon_stiffness_n_per_m(force, ls, v) / 1e3
        elif what == "passive_strain":
            out["muscle_N_per_m"][m] = muscle_stiffness_n_per_m(force, leg.optimal_fiber_length_m(m), v)
    return out


def achilles_stiffness_kn_per_m(tendons_n_per_m: dict[str, float]) -> float:
    """The Achilles tendon as the calf tendons in parallel (kN/m)."""
    missing = [t for t in CALF_TENDONS if t not in tendons_n_per_m]
    if missing:
        raise ValueError(f"the Achilles needs {CALF_TENDONS}; missing {missing}")
    return sum(tendons_n_per_m[t] for t in CALF_TENDONS) / 1e3


def dissertation_tendon_constant() -> float:
    """The 1.97 of eq 3.13: 1.1·ln((1 + c₃)/c₁)."""
    return 1.1 * math.log((1.0 + C3) / C1)
