"""Operator GUI: frame rate and event-loop stalls while all three devices stream; e-stop latency.

Offscreen (``QT_QPA_PLATFORM=offscreen``): the window plots the simulated lab's force plate
(1 kHz), dynamometer (100 Hz) and replica torque sensor (Modbus, polled) from the acquisition
engine's ring buffers on its 30 Hz timer, while motion capture streams too. Measured over the
run: plot refreshes per second (``fps``, against the 30 Hz the timer asks for, in the same
run), and the longest event-loop stall (``max_stall_ms``): the largest lateness of a 1 ms probe
timer, i.e. the longest time the GUI thread could not react. Then, in five short knee trials,
the time from the e-stop call on the GUI thread to the simulated dynamometer latching its
emergency stop (``estop_latency_ms``), against the 10 ms telemetry period.
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")


def _stream_and_measure(seconds: float) -> dict[str, Any]:
    from PySide6 import QtCore, QtWidgets

    from drivers import open_device
    from drivers.simulation.lab import LabConfig, SimulatedLab
    from instrument.gui.window import REFRESH_HZ, MainWindow
    from instrument.live.acquisition import NOMINAL_RATES_HZ, AcquisitionEngine
    from instrument.sim.source import SimulatedSource
    from instrument.store import SessionStore

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    tmp = Path(tempfile.mkdtemp())
    store = SessionStore(tmp / "store")
    lab = SimulatedLab(LabConfig())
    names = ("force_plate", "dynamometer", "torque_sensor", "mocap")
    engine = AcquisitionEngine({n: open_device(n, lab.urls[n]) for n in names},
                               nominal_rates_hz={n: NOMINAL_RATES_HZ[n] for n in names})
    engine.open()
    engine.start()
    window = MainWindow(store, SimulatedSource())
    window.resize(1280, 800)
    window.show()
    window.monitor_engine = engine
    probe = {"last": time.perf_counter(), "max_gap": 0.0, "ticks": 0}

    def tick() -> None:
        now = time.perf_counter()
        if probe["ticks"] > 5:  # past start-up
            probe["max_gap"] = max(probe["max_gap"], now - probe["last"])
        probe["last"] = now
        probe["ticks"] += 1

    timer = QtCore.QTimer()
    timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
    timer.timeout.connect(tick)
    timer.start(1)
    loop = QtCore.QEventLoop()
    QtCore.QTimer.singleShot(int(seconds * 1000), loop.quit)
    window.frames.__init__()  # count from here
    loop.exec()
    timer.stop()
    fps = window.frames.fps()
    samples = {n: engine.reports[n].samples for n in names}
    window.monitor_engine = None
    engine.stop()
    engine.close()
    window.close()
    lab.close()
    store.close()
    app.processEvents()
    return {"fps": fps, "fps_target": REFRESH_HZ, "fps_ratio": fps / REFRESH_HZ,
            "max_stall_ms": probe["max_gap"] * 1e3 - 1.0, "probe_ticks_per_s": probe["ticks"] / seconds,
            "samples_streamed": samples, "stream_seconds": seconds}


def _estop_latency(repeats: int) -> list[float]:
    from drivers.dynamometer.protocol import State
    from instrument.kinds.knee import KneeProtocol
    from instrument.live.runner import TrialRunner
    from instrument.sim.source import SimulatedSource
    from instrument.store import SessionStore, Subject

    tmp = Path(tempfile.mkdtemp())
    store = SessionStore(tmp / "store")
    store.add_subject(Subject("B1", mass_kg=75.0))
    session = store.new_session("B1")
    source = SimulatedSource()
    out = []
    for _ in range(repeats):
        proto = KneeProtocol(end_deg=20.0, speed_deg_s=10.0)
        with source.devices(proto) as devices:
            runner = TrialRunner(store, session, proto, devices)
            runner.start()
            runner.sweep_started.wait(20.0)
            time.sleep(0.3)
            sim = source.lab.dynamometer
            t0 = time.perf_counter()
            runner.emergency_stop("benchmark")
            while sim.state != State.ESTOP and time.perf_counter() - t0 < 1.0:
                time.sleep(0.0002)  # poll without holding the GIL the simulator needs
            out.append((time.perf_counter() - t0) * 1e3)
            runner.wait(10.0)
    store.close()
    return out


def run(quick: bool = False) -> dict[str, Any]:
    seconds = 4.0 if quick else 15.0
    res = _stream_and_measure(seconds)
    lat = _estop_latency(2 if quick else 5)
    res.update({"estop_latency_ms_median": statistics.median(lat), "estop_latency_ms_max": max(lat),
                "telemetry_period_ms": 10.0, "estop_latency_vs_telemetry_period": max(lat) / 10.0, "quick": quick})
    print(f"{'quantity':<36}{'value':>14}")
    for k, v in res.items():
        print(f"{k:<36}{v!s:>14}" if not isinstance(v, float) else f"{k:<36}{v:>14.3f}")
    return res
