"""``expected_protocol`` for byte-stream devices (after pymeasure): a scripted peer on a TCP port.

The peer expects each request's exact bytes in order and answers with the scripted reply.
A mismatch, a missing request or leftover bytes fail the test.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator
from contextlib import contextmanager


class ScriptedPeer:
    def __init__(self, pairs: list[tuple[bytes, bytes]], linger_s: float = 0.2) -> None:
        self.pairs = list(pairs)
        self.linger_s = linger_s
        self.received: list[bytes] = []
        self.errors: list[str] = []
        self.leftover = b""
        self._srv = socket.socket()
        self._srv.bind(("127.0.0.1", 0))
        self._srv.listen(1)
        self.port = self._srv.getsockname()[1]
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        conn, _ = self._srv.accept()
        conn.settimeout(2.0)
        buf = b""
        try:
            for expected, reply in self.pairs:
                while len(buf) < len(expected):
                    chunk = conn.recv(4096)
                    if not chunk:
                        self.errors.append(f"connection closed while expecting {expected.hex()}")
                        return
                    buf += chunk
                got, buf = buf[: len(expected)], buf[len(expected):]
                self.received.append(got)
                if got != expected:
                    self.errors.append(f"expected {expected.hex()}, got {got.hex()}")
                    return
                conn.sendall(reply)
            conn.settimeout(self.linger_s)
            try:
                buf += conn.recv(4096)
            except (TimeoutError, OSError):
                pass
            self.leftover = buf
        except (TimeoutError, OSError) as err:
            self.errors.append(f"peer: {err!r} after {len(self.received)} requests")
        finally:
            conn.close()

    def check(self) -> None:
        self._thread.join(3.0)
        assert not self.errors, self.errors
        assert len(self.received) == len(self.pairs), f"only {len(self.received)}/{len(self.pairs)} requests sent"


@contextmanager
def expected_protocol(pairs: list[tuple[bytes, bytes]], linger_s: float = 0.2) -> Iterator[ScriptedPeer]:
    """A scripted peer; after the last reply it keeps the line open ``linger_s`` s (a silent device)."""
    peer = ScriptedPeer(pairs, linger_s)
    try:
        yield peer
    finally:
        peer._srv.close()
    peer.check()
