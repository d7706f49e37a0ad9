"""The CiA 402 dynamometer back end against the simulated drive (a canopen LocalNode on the virtual bus):
golden frames, configuration read back, the state machine, every stop path in the drive, telemetry gaps."""

from __future__ import annotations

import itertools
import math
import os
import struct
import time
from collections.abc import Callable, Iterator

import can
import canopen
import pytest

from drivers.dynamometer import DynamometerLimits, open_dynamometer
from drivers.dynamometer import cia402 as c
from drivers.dynamometer.canopen_driver import CanopenDynamometer
from drivers.dynamometer.cia402 import PowerState
from drivers.dynamometer.cia402_simulator import Cia402DriveSimulator
from drivers.dynamometer.protocol import State
from drivers.errors import CommandRefusedError, DeviceNotAvailableError, DeviceTimeoutError, LimitViolationError
from drivers.simulation.faults import FaultConfig

NODE = 0x10
_ids = itertools.count()


def _channel() -> str:
    return f"t402-{os.getpid()}-{next(_ids)}"


def _frames(tap: can.BusABC) -> list[can.Message]:
    out = []
    while (msg := tap.recv(timeout=0)) is not None:
        out.append(msg)
    return out


def _wait(condition: Callable[[], bool], timeout_s: float = 3.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.002)
    return True


Rig = tuple[Cia402DriveSimulator, CanopenDynamometer, can.BusABC]


@pytest.fixture
def rig() -> Iterator[Rig]:
    channel = _channel()
    tap = can.Bus(interface="virtual", channel=channel)
    sim = Cia402DriveSimulator(channel=channel, start_position_deg=0.0)
    dyno = open_dynamometer(f"canopen://virtual/{channel}?rate=100")
    assert isinstance(dyno, CanopenDynamometer)
    dyno.open()
    try:
        yield sim, dyno, tap
    finally:
        dyno.close()
        sim.close()
        tap.shutdown()


def test_the_eds_maps_position_torque_velocity_statusword_and_the_counter() -> None:
    od = canopen.import_od(str(c.EDS_PATH), NODE)
    signed = c.signed_objects(od)
    one = c.PdoLayout.from_mapping(c.mapping_words(od, c.TPDO1_MAP), signed)
    two = c.PdoLayout.from_mapping(c.mapping_words(od, c.TPDO2_MAP), signed)
    assert [e[0] for e in one.entries] == [c.POSITION_ACTUAL, c.TORQUE_ACTUAL, c.SAMPLE_COUNTER]
    assert [e[0] for e in two.entries] == [c.VELOCITY_ACTUAL, c.STATUSWORD, c.SAMPLE_COUNTER]
    assert one.fmt.size == two.fmt.size == 8  # one classic CAN frame each
    frame = one.encode({c.POSITION_ACTUAL: -12345, c.TORQUE_ACTUAL: -250, c.SAMPLE_COUNTER: 65535})
    assert frame == struct.pack("<ihH", -12345, -250, 65535)
    assert one.decode(frame)[c.POSITION_ACTUAL] == -12345
    assert int(od[c.DEVICE_TYPE].default) & 0xFFFF == c.CIA402_PROFILE


def test_statusword_decoding_follows_the_profile() -> None:
    assert c.state_of(0x0250) == PowerState.SWITCH_ON_DISABLED
    assert c.state_of(0x0231) == PowerState.READY_TO_SWITCH_ON
    assert c.state_of(0x0233) == PowerState.SWITCHED_ON
    assert c.state_of(0x0637) == PowerState.OPERATION_ENABLED
    assert c.state_of(0x0217) == PowerState.QUICK_STOP_ACTIVE
    assert c.state_of(0x0218) == PowerState.FAULT
    for state in PowerState:
        assert c.state_of(c.statusword_of(state)) == state


def test_open_configures_by_sdo_and_the_frames_are_the_profile_s(rig: Rig) -> None:
    sim, dyno, tap = rig
    frames = _frames(tap)
    sdo = [bytes(m.data) for m in frames if m.arbitration_id == 0x600 + NODE]
    # expedited downloads: quick stop "ramp, then disabled" (0x605A = 2, 2 bytes), halt on the quick-stop ramp
    assert bytes([0x2B, 0x5A, 0x60, 0x00, 0x02, 0x00, 0x00, 0x00]) in sdo
    assert bytes([0x2B, 0x5D, 0x60, 0x00, 0x02, 0x00, 0x00, 0x00]) in sdo
    # the consumer heartbeat watches the host (node 0x7F, 500 ms), 4 bytes to 0x1016 sub 1
    assert bytes([0x23, 0x16, 0x10, 0x01]) + struct.pack("<I", 0x7F << 16 | 500) in sdo
    # the software limits are the envelope's (0.001° counts)
    lo, hi = sim.rom_deg
    assert (lo, hi) == pytest.approx(tuple(math.degrees(v) for v in (dyno.limits.rom_min_rad, dyno.limits.rom_max_rad)))
    assert any(m.arbitration_id == 0x000 and bytes(m.data) == bytes([0x01, NODE]) for m in frames)  # NMT start
    assert any(m.arbitration_id == 0x700 + c.HOST_NODE_ID and bytes(m.data) == b"\x05" for m in frames)
    assert sim.node.nmt.state == "OPERATIONAL"
    assert sim.rate_hz == 100.0 and dyno.rated_torque_nm == 10.0
    assert dyno.identity()["protocol"] == "CiA 402 (CANopen)"


