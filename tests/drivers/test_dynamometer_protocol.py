"""Golden CAN payloads of the dynamometer protocol, both directions."""

from __future__ import annotations

import pytest

from drivers.dynamometer import protocol as p


def test_identifiers_of_node_16() -> None:
    assert p.ids(0x10) == {"estop": 0x090, "telemetry": 0x190, "command": 0x210, "status": 0x290,
                           "ack": 0x310, "heartbeat": 0x710}
    with pytest.raises(ValueError):
        p.ids(0)


TELEMETRY = [
    ("ffffeee7b80bfa00", p.Telemetry(65535, -61.62, 30.0, 5.0)),
    ("0000000000000000", p.Telemetry(0, 0.0, 0.0, 0.0)),
    ("0a00e803d8dc38ff", p.Telemetry(10, 10.0, -90.0, -4.0)),
]


@pytest.mark.parametrize("hexdata,telemetry", TELEMETRY)
def test_telemetry_golden(hexdata: str, telemetry: p.Telemetry) -> None:
    assert telemetry.encode().hex() == hexdata
    back = p.Telemetry.decode(bytes.fromhex(hexdata))
    assert back.counter == telemetry.counter
    assert back.torque_nm == pytest.approx(telemetry.torque_nm, abs=p.TORQUE_LSB_NM / 2)
    assert back.position_deg == pytest.approx(telemetry.position_deg, abs=p.POSITION_LSB_DEG / 2)
    assert back.velocity_deg_s == pytest.approx(telemetry.velocity_deg_s, abs=p.VELOCITY_LSB_DEG_S / 2)


def test_truncated_telemetry_rejected() -> None:
    with pytest.raises(ValueError):
        p.Telemetry.decode(bytes.fromhex("ffffeee7b80b"))


def test_out_of_range_value_rejected() -> None:
    with pytest.raises(ValueError):
        p.Telemetry(0, 400.0, 0.0, 0.0).encode()


COMMANDS = [
    ("0307000028230000", p.Command.SET_ROM, 7, (0, 9000)),
    ("0508282300000000", p.Command.START, 8, (9000,)),
    ("0209f401" + "0000" * 2, p.Command.SET_SPEED, 9, (500,)),
    ("0601" + "00" * 6, p.Command.STOP, 1, ()),
]


@pytest.mark.parametrize("hexdata,command,seq,args", COMMANDS)
def test_command_golden(hexdata: str, command: p.Command, seq: int, args: tuple) -> None:
    assert p.encode_command(command, seq, *args).hex() == hexdata
    assert p.decode_command(bytes.fromhex(hexdata)) == (command, seq, args)


def test_unknown_command_code() -> None:
    with pytest.raises(ValueError, match="unknown command"):
        p.decode_command(bytes.fromhex("7f01000000000000"))


def test_status_ack_estop_golden() -> None:
    status = p.Status(p.State.MOVING, p.Mode.PASSIVE_ISOKINETIC, p.Fault.NONE, 100, 150.0)
    assert status.encode().hex() == "0101006400dc0500"
    assert p.Status.decode(bytes.fromhex("0101006400dc0500")) == status
    assert p.encode_ack(5, 8, p.Result.OUT_OF_RANGE).hex() == "050801"
    assert p.decode_ack(bytes.fromhex("050801")) == (5, 8, p.Result.OUT_OF_RANGE)
    assert p.encode_estop().hex() == "e570"
    assert p.is_estop(bytes.fromhex("e570")) and not p.is_estop(bytes.fromhex("e571"))
