"""Plate and cameras aligned by the sync pulse in the plate's trigger channel, not the host's stamps."""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from instrument.live.motion import motion_from_channels

MOCAP_HZ, PLATE_HZ = 100, 1000


def _force_z(t_true_s: np.ndarray) -> np.ndarray:
    """A plate load that changes fast enough for a millisecond to show (N)."""
    return 200.0 + 80.0 * np.sin(2 * np.pi * 3.0 * t_true_s)


def _channels(first_frame: int, first_sample: int, plate_lag_s: np.ndarray | float, origin_s: float = 500.0,
              sync: bool = True) -> tuple[dict[str, np.ndarray], dict[str, Any], dict[str, np.ndarray], dict[str, Any]]:
    """Three seconds of markers and plate sharing one time origin; the plate's host stamps arrive late
    by ``plate_lag_s`` (s) — as a host stamping blocks on arrival does."""
    frames = np.arange(first_frame, first_frame + 3 * MOCAP_HZ)
    samples = np.arange(first_sample, first_sample + 3 * PLATE_HZ)
    markers = {"counter": frames, "time_s": origin_s + frames / MOCAP_HZ,
               "position_m": np.zeros((frames.size, 1, 3))}
    t_plate = samples / PLATE_HZ
    force = np.column_stack([np.zeros_like(t_plate), np.zeros_like(t_plate), _force_z(t_plate)])
    plate = {"counter": samples, "time_s": origin_s + t_plate + plate_lag_s, "force_n": force,
             "cop_m": np.zeros((samples.size, 2)), "free_moment_nm": np.zeros(samples.size),
             "trigger": (samples % PLATE_HZ == 0).astype(np.uint8)}
    mocap_id: dict[str, Any] = {"rate_hz": MOCAP_HZ, "labels": ["M"]}
    if sync:
        mocap_id["sync_pulse_every_frames"] = MOCAP_HZ
    return markers, mocap_id, plate, {"rate_hz": PLATE_HZ}


def _plate_error_n(trial: Any, first_frame: int) -> float:
    """Largest error (N) of the plate load on the marker clock against the load at that true time."""
    t_true = trial.plate_time_s + first_frame / MOCAP_HZ
    inside = np.isfinite(trial.force_n[:, 2])
    return float(np.max(np.abs(trial.force_n[inside, 2] - _force_z(t_true[inside]))))


@settings(max_examples=25, deadline=None)
@given(lag_ms=st.floats(0.5, 40.0), jitter_ms=st.floats(0.0, 5.0), seed=st.integers(0, 1000),
       first_frame=st.integers(1, 150))
def test_sync_pulse_aligns_to_the_sample_whatever_the_host_stamps(lag_ms: float, jitter_ms: float, seed: int,
                                                                  first_frame: int) -> None:
    rng = np.random.default_rng(seed)
    first_sample = first_frame * (PLATE_HZ // MOCAP_HZ) - int(rng.integers(0, 400))
    lag = lag_ms * 1e-3 + jitter_ms * 1e-3 * rng.random(3 * PLATE_HZ)
    trial = motion_from_channels(*_channels(first_frame, first_sample, lag))
    assert _plate_error_n(trial, first_frame) < 1e-6
    # the same device data stamped by another run's host give the same trial
    again = motion_from_channels(*_channels(first_frame, first_sample, lag_ms * 2e-3))
    np.testing.assert_array_equal(trial.plate_time_s, again.plate_time_s)
    np.testing.assert_array_equal(trial.force_n, again.force_n)


def test_without_a_sync_the_host_stamps_are_used_and_their_lag_shows() -> None:
    trial = motion_from_channels(*_channels(20, 150, 0.010, sync=False))
    assert _plate_error_n(trial, 20) > 1.0  # 10 ms late on a 3 Hz, 80 N swing: several newtons


def test_host_clocks_too_far_apart_to_pick_the_pulse_fall_back_to_the_stamps() -> None:
    # 0.4 s apart: the pulse could be this frame's or the next second's; no guess
    trial = motion_from_channels(*_channels(20, 150, 0.4))
    assert _plate_error_n(trial, 20) > 1.0


def test_a_trigger_channel_of_the_wrong_length_falls_back_to_the_stamps() -> None:
    markers, mocap_id, plate, plate_id = _channels(20, 150, 0.002)
    plate["trigger"] = plate["trigger"][:-7]  # a damaged file: the channels disagree
    trial = motion_from_channels(markers, mocap_id, plate, plate_id)
    assert trial.plate_time_s.size > 0 and _plate_error_n(trial, 20) > 0.1  # host stamps, 2 ms late
