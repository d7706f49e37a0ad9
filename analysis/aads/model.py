"""The AADS jig/AFO description: segments, hinge, marker set, spring; read from TOML or JSON (SI units).

The file format is documented by the default model, ``default_jig.toml`` next to this module
(the dissertation's jig). Every key of the default may be overridden; missing keys keep the
default's value, so a lab's file only needs what differs on its jig.
"""

from __future__ import annotations

import functools
import json
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataFileError

BRANCHES = ("loading", "unloading", "both")


@dataclass(frozen=True)
class Segment:
    """A rigid segment: mass (kg), centre of mass (m), inertia about the COM (kg·m², 3×3), markers (m)."""

    name: str
    mass_kg: float
    com_m: np.ndarray
    inertia_kgm2: np.ndarray
    markers_m: dict[str, np.ndarray]

    @property
    def marker_labels(self) -> list[str]:
        return list(self.markers_m)

    def marker_array_m(self) -> np.ndarray:
        """Marker coordinates (markers, 3) in m, in ``marker_labels`` order."""
        return np.array([self.markers_m[k] for k in self.markers_m], dtype=float)


@dataclass(frozen=True)
class JigModel:
    """Everything the AADS analysis needs to know about the jig and the AFO (SI; angles in degrees at the edge)."""

    name: str
    foot: Segment
    shank: Segment
    hinge_in_foot_m: np.ndarray
    hinge_in_shank_m: np.ndarray
    hinge_axis_in_foot: np.ndarray
    stop_deg: float
    pylon_top_in_shank_m: np.ndarray
    spring_top_marker: str
    spring_top_in_shank_m: np.ndarray
    spring_bottom_marker: str
    spring_bottom_in_foot_m: np.ndarray
    spring_rest_length_m: float
    springs_n_per_m: dict[int, float]
    residual_force_n: float
    residual_moment_nm: float
    ankle_torque_nm: float
    filter_cutoff_hz: float
    fit_window_deg: tuple[float, float]
    branch_min_speed_deg_s: float
    reported_branch: str
    max_marker_error_m: float
    rms_marker_error_m: float
    max_gap_s: float
    source: str = "default"

    def spring_n_per_m(self, spring: int | str) -> float:
        """Stiffness (N/m) of spring number ``spring`` of this model."""
        try:
            return self.springs_n_per_m[int(spring)]
        except (KeyError, ValueError):
            raise DataFileError(self.source, f"no spring {spring!r}; springs are {sorted(self.springs_n_per_m)}") from None

    def optimal_forces(self) -> np.ndarray:
        """Optimal force of the 7 actuators (F_op x,y,z in N; M_op x,y,z in N·m; ankle in N·m)."""
        f, m = self.residual_force_n, self.residual_moment_nm
        return np.array([f, f, f, m, m, m, self.ankle_torque_nm])


