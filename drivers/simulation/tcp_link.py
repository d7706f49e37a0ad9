"""A loopback TCP port standing in for a serial cable (the device end), with vanishing on demand.

pyserial opens the other end as ``socket://127.0.0.1:PORT``. The device can "vanish" (close the
client and stop listening) and come back on the same port, which is how simulators test a
driver's reconnection.
"""

from __future__ import annotations

import select
import socket
import threading


class TcpDeviceLink:
    """Listening socket on 127.0.0.1 serving one client at a time.

    :param port: TCP port; 0 picks a free one (read it back from :attr:`port`).
    """

    def __init__(self, port: int = 0, host: str = "127.0.0.1") -> None:
        self.host = host
        self._listener: socket.socket | None = None
        self.client: socket.socket | None = None
        self.port = port
        self._lock = threading.Lock()
        self.listen()

    @property
    def url(self) -> str:
        """pyserial URL of the driver's end."""
        return f"socket://{self.host}:{self.port}"

    def listen(self) -> None:
        """(Re)open the listening socket on the same port."""
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        s.bind((self.host, self.port))
        s.listen(1)
        s.setblocking(False)
        self.port = s.getsockname()[1]
        self._listener = s

    def accept(self, timeout_s: float) -> bool:
        """Wait up to ``timeout_s`` for a client; True when one is connected."""
        if self.client is not None:
            return True
        if self._listener is None:
            return False
        ready, _, _ = select.select([self._listener], [], [], timeout_s)
        if not ready:
            return False
        try:
            conn, _ = self._listener.accept()
        except BlockingIOError:
            return False
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        conn.setblocking(False)
        self.client = conn
        return True

    def recv(self, timeout_s: float) -> bytes | None:
        """Bytes from the client (b"" if none in ``timeout_s``); None if the client left."""
        if self.client is None:
            return None
        ready, _, _ = select.select([self.client], [], [], timeout_s)
        if not ready:
            return b""
        try:
            data = self.client.recv(65536)
        except (BlockingIOError, InterruptedError):
            return b""
        except OSError:
            data = b""
        if not data:
            self.drop_client()
            return None
        return data

    def send(self, data: bytes) -> bool:
        """Send all of ``data``; False if the client is gone."""
        if self.client is None or not data:
            return self.client is not None
        try:
            self.client.setblocking(True)
            self.client.sendall(data)
            self.client.setblocking(False)
            return True
        except OSError:
            self.drop_client()
            return False

    def drop_client(self) -> None:
        if self.client is not None:
            try:
                self.client.close()
            finally:
                self.client = None

    def vanish(self) -> None:
        """The device disappears: client dropped and the port stops accepting."""
        self.drop_client()
        if self._listener is not None:
            self._listener.close()
            self._listener = None

    def close(self) -> None:
        self.vanish()
