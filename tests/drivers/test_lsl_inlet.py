"""Other systems' streams in over the Lab Streaming Layer (loopback, simulated Delsys-like senders):
labels, units, rate, time, gaps; the EMG envelope check; refusals."""

from __future__ import annotations

import os
import time

import numpy as np
import pytest

pytest.importorskip("pylsl")

from drivers.blocks import StreamBlock
from drivers.errors import DeviceInitializationError, DeviceNotAvailableError
from drivers.lsl import LslStream, open_lsl_stream
from drivers.simulation.lsl_outlets import EMG_RATE_HZ, GONIOMETER_RATE_HZ, emg, goniometer
from instrument.live.relaxation import EmgEnvelopeMonitor


def _tag(what: str) -> str:
    return f"{what}-{os.getpid()}-{time.monotonic_ns()}"


def _collect(dev: LslStream, seconds: float) -> list[StreamBlock]:
    blocks = []
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        got, errors = dev.read_available()
        assert not errors
        blocks += got
        time.sleep(0.02)
    return blocks


def test_a_goniometer_stream_arrives_with_labels_units_rate_and_host_time() -> None:
    sender = goniometer(_tag("gon"), hip_deg=53.0, seed=1)
    try:
        dev = open_lsl_stream(f"lsl://?source_id={sender.source_id}", name="goniometer")
        with dev:
            assert dev.labels == ("hip_flexion", "knee_flexion") and dev.units == ("degrees", "degrees")
            assert dev.nominal_rate_hz == pytest.approx(GONIOMETER_RATE_HZ, rel=1e-4)
            assert dev.channel_layout()["values"] == ((2,), "f8")
            dev.start()
            blocks = _collect(dev, 1.0)
            now = time.monotonic()
        values = np.concatenate([b.values for b in blocks])
        counter = np.concatenate([b.counter for b in blocks])
        stamps = np.concatenate([b.time_s for b in blocks])
    finally:
        sender.close()
    assert len(values) > 0.7 * GONIOMETER_RATE_HZ
    assert np.all(np.diff(counter) == 1) and dev.stats.gaps == 0  # every sample, in order
    assert float(np.median(values[:, 0])) == pytest.approx(53.0, abs=0.1)
    assert 0.0 <= now - stamps[-1] < 0.5  # the sender's LSL stamps on the instrument's clock
    assert dev.identity()["stream_type"] == "Angle" and dev.identity()["resolved_by"] == {"source_id": sender.source_id}


def test_no_stream_and_two_streams_are_typed_errors() -> None:
    with pytest.raises(DeviceNotAvailableError, match="no LSL stream"):
        open_lsl_stream(f"lsl://?name={_tag('nobody')}&timeout=0.3").open()
    a, b = goniometer(_tag("a"), seed=1), goniometer(_tag("b"), seed=2)
    try:  # two goniometers on the network: the name alone does not say which
        with pytest.raises(DeviceInitializationError, match="name one"):
            open_lsl_stream("lsl://?name=Goniometer&timeout=1.0").open()
    finally:
        a.close()
        b.close()
    with pytest.raises(ValueError, match="exactly one"):
        open_lsl_stream("lsl://?name=a&type=b")


@pytest.mark.parametrize("seed", [3, 8, 21])
def test_the_emg_envelope_flags_a_seeded_burst_and_nothing_while_relaxed(seed: int) -> None:
    rng = np.random.default_rng(seed)
    rate = EMG_RATE_HZ
    t = np.arange(int(8.0 * rate)) / rate
    x = 5e-6 * rng.standard_normal((t.size, 4))
    burst_at = float(rng.uniform(2.0, 6.0))
    relaxed = EmgEnvelopeMonitor(("a", "b", "c", "d"))
    assert relaxed.update(t, x, lambda _: 10.0) == []  # eight relaxed seconds: no alarm
    inside = (t >= burst_at) & (t < burst_at + 0.3)
    x[inside, 2] += 40e-6 * rng.standard_normal(int(inside.sum()))
    monitor = EmgEnvelopeMonitor(("a", "b", "c", "d"))
    alarms = []
    for k in range(0, t.size, 37):  # in blocks, as the ring buffer hands them over
        alarms += monitor.update(t[k:k + 37], x[k:k + 37], lambda _: 42.0)
    assert len(alarms) == 1 and alarms[0].source.startswith("emg c ")
    assert burst_at <= alarms[0].time_s <= burst_at + 0.1 and alarms[0].angle_deg == 42.0


def test_an_emg_sender_s_burst_arrives_through_the_inlet() -> None:
    sender = emg(_tag("emg"), seed=5)
    try:
        dev = open_lsl_stream(f"lsl://?source_id={sender.source_id}", name="emg")
        with dev:
            dev.start()
            burst = sender.burst_after(1.2)
            blocks = _collect(dev, 2.2)
        monitor = EmgEnvelopeMonitor(dev.labels)
        alarms = [a for b in blocks for a in monitor.update(b.lsl_time_s, b.values, lambda _: 0.0)]
        burst_lsl_s = sender.clock_origin_s + burst.start_s
    finally:
        sender.close()
    assert dev.stats.gaps == 0
    assert len(alarms) == 1 and "rectus_femoris" in alarms[0].source
    assert 0.0 <= alarms[0].time_s - burst_lsl_s <= 0.15  # within the envelope's window and its 50 ms
