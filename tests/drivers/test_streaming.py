"""Each driver streams from its simulator: contiguous counters, nominal rate, and every fault knob
gives a counted, skipped frame or a typed error, never a crash or a hang; drivers recover."""

from __future__ import annotations

import numpy as np
import pytest

from drivers import ConnectionLostError, DeviceTimeoutError
from drivers.simulation.faults import FaultConfig
from drivers.torque import registers

from .streaming import DEVICES, collect, counters, device_with_simulator

NOMINAL_HZ = {"force_plate": 1000.0, "dynamometer": 100.0}


@pytest.mark.parametrize("kind", DEVICES)
def test_clean_stream_has_contiguous_counters(kind: str) -> None:
    with device_with_simulator(kind) as (dev, _):
        blocks, errors, _ = collect(dev, 2.0)
    c = counters(blocks)
    assert not errors
    assert c.size > 0 and np.all(np.diff(c) == 1), "a sample was lost or repeated"
    assert dev.stats.lost_samples == 0 and dev.stats.crc_errors == 0 and dev.stats.malformed_frames == 0
    t = np.concatenate([b.time_s for b in blocks])
    assert np.all(np.diff(t) > 0), "timestamps must increase"
    if kind in NOMINAL_HZ:
        # the stamps come from the device counter at its nominal rate (content, not the host's pace)
        assert np.median(np.diff(t)) == pytest.approx(1.0 / NOMINAL_HZ[kind], rel=0.02)
    else:  # polled: never above what the wire can carry
        assert c.size > 10 and dev.stats.rate_hz() <= registers.max_poll_rate_hz(115200)


def test_force_plate_delivers_the_jig_physics() -> None:
    with device_with_simulator("force_plate") as (dev, sim):
        blocks, _, _ = collect(dev, 1.0)
    c = counters(blocks)
    f = np.concatenate([b.force_n for b in blocks])
    truth = sim.jig.state(c / 1000.0).force_n  # type: ignore[attr-defined]  # the plate simulator has its jig
    resid = f - truth
    assert np.abs(resid.mean(axis=0)).max() < 0.1  # N: calibration and zero applied correctly
    assert resid.std(axis=0).max() < 0.4  # N: the simulator's 0.25 N noise plus ADC steps


RATE_FAULTS = {
    "noise": FaultConfig(noise_scale=5.0),
    "drop": FaultConfig(drop_rate=0.05),
    "corrupt": FaultConfig(corrupt_rate=0.05),
    "garbage": FaultConfig(garbage_rate=0.05),
    "truncate": FaultConfig(truncate_rate=0.05),
}


@pytest.mark.parametrize("fault", sorted(RATE_FAULTS))
@pytest.mark.parametrize("kind", DEVICES)
def test_frame_faults_are_counted_and_skipped(kind: str, fault: str) -> None:
    with device_with_simulator(kind, RATE_FAULTS[fault], seed=3) as (dev, _):
        blocks, errors, _ = collect(dev, 2.0)
    s = dev.stats
    c = counters(blocks)
    assert c.size > 50, "the stream must go on through bad frames"
    assert np.all(np.diff(c) >= 1), "counters never go backwards"
    assert not [e for _, e in errors if isinstance(e, ConnectionLostError)]
    if fault == "noise":
        # noise costs no frame; a polled device's only losses are polls that failed on a loaded host: mostly
        # unanswered in time (poll timeouts), or a late reply landing in the next poll (a bad frame). Each is
        # one missing sample, counted (the last may have no later sample to show its gap)
        failed = s.poll_timeouts + s.malformed_frames
        assert s.crc_errors == 0
        assert failed - 1 <= s.lost_samples <= failed
    elif fault == "drop":
        assert s.lost_samples > 0 and s.gaps > 0
        assert s.lost_samples == int((np.diff(c) - 1).sum())
    elif fault == "corrupt":
        # every corrupted sample is lost, and counted as a gap once a later sample arrives: one
        # corrupted at the very end of the stream has no later sample to show its gap
        assert s.crc_errors > 0 and s.lost_samples >= (s.crc_errors - 1 if kind != "torque_sensor" else 1)
    elif fault == "garbage":
        assert s.garbage_bytes + s.crc_errors + s.malformed_frames > 0
    elif fault == "truncate":
        assert s.malformed_frames + s.crc_errors > 0 and s.lost_samples > 0


