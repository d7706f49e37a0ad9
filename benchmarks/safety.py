"""Stop paths: how far the arm travels, and how long it takes to halt, after each way a trial ends.

Each run is a knee sweep 0→60° at 20 °/s through a real dynamometer driver, the Qt-free trial runner
and the simulated dynamometer, on both wires: the CiA 402 servo drive over CANopen (``cia402``: the
e-stop a quick-stop controlword, the watchdog the drive's heartbeat consumer, the device ROM its software
position limits) and the project's CAN frame set (``frames``). One second into the sweep the trial is
ended by one path:

* ``operator_stop``: the operator's Stop (the protocol's shutdown halts the arm by command);
* ``emergency_stop``: the e-stop frame;
* ``estop_one_frame_lost``: the first e-stop frame never arrives (re-sent after two periods);
* ``estop_never_arrives``: no e-stop frame arrives (halt by command, heartbeat withdrawn, alarm);
* ``limit_breach``: the runner's envelope is narrowed below the arm (the stream breaches it);
* ``device_rom``: the device's own ROM is narrowed mid-move (the device stops itself);
* ``lost_host``: the host heartbeat stops (the device's watchdog; the "command" is the last
  heartbeat, so its travel includes the watchdog timeout).

From the recorded telemetry (host clock): the position at the command time (interpolated), the
first sample after it with zero velocity (the halt), the travel between them (°) and the time
(ms, and in telemetry periods). Target: ≤ 1 telemetry period and ≤ 0.5° at 20 °/s.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from drivers.dynamometer.cia402 import HEARTBEAT_CONSUMER_S
from drivers.dynamometer.protocol import WATCHDOG_TIMEOUT_S
from instrument.kinds.knee import KneeProtocol
from instrument.live.recording import read_trial
from instrument.live.runner import SafetyLimits, TrialRunner
from instrument.sim.source import SimulatedSource
from instrument.store import SessionStore, Subject

SPEED_DEG_S = 20.0
END_DEG = 60.0
TELEMETRY_PERIOD_S = 0.01


def _operator_stop(runner: TrialRunner, sim: Any, dyno: Any) -> float:
    t = time.monotonic()
    runner.request_stop()
    return t


def _estop(runner: TrialRunner, sim: Any, dyno: Any) -> float:
    t = time.monotonic()
    runner.emergency_stop("benchmark")
    return t


def _estop_lost(frames: int) -> Callable[[TrialRunner, Any, Any], float]:
    def stop(runner: TrialRunner, sim: Any, dyno: Any) -> float:
        sim.lose_estop_frames = frames
        return _estop(runner, sim, dyno)
    return stop


def _limit_breach(runner: TrialRunner, sim: Any, dyno: Any) -> float:
    t = time.monotonic()
    object.__setattr__(runner.limits, "rom_deg", (-5.0, sim.position_deg - 3.0))  # the next block breaches
    return t


def _device_rom(runner: TrialRunner, sim: Any, dyno: Any) -> float:
    t = time.monotonic()
    sim.rom_deg = (sim.rom_deg[0], sim.position_deg + 0.01)
    return t


def _lost_host(runner: TrialRunner, sim: Any, dyno: Any) -> float:
    dyno.suspend_heartbeat(True)
    last = sim.last_heartbeat_s if sim.last_heartbeat_s is not None else time.monotonic()
    deadline = time.monotonic() + 3.0
    while sim.state.name == "MOVING" and time.monotonic() < deadline:
        time.sleep(0.005)
    runner.request_stop()
    return float(last)


PATHS: dict[str, Callable[[TrialRunner, Any, Any], float]] = {
    "operator_stop": _operator_stop, "emergency_stop": _estop, "estop_one_frame_lost": _estop_lost(1),
    "estop_never_arrives": _estop_lost(1000), "limit_breach": _limit_breach, "device_rom": _device_rom,
    "lost_host": _lost_host,
}


def one_run(store: SessionStore, path: str, seed: int, wire: str = "cia402") -> dict[str, float]:
    source = SimulatedSource(seed=seed, dynamometer_protocol=wire)
    proto = KneeProtocol(end_deg=END_DEG, speed_deg_s=SPEED_DEG_S)
    with source.devices(proto) as devices:
        sim = source.lab.dynamometer  # type: ignore[union-attr]  # inside the source's trial the lab is set
        runner = TrialRunner(store, store.new_session("B01"), proto, devices,
                             limits=SafetyLimits(rom_deg=(-5.0, 65.0)))
        runner.start()
        if not runner.sweep_started.wait(20.0):
            raise RuntimeError("sweep did not start")
        time.sleep(1.0)
        command_s = PATHS[path](runner, sim, devices["dynamometer"])
        runner.wait(30.0)
    snap = runner.snapshot()
    if snap.outcome is None:
        raise RuntimeError(f"{path}: trial failed: {snap.error}")
    d = read_trial(store.trial(snap.outcome.trial_id).path).devices["dynamometer"].channels
    t, pos, vel = d["time_s"], np.rad2deg(d["position_rad"]), np.rad2deg(d["velocity_rad_s"])
    after = np.flatnonzero((t >= command_s) & (vel == 0.0))
    if after.size == 0:
        return {"halted": 0.0, "travel_deg": float("nan"), "halt_ms": float("nan")}
    k = int(after[0])
    pos_at_command = float(np.interp(command_s, t, pos))
    return {"halted": 1.0, "travel_deg": abs(float(pos[k]) - pos_at_command),
            "halt_ms": 1000.0 * (float(t[k]) - command_s),
            "unconfirmed_alarm": float(snap.estop_unconfirmed is not None)}


WIRES = ("cia402", "frames")


def run(quick: bool = False) -> dict[str, Any]:
    repeats = 1 if quick else 5
    out: dict[str, Any] = {"speed_deg_s": SPEED_DEG_S, "telemetry_period_ms": 1000 * TELEMETRY_PERIOD_S,
                           "watchdog_timeout_ms": 1000 * WATCHDOG_TIMEOUT_S,
                           "cia402_heartbeat_consumer_ms": 1000 * HEARTBEAT_CONSUMER_S, "repeats": repeats,
                           "wires": {}}
    commanded = [p for p in PATHS if p not in ("lost_host", "estop_never_arrives", "estop_one_frame_lost")]
    with tempfile.TemporaryDirectory() as tmp:
        store = SessionStore(Path(tmp) / "store")
        store.add_subject(Subject("B01", mass_kg=75.0))
        for wire in WIRES:
            paths: dict[str, Any] = {}
            print(f"\n{wire}\n{'path':<22} {'halted':>7} {'travel max °':>13} {'halt max ms':>12} {'periods':>8}")
            for path in PATHS:
                runs = [one_run(store, path, seed, wire) for seed in range(repeats)]
                travel = [r["travel_deg"] for r in runs]
                halt = [r["halt_ms"] for r in runs]
                row = {"halted": int(sum(r["halted"] for r in runs)), "runs": repeats,
                       "travel_deg_max": float(np.nanmax(travel)), "travel_deg_median": float(np.nanmedian(travel)),
                       "halt_ms_max": float(np.nanmax(halt)), "halt_ms_median": float(np.nanmedian(halt)),
                       "halt_periods_max": float(np.nanmax(halt)) / (1000 * TELEMETRY_PERIOD_S),
                       "unconfirmed_alarms": int(sum(r.get("unconfirmed_alarm", 0.0) for r in runs))}
                paths[path] = row
                print(f"{path:<22} {row['halted']:>4}/{repeats:<2} {row['travel_deg_max']:>13.3f} "
                      f"{row['halt_ms_max']:>12.1f} {row['halt_periods_max']:>8.2f}")
            out["wires"][wire] = {
                "paths": paths,
                "commanded_paths_travel_deg_max": max(paths[p]["travel_deg_max"] for p in commanded),
                "commanded_paths_halt_periods_max": max(paths[p]["halt_periods_max"] for p in commanded)}
        store.close()
    # the headline keys are the CiA 402 drive's (the simulated lab's default dynamometer)
    out["paths"] = out["wires"]["cia402"]["paths"]
    out["commanded_paths_travel_deg_max"] = out["wires"]["cia402"]["commanded_paths_travel_deg_max"]
    out["commanded_paths_halt_periods_max"] = out["wires"]["cia402"]["commanded_paths_halt_periods_max"]
    return out
