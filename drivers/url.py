"""Device URLs, as pyserial's ``serial_for_url`` takes them.

``scheme://[host[:port]][/path]?key=value&...``. The scheme picks the back end from a
per-device-kind table; the rest is handed to it, with the host's case and the path's leading
slash kept (``pcan://PCAN_USBBUS1``, ``slcan:///dev/ttyACM0``). Unknown query keys are an error, so a typo
in a lab's configuration never passes silently.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from urllib.parse import parse_qsl, urlsplit

from .errors import DeviceNotAvailableError


@dataclass(frozen=True)
class DeviceUrl:
    """A parsed device URL."""

    scheme: str
    host: str
    port: int | None
    path: str
    query: dict[str, str] = field(default_factory=dict)
    text: str = ""

    @classmethod
    def parse(cls, url: str) -> DeviceUrl:
        """Parse ``url``; raises ``ValueError`` if it has no scheme."""
        scheme, sep, rest = url.partition("://")
        if not sep or not scheme:
            raise ValueError(f"device URL {url!r} has no scheme (expected e.g. 'virtual://dyno')")
        # the scheme is split off by hand: python-can's interface names (udp_multicast) are not
        # RFC 3986 schemes, and urlsplit would refuse them
        parts = urlsplit("x://" + rest)
        netloc = parts.netloc.rsplit("@", 1)[-1]
        host, port = netloc, None
        if netloc.count(":") == 1 and netloc.rsplit(":", 1)[1].isdigit():
            host, port_text = netloc.rsplit(":", 1)
            port = int(port_text)
        query = dict(parse_qsl(parts.query, keep_blank_values=True))
        return cls(
            scheme=scheme.lower(),
            host=host,  # case kept: PCAN_USBBUS1 is not pcan_usbbus1
            port=port,
            path=parts.path,  # leading slash kept: slcan:///dev/ttyACM0 is /dev/ttyACM0
            query=query,
            text=url,
        )

    def take(self, known: dict[str, type]) -> dict[str, object]:
        """Convert the query to typed options; raises ``ValueError`` on an unknown key."""
        unknown = set(self.query) - set(known)
        if unknown:
            raise ValueError(f"unknown option(s) {sorted(unknown)} in {self.text!r}; known: {sorted(known)}")
        out: dict[str, object] = {}
        for key, value in self.query.items():
            kind = known[key]
            if kind is bool:
                out[key] = value.lower() in ("1", "true", "yes", "on")
            else:
                out[key] = kind(value)
        return out


def load_backend(table: dict[str, tuple[str, str]], url: DeviceUrl, kind: str) -> type:
    """Import the class registered for ``url.scheme`` in ``table`` (lazy import).

    :raises DeviceNotAvailableError: unknown scheme, or the back end's import failed.
    """
    try:
        module_name, class_name = table[url.scheme]
    except KeyError:
        raise DeviceNotAvailableError(
            f"no {kind} back end for scheme {url.scheme!r}; known: {sorted(table)}"
        ) from None
    try:
        module = importlib.import_module(module_name)
    except ImportError as err:
        raise DeviceNotAvailableError(f"{kind} back end {url.scheme!r} cannot be imported: {err}") from err
    return getattr(module, class_name)