@pytest.mark.parametrize("kind", DEVICES)
def test_device_vanishes_then_comes_back(kind: str) -> None:
    faults = FaultConfig(disconnect_after_s=0.8, reconnect_after_s=1.2)  # well past the 0.5 s silence timeout
    expected = DeviceTimeoutError if kind == "dynamometer" else ConnectionLostError  # CAN: the node falls silent

    def reported_and_back(errors: list, arrivals: list) -> bool:
        hits = [t for t, e in errors if isinstance(e, expected)]
        return bool(hits) and any(t > hits[0] + 0.1 for t in arrivals)

    with device_with_simulator(kind, faults) as (dev, _):
        blocks, errors, arrivals = collect(dev, 3.0, until=reported_and_back)
    hits = [t for t, e in errors if isinstance(e, expected)]
    assert hits, f"no {expected.__name__} reported: {errors}"
    assert any(t > hits[0] + 0.1 for t in arrivals), "no data after the device came back"
    assert dev.stats.lost_samples > 0  # what the device produced while away is a counted gap
    if kind != "dynamometer":
        assert dev.stats.reconnects >= 1


@pytest.mark.parametrize("kind", DEVICES)
def test_silence_is_a_timeout_then_streaming_resumes(kind: str) -> None:
    faults = FaultConfig(silence_after_s=0.8, silence_for_s=1.0)

    def timed_out_and_back(errors: list, arrivals: list) -> bool:
        hits = [t for t, e in errors if isinstance(e, DeviceTimeoutError)]
        return bool(hits) and any(t > hits[0] + 0.1 for t in arrivals)

    with device_with_simulator(kind, faults) as (dev, _):
        blocks, errors, arrivals = collect(dev, 3.0, until=timed_out_and_back)
    timeouts = [t for t, e in errors if isinstance(e, DeviceTimeoutError)]
    assert len(timeouts) == 1, errors
    assert any(t > timeouts[0] + 0.1 for t in arrivals)
    assert dev.stats.timeouts == 1


def test_a_counting_transmitter_streams_each_conversion_once_with_its_seeded_value() -> None:
    """A transmitter converting at 100 Hz and polled faster: repeats are dropped, every kept sample is
    the simulator's conversion of that number (its noise seeded by the number, not the read time),
    and what no poll read is a counted gap."""
    from drivers import open_torque_sensor
    from drivers.torque.simulator import TorqueSensorSimulator

    with TorqueSensorSimulator(seed=5, output_rate_hz=100.0) as sim:
        dev = open_torque_sensor(sim.url + "&timeout=0.25", silence_timeout_s=0.5)
        try:
            blocks, errors, _ = collect(dev, 1.5, until=lambda e, a: dev.stats.samples >= 60)
        finally:
            dev.close()
        c = counters(blocks)
        torque = np.concatenate([b.torque_nm for b in blocks])
        expected = np.array([sim.conversion_nm(int(k)) - sim.zero_nm for k in c], dtype=np.float32)
    assert not errors and c.size >= 60
    assert np.all(np.diff(c) >= 1)  # each conversion once
    assert np.array_equal(torque.astype(np.float32), expected)
    assert dev.stats.lost_samples == int((np.diff(c) - 1).sum())
    # a second simulator of the same seed gives conversion k of the schedule the same value
    with TorqueSensorSimulator(seed=5, output_rate_hz=100.0) as other:
        assert all(other.conversion_nm(int(k)) == sim.conversion_nm(int(k)) for k in c[:20])
