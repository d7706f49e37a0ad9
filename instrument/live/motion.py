"""Markers and force plate of an AADS trial as the analysis's ``MotionTrial``: from a recorded trial
file, or from the live ring buffers while the operator bends the AFO (the same adapter for both)."""

from __future__ import annotations

from typing import Any

import numpy as np

from analysis.motion import MotionTrial
from analysis.timebase import resample, uniform_grid

from ..errors import RecordingError
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


def _synchronised_times(markers: dict[str, np.ndarray], mocap_identity: dict[str, Any], plate: dict[str, np.ndarray],
                        plate_identity: dict[str, Any]) -> tuple[np.ndarray, np.ndarray] | None:
    """(marker times, plate times) in s on the cameras' clock from the devices' own counters, aligned
    by the camera system's sync pulse in the plate's trigger channel; ``None`` without a sync.

    The host stamps each device's blocks on arrival, so two devices' host times disagree by a few
    milliseconds, differently every run; the sync pulse ties a plate sample to a camera frame exactly.
    The host times only say *which* frame (pulses are a second apart, the host is off by milliseconds).
    """
    every = int(mocap_identity.get("sync_pulse_every_frames") or 0)
    mk_rate, fp_rate = float(mocap_identity.get("rate_hz") or 0.0), float(plate_identity.get("rate_hz") or 0.0)
    if every <= 0 or mk_rate <= 0 or fp_rate <= 0 or not {"counter", "trigger"} <= set(plate) \
            or "counter" not in markers or len(markers["counter"]) == 0:
        return None
    n_plate = len(plate["counter"])
    if len(plate["trigger"]) != n_plate or len(plate["time_s"]) != n_plate \
            or len(markers["counter"]) != len(markers["time_s"]):
        return None  # channels of unequal length (a damaged file): the stamps, which the resampler checks
    trig = np.asarray(plate["trigger"]).astype(bool)
    rises = np.flatnonzero(trig[1:] & ~trig[:-1]) + 1
    if rises.size == 0:
        return None
    mk_c, fp_c = np.asarray(markers["counter"], dtype=np.int64), np.asarray(plate["counter"], dtype=np.int64)
    pulse = int(rises[0])
    frame_estimate = float(mk_c[0]) + (float(plate["time_s"][pulse]) - float(markers["time_s"][0])) * mk_rate
    frame = int(round(frame_estimate / every)) * every
    if abs(frame - frame_estimate) > every / 4:
        return None  # the host clocks disagree by more than a quarter of the pulse spacing: no safe match
    t_markers = float(markers["time_s"][0]) + (mk_c - mk_c[0]) / mk_rate
    t_plate = float(markers["time_s"][0]) + (frame - mk_c[0]) / mk_rate + (fp_c - fp_c[pulse]) / fp_rate
    return t_markers, t_plate


def motion_from_channels(markers: dict[str, np.ndarray], mocap_identity: dict[str, Any], plate: dict[str, np.ndarray],
                         plate_identity: dict[str, Any], source: str = "") -> MotionTrial:
    """A MotionTrial from recorded (or live ring-buffer) mocap and force-plate channels, on the marker clock
    (aligned by the sync pulse when the recording has one, else by the host's stamps)."""
    labels = mocap_identity.get("labels") or [f"M{i}" for i in range(markers["position_m"].shape[1])]
    synced = _synchronised_times(markers, mocap_identity, plate, plate_identity)
    t_mk, t_fp = synced if synced is not None else (np.asarray(markers["time_s"]), np.asarray(plate["time_s"]))
    t0 = float(t_mk[0])
    plate_rate = float(plate_identity.get("rate_hz") or 1000.0)
    grid = uniform_grid(t0, min(float(t_fp[-1]), float(t_mk[-1])), plate_rate)
    stacked = np.hstack([plate["force_n"], plate["cop_m"], plate["free_moment_nm"][:, None]])
    on_grid = resample(t_fp, stacked, grid, max_gap_s=2.5 / plate_rate)
    cop = np.column_stack([on_grid[:, 3:5], np.zeros(grid.size)])
    return MotionTrial(t_mk - t0, markers["position_m"], list(labels), grid - t0,
                       on_grid[:, :3], cop, np.nan_to_num(on_grid[:, 5]), source,
                       {"plate_identity": plate_identity, "mocap_identity": mocap_identity})


__all__ = ["MotionDataError", "motion_from_channels", "motion_trial"]
