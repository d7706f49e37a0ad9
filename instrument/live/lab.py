"""The lab file: which devices a lab has (by URL), the subject's safety envelope, and a probe of what answers.

A lab file is TOML, read by the command line (``instrument devices --lab``, ``instrument record
--lab``) and the operator window alike::

    [devices]                       # device kind = URL (see docs/hardware.md for the back ends)
    dynamometer = "socketcan://can0?rate=100"
    torque_sensor = "rtu:///dev/ttyUSB0?baud=115200"
    force_plate = "serial:///dev/ttyACM0?rate=1000"

    [limits]                        # the subject's envelope: the driver refuses commands outside it,
    rom_deg = [-35.0, 95.0]         # the live checks stop the arm on a breach
    max_speed_deg_s = 30.0
    max_torque_nm = 150.0

    [probe]
    seconds = 1.0                   # how long each device must stream to count as answering

    [lsl]
    publish = true                  # every device stream as a Lab Streaming Layer outlet (LabRecorder)

    [streams]                       # other systems' LSL streams recorded into every trial (name = lsl://...)
    emg = "lsl://?type=EMG"         # an EMG stream (type EMG) adds its envelope to the live relaxation check
    goniometer = "lsl://?name=Goniometer"  # a channel labelled hip_flexion gives the pmp fit the measured hip

Nothing in it names a subject. Units are in the keys; the envelope may only narrow the driver's
own defaults.
"""

from __future__ import annotations

import math
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from drivers import DEVICE_OPENERS, DriverError, DynamometerLimits, StreamingDevice, open_device
from drivers.dynamometer import SUBJECT_ENVELOPE_DEG, SUBJECT_MAX_SPEED_DEG_S, SUBJECT_MAX_TORQUE_NM
from drivers.lsl import open_lsl_stream

from ..errors import InstrumentError
from .monitors import SafetyLimits

#: how long a probed device must stream (s), unless the lab file says otherwise
PROBE_SECONDS = 1.0


class LabFileError(InstrumentError):
    """The lab file cannot be read or says something the instrument cannot do (names the file and the key)."""


