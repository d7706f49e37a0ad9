"""Muscle-tendon lengths and moment arms of the eleven leg muscles over hip, knee and ankle angle.

``tools/fit_muscle_paths.py`` asks OpenSim (Rajagopal et al. 2016) for each muscle's length
(``getLength``) and moment arms (``computeMomentArm``) on a 1° grid (2.5° over the hip) of the
joints it crosses; ``data/rajagopal2016_paths.json`` holds those tables (interpolated here by cubic
B-splines, :class:`SplineGrid`), a smooth polynomial fit kept as the fallback, the muscles' generic
parameters, the model's segment lengths and the errors against OpenSim between the grid nodes.
Angles in radians (hip flexion, knee flexion, ankle dorsiflexion positive); lengths in m. A
moment arm (m, positive when the muscle pulls toward positive angle) is OpenSim's
``computeMomentArm``, tabulated on its own: where the coupled knee or a wrapping surface kinks the
path it is not −∂L/∂q of the length (the gastrocnemius near full extension: 17 mm apart), and
OpenSim's joint moment is tendon force × that moment arm. Every function accepts numpy arrays or
CasADi symbols.
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
    moment_arm_coefficients_m: dict[str, tuple[float, ...]] | None = None
    passive_strain: float = 0.6
    tendon_strain: float = 0.049
    #: OpenSim's lengths and moment arms on a fine grid of the joints' angles, interpolated by cubic
    #: B-splines (see :class:`SplineGrid`); when present they replace the polynomials
    spline: SplineGrid | None = None

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
        if self.spline is not None:
            return self.spline.evaluate("length", self._args(angles_rad))
        return self._polynomial(self.coefficients_m, self._args(angles_rad))

    def moment_arm_m(self, joint: str, **angles_rad: Any) -> Any:
        """OpenSim's moment arm about ``joint`` (m); zero for a joint the muscle does not cross."""
        if joint not in self.joints:
            return 0.0 * angles_rad[joint]
        if self.spline is not None:
            return self.spline.evaluate(joint, self._args(angles_rad))
        if self.moment_arm_coefficients_m is not None:
            return self._polynomial(self.moment_arm_coefficients_m[joint], self._args(angles_rad))
        return self.length_derivative_moment_arm_m(joint, **angles_rad)

    def length_derivative_moment_arm_m(self, joint: str, **angles_rad: Any) -> Any:
        """r = −∂L/∂q of the length (m): the conservative moment arm."""
        if joint not in self.joints:
            return 0.0 * angles_rad[joint]
        if self.spline is not None:
            return -self.spline.evaluate("length", self._args(angles_rad), slope_of=joint)
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


