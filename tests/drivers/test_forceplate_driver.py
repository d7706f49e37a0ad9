"""Force plate driver: exact bytes against a scripted amplifier, and calibration applied in the driver."""

from __future__ import annotations

import numpy as np
import pytest

from drivers.blocks import ForcePlateBlock
from drivers.errors import CommandRefusedError, DeviceNotAvailableError, DeviceTimeoutError
from drivers.forceplate import open_force_plate
from drivers.forceplate import protocol as p
from drivers.forceplate.simulator import default_plate_info
from tests.protocol_peer import expected_protocol


def test_exact_bytes_open_start_stream_stop() -> None:
    info = default_plate_info(1000)
    loads = np.array([[1.0, -2.0, 650.0, 12.0, -30.0, 0.5]] * 3)
    counts = p.counts_from_loads(loads, info)
    samples = b"".join(p.encode_sample(100 + i, counts[i]) for i in range(3))
    pairs = [
        (bytes.fromhex("a50205000200000000bc83"), p.encode_reply(2, p.Status.OK)),  # STOP, golden
        (p.encode_command(p.Command.GET_INFO), p.encode_frame(p.Kind.INFO, info.to_payload())),
        (p.encode_command(p.Command.SET_RATE, 1000), p.encode_reply(3, p.Status.OK)),
        (p.encode_command(p.Command.START), p.encode_reply(1, p.Status.OK) + samples),
        (p.encode_command(p.Command.STOP), p.encode_reply(2, p.Status.OK)),
    ]
    with expected_protocol(pairs) as peer:
        plate = open_force_plate(f"socket://127.0.0.1:{peer.port}?rate=1000")
        plate.start()
        blocks = [plate.read(timeout=2.0)]
        plate.close()
        blocks += plate.read_available()[0]
    block = ForcePlateBlock(**{k: (np.concatenate([getattr(b, k) for b in blocks]) if k != "device" else "fp")
                               for k in vars(blocks[0])})
    assert block.counter.tolist() == [100, 101, 102]
    lsb = np.abs(info.sensitivity).sum(axis=1) * info.volts_per_count
    np.testing.assert_allclose(block.force_n, loads[:, :3], atol=lsb[:3].max())
    np.testing.assert_allclose(block.moment_nm, loads[:, 3:], atol=lsb[3:].max())
    # the CoP follows from the calibrated wrench and the plate origin
    cop, _ = p.centre_of_pressure(loads[:, :3], loads[:, 3:], info.origin_m)
    np.testing.assert_allclose(block.cop_m, cop, atol=1e-4)
    assert plate.identity()["amplifier"]["serial_number"] == info.serial_number


def _opening(info: p.PlateInfo) -> list[tuple[bytes, bytes]]:
    return [(p.encode_command(p.Command.STOP), p.encode_reply(2, p.Status.OK)),
            (p.encode_command(p.Command.GET_INFO), p.encode_frame(p.Kind.INFO, info.to_payload())),
            (p.encode_command(p.Command.SET_RATE, 1000), p.encode_reply(3, p.Status.OK))]


def test_a_start_left_unanswered_is_sent_again_and_counted() -> None:
    """A lost reply (or a starved host) costs one repeat of the idempotent START, counted, not the trial."""
    info = default_plate_info(1000)
    counts = p.counts_from_loads(np.array([[0.0, 0.0, 700.0, 0.0, 0.0, 0.0]] * 2), info)
    samples = b"".join(p.encode_sample(7 + i, counts[i]) for i in range(2))
    pairs = _opening(info) + [
        (p.encode_command(p.Command.START), b""),  # the amplifier's reply is lost
        (p.encode_command(p.Command.START), p.encode_reply(1, p.Status.OK) + samples),
        (p.encode_command(p.Command.STOP), p.encode_reply(2, p.Status.OK)),
    ]
    with expected_protocol(pairs) as peer:
        plate = open_force_plate(f"socket://127.0.0.1:{peer.port}?rate=1000")
        plate.start()
        block = plate.read(timeout=2.0)
        assert plate.stats.command_retries == 1
        plate.close()
    assert block is not None and block.counter.tolist()[0] == 7


def test_a_start_never_answered_is_a_typed_timeout_after_two_attempts() -> None:
    info = default_plate_info(1000)
    pairs = _opening(info) + [(p.encode_command(p.Command.START), b""), (p.encode_command(p.Command.START), b"")]
    with expected_protocol(pairs, linger_s=3.0) as peer:
        plate = open_force_plate(f"socket://127.0.0.1:{peer.port}?rate=1000")
        with pytest.raises(DeviceTimeoutError, match="no reply to START in 2 attempts"):
            plate.start()
        assert plate.stats.command_retries == 1
        plate.close()


def test_refused_rate_is_a_typed_error() -> None:
    info = default_plate_info(1000)
    pairs = [
        (p.encode_command(p.Command.STOP), p.encode_reply(2, p.Status.OK)),
        (p.encode_command(p.Command.GET_INFO), p.encode_frame(p.Kind.INFO, info.to_payload())),
        (p.encode_command(p.Command.SET_RATE, 2000), p.encode_reply(3, p.Status.BAD_ARGUMENT)),
    ]
    with expected_protocol(pairs) as peer:
        plate = open_force_plate(f"socket://127.0.0.1:{peer.port}?rate=2000")
        with pytest.raises(CommandRefusedError, match="BAD_ARGUMENT"):
            plate.open()
        plate.close()


def test_url_errors() -> None:
    with pytest.raises(DeviceNotAvailableError):
        open_force_plate("carrier-pigeon://coop")
    with pytest.raises(ValueError, match="unknown option"):
        open_force_plate("socket://127.0.0.1:1?bauds=9600")
    with pytest.raises(ValueError, match="bit/s"):
        open_force_plate("serial:///dev/ttyACM0?baud=115200&rate=1000")
    with pytest.raises(ValueError, match="not supported"):
        open_force_plate("serial:///dev/ttyACM0?rate=1234")
