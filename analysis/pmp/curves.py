"""DeGroote–Fregly 2016 passive fibre and tendon force curves, as OpenSim's ``DeGrooteFregly2016Muscle``.

Dimensionless: lengths normalised by the optimal fibre length (fibre) or the tendon slack length
(tendon), forces by the maximum isometric force. Every function takes numpy arrays or CasADi
symbols (``SX``/``MX``) alike, so the collocation problem differentiates the same expressions
the tests compare with OpenSim.

- passive fibre (eqs 3.3–3.4): f = (e^{k(l̃−1)/ε₀} − b)/(e^{k} − b), b = e^{k(l̃min−1)/ε₀},
  k = 4, l̃min = 0.2 (OpenSim's offset: zero force at the minimum fibre length);
- active fibre force–length (DeGroote et al. 2016, their supplement's eq S2): a sum of three
  Gaussian-like terms b₁ᵢ·exp(−½ (l̃ − b₂ᵢ)² / (b₃ᵢ + b₄ᵢ l̃)²), 1 at l̃ ≈ 1 (OpenSim's curve; used
  for the low tonic activation of a subject who is never quite relaxed);
- tendon (eqs 3.5–3.6): f = c₁ e^{m(l̃−c₂)} − c₃, m = ln((1 + c₃)/c₁)/(1 + ε_T0 − c₂),
  c₁ = 0.2, c₂ = 1, c₃ = 0.2 (OpenSim's c₂ is 1, so f(1) = 0 and f(1 + ε_T0) = 1).
"""

from __future__ import annotations

from typing import Any

import numpy as np

K_PE = 4.0
MIN_NORM_FIBER_LENGTH = 0.2
C1, C2, C3 = 0.2, 1.0, 0.2
#: (b₁, b₂, b₃, b₄) of the three terms of the active force–length curve (DeGroote et al. 2016, eq S2), the
#: first b₁ as OpenSim's DeGrooteFregly2016Muscle has it (0.81507 for the paper's 0.81448: the peak is 1, not 0.99943)
ACTIVE_FORCE_LENGTH = ((0.8150671134243542, 1.055033428970575, 0.162384573599574, 0.063303448465465),
                       (0.433004984392647, 0.716775413397760, -0.029947116970696, 0.200356847296188),
                       (0.1, 1.0, 0.5 * 0.5**0.5, 0.0))


def _exp(x: Any) -> Any:
    if isinstance(x, (np.ndarray, float, int, np.floating)):
        return np.exp(x)
    import casadi as ca

    return ca.exp(x)


def _log(x: Any) -> Any:
    if isinstance(x, (np.ndarray, float, int, np.floating)):
        return np.log(x)
    import casadi as ca

    return ca.log(x)


def passive_fiber_force(norm_fiber_length: Any, strain_at_one: Any = 0.6) -> Any:
    """Normalised passive fibre force (eq 3.3 with OpenSim's offset b of eq 3.4)."""
    b = _exp(K_PE * (MIN_NORM_FIBER_LENGTH - 1.0) / strain_at_one)
    return (_exp(K_PE * (norm_fiber_length - 1.0) / strain_at_one) - b) / (_exp(K_PE) - b)


def active_fiber_force(norm_fiber_length: Any) -> Any:
    """Normalised active fibre force at full activation and zero fibre velocity (eq S2): the isometric
    force–length curve (a sweep at 5°/s moves fibres at well under 1 % of their maximum speed)."""
    total: Any = 0.0
    for b1, b2, b3, b4 in ACTIVE_FORCE_LENGTH:
        total = total + b1 * _exp(-0.5 * (norm_fiber_length - b2) ** 2 / (b3 + b4 * norm_fiber_length) ** 2)
    return total


def tendon_exponent(strain_at_one: Any = 0.049) -> Any:
    """m of eq 3.6 for tendon strain ``strain_at_one`` at one normalised force."""
    return _log((1.0 + C3) / C1) / (1.0 + strain_at_one - C2)


def tendon_force(norm_tendon_length: Any, strain_at_one: Any = 0.049) -> Any:
    """Normalised tendon force (eq 3.5)."""
    return C1 * _exp(tendon_exponent(strain_at_one) * (norm_tendon_length - C2)) - C3


def tendon_length_from_force(norm_force: Any, strain_at_one: Any = 0.049) -> Any:
    """Inverse of eq 3.5: normalised tendon length carrying ``norm_force``."""
    return C2 + _log((norm_force + C3) / C1) / tendon_exponent(strain_at_one)


def tendon_stiffness(norm_tendon_length: Any, strain_at_one: Any = 0.049) -> Any:
    """d f_T / d l̃_T (dimensionless): the basis of eqs 3.11–3.13."""
    m = tendon_exponent(strain_at_one)
    return C1 * m * _exp(m * (norm_tendon_length - C2))


def passive_fiber_stiffness(norm_fiber_length: Any, strain_at_one: Any = 0.6) -> Any:
    """d f_pas / d l̃_M (dimensionless): the basis of eqs 3.14–3.16."""
    b = _exp(K_PE * (MIN_NORM_FIBER_LENGTH - 1.0) / strain_at_one)
    return K_PE / strain_at_one * _exp(K_PE * (norm_fiber_length - 1.0) / strain_at_one) / (_exp(K_PE) - b)
