"""Muscle-tendon lengths and moment arms of the eleven leg muscles as smooth polynomials of hip, knee and ankle angle.

The coefficients come from ``tools/fit_muscle_paths.py`` run on Rajagopal et al. (2016), stored
in ``data/rajagopal2016_paths.json`` with the muscles' generic parameters, the model's segment
lengths and the fit's errors against OpenSim's own path geometry. Angles in radians (hip
flexion, knee flexion, ankle dorsiflexion positive); lengths in m. A moment arm (m, positive
when the muscle pulls toward positive angle) is OpenSim's ``computeMomentArm``, fitted by its
own polynomial: where the coupled knee or a wrapping surface kinks the path it is not −∂L/∂q of
the length (the gastrocnemius near full extension: 17 mm apart), and OpenSim's joint moment is
tendon force × that moment arm. Paths fitted before moment arms had their own polynomials fall
back to r = −∂L/∂q. Every function accepts numpy arrays or CasADi symbols.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

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
    moment_arm_coefficients_m: dict[str, tuple[float, ...]] | None = None
    passive_strain: float = 0.6
    tendon_strain: float = 0.049

    def _args(self, angles: dict[str, Any]) -> list[Any]:
        return [angles[j] for j in self.joints]

    def _polynomial(self, coefficients: tuple[float, ...], q: list[Any]) -> Any:
        total = 0.0
        for e, c in zip(self.exponents, coefficients):
            term = c
            for qi, k in zip(q, e):
                if k:
                    term = term * qi**k
            total = total + term
        return total

    def length_m(self, **angles_rad: Any) -> Any:
        """Muscle-tendon length (m) at ``hip=…, knee=…, ankle=…`` (rad; joints it does not cross are ignored)."""
        return self._polynomial(self.coefficients_m, self._args(angles_rad))

    def moment_arm_m(self, joint: str, **angles_rad: Any) -> Any:
        """OpenSim's moment arm about ``joint`` (m); zero for a joint the muscle does not cross."""
        if joint not in self.joints:
            return 0.0 * angles_rad[joint]
        if self.moment_arm_coefficients_m is not None:
            return self._polynomial(self.moment_arm_coefficients_m[joint], self._args(angles_rad))
        return self.length_derivative_moment_arm_m(joint, **angles_rad)

    def length_derivative_moment_arm_m(self, joint: str, **angles_rad: Any) -> Any:
        """r = −∂L/∂q of the length polynomial (m): the conservative moment arm."""
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
    data = _data(name)
    out = {}
    for m, d in data["muscles"].items():
        arms = d.get("moment_arm_coefficients_m")
        out[m] = MusclePath(m, tuple(d["coordinates"]), tuple(tuple(e) for e in d["exponents"]),
                            tuple(d["coefficients_m"]), d["max_isometric_force_n"], d["optimal_fiber_length_m"],
                            d["tendon_slack_length_m"], d["pennation_at_optimal_rad"], d["min_length_m"], d["fit"],
                            {k: tuple(v) for k, v in arms.items()} if arms else None,
                            float(d.get("passive_strain", 0.6)), float(d.get("tendon_strain", 0.049)))
    return out


@lru_cache(maxsize=4)
def _data(name: str) -> dict[str, Any]:
    return json.loads(resources.files(__package__).joinpath("data", name).read_text(encoding="utf-8"))


def path_ranges_deg(name: str = "rajagopal2016_paths.json") -> dict[str, tuple[float, float]]:
    """The joint ranges (deg) the paths were fitted over: outside them the polynomials extrapolate."""
    return {k: (float(v[0]), float(v[1])) for k, v in _data(name)["ranges_deg"].items()}


def model_segment_lengths_m(name: str = "rajagopal2016_paths.json") -> dict[str, float]:
    """The generic model's own segment lengths between joint centres (m): thigh (hip–knee) and
    shank (knee–ankle), read from the ``.osim`` by the fitting tool. They are the reference of
    subject scaling (as OpenSim's scale tool divides measured by model distances)."""
    segments = _data(name).get("segments")
    if not segments:
        raise KeyError(f"{name} has no segment lengths: regenerate it with tools/fit_muscle_paths.py")
    return {k: float(v) for k, v in segments.items()}


def fit_errors() -> dict[str, dict[str, float]]:
    """The committed fit's errors against OpenSim (mm) per muscle."""
    return {m: dict(p.fit) for m, p in load_paths().items()}


__all__ = ["MUSCLES", "JOINTS", "MusclePath", "load_paths", "fit_errors", "model_segment_lengths_m", "path_ranges_deg"]