class SplineGrid:
    """Values sampled by OpenSim on a regular grid of the muscle's joint angles, as CasADi cubic
    B-spline interpolants (``casadi.interpolant(…, "bspline", …)``): the path length and a moment
    arm per joint. A grid of 1° (2.5° for the hip) follows the patella-coupled knee and the
    gastrocnemius wrap, which a global polynomial smooths over.

    Evaluates CasADi symbols (SX or MX: the estimator's collocation) and NumPy arrays or floats
    alike, through the same interpolant.
    """

    def __init__(self, joints: tuple[str, ...], axes_deg: dict[str, tuple[float, float, int]],
                 values: dict[str, list[float]]) -> None:
        self.joints = joints
        self.axes_rad = [np.deg2rad(np.linspace(*axes_deg[j])) for j in joints]
        self.values = {k: np.asarray(v, dtype=float) for k, v in values.items()}
        self._functions: dict[str, Any] = {}
        self._maps: dict[tuple[str, int], Any] = {}

    def __getstate__(self) -> dict[str, Any]:
        """The grid without its CasADi functions (rebuilt on first use): a pickled leg for a worker process
        is then kilobytes, not the 124 MB its compiled interpolants and maps take."""
        return {**self.__dict__, "_functions": {}, "_maps": {}}

    def _function(self, what: str) -> Any:
        """The interpolant, continued linearly outside the grid (a B-spline is zero past its last knot)."""
        if what not in self._functions:
            import casadi as ca

            # values are stored with the first joint varying fastest (CasADi's column-major grid order)
            spline = ca.interpolant(f"path_{what}", "bspline", [a.tolist() for a in self.axes_rad],
                                    self.values[what].tolist())
            y = ca.SX.sym("y", len(self.joints))
            slope = ca.Function("slope", [y], [ca.jacobian(spline(y), y)])
            x = ca.SX.sym("q", len(self.joints))
            inside = ca.fmin(ca.fmax(x, ca.DM([a[0] for a in self.axes_rad])), ca.DM([a[-1] for a in self.axes_rad]))
            self._functions[what] = ca.Function(f"path_{what}", [x], [spline(inside) + slope(inside) @ (x - inside)])
        return self._functions[what]

    def _slope(self, what: str, joint: str) -> Any:
        key = f"d{what}/d{joint}"
        if key not in self._functions:
            import casadi as ca

            x = ca.SX.sym("q", len(self.joints))
            value = self._function(what)(x)
            self._functions[key] = ca.Function(f"path_{what}_slope_{joint}", [x],
                                               [ca.jacobian(value, x[self.joints.index(joint)])])
        return self._functions[key]

    def evaluate(self, what: str, q: list[Any], slope_of: str | None = None) -> Any:
        """``what`` ("length" or a joint's moment arm) at angles ``q`` (rad, in ``joints`` order), or
        its derivative with respect to the joint ``slope_of`` (per rad)."""
        import casadi as ca

        f = self._function(what) if slope_of is None else self._slope(what, slope_of)
        if slope_of is not None:
            what = f"d{what}/d{slope_of}"
        if any(isinstance(x, (ca.SX, ca.MX)) for x in q):
            return f(ca.vertcat(*q))
        arrays = np.broadcast_arrays(*[np.asarray(x, dtype=float) for x in q])
        shape = arrays[0].shape
        n = int(np.prod(shape)) if shape else 1
        key = (what, n)
        if key not in self._maps:
            self._maps[key] = f.map(n)
        out = np.asarray(self._maps[key](np.vstack([a.reshape(1, -1) for a in arrays]))).reshape(shape)
        return float(out) if not shape else out


@lru_cache(maxsize=4)
def load_paths(name: str = "rajagopal2016_paths.json") -> dict[str, MusclePath]:
    """The fitted paths shipped with the package."""
    data = _data(name)
    out = {}
    for m, d in data["muscles"].items():
        arms = d.get("moment_arm_coefficients_m")
        grid = d.get("spline")
        joints = tuple(d["coordinates"])
        spline = SplineGrid(joints, {j: tuple(v) for j, v in grid["axes_deg"].items()},  # type: ignore[misc]  # the JSON grid's axes are tuples of floats at run time
                            {"length": grid["length_m"], **grid["moment_arm_m"]}) if grid else None
        out[m] = MusclePath(m, joints, tuple(tuple(e) for e in d["exponents"]),
                            tuple(d["coefficients_m"]), d["max_isometric_force_n"], d["optimal_fiber_length_m"],
                            d["tendon_slack_length_m"], d["pennation_at_optimal_rad"], d["min_length_m"], d["fit"],
                            {k: tuple(v) for k, v in arms.items()} if arms else None,
                            float(d.get("passive_strain", 0.6)), float(d.get("tendon_strain", 0.049)), spline)
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


@lru_cache(maxsize=4)
def segment_fractions(name: str = "rajagopal2016_segment_fractions.json") -> dict[str, dict[str, float]]:
    """Per muscle, how its path length follows each segment's scale ((ΔL/L)/δ for the segment's bodies scaled
    by 1 + δ, the mean over seated poses; ``tools/fit_segment_fractions.py``): ``{"thigh": …, "shank": …,
    "foot": …}``, summing to about 1."""
    data = _data(name)
    return {m: {seg: float(v["mean"]) for seg, v in row.items()} for m, row in data["muscles"].items()}


def fit_errors() -> dict[str, dict[str, float]]:
    """The committed fit's errors against OpenSim (mm) per muscle."""
    return {m: dict(p.fit) for m, p in load_paths().items()}


__all__ = ["MUSCLES", "JOINTS", "MusclePath", "load_paths", "fit_errors", "model_segment_lengths_m", "path_ranges_deg",
           "segment_fractions"]
