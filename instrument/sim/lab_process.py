"""The simulated lab as its own process (``instrument simulate-lab``): a lab file's devices to try before the
hardware arrives, reached exactly as real ones are.

* the dynamometer: the CiA 402 servo drive (:mod:`drivers.dynamometer.cia402_simulator`) behind an slcan
  USB–CAN adapter on a pseudo-terminal (:mod:`drivers.simulation.slcan_pty`): ``canopen://slcan//dev/pts/N``;
* the torque sensor: Modbus RTU over TCP; the force plate: its serial framing over TCP;
* with ``streams``, a Delsys-like goniometer and EMG as LSL senders (:mod:`drivers.simulation.lsl_outlets`).

It writes the lab file that names them (``instrument devices --lab``, ``record --lab``, ``gui --lab`` in
another terminal use it) and serves until interrupted or for ``seconds``.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from pathlib import Path

from drivers.simulation.lab import SimulatedLab
from drivers.simulation.lsl_outlets import SimulatedLslSender, emg, goniometer
from drivers.simulation.slcan_pty import SlcanPtyBridge
from drivers.url import DeviceUrl

from ..kinds.base import TrialProtocol
from .simulate import lab_config_for


def lab_file_text(urls: dict[str, str], streams: dict[str, str]) -> str:
    """A lab file (TOML) naming ``urls`` (device kind → URL) and ``streams`` (name → lsl:// URL)."""
    lines = ["# written by `instrument simulate-lab`: the simulated lab's devices, reached as real ones", "[devices]"]
    lines += [f'{kind} = "{url}"' for kind, url in urls.items()]
    if streams:
        lines += ["", "[streams]"] + [f'{name} = "{url}"' for name, url in streams.items()]
    return "\n".join(lines) + "\n"


def serve_lab(protocol: TrialProtocol, lab_file: Path, *, seconds: float | None = None, streams: bool = True,
              seed: int = 0, stop: threading.Event | None = None, say: Callable[[str], None] = print) -> None:
    """Run the simulated lab for ``protocol``'s subject and rig until ``stop`` is set, ``seconds`` pass or the
    process is interrupted; ``lab_file`` is written once every device listens."""
    stop = stop or threading.Event()
    lab = SimulatedLab(lab_config_for(protocol, seed=seed))
    channel = DeviceUrl.parse(lab.urls["dynamometer"]).path.lstrip("/")
    bridge = SlcanPtyBridge(channel)
    senders: list[SimulatedLslSender] = []
    try:
        tag = f"simlab-{os.getpid()}"
        stream_urls: dict[str, str] = {}
        if streams:
            leg = lab.config.leg  # the goniometer reads the seated subject's actual hip and knee
            senders = [goniometer(f"{tag}-goniometer", hip_deg=leg.hip_flexion_deg, knee_deg=leg.knee_flexion_deg,
                                  seed=seed), emg(f"{tag}-emg", seed=seed)]
            stream_urls = {"goniometer": f"lsl://?source_id={tag}-goniometer", "emg": f"lsl://?source_id={tag}-emg"}
        rate = lab.config.telemetry_rate_hz
        urls = {"dynamometer": f"canopen://slcan/{bridge.path}?rate={rate}",
                "force_plate": lab.urls["force_plate"], "torque_sensor": lab.urls["torque_sensor"]}
        lab_file.parent.mkdir(parents=True, exist_ok=True)
        tmp = lab_file.with_suffix(".part")
        tmp.write_text(lab_file_text(urls, stream_urls), encoding="utf-8")
        tmp.replace(lab_file)  # appears whole: a watcher never reads half a lab file
        say(f"simulated lab serving ({protocol.name} rig): dynamometer CiA 402 via slcan on {bridge.path}, "
            f"force plate {urls['force_plate']}, torque sensor {urls['torque_sensor']}"
            + (", LSL goniometer and EMG" if senders else ""))
        say(f"lab file: {lab_file}   (instrument devices --lab {lab_file}; Ctrl-C stops the lab)")
        deadline = time.monotonic() + seconds if seconds is not None else None
        while not stop.wait(0.2):
            if deadline is not None and time.monotonic() >= deadline:
                break
    finally:
        for s in senders:
            s.close()
        bridge.close()
        lab.close()
