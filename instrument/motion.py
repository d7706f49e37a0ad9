"""Markers and force plate of an AADS trial as the analysis's ``MotionTrial``: from a recorded trial
file, or from the live ring buffers while the operator bends the AFO (the same adapter for both)."""

from __future__ import annotations

from typing import Any

import numpy as np

from analysis.motion import MotionTrial
from analysis.timebase import resample, uniform_grid

from .errors import RecordingError
from .recording import TrialFile


class MotionDataError(RecordingError):
    """A trial without the markers and plate samples an AADS analysis needs."""


def motion_trial(trial: TrialFile) -> MotionTrial:
    """Markers and force plate of an AADS trial, times relative to the first marker frame."""
    if "mocap" not in trial.devices or "force_plate" not in trial.devices:
        raise MotionDataError(f"{trial.path}: needs motion capture and force plate data (has {sorted(trial.devices)})")
    mk, fp = trial.devices["mocap"], trial.devices["force_plate"]
    if mk.samples == 0 or fp.samples == 0:
        raise MotionDataError(f"{trial.path}: no samples (markers {mk.samples}, plate {fp.samples})")
    return motion_from_channels(mk.channels, mk.identity, fp.channels, fp.identity, str(trial.path))


def motion_from_channels(markers: dict[str, np.ndarray], mocap_identity: dict[str, Any], plate: dict[str, np.ndarray],
                         plate_identity: dict[str, Any], source: str = "") -> MotionTrial:
    """A MotionTrial from recorded (or live ring-buffer) mocap and force-plate channels, on the marker clock."""
    labels = mocap_identity.get("labels") or [f"M{i}" for i in range(markers["position_m"].shape[1])]
    t0 = float(markers["time_s"][0])
    plate_rate = float(plate_identity.get("rate_hz") or 1000.0)
    t_fp = plate["time_s"]
    grid = uniform_grid(t0, min(float(t_fp[-1]), float(markers["time_s"][-1])), plate_rate)
    stacked = np.hstack([plate["force_n"], plate["cop_m"], plate["free_moment_nm"][:, None]])
    on_grid = resample(t_fp, stacked, grid, max_gap_s=2.5 / plate_rate)
    cop = np.column_stack([on_grid[:, 3:5], np.zeros(grid.size)])
    return MotionTrial(markers["time_s"] - t0, markers["position_m"], list(labels), grid - t0,
                       on_grid[:, :3], cop, np.nan_to_num(on_grid[:, 5]), source,
                       {"plate_identity": plate_identity, "mocap_identity": mocap_identity})


__all__ = ["MotionDataError", "motion_from_channels", "motion_trial"]