def test_a_sweep_walks_the_state_machine_and_streams_paired_samples(rig: Rig) -> None:
    sim, dyno, tap = rig
    dyno.set_range_of_motion(math.radians(-1.0), math.radians(11.0))
    dyno.set_torque_limit(100.0)
    dyno.set_passive_isokinetic(math.radians(20.0))
    _frames(tap)
    dyno.start()
    dyno.move_to(math.radians(10.0))
    controlwords = [struct.unpack_from("<H", bytes(m.data), 4)[0] for m in _frames(tap)
                    if m.arbitration_id == 0x600 + NODE and bytes(m.data)[:3] == b"\x2b\x40\x60"]  # downloads
    assert controlwords[:3] == [c.CW_SHUTDOWN, c.CW_SWITCH_ON, c.CW_ENABLE_OPERATION]
    assert controlwords[3] & c.CW_NEW_SETPOINT and not controlwords[4] & c.CW_NEW_SETPOINT
    assert _wait(lambda: sim.position_deg == 10.0 and sim.velocity_deg_s == 0.0)
    sent = sim.counter
    blocks = []

    def caught_up() -> bool:
        blocks.extend(dyno.read_available()[0])
        return bool(blocks) and int(blocks[-1].counter[-1]) % 65536 > sent % 65536

    assert _wait(caught_up)
    counters = [int(k) for b in blocks for k in b.counter]
    assert counters == sorted(counters) and dyno.stats.gaps == 0
    last = blocks[-1]
    assert math.degrees(float(last.position_rad[-1])) == pytest.approx(10.0, abs=1e-3)
    assert abs(float(last.torque_nm[-1])) > 0.0  # the leg's torque, in N·m from per mille of the rated torque


def test_limits_are_checked_before_anything_reaches_the_bus(rig: Rig) -> None:
    sim, dyno, tap = rig
    _frames(tap)
    with pytest.raises(LimitViolationError):
        dyno.move_to(math.radians(120.0))
    with pytest.raises(LimitViolationError):
        dyno.set_passive_isokinetic(math.radians(45.0))
    with pytest.raises(LimitViolationError):
        dyno.set_torque_limit(float("nan"))
    assert not any(m.arbitration_id in (0x600 + NODE, 0x200 + NODE) for m in _frames(tap))


def test_an_sdo_request_left_unanswered_is_sent_again_once_and_counted(rig: Rig) -> None:
    """A lost SDO answer (or a drive starved past the host's timeout) costs one counted repeat; two in a row
    are a typed timeout naming the object, and the drive's value is the one set."""
    sim, dyno, _ = rig
    dyno.start()
    sim.lose_sdo_requests = 1
    dyno.set_torque_limit(40.0)
    assert (sim.sdo_requests_lost, dyno.stats.command_retries) == (1, 1)
    assert sim._get(c.MAX_TORQUE) == round(1000 * 40.0 / dyno.rated_torque_nm)
    sim.lose_sdo_requests = 2
    with pytest.raises(DeviceTimeoutError, match="no answer to write 0x6072"):
        dyno.set_torque_limit(30.0)
    assert (sim.sdo_requests_lost, dyno.stats.command_retries) == (3, 2)


def test_a_drive_that_cannot_take_the_limits_is_refused_at_open() -> None:
    channel = _channel()
    with Cia402DriveSimulator(channel=channel, device_rom_deg=(-10.0, 50.0)):
        dyno = open_dynamometer(f"canopen://virtual/{channel}")
        with pytest.raises(CommandRefusedError, match="0x607D"):
            dyno.open()


def test_no_drive_on_the_bus_is_a_typed_error() -> None:
    dyno = open_dynamometer(f"canopen://virtual/{_channel()}")
    with pytest.raises(DeviceNotAvailableError, match="no heartbeat"):
        dyno.open()


def _moving(sim: Cia402DriveSimulator, dyno: CanopenDynamometer) -> None:
    dyno.set_passive_isokinetic(math.radians(20.0))
    dyno.start()
    dyno.move_to(math.radians(60.0))
    assert _wait(lambda: sim.position_deg > 3.0)


