"""The writer's lock on a trial file: how recovery tells a live writer from a dead one."""

from __future__ import annotations

import fcntl
import os
import socket
from pathlib import Path

from ..errors import StoreError


class TrialLock:
    """An exclusive ``flock`` on ``TRIAL.h5.lock`` for as long as a trial is being written.

    Any process that opens the store respects it, whatever its host or PID namespace: the kernel
    (or NFS's lock manager) releases it when the writer ends, however it ends, so a free lock on
    a trial still marked ``recording`` means its writer is gone.
    """

    def __init__(self, data_path: Path) -> None:
        self.path = TrialLock.path_for(data_path)
        self._fd: int | None = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(self._fd)
            self._fd = None
            raise StoreError(f"{self.path}: trial file is locked by another writer: {err}") from err
        os.write(self._fd, f"{socket.gethostname()} {os.getpid()}\n".encode())

    @staticmethod
    def path_for(data_path: Path) -> Path:
        return data_path.with_name(data_path.name + ".lock")

    def release(self) -> None:
        """Unlock and remove the lock file (the trial is complete)."""
        if self._fd is None:
            return
        self.path.unlink(missing_ok=True)
        fcntl.flock(self._fd, fcntl.LOCK_UN)
        os.close(self._fd)
        self._fd = None

    @staticmethod
    def held(data_path: Path) -> bool | None:
        """True while a writer holds the trial's lock, False when the lock is free, None when the
        trial has no lock file (written before writer locks existed)."""
        lock = TrialLock.path_for(data_path)
        try:
            fd = os.open(lock, os.O_RDONLY)
        except FileNotFoundError:
            return None
        except OSError:
            return True  # cannot tell: never take a file from a writer that may be alive
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        except OSError:
            return True
        else:
            fcntl.flock(fd, fcntl.LOCK_UN)
            return False
        finally:
            os.close(fd)

    @staticmethod
    def remove_stale(data_path: Path) -> None:
        TrialLock.path_for(data_path).unlink(missing_ok=True)


def pid_alive(pid: int | None) -> bool:
    if not pid:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    # a zombie (killed child not yet reaped) is not a writer
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return True


__all__ = ["TrialLock", "pid_alive"]
