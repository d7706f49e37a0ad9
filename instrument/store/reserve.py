"""Disk ballast: a store keeps a little space it gives back when the disk fills mid-trial."""

from __future__ import annotations

import os
from pathlib import Path

#: bytes of ballast each writable store keeps, released when the disk fills mid-trial
RESERVE_BYTES = 1 << 20


class DiskReserve:
    """A ballast file at ``path`` (``RESERVE_BYTES``), made when a writable store opens."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def ensure(self) -> None:
        """Make the ballast if it is not there (nothing when the disk has too little room to keep it)."""
        if self.path.exists():
            return
        try:
            with open(self.path, "wb") as fh:
                os.posix_fallocate(fh.fileno(), 0, RESERVE_BYTES)
        except OSError:  # too little room to keep a reserve: nothing to give back later
            self.path.unlink(missing_ok=True)

    def release(self) -> bool:
        """Delete the ballast; True if there was one."""
        try:
            self.path.unlink()
            return True
        except FileNotFoundError:
            return False


__all__ = ["RESERVE_BYTES", "DiskReserve"]
