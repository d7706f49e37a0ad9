"""Fault knobs shared by every simulator, and the byte-stream fault injector."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np


@dataclass
class FaultConfig:
    """What a simulated device does wrong. Rates are probabilities per frame (0..1).

    :ivar noise_scale: multiplies the model's nominal sensor noise (0 = noiseless, 1 = nominal).
    :ivar drop_rate: frames the device never sends (the counter still advances: a gap).
    :ivar corrupt_rate: frames sent with one flipped bit (a CRC error on serial links).
    :ivar garbage_rate: random bytes (1..16) inserted before a frame.
    :ivar truncate_rate: frames cut short (the rest never sent).
    :ivar disconnect_after_s: the link vanishes this many seconds after streaming starts (None: never).
    :ivar reconnect_after_s: the device is back this long after it vanished.
    :ivar silence_after_s: the device stops sending (link stays up) after this long (None: never).
    :ivar silence_for_s: how long the silence lasts.
    """

    noise_scale: float = 1.0
    drop_rate: float = 0.0
    corrupt_rate: float = 0.0
    garbage_rate: float = 0.0
    truncate_rate: float = 0.0
    disconnect_after_s: float | None = None
    reconnect_after_s: float = 0.5
    silence_after_s: float | None = None
    silence_for_s: float = 1.5

    def as_dict(self) -> dict[str, object]:
        return asdict(self)

    def vanished_at(self, t_stream: float) -> bool:
        """True while the device is disconnected (``disconnect_after_s`` … + ``reconnect_after_s``)."""
        d = self.disconnect_after_s
        return d is not None and d <= t_stream < d + self.reconnect_after_s

    def silent_at(self, t_s: float) -> bool:
        """True while the scheduled silence is on at stream time ``t_s``."""
        return self.silence_after_s is not None and self.silence_after_s <= t_s < self.silence_after_s + self.silence_for_s


class ByteFaults:
    """Applies a :class:`FaultConfig` to outgoing frames of a byte stream."""

    def __init__(self, config: FaultConfig, seed: int | None = None) -> None:
        self.config = config
        self.rng = np.random.default_rng(seed)
        self.dropped = 0
        self.corrupted = 0
        self.garbage = 0
        self.truncated = 0

    def apply(self, frame: bytes) -> bytes:
        """The bytes that actually go on the wire for ``frame`` (may be empty)."""
        c, rng = self.config, self.rng
        if c.drop_rate and rng.random() < c.drop_rate:
            self.dropped += 1
            return b""
        out = bytearray(frame)
        if c.corrupt_rate and rng.random() < c.corrupt_rate:
            i = int(rng.integers(1, len(out)))
            out[i] ^= 1 << int(rng.integers(0, 8))
            self.corrupted += 1
        if c.truncate_rate and rng.random() < c.truncate_rate:
            out = out[: int(rng.integers(1, len(out)))]
            self.truncated += 1
        if c.garbage_rate and rng.random() < c.garbage_rate:
            junk = rng.integers(0, 256, int(rng.integers(1, 17)), dtype=np.uint8).tobytes()
            out = bytearray(junk) + out
            self.garbage += 1
        return bytes(out)
