"""Lab Streaming Layer outlets on the loopback: loss and latency of the dynamometer stream during a sweep.

The instrument's outlet (:class:`instrument.live.lsl.LslPublisher`, the acquisition engine's sink)
and a LabRecorder-like inlet in the same process; a simulated knee sweep streams at 100 Hz for
10 s (3 s with ``--quick``). Measured: samples pushed, received and lost, and the latency from a
sample's device time stamp (the host time its driver gave it, on LSL's clock) to the inlet's pull.
The latency includes the driver's telemetry blocks and the engine's pump, not only LSL's
transport: it is what a receiver sees. Reference in the same run: the pump's own delay, from the
same time stamp to the engine's ring buffer (the latency any live view of the instrument has).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np


def run(quick: bool = False) -> dict[str, Any]:
    import pylsl

    from instrument.kinds.knee import KneeProtocol
    from instrument.live.acquisition import AcquisitionEngine
    from instrument.live.lsl import LslPublisher
    from instrument.sim.simulate import lab_config_for, simulated_devices

    seconds = 3.0 if quick else 10.0
    proto = KneeProtocol(end_deg=10.0, speed_deg_s=10.0)
    session = f"bench-{time.monotonic_ns()}"
    ring_delay: list[float] = []
    with simulated_devices(proto, lab_config_for(proto, seed=2)) as (_, devices):
        engine = AcquisitionEngine(devices)
        engine.open()
        publisher = LslPublisher(devices, session=session)
        engine.sinks.append(publisher)
        engine.sinks.append(lambda name, ch: ring_delay.extend((time.monotonic() - ch["time_s"]).tolist())
                            if name == "dynamometer" else None)
        (info,) = pylsl.resolve_byprop("source_id", f"instrument:{session}:dynamometer", timeout=5.0)
        inlet = pylsl.StreamInlet(info, max_buflen=60, processing_flags=0)
        inlet.open_stream(timeout=5.0)
        engine.start()
        latency: list[float] = []
        received = 0
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            chunk, stamps = inlet.pull_chunk(timeout=0.01)
            now = pylsl.local_clock()
            received += len(chunk)
            latency += [now - s for s in stamps]
        engine.stop()
        deadline = time.monotonic() + 2.0
        while received < publisher.pushed["dynamometer"] and time.monotonic() < deadline:
            chunk, _ = inlet.pull_chunk(timeout=0.1)
            received += len(chunk)
        engine.close()
        publisher.close()
    lat = np.array(latency) * 1e3
    ring = np.array(ring_delay) * 1e3
    out = {"seconds": seconds, "quick": quick, "pushed": publisher.pushed["dynamometer"], "received": received,
           "lost": publisher.pushed["dynamometer"] - received,
           "latency_ms_median": float(np.median(lat)), "latency_ms_p95": float(np.percentile(lat, 95)),
           "latency_ms_max": float(lat.max()),
           "reference_ring_delay_ms_median": float(np.median(ring)),
           "reference_ring_delay_ms_p95": float(np.percentile(ring, 95)),
           "latency_over_ring_delay_median": float(np.median(lat) / max(np.median(ring), 1e-9))}
    print(f"{'quantity':<36}{'value':>12}")
    for k, v in out.items():
        print(f"{k:<36}{v:>12.4g}" if isinstance(v, float) else f"{k:<36}{v!s:>12}")
    return out
