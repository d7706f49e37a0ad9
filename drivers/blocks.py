"""Typed sample blocks: what every driver hands out.

A block is a run of consecutive samples from one device: numpy arrays of equal length, the
device's own sample counter (unwrapped to int64, so gaps show as jumps) and timestamps on the
host's single monotonic clock (:func:`drivers.clock.monotonic_s`). SI units throughout.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np


@dataclass(frozen=True)
class SampleBlock:
    """Samples common to every device.

    :ivar device: device name (as configured; e.g. ``"force_plate"``).
    :ivar counter: device sample counter, unwrapped, int64, shape (n,).
    :ivar time_s: host monotonic time of each sample in seconds, float64, shape (n,).
    """

    device: str
    counter: np.ndarray
    time_s: np.ndarray

    def __len__(self) -> int:
        return int(self.counter.shape[0])

    def channels(self) -> dict[str, np.ndarray]:
        """Every array of the block by field name (units are in the names)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "device"}

    #: per-sample shape and dtype of each channel (recorders create their datasets from this)
    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {"counter": ((), "i8"), "time_s": ((), "f8")}


@dataclass(frozen=True)
class TorqueBlock(SampleBlock):
    """Rotary torque transducer samples.

    :ivar torque_nm: shaft torque in N·m, tare applied.
    :ivar speed_rad_s: shaft angular speed in rad/s (NaN when not polled).
    """

    torque_nm: np.ndarray
    speed_rad_s: np.ndarray

    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {
        **SampleBlock.LAYOUT, "torque_nm": ((), "f8"), "speed_rad_s": ((), "f8")}


@dataclass(frozen=True)
class DynamometerBlock(SampleBlock):
    """Isokinetic dynamometer telemetry.

    :ivar torque_nm: torque at the dynamometer shaft in N·m (arm weight not removed).
    :ivar position_rad: arm angle in rad (device zero).
    :ivar velocity_rad_s: arm angular velocity in rad/s.
    :ivar state: device state code per sample (see :class:`drivers.dynamometer.protocol.DeviceState`).
    """

    torque_nm: np.ndarray
    position_rad: np.ndarray
    velocity_rad_s: np.ndarray
    state: np.ndarray

    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {
        **SampleBlock.LAYOUT, "torque_nm": ((), "f8"), "position_rad": ((), "f8"),
        "velocity_rad_s": ((), "f8"), "state": ((), "u1")}


@dataclass(frozen=True)
class ForcePlateBlock(SampleBlock):
    """Force plate samples in the plate frame (x anterior, y left, z up; origin at the surface centre).

    :ivar force_n: ground reaction force on the specimen in N, shape (n, 3).
    :ivar moment_nm: moment of that force about the plate's calibration origin in N·m, shape (n, 3).
    :ivar cop_m: centre of pressure on the surface (x, y) in m, NaN where |Fz| is below threshold, shape (n, 2).
    :ivar free_moment_nm: vertical free moment about the CoP in N·m, shape (n,).
    :ivar trigger: amplifier trigger/sync input per sample (0 or 1), uint8.
    """

    force_n: np.ndarray
    moment_nm: np.ndarray
    cop_m: np.ndarray
    free_moment_nm: np.ndarray
    trigger: np.ndarray

    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {
        **SampleBlock.LAYOUT, "force_n": ((3,), "f8"), "moment_nm": ((3,), "f8"), "cop_m": ((2,), "f8"),
        "free_moment_nm": ((), "f8"), "trigger": ((), "u1")}


@dataclass(frozen=True)
class StreamBlock(SampleBlock):
    """Samples of another system's stream (Lab Streaming Layer: a goniometer, an EMG system).

    :ivar values: the stream's channels in its own units, shape (n, channels); the labels and units are
        the device's ``labels`` and ``units`` (fixed for a stream), in this order.
    :ivar lsl_time_s: each sample's time stamp on this host's LSL clock (the sender's stamp with LSL's
        clock offset applied), s.
    """

    values: np.ndarray
    lsl_time_s: np.ndarray

    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {
        **SampleBlock.LAYOUT, "values": ((0,), "f8"), "lsl_time_s": ((), "f8")}


@dataclass(frozen=True)
class MarkerBlock(SampleBlock):
    """Motion-capture frames: marker positions in the lab frame.

    :ivar position_m: marker positions in m, shape (n, markers, 3); NaN where a marker is occluded.
    The marker labels are the device's ``labels`` (fixed for a stream), in this order.
    """

    position_m: np.ndarray

    LAYOUT: ClassVar[dict[str, tuple[tuple[int, ...], str]]] = {**SampleBlock.LAYOUT, "position_m": ((0, 3), "f8")}
