"""Golden frames of the force plate protocol, both directions, with garbage, bad CRC and truncation."""

from __future__ import annotations

import numpy as np
import pytest

from drivers.forceplate import protocol as p
from drivers.forceplate.simulator import default_plate_info

GOLDEN = [
    # (description, frame bytes, kind, decoded)
    ("sample, trigger set", "a5011d000101000000640000009cffffff400d030000000000ffffffff07000000aa0e",
     p.Kind.SAMPLE, (1, 1, [100, -100, 200000, 0, -1, 7])),
    ("sample, counter at wrap", "a5011d0000ffffffff00000000000000000000000000000000000000000000000040f0",
     p.Kind.SAMPLE, (0, 0xFFFFFFFF, [0] * 6)),
    ("command START", "a502050001000000006e6d", p.Kind.COMMAND, (p.Command.START, 0)),
    ("command SET_RATE 1000", "a502050003e80300009471", p.Kind.COMMAND, (p.Command.SET_RATE, 1000)),
    ("reply START ok", "a503020001008721", p.Kind.REPLY, (1, p.Status.OK)),
    ("reply SET_RATE bad argument", "a50302000301c457", p.Kind.REPLY, (3, p.Status.BAD_ARGUMENT)),
]


def test_crc_is_ccitt_false() -> None:
    assert p.crc16(b"123456789") == 0x29B1  # the catalogued check value of CRC-16/CCITT-FALSE


def _encode(kind: p.Kind, decoded: tuple) -> bytes:
    if kind == p.Kind.SAMPLE:
        flags, counter, counts = decoded
        return p.encode_sample(counter, counts, flags)
    if kind == p.Kind.COMMAND:
        return p.encode_command(*decoded)
    return p.encode_reply(*decoded)


@pytest.mark.parametrize("desc,hexframe,kind,decoded", GOLDEN, ids=[g[0] for g in GOLDEN])
def test_encode_matches_golden(desc: str, hexframe: str, kind: p.Kind, decoded: tuple) -> None:
    assert _encode(kind, decoded).hex() == hexframe


@pytest.mark.parametrize("desc,hexframe,kind,decoded", GOLDEN, ids=[g[0] for g in GOLDEN])
@pytest.mark.parametrize("before,after", [(b"", b""), (b"\x00\xff\x13", b""), (b"", b"\xa5\x01"), (b"\xa5\xa5\x07", b"\x99")])
def test_decode_golden_with_garbage(desc: str, hexframe: str, kind: p.Kind, decoded: tuple,
                                    before: bytes, after: bytes) -> None:
    parser = p.FrameParser()
    samples, others = parser.feed(before + bytes.fromhex(hexframe) + after)
    if kind == p.Kind.SAMPLE:
        flags, counter, counts = decoded
        assert samples.counters.tolist() == [counter]
        assert samples.flags.tolist() == [flags]
        assert samples.counts.tolist() == [counts]
        assert others == []
    else:
        assert samples.counters.size == 0
        assert [k for k, _ in others] == [kind]
    assert parser.crc_errors == 0
    assert parser.garbage_bytes + parser.malformed_frames >= (1 if before else 0)


def test_bad_crc_is_counted_and_next_frame_survives() -> None:
    good = bytes.fromhex(GOLDEN[0][1])
    bad = bytearray(good)
    bad[10] ^= 0x04
    parser = p.FrameParser()
    samples, _ = parser.feed(bytes(bad) + good)
    assert samples.counters.tolist() == [1]
    assert parser.crc_errors == 1


def test_truncated_frame_then_good_frame() -> None:
    good = bytes.fromhex(GOLDEN[0][1])
    parser = p.FrameParser()
    samples, _ = parser.feed(good[:20] + good)
    assert samples.counters.tolist() == [1]
    assert parser.crc_errors + parser.malformed_frames >= 1


def test_split_delivery_byte_by_byte() -> None:
    stream = b"".join(p.encode_sample(i, [i] * 6) for i in range(5))
    parser = p.FrameParser()
    got: list[int] = []
    for b in stream:
        s, _ = parser.feed(bytes([b]))
        got += s.counters.tolist()
    assert got == [0, 1, 2, 3, 4]
    assert parser.pending_bytes() == 0


def test_impossible_length_is_malformed() -> None:
    parser = p.FrameParser()
    parser.feed(bytes([0xA5, 0x01, 0xFF, 0x7F]) + bytes.fromhex(GOLDEN[2][1]))
    assert parser.malformed_frames == 1


def test_info_round_trip() -> None:
    info = default_plate_info(1000)
    back = p.PlateInfo.from_payload(info.to_payload())
    np.testing.assert_allclose(back.sensitivity, info.sensitivity, rtol=1e-6)
    np.testing.assert_allclose(back.zero_v, info.zero_v, rtol=1e-6)
    assert back.model == info.model and back.serial_number == info.serial_number


def test_calibration_round_trip_within_one_count() -> None:
    info = default_plate_info()
    loads = np.array([[12.0, -3.0, 700.0, 15.0, -40.0, 2.0], [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]])
    counts = p.counts_from_loads(loads, info)
    back = p.loads_from_counts(counts, info, info.zero_v)
    lsb_load = np.abs(info.sensitivity).sum(axis=1) * info.volts_per_count
    assert np.all(np.abs(back - loads) <= lsb_load)


def test_centre_of_pressure_of_a_point_load() -> None:
    # a 600 N vertical load with a 20 N forward shear at surface point (0.10, -0.05)
    origin = np.array([0.0, 0.0, -0.04])
    point = np.array([0.10, -0.05, 0.04])  # relative to the origin: the surface is 40 mm above it
    force = np.array([[20.0, 0.0, 600.0]])
    moment = np.cross(point, force[0])[None, :] + np.array([[0.0, 0.0, 1.5]])
    cop, tz = p.centre_of_pressure(force, moment, origin)
    np.testing.assert_allclose(cop[0], [0.10, -0.05], atol=1e-12)
    np.testing.assert_allclose(tz, [1.5], atol=1e-12)
    cop_unloaded, _ = p.centre_of_pressure(np.array([[0.0, 0.0, 1.0]]), np.zeros((1, 3)), origin)
    assert np.isnan(cop_unloaded).all()
