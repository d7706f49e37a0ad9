"""A USB–CAN adapter as the host sees one: the Lawicel/slcan ASCII protocol on a pseudo-terminal, bridged
to a python-can bus of this process (the simulated drive's virtual bus).

The host opens the pty's path as python-can's ``slcan`` interface (``canopen://slcan//dev/pts/N``), as it
would a CANable or a Lawicel adapter at ``/dev/ttyACM0``: ``C``, ``S<n>``, ``O`` and the like are answered
with CR, ``V`` with a version; ``tIIIL<data>`` and ``TIIIIIIIIL<data>`` lines become frames on the bus, and
every frame on the bus goes out as such a line. Error frames are not forwarded (an slcan adapter reports
bus errors by status flags, which python-can does not read).
"""

from __future__ import annotations

import os
import select
import threading
import tty

import can


def encode(msg: can.Message) -> bytes:
    """One frame as an slcan line (CR-terminated)."""
    data = bytes(msg.data)
    head = f"T{msg.arbitration_id:08X}" if msg.is_extended_id else f"t{msg.arbitration_id:03X}"
    return f"{head}{len(data)}{data.hex().upper()}\r".encode()


def decode(line: bytes) -> can.Message | None:
    """A ``t``/``T`` line as a frame; None for anything else (a command, or a malformed line)."""
    text = line.decode("ascii", "replace")
    try:
        if text[:1] == "t" and len(text) >= 5:
            ident, dlc, payload = int(text[1:4], 16), int(text[4]), text[5:]
            extended = False
        elif text[:1] == "T" and len(text) >= 10:
            ident, dlc, payload = int(text[1:9], 16), int(text[9]), text[10:]
            extended = True
        else:
            return None
        data = bytes.fromhex(payload[: 2 * dlc])
    except ValueError:
        return None
    if len(data) != dlc or dlc > 8:
        return None
    return can.Message(arbitration_id=ident, data=data, is_extended_id=extended)


class SlcanPtyBridge:
    """A pty whose far end speaks slcan, bridged to ``channel`` on the python-can ``interface``."""

    def __init__(self, channel: str, interface: str = "virtual") -> None:
        self.master, self._slave = os.openpty()
        tty.setraw(self._slave)  # no echo, no CR→NL before the host's pyserial opens it
        os.set_blocking(self.master, False)  # a host that stops reading loses frames; the bridge never blocks
        self.path = os.ttyname(self._slave)
        self.bus = can.Bus(interface=interface, channel=channel, receive_own_messages=False)
        self.frames_in = self.frames_out = self.bad_lines = 0
        self._stop = threading.Event()
        self._threads = [threading.Thread(target=self._from_host, name="slcan-in", daemon=True),
                         threading.Thread(target=self._to_host, name="slcan-out", daemon=True)]
        self._open = False  # the host sent O (frames flow only while the channel is open)
        for t in self._threads:
            t.start()

    def _from_host(self) -> None:
        pending = b""
        while not self._stop.is_set():
            ready, _, _ = select.select([self.master], [], [], 0.1)
            if not ready:
                continue
            try:
                pending += os.read(self.master, 4096)
            except OSError:  # no host holds the pty (EIO), or nothing after all: wait
                self._stop.wait(0.05)
                continue
            *lines, pending = pending.split(b"\r")
            for line in lines:
                self._command(line.strip(b"\n"))

    def _command(self, line: bytes) -> None:
        head = line[:1]
        if head in (b"t", b"T"):
            msg = decode(line)
            if msg is None:
                self.bad_lines += 1
                self._write(b"\a")
                return
            if self._open:
                self.bus.send(msg)
                self.frames_in += 1
            self._write(b"z\r" if head == b"t" else b"Z\r")
        elif head == b"O" or head == b"L":
            self._open = True
            self._write(b"\r")
        elif head == b"C":
            self._open = False
            self._write(b"\r")
        elif head == b"V":
            self._write(b"V1013\r")
        elif head == b"N":
            self._write(b"NSIM1\r")
        else:  # S<n> bit rate, s<btr>, Z timestamps, F flags, an empty line: accepted
            self._write(b"\r")

    def _to_host(self) -> None:
        while not self._stop.is_set():
            msg = self.bus.recv(timeout=0.1)
            if msg is None or msg.is_error_frame or not self._open:
                continue
            self._write(encode(msg))
            self.frames_out += 1

    def _write(self, data: bytes) -> None:
        try:
            os.write(self.master, data)
        except OSError:
            pass  # the host closed the pty: its frames are lost, as on a pulled adapter

    def close(self) -> None:
        self._stop.set()
        for t in self._threads:
            t.join(1.0)
        self.bus.shutdown()
        for fd in (self.master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass
