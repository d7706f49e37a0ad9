"""Counters are modular with a plausibility window: no valid sample is ever dropped for its counter.

One corrupted counter (valid checksum), a device that restarts its counter, and random traffic
each leave every valid sample in the stream; implausible jumps are reported in order as
``CounterResyncError`` events, plausible forward jumps as gaps, repeats are dropped.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drivers import CounterResyncError, TorqueBlock
from drivers.base import StreamingDevice
from drivers.clock import CounterClock, CounterUnwrapper


class _Device(StreamingDevice):
    """The base's accounting alone (no link)."""

    def _open_internal(self) -> None: ...
    def _read_internal(self) -> None: ...
    def _close_internal(self) -> None: ...


def _block(counters: list[int]) -> TorqueBlock:
    c = np.asarray(counters, dtype=np.int64)
    return TorqueBlock(device="t", counter=c, time_s=np.arange(c.size) * 1e-3, torque_nm=c.astype(float),
                       speed_rad_s=np.zeros(c.size))


def _feed(raw: list[int], bits: int = 16, block: int = 7) -> tuple[list[int], list[Exception], _Device]:
    dev, unwrap = _Device(), CounterUnwrapper(bits)
    values = [unwrap.unwrap(c) for c in raw]
    kept: list[int] = []
    for k in range(0, len(values), block):
        dev._deliver(_block(values[k:k + block]))
    blocks, errors = dev.read_available()
    for b in blocks:
        kept.extend(b.counter.tolist())
    return kept, errors, dev


def test_one_corrupted_counter_drops_nothing_after_it() -> None:
    raw = list(range(100, 200))
    raw[40] = 40000  # a valid-CRC frame with a nonsense counter
    kept, errors, dev = _feed(raw)
    assert len(kept) == len(raw)  # every sample kept
    assert dev.stats.duplicate_samples == 0 and dev.stats.lost_samples == 0
    assert len(errors) == 2 and all(isinstance(e, CounterResyncError) for e in errors)


def test_a_device_that_restarts_its_counter_keeps_streaming() -> None:
    raw = list(range(5000, 5300)) + list(range(0, 300))
    kept, errors, dev = _feed(raw)
    assert len(kept) == 600 and dev.stats.counter_resyncs == 1 and len(errors) == 1
    assert "resynchronised" in str(errors[0])


def test_wrap_gaps_and_repeats_are_still_told_apart() -> None:
    raw = [65530, 65531, 65531, 65533, 65535, 0, 1, 1, 2, 5]
    kept, errors, dev = _feed(raw)
    assert errors == []
    assert dev.stats.duplicate_samples == 2 and dev.stats.gaps == 3 and dev.stats.lost_samples == 1 + 1 + 2
    assert np.all(np.diff(kept) > 0)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 65535), st.integers(50, 400), st.lists(st.tuples(st.integers(1, 398), st.integers(0, 65535)),
                                                             max_size=5))
def test_random_corrupted_counters_never_cost_a_valid_sample(start: int, n: int, bad) -> None:
    raw = [(start + i) % 65536 for i in range(n)]
    corrupted = set()
    for index, value in bad:
        if index < n:
            raw[index] = value
            corrupted.add(index)
    kept, errors, dev = _feed(raw)
    valid = n - len(corrupted)
    # a corrupted counter costs at most the repeats it shadows (a small forward jump is
    # indistinguishable from a gap until the next frames), never every later sample
    assert len(kept) >= valid - len(corrupted) * StreamingDevice.reorder_window
    assert dev.stats.lost_samples <= len(corrupted) * StreamingDevice.max_counter_jump
    assert all(isinstance(e, CounterResyncError) for e in errors)


def test_clock_anchors_again_after_a_counter_jump() -> None:
    clock = CounterClock(1000.0)
    t1 = clock.stamp(np.arange(1000, 1010), arrival_s=50.010)
    t2 = clock.stamp(np.arange(0, 10), arrival_s=50.020)  # the device restarted its counter
    assert abs(t1[-1] - 50.010) < 1e-9 and abs(t2[-1] - 50.020) < 1e-9