@dataclass(frozen=True)
class LabFile:
    """A lab's devices by URL and the subject's safety envelope (degrees at this edge, as operators set them)."""

    path: Path
    devices: dict[str, str]
    limits: SafetyLimits = field(default_factory=SafetyLimits)
    probe_seconds: float = PROBE_SECONDS
    #: publish every device stream as a Lab Streaming Layer outlet (``[lsl] publish = true``)
    lsl_publish: bool = False
    #: other systems' LSL streams recorded beside the devices (``[streams]`` name = ``lsl://...``)
    streams: dict[str, str] = field(default_factory=dict)

    @classmethod
    def load(cls, path: str | Path) -> LabFile:
        """Read a lab file.

        :raises LabFileError: unreadable, not TOML, an unknown device kind, a URL that is not a
            string, or an envelope wider than the driver's (named in one line).
        """
        p = Path(path)
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except OSError as err:
            raise LabFileError(f"{p}: cannot read the lab file: {err.strerror or err}") from err
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
            raise LabFileError(f"{p}: not a TOML lab file: {err}") from err
        devices = data.get("devices")
        if not isinstance(devices, dict) or not devices:
            raise LabFileError(f"{p}: no [devices] table (device kind = URL)")
        for kind, url in devices.items():
            if kind not in DEVICE_OPENERS:
                raise LabFileError(f"{p}: [devices] {kind}: no such device kind; one of {', '.join(DEVICE_OPENERS)}")
            if not isinstance(url, str) or "://" not in url:
                raise LabFileError(f"{p}: [devices] {kind}: {url!r} is not a device URL (scheme://...)")
        limits = data.get("limits", {})
        try:
            rom = tuple(float(v) for v in limits.get("rom_deg", SUBJECT_ENVELOPE_DEG))
            speed = float(limits.get("max_speed_deg_s", SUBJECT_MAX_SPEED_DEG_S))
            torque = float(limits.get("max_torque_nm", SUBJECT_MAX_TORQUE_NM))
            seconds = float(data.get("probe", {}).get("seconds", PROBE_SECONDS))
        except (TypeError, ValueError, AttributeError) as err:
            raise LabFileError(f"{p}: [limits] must hold numbers (rom_deg = [low, high], max_speed_deg_s, "
                               f"max_torque_nm): {err}") from err
        if len(rom) != 2 or not all(math.isfinite(v) for v in (*rom, speed, torque, seconds)):
            raise LabFileError(f"{p}: [limits] rom_deg must be [low, high] and every limit finite")
        lo, hi = SUBJECT_ENVELOPE_DEG
        if not (lo <= rom[0] < rom[1] <= hi and 0 < speed <= SUBJECT_MAX_SPEED_DEG_S
                and 0 < torque <= SUBJECT_MAX_TORQUE_NM and seconds > 0):
            raise LabFileError(f"{p}: [limits] may only narrow the subject's envelope (range {lo:g}..{hi:g}°, "
                               f"speed ≤ {SUBJECT_MAX_SPEED_DEG_S:g}°/s, torque ≤ {SUBJECT_MAX_TORQUE_NM:g} N·m)")
        lsl = data.get("lsl", {})
        if not isinstance(lsl, dict) or not isinstance(lsl.get("publish", False), bool):
            raise LabFileError(f"{p}: [lsl] publish must be true or false")
        streams = data.get("streams", {})
        if not isinstance(streams, dict):
            raise LabFileError(f"{p}: [streams] must be a table (name = \"lsl://?type=...\")")
        for name, url in streams.items():
            if name in DEVICE_OPENERS or not str(name).isidentifier():
                raise LabFileError(f"{p}: [streams] {name}: a stream's name must be a word that is not a device kind")
            if not isinstance(url, str) or not url.startswith("lsl://"):
                raise LabFileError(f"{p}: [streams] {name}: {url!r} is not an LSL stream URL (lsl://?type=... or ?name=...)")
        return cls(p, {str(k): str(v) for k, v in devices.items()},
                   SafetyLimits((rom[0], rom[1]), speed, torque), seconds, bool(lsl.get("publish", False)),
                   {str(k): str(v) for k, v in streams.items()})

    def driver_limits(self) -> DynamometerLimits:
        """The envelope as the dynamometer driver enforces it (it refuses any command outside)."""
        lim = self.limits
        return DynamometerLimits.from_degrees(lim.rom_deg[0], lim.rom_deg[1], lim.max_speed_deg_s, lim.max_torque_nm)

    def open(self, kind: str) -> StreamingDevice:
        """The (unopened) driver of the lab's ``kind`` device, the dynamometer with the lab's envelope.

        :raises LabFileError: the lab file has no such device.
        """
        if kind in self.streams:
            return open_lsl_stream(self.streams[kind], name=kind)
        if kind not in self.devices:
            raise LabFileError(f"{self.path}: no {kind} in [devices] (the trial needs it)")
        extra: dict[str, Any] = {"limits": self.driver_limits()} if kind == "dynamometer" else {}
        return open_device(kind, self.devices[kind], **extra)


