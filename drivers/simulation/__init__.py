"""Physics models and wire-level simulators of the lab's devices (the mock back ends).

Each simulator speaks the device's real wire protocol over a mock link (python-can's virtual
bus, a loopback TCP port for serial framing, a pymodbus server behind a baud-rate-throttled
RTU link) and is driven by a physics model, never canned numbers.
"""
