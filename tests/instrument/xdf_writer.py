"""A small XDF writer for the tests, written from the XDF 1.0 specification (github.com/sccn/xdf wiki),
independent of pyxdf and of the importer: magic ``XDF:``, then chunks of [length bytes][length][tag][content]
(tag 1 file header, 2 stream header, 3 samples, 4 clock offset, 6 stream footer)."""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np


@dataclass
class XdfStream:
    name: str
    stream_type: str
    labels: list[str]
    units: list[str]
    rate_hz: float
    time_s: np.ndarray
    values: np.ndarray  # (n, channels)
    manufacturer: str = ""
    source_id: str = ""
    extra_desc: dict[str, str] = field(default_factory=dict)


def _chunk(tag: int, content: bytes) -> bytes:
    body = struct.pack("<H", tag) + content
    return bytes([8]) + struct.pack("<Q", len(body)) + body


def _varlen(n: int) -> bytes:
    return bytes([1, n]) if n < 256 else bytes([4]) + struct.pack("<I", n)


def _header(s: XdfStream) -> bytes:
    chans = "".join(f"<channel><label>{escape(lab)}</label><unit>{escape(u)}</unit></channel>"
                    for lab, u in zip(s.labels, s.units))
    extra = "".join(f"<{k}>{escape(v)}</{k}>" for k, v in s.extra_desc.items())
    manufacturer = f"<manufacturer>{escape(s.manufacturer)}</manufacturer>" if s.manufacturer else ""
    xml = (f'<?xml version="1.0"?><info><name>{escape(s.name)}</name><type>{escape(s.stream_type)}</type>'
           f"<channel_count>{len(s.labels)}</channel_count><nominal_srate>{s.rate_hz}</nominal_srate>"
           f"<channel_format>double64</channel_format><source_id>{escape(s.source_id)}</source_id>"
           f"<created_at>{s.time_s[0] if len(s.time_s) else 0.0}</created_at>"
           f"<desc><channels>{chans}</channels>{manufacturer}{extra}</desc></info>")
    return xml.encode()


def write_xdf(path: Path, streams: list[XdfStream], chunk_samples: int = 200) -> Path:
    out = bytearray(b"XDF:")
    out += _chunk(1, b'<?xml version="1.0"?><info><version>1.0</version></info>')
    for sid, s in enumerate(streams, start=1):
        out += _chunk(2, struct.pack("<I", sid) + _header(s))
    for sid, s in enumerate(streams, start=1):
        t0, t1 = float(s.time_s[0]), float(s.time_s[-1])
        out += _chunk(4, struct.pack("<I", sid) + struct.pack("<dd", t0, 0.0))
        for k in range(0, len(s.time_s), chunk_samples):
            ts, vs = s.time_s[k:k + chunk_samples], s.values[k:k + chunk_samples]
            samples = b"".join(b"\x08" + struct.pack("<d", float(t)) + np.asarray(v, dtype="<f8").tobytes()
                               for t, v in zip(ts, vs))
            out += _chunk(3, struct.pack("<I", sid) + _varlen(len(ts)) + samples)
        out += _chunk(4, struct.pack("<I", sid) + struct.pack("<dd", t1, 0.0))
        footer = (f'<?xml version="1.0"?><info><first_timestamp>{t0}</first_timestamp><last_timestamp>{t1}'
                  f"</last_timestamp><sample_count>{len(s.time_s)}</sample_count></info>")
        out += _chunk(6, struct.pack("<I", sid) + footer.encode())
    path.write_bytes(bytes(out))
    return path