def test_emergency_stop_latches_until_reset(rig: Rig) -> None:
    sim, dyno, tap = rig
    _moving(sim, dyno)
    sent = dyno.emergency_stop()
    assert _wait(lambda: dyno.stop_latched_since(sent))
    assert _wait(lambda: sim.power == PowerState.SWITCH_ON_DISABLED)  # the ramp done, the drive disabled
    assert sim.state == State.ESTOP and sim.velocity_deg_s == 0.0
    with pytest.raises(CommandRefusedError, match="emergency stop was sent"):
        dyno.move_to(math.radians(30.0))
    dyno.halt()  # a halt word never re-enables a stopped drive
    sim._controlword(c.CW_ENABLE_OPERATION | c.CW_CHANGE_IMMEDIATELY)  # a move's word in flight: no effect
    assert sim.power == PowerState.SWITCH_ON_DISABLED and sim.state == State.ESTOP
    dyno.reset()
    assert sim.power == PowerState.SWITCH_ON_DISABLED
    dyno.move_to(math.radians(8.0))  # after the reset the host walks the state machine again
    assert _wait(lambda: sim.power == PowerState.OPERATION_ENABLED and sim.state != State.ESTOP)


def test_a_lost_quick_stop_frame_is_not_confirmed_and_a_second_one_is(rig: Rig) -> None:
    sim, dyno, tap = rig
    _moving(sim, dyno)
    sim.lose_estop_frames = 1
    sent = dyno.emergency_stop()
    assert not _wait(lambda: dyno.stop_latched_since(sent), 0.1)
    assert sim.estop_frames_lost == 1
    sent = dyno.emergency_stop()
    assert _wait(lambda: dyno.stop_latched_since(sent))


def test_the_drive_faults_when_the_host_heartbeat_stops(rig: Rig) -> None:
    sim, dyno, tap = rig
    _moving(sim, dyno)
    dyno.suspend_heartbeat(True)
    assert _wait(lambda: sim.power == PowerState.FAULT, 3.0)
    assert sim.error_code == c.EMCY_HEARTBEAT and sim.velocity_deg_s == 0.0
    assert any(m.arbitration_id == 0x80 + NODE and struct.unpack_from("<H", bytes(m.data))[0] == c.EMCY_HEARTBEAT
               for m in _frames(tap))
    assert _wait(lambda: dyno.stop_latched_since(float("-inf")))  # the next TPDO shows it
    with pytest.raises(CommandRefusedError):  # the fault stays while the host is silent
        dyno.reset()
    dyno.suspend_heartbeat(False)
    assert _wait(lambda: sim._host_alive(time.monotonic()))
    dyno.reset()
    assert sim.power == PowerState.SWITCH_ON_DISABLED


def test_the_drive_stops_itself_at_its_software_limit(rig: Rig) -> None:
    sim, dyno, tap = rig
    _moving(sim, dyno)
    edge = sim.position_deg + 0.5
    sim.rom_deg = (sim.rom_deg[0], edge)  # narrowed mid-move, from the drive's side
    assert _wait(lambda: sim.power == PowerState.FAULT)
    assert sim.error_code == c.EMCY_POSITION_LIMIT and sim.position_deg <= edge + 1e-9


def test_a_set_point_without_the_host_heartbeat_is_refused(rig: Rig) -> None:
    sim, dyno, tap = rig
    dyno.set_passive_isokinetic(math.radians(20.0))
    dyno.suspend_heartbeat(True)
    assert _wait(lambda: not sim._host_alive(time.monotonic()))
    with pytest.raises(CommandRefusedError, match="set-point"):
        dyno.move_to(math.radians(20.0))
    assert sim.target_deg is None


def test_bad_frames_are_counted_and_dropped_samples_are_gaps() -> None:
    channel = _channel()
    faults = FaultConfig(drop_rate=0.05, corrupt_rate=0.03, truncate_rate=0.03, garbage_rate=0.03)
    with Cia402DriveSimulator(channel=channel, faults=faults, seed=3) as sim:
        dyno = open_dynamometer(f"canopen://virtual/{channel}?rate=200", limits=DynamometerLimits.from_degrees(
            -35.0, 95.0, 30.0, 150.0))
        with dyno:
            dyno.start()
            blocks = []
            assert _wait(lambda: (blocks.extend(dyno.read_available()[0]) or True) and sim.sent >= 300, 10.0)
            time.sleep(0.05)
            blocks.extend(dyno.read_available()[0])
            stats = dyno.stats
    received = sum(b.counter.size for b in blocks)
    assert stats.gaps > 0 and stats.lost_samples > 0
    assert stats.crc_errors > 0 and stats.malformed_frames > 0 and stats.garbage_bytes > 0
    assert received + stats.lost_samples >= sim.sent - 5  # every sample is either received or counted lost
