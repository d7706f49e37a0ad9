from __future__ import annotations

import numpy as np
import pytest

from drivers import DeviceNotAvailableError, open_dynamometer, open_torque_sensor
from drivers.clock import CounterClock, CounterUnwrapper
from drivers.url import DeviceUrl


def test_unwrapper_crosses_the_wrap() -> None:
    u = CounterUnwrapper(16)
    assert [u.unwrap(c) for c in (65534, 65535, 0, 1)] == [65534, 65535, 65536, 65537]


def test_counter_clock_takes_the_least_delayed_packet() -> None:
    clock = CounterClock(1000.0)
    t1 = clock.stamp(np.arange(0, 10), arrival_s=100.012)  # arrived 3 ms late
    assert t1[-1] == pytest.approx(100.012)
    stamps = [t1]
    for k in range(1, 8):  # later blocks arrive only 0.5 ms late: the offset slews toward them
        stamps.append(clock.stamp(np.arange(10 * k, 10 * k + 10), arrival_s=100.009 + 0.010 * k + 0.0005))
    t = np.concatenate(stamps)
    assert np.all(np.diff(t) > 0), "never backwards"
    assert stamps[-1][-1] == pytest.approx(100.009 + 0.070 + 0.0005, abs=1e-9)


def test_url_parsing() -> None:
    u = DeviceUrl.parse("modbus-rtu:///dev/ttyUSB0?unit=1&baud=115200")
    assert (u.scheme, u.path, u.query) == ("modbus-rtu", "/dev/ttyUSB0", {"unit": "1", "baud": "115200"})
    assert u.take({"unit": int, "baud": int}) == {"unit": 1, "baud": 115200}
    with pytest.raises(ValueError):
        DeviceUrl.parse("no-scheme")


def test_unknown_schemes_are_typed_errors() -> None:
    with pytest.raises(DeviceNotAvailableError):
        open_torque_sensor("modbus-ascii:///dev/ttyUSB0")
    with pytest.raises(DeviceNotAvailableError):
        open_dynamometer("carrier-pigeon://coop")


def test_unreachable_device_is_an_initialisation_error() -> None:
    from drivers import DeviceInitializationError

    sensor = open_torque_sensor("modbus-rtu+socket://127.0.0.1:9?timeout=0.05")
    with pytest.raises(DeviceInitializationError):
        sensor.open()


@pytest.mark.parametrize("url, channel", [
    ("slcan:///dev/ttyACM0", "/dev/ttyACM0"),        # a device path keeps its leading slash
    ("pcan://PCAN_USBBUS1", "PCAN_USBBUS1"),         # channel names keep their case
    ("udp_multicast://239.74.163.2", "239.74.163.2"),  # python-can's own interface names
    ("socketcan://can0?node=16", "can0"),
])
def test_can_urls_reach_python_can_as_written(url: str, channel: str) -> None:
    dyno = open_dynamometer(url)
    assert dyno.channel == channel and dyno.interface == url.split("://")[0]
