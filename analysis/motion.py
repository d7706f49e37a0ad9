"""Motion-capture trials as the analysis sees them: markers and one force plate on their own clocks (SI)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import InputError


@dataclass
class MotionTrial:
    """Markers and force-plate data of one trial, in the lab frame.

    :ivar marker_time_s: time of each marker frame (s), shape (n,).
    :ivar markers_m: marker positions (n, markers, 3) in m; NaN where occluded.
    :ivar marker_labels: label of each marker column.
    :ivar plate_time_s: time of each force-plate sample (s), shape (k,).
    :ivar force_n: ground reaction force on the specimen (k, 3) in N.
    :ivar cop_m: centre of pressure (k, 3) in m (NaN where the vertical load is too small).
    :ivar free_moment_nm: vertical free moment about the CoP (k,) in N·m.
    """

    marker_time_s: np.ndarray
    markers_m: np.ndarray
    marker_labels: list[str]
    plate_time_s: np.ndarray
    force_n: np.ndarray
    cop_m: np.ndarray
    free_moment_nm: np.ndarray
    source: str = ""
    metadata: dict = field(default_factory=dict)

    def marker(self, label: str) -> np.ndarray:
        """Trajectory (n, 3) of one marker, in m."""
        try:
            return self.markers_m[:, self.marker_labels.index(label)]
        except ValueError:
            raise InputError(f"{self.source or 'trial'}: no marker {label!r}; has {self.marker_labels}") from None

    def moment_about_nm(self, point_m: np.ndarray) -> np.ndarray:
        """Moment of the plate load about a fixed lab point (k, 3) in N·m: (CoP − p) × F + free moment ẑ."""
        r = np.nan_to_num(self.cop_m) - np.asarray(point_m)[None, :]
        m = np.cross(r, self.force_n)
        m[:, 2] += self.free_moment_nm
        return m


def cop_from_moment(force_n: np.ndarray, moment_nm: np.ndarray, origin_m: np.ndarray,
                    surface_z_m: float = 0.0, min_fz_n: float = 5.0) -> tuple[np.ndarray, np.ndarray]:
    """CoP on the plate surface and free moment from force and moment about ``origin_m`` (lab frame, SI)."""
    f, m, o = np.asarray(force_n), np.asarray(moment_nm), np.asarray(origin_m)
    fz = f[:, 2]
    dz = surface_z_m - o[2]
    with np.errstate(divide="ignore", invalid="ignore"):
        x = o[0] + (-m[:, 1] + dz * f[:, 0]) / fz
        y = o[1] + (m[:, 0] + dz * f[:, 1]) / fz
    cop = np.column_stack([x, y, np.full_like(x, surface_z_m)])
    cop[np.abs(fz) < min_fz_n] = np.nan
    r = cop - o[None, :]
    free = m[:, 2] - (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])
    return cop, np.where(np.isnan(cop[:, 0]), 0.0, free)
