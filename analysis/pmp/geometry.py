"""Muscle-tendon lengths and moment arms of the eleven leg muscles as smooth polynomials of hip, knee and ankle angle.

The coefficients come from ``tools/fit_muscle_paths.py`` run on Rajagopal et al. (2016), stored
in ``data/rajagopal2016_paths.json`` with the muscles' generic parameters and the fit's errors
against OpenSim's own path geometry. Angles in radians (hip flexion, knee flexion, ankle
dorsiflexion positive); lengths in m; a moment arm is r = −∂L/∂q (m), positive when the muscle
pulls toward positive angle. Every function accepts numpy arrays or CasADi symbols.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

MUSCLES = ("bflh", "bfsh", "gaslat", "gasmed", "soleus", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem")
JOINTS = ("hip", "knee", "ankle")


@dataclass(frozen=True)
class MusclePath:
    """One muscle: the joints it crosses, its length polynomial and its generic (Rajagopal 2016) parameters."""

    name: str
    joints: tuple[str, ...]
    exponents: tuple[tuple[int, ...], ...]
    coefficients_m: tuple[float, ...]
    max_isometric_force_n: float
    optimal_fiber_length_m: float
    tendon_slack_length_m: float
    pennation_at_optimal_rad: float
    min_length_m: float
    fit: dict[str, float]

    def _args(self, angles: dict[str, Any]) -> list[Any]:
        return [angles[j] for j in self.joints]

    def length_m(self, **angles_rad: Any) -> Any:
        """Muscle-tendon length (m) at ``hip=…, knee=…, ankle=…`` (rad; joints it does not cross are ignored)."""
        q = self._args(angles_rad)
        total = 0.0
        for e, c in zip(self.exponents, self.coefficients_m):
            term = c
            for qi, k in zip(q, e):
                if k:
                    term = term * qi**k
            total = total + term
        return total

    def moment_arm_m(self, joint: str, **angles_rad: Any) -> Any:
        """r = −∂L/∂q of ``joint`` (m); zero for a joint the muscle does not cross."""
        if joint not in self.joints:
            return 0.0 * angles_rad[joint]
        j = self.joints.index(joint)
        q = self._args(angles_rad)
        total = 0.0
        for e, c in zip(self.exponents, self.coefficients_m):
            if e[j] == 0:
                continue
            term = c * e[j]
            for i, (qi, k) in enumerate(zip(q, e)):
                p = k - 1 if i == j else k
                if p:
                    term = term * qi**p
            total = total + term
        return -total


@lru_cache(maxsize=4)
def load_paths(name: str = "rajagopal2016_paths.json") -> dict[str, MusclePath]:
    """The fitted paths shipped with the package."""
    data = json.loads(resources.files(__package__).joinpath("data", name).read_text(encoding="utf-8"))
    out = {}
    for m, d in data["muscles"].items():
        out[m] = MusclePath(m, tuple(d["coordinates"]), tuple(tuple(e) for e in d["exponents"]),
                            tuple(d["coefficients_m"]), d["max_isometric_force_n"], d["optimal_fiber_length_m"],
                            d["tendon_slack_length_m"], d["pennation_at_optimal_rad"], d["min_length_m"], d["fit"])
    return out


def fit_errors() -> dict[str, dict[str, float]]:
    """The committed fit's errors against OpenSim (mm) per muscle."""
    return {m: dict(p.fit) for m, p in load_paths().items()}


__all__ = ["MUSCLES", "JOINTS", "MusclePath", "load_paths", "fit_errors"]