def _default_dict() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("default_jig.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in over.items():
        # marker tables replace the default's set (a lab's marker set is not a patch of ours)
        if isinstance(v, dict) and isinstance(out.get(k), dict) and k not in ("markers", "stiffness_n_per_m"):
            out[k] = _merge(out[k], v)
        else:
            out[k] = v
    return out


def _vec(d: dict[str, Any], key: str, where: str, source: str, n: int = 3) -> np.ndarray:
    try:
        v = np.asarray(d[key], dtype=float)
    except KeyError:
        raise DataFileError(source, f"missing {where}.{key}") from None
    except (TypeError, ValueError):
        raise DataFileError(source, f"{where}.{key} must be {n} numbers, got {d[key]!r}") from None
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise DataFileError(source, f"{where}.{key} must be {n} finite numbers, got {d[key]!r}")
    return v


def _inertia(values: np.ndarray) -> np.ndarray:
    ixx, iyy, izz, ixy, ixz, iyz = values
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _segment(name: str, d: dict[str, Any], source: str) -> Segment:
    where = f"segments.{name}"
    markers = d.get("markers") or {}
    if len(markers) < 3:
        raise DataFileError(source, f"{where}.markers needs at least 3 markers to fit a pose, has {len(markers)}")
    mass = float(d.get("mass_kg", float("nan")))
    if not mass > 0:
        raise DataFileError(source, f"{where}.mass_kg must be positive")
    inertia = _inertia(_vec(d, "inertia_kgm2", where, source, 6))
    if np.any(np.linalg.eigvalsh(inertia) < 0):
        raise DataFileError(source, f"{where}.inertia_kgm2 is not positive semi-definite")
    return Segment(name, mass, _vec(d, "com_m", where, source), inertia,
                   {str(k): _vec(markers, k, f"{where}.markers", source) for k in markers})


def jig_model_from_dict(data: dict[str, Any], source: str = "<dict>") -> JigModel:
    """Build a model from a parsed TOML/JSON document, over the default jig's values."""
    d = _merge(_default_dict(), data)
    try:
        seg, hinge, spring = d["segments"], d["hinge"], d["spring"]
        so, filt, stiff, qual = d["static_optimisation"], d["filter"], d["stiffness"], d["quality"]
        axis = _vec(hinge, "axis_in_foot", "hinge", source)
        if np.linalg.norm(axis) < 1e-9:
            raise DataFileError(source, "hinge.axis_in_foot is a zero vector")
        window = tuple(float(x) for x in stiff["fit_window_deg"])
        if len(window) != 2 or not window[0] < window[1]:
            raise DataFileError(source, f"stiffness.fit_window_deg must be [low, high], got {stiff['fit_window_deg']}")
        branch = str(stiff.get("reported_branch", "loading"))
        if branch not in BRANCHES:
            raise DataFileError(source, f"stiffness.reported_branch must be one of {BRANCHES}, got {branch!r}")
        springs = {int(k): float(v) for k, v in spring.get("stiffness_n_per_m", {}).items()}
        model = JigModel(
            name=str(d.get("name", "")), foot=_segment("foot", seg["foot"], source),
            shank=_segment("shank", seg["shank"], source),
            hinge_in_foot_m=_vec(hinge, "point_in_foot_m", "hinge", source),
            hinge_in_shank_m=_vec(hinge, "point_in_shank_m", "hinge", source),
            hinge_axis_in_foot=axis / np.linalg.norm(axis), stop_deg=float(hinge["stop_deg"]),
            pylon_top_in_shank_m=_vec(seg["shank"], "pylon_top_m", "segments.shank", source),
            spring_top_marker=str(spring["top_marker"]),
            spring_top_in_shank_m=_vec(spring, "top_in_shank_m", "spring", source),
            spring_bottom_marker=str(spring["bottom_marker"]),
            spring_bottom_in_foot_m=_vec(spring, "bottom_in_foot_m", "spring", source),
            spring_rest_length_m=float(spring["rest_length_m"]), springs_n_per_m=springs,
            residual_force_n=float(so["residual_force_n"]), residual_moment_nm=float(so["residual_moment_nm"]),
            ankle_torque_nm=float(so["ankle_torque_nm"]), filter_cutoff_hz=float(filt["cutoff_hz"]),
            fit_window_deg=(window[0], window[1]),
            branch_min_speed_deg_s=float(stiff["branch_min_speed_deg_s"]), reported_branch=branch,
            max_marker_error_m=float(qual["max_marker_error_m"]), rms_marker_error_m=float(qual["rms_marker_error_m"]),
            max_gap_s=float(qual["max_gap_s"]), source=source)
    except KeyError as err:
        raise DataFileError(source, f"missing key {err}") from None
    except (TypeError, ValueError) as err:
        raise DataFileError(source, f"bad value: {err}") from None
    if not (model.filter_cutoff_hz > 0 and model.spring_rest_length_m > 0):
        raise DataFileError(source, "filter.cutoff_hz and spring.rest_length_m must be positive")
    return model


@functools.cache
def default_jig_model() -> JigModel:
    """The dissertation's jig, read once: its fit window and hinge stop are what every AADS trial uses,
    and the live AADS loop re-analyses with it every 0.25 s."""
    return load_jig_model()


def load_jig_model(path: str | Path | None = None) -> JigModel:
    """Read a jig model from a ``.toml`` or ``.json`` file; ``None`` gives the dissertation's jig.

    :raises DataFileError: the file is missing, unparsable or inconsistent.
    """
    if path is None:
        return jig_model_from_dict({}, "default_jig.toml")
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise DataFileError(path, f"cannot read the jig model: {err.strerror or err}") from err
    try:
        data = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as err:
        raise DataFileError(path, f"not valid {'JSON' if path.suffix.lower() == '.json' else 'TOML'}: {err}") from err
    if not isinstance(data, dict):
        raise DataFileError(path, "the jig model must be a table/object at the top level")
    return jig_model_from_dict(data, str(path))
