"""The device streams as Lab Streaming Layer outlets: labels, units, rate, every sample with its device time."""

from __future__ import annotations

import time

import numpy as np
import pytest

pylsl = pytest.importorskip("pylsl")

from instrument.kinds.knee import KneeProtocol  # noqa: E402 - after the optional import is known
from instrument.live.acquisition import AcquisitionEngine  # noqa: E402 - after the optional import is known
from instrument.live.lsl import LslPublisher, channel_labels, unit_of  # noqa: E402 - after the optional import is known
from instrument.sim.simulate import lab_config_for, simulated_devices  # noqa: E402 - after the optional import is known


def test_channel_labels_and_units_come_from_the_layout() -> None:
    layout = {"counter": ((), "i8"), "time_s": ((), "f8"), "torque_nm": ((), "f8"), "force_n": ((3,), "f8"),
              "position_rad": ((), "f8"), "velocity_rad_s": ((), "f8")}
    assert channel_labels(layout) == [("counter", "count", "counter"), ("torque_nm", "N.m", "torque_nm"),
                                      ("force_n_x", "N", "force_n"), ("force_n_y", "N", "force_n"),
                                      ("force_n_z", "N", "force_n"), ("position_rad", "rad", "position_rad"),
                                      ("velocity_rad_s", "rad/s", "velocity_rad_s")]
    assert unit_of("cop_m") == "m" and unit_of("speed_rpm") == "rpm"


def test_an_inlet_receives_every_dynamometer_sample_with_its_device_time() -> None:
    """Loopback: the instrument's outlet, a LabRecorder-like inlet; counts, values, stamps and labels."""
    proto = KneeProtocol(end_deg=10.0, speed_deg_s=10.0)
    session = f"test-{time.monotonic_ns()}"
    with simulated_devices(proto, lab_config_for(proto, seed=2)) as (_, devices):
        engine = AcquisitionEngine(devices)
        engine.open()
        publisher = LslPublisher(devices, session=session, subject_code="S01")
        engine.sinks.append(publisher)
        (info,) = [i for i in pylsl.resolve_byprop("source_id", f"instrument:{session}:dynamometer", timeout=5.0)]
        inlet = pylsl.StreamInlet(info, max_buflen=60, processing_flags=0)
        inlet.open_stream(timeout=5.0)
        full = inlet.info(timeout=5.0)
        engine.start()
        time.sleep(1.0)
        engine.stop()
        got, stamps = [], []
        deadline = time.monotonic() + 5.0
        while sum(len(c) for c in got) < publisher.pushed["dynamometer"] and time.monotonic() < deadline:
            chunk, ts = inlet.pull_chunk(timeout=0.5)
            if chunk:
                got.append(chunk)
                stamps += ts
        ring = engine.rings["dynamometer"].latest()
        engine.close()
        publisher.close()
    data = np.concatenate([np.asarray(c) for c in got])
    assert publisher.pushed["dynamometer"] == len(ring["counter"]) > 50
    assert len(data) == publisher.pushed["dynamometer"]  # none lost on the loopback
    labels = []
    ch = full.desc().child("channels").child("channel")
    while not ch.empty():
        labels.append((ch.child_value("label"), ch.child_value("unit")))
        ch = ch.next_sibling()
    names = [lab for lab, _ in labels]
    assert ("torque_nm", "N.m") in labels and names[0] == "counter"
    assert full.nominal_srate() == 100.0 and full.type() == "Torque" and full.desc().child_value("subject") == "S01"
    np.testing.assert_array_equal(data[:, 0], ring["counter"])
    np.testing.assert_allclose(data[:, names.index("torque_nm")], ring["torque_nm"])
    np.testing.assert_allclose(stamps, ring["time_s"], atol=1e-9)  # the device's host time is the LSL stamp
    before = time.monotonic()
    lsl_now = pylsl.local_clock()
    after = time.monotonic()
    assert before - 1e-3 <= lsl_now <= after + 1e-3  # one steady clock (bracketed: a preemption only widens it)