@dataclass(frozen=True)
class DeviceProbe:
    """What one device did when probed: answered (streamed at least one sample), how, and why not."""

    kind: str
    url: str
    answered: bool
    samples: int = 0
    rate_hz: float = float("nan")
    identity: dict[str, Any] = field(default_factory=dict)
    problem: str = ""

    def line(self) -> str:
        """One line for the operator: ``<device> <url> answers ...`` or ``... NO ANSWER: why``."""
        if not self.answered:
            return f"{self.kind:<14} {self.url}  NO ANSWER: {self.problem}"
        what = self.identity.get("protocol") or self.identity.get("model") or ""
        if self.identity.get("labels"):  # another system's stream: what it is and which channels
            what += (f" {self.identity.get('stream_type', '')} '{self.identity.get('stream_name', '')}': "
                     + ", ".join(f"{lab} ({unit})" if unit else lab
                                 for lab, unit in zip(self.identity["labels"], self.identity.get("units", []))))
        limits = self.identity.get("limits")
        lim = (f", limits ROM {math.degrees(limits['rom_min_rad']):.0f}..{math.degrees(limits['rom_max_rad']):.0f}°"
               f" speed ≤ {math.degrees(limits['max_speed_rad_s']):.0f}°/s torque ≤ {limits['max_torque_nm']:.0f} N·m"
               if isinstance(limits, dict) and "rom_min_rad" in limits else "")
        return (f"{self.kind:<14} {self.url}  answers: {self.samples} samples, {self.rate_hz:.1f} Hz"
                + (f", {what}" if what else "") + lim)


def probe(lab: LabFile, kinds: list[str] | None = None) -> list[DeviceProbe]:
    """Open each of the lab's devices (or those of ``kinds``), stream for ``lab.probe_seconds`` and close it.

    A device answers when it opens and streams at least one sample; the dynamometer must also
    report the lab's envelope back as its limits. Nothing is commanded to move.
    """
    out = []
    for kind in kinds or [*lab.devices, *lab.streams]:
        url = lab.devices.get(kind, "") or lab.streams.get(kind, "")
        if not url:
            out.append(DeviceProbe(kind, "(none)", False, problem="not in the lab file's [devices] or [streams]"))
            continue
        try:
            dev = lab.open(kind)
        except (DriverError, LabFileError, OSError, ValueError) as err:
            out.append(DeviceProbe(kind, url, False, problem=_one_line(err)))
            continue
        try:
            dev.open()
            dev.start()
            deadline = time.monotonic() + lab.probe_seconds
            samples, first, last = 0, None, None
            while time.monotonic() < deadline:
                blocks, errors = dev.read_available()
                if errors:
                    raise errors[0]
                for b in blocks:
                    n = len(b.time_s)
                    if n:
                        samples += n
                        first = float(b.time_s[0]) if first is None else first
                        last = float(b.time_s[-1])
                time.sleep(0.02)
            identity = dict(dev.identity() or {})
            if samples == 0:
                out.append(DeviceProbe(kind, url, False, identity=identity,
                                       problem=f"opened but sent no sample in {lab.probe_seconds:g} s"))
                continue
            rate = (samples - 1) / (last - first) if first is not None and last is not None and last > first else float("nan")
            problem = _limits_differ(lab, identity) if kind == "dynamometer" else ""
            out.append(DeviceProbe(kind, url, not problem, samples, rate, identity, problem))
        except (DriverError, OSError, ValueError) as err:
            out.append(DeviceProbe(kind, url, False, problem=_one_line(err)))
        finally:
            try:
                dev.close()
            except (DriverError, OSError):
                pass
    return out


def _limits_differ(lab: LabFile, identity: dict[str, Any]) -> str:
    """Why the dynamometer's reported limits are not the lab's envelope ("" when they are)."""
    reported = identity.get("limits")
    if not isinstance(reported, dict):
        return "the dynamometer does not report its limits: they cannot be read back"
    wanted = lab.driver_limits().as_dict()
    # a drive holds its limits in its own units: equal within half a step of the coarsest wire in use
    # (0.001° and 0.001 °/s of a CiA 402 drive, 0.01 N·m of its per-mille torque)
    tolerance = {"max_torque_nm": 0.01}
    off = [k for k, v in wanted.items() if not math.isclose(float(reported.get(k, float("nan"))), v, rel_tol=1e-9,
                                                            abs_tol=tolerance.get(k, 1e-5))]
    return f"limits read back differ from the lab file's: {', '.join(off)}" if off else ""


def _one_line(err: BaseException) -> str:
    text = str(err).strip()
    return text.splitlines()[0] if text else type(err).__name__


__all__ = ["PROBE_SECONDS", "DeviceProbe", "LabFile", "LabFileError", "probe"]
