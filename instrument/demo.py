"""``instrument demo``: the simulated lab, streamed through the real drivers (no hardware)."""

from __future__ import annotations

import json
import math
import threading
from pathlib import Path
from typing import Any

import numpy as np

from drivers import open_dynamometer, open_force_plate, open_torque_sensor
from drivers.dynamometer import protocol as dyn_protocol
from drivers.forceplate import protocol as fp_protocol
from drivers.simulation.faults import FaultConfig
from drivers.simulation.lab import LabConfig, SimulatedLab
from drivers.torque import registers

from .stream import StreamResult, stream_devices


def _wire_limit_hz(name: str, lab: SimulatedLab) -> float:
    if name == "force_plate":
        return fp_protocol.max_sample_rate_hz(921600)
    if name == "dynamometer":
        return dyn_protocol.max_frame_rate_hz()
    return registers.max_poll_rate_hz(lab.config.torque_baud)


def run_streams(seconds: float, config: LabConfig | None = None) -> tuple[dict[str, StreamResult], SimulatedLab]:
    """Stream all three devices for ``seconds``; the dynamometer runs a 5°/s knee flexion meanwhile."""
    lab = SimulatedLab(config)
    try:
        devices = {
            "force_plate": open_force_plate(lab.urls["force_plate"]),
            "dynamometer": open_dynamometer(lab.urls["dynamometer"]),
            "torque_sensor": open_torque_sensor(lab.urls["torque_sensor"]),
        }
        dyno = devices["dynamometer"]
        dyno.open()
        dyno.set_passive_isokinetic(math.radians(5.0))
        dyno.set_range_of_motion(0.0, math.radians(90.0))

        def move() -> None:
            dyno.move_to(math.radians(90.0))

        threading.Timer(0.3, move).start()
        results = stream_devices(devices, seconds)
        for dev in devices.values():
            dev.close()
    finally:
        lab.close()
    return results, lab


def _row(name: str, res: StreamResult, lab: SimulatedLab) -> dict[str, Any]:
    st = res.stats
    rate = float(st["rate_hz"])  # type: ignore[arg-type]
    return {"device": name, "samples": res.samples, "rate_hz": rate, "gaps": st["gaps"],
            "lost_samples": st["lost_samples"], "crc_errors": st["crc_errors"],
            "malformed_frames": st["malformed_frames"], "errors_reported": len(res.errors),
            "wire_limit_ratio": rate / _wire_limit_hz(name, lab) if math.isfinite(rate) else float("nan")}


def _print_table(rows: list[dict[str, Any]], title: str) -> None:
    print(f"\n{title}")
    print(f"{'device':<14}{'samples':>9}{'rate Hz':>10}{'gaps':>6}{'lost':>7}{'CRC err':>9}{'malformed':>11}{'wire use':>10}")
    for r in rows:
        print(f"{r['device']:<14}{r['samples']:>9}{r['rate_hz']:>10.1f}{r['gaps']:>6}{r['lost_samples']:>7}"
              f"{r['crc_errors']:>9}{r['malformed_frames']:>11}{r['wire_limit_ratio']:>10.3f}")


def physics_summary(results: dict[str, StreamResult]) -> dict[str, float]:
    fp, dy, tq = results["force_plate"], results["dynamometer"], results["torque_sensor"]
    fz = fp.channel("force_n")[:, 2] if fp.samples else np.zeros(1)
    pos = np.rad2deg(dy.channel("position_rad")) if dy.samples else np.zeros(1)
    return {
        "plate_fz_min_n": float(fz.min()), "plate_fz_max_n": float(fz.max()),
        "dyno_position_end_deg": float(pos[-1]),
        "dyno_torque_range_nm": float(np.ptp(dy.channel("torque_nm"))) if dy.samples else float("nan"),
        "torque_sensor_mean_nm": float(tq.channel("torque_nm").mean()) if tq.samples else float("nan"),
    }


def lab_day(out: Path, quick: bool) -> tuple[list[dict[str, Any]], bool]:
    """Record the simulated lab day into ``out/store`` and export one trial of each kind."""
    from .export import export_trial
    from .lab_day import record_lab_day, summary_rows
    from .recording import read_trial

    store_dir = out / "store"
    if (store_dir / "store.sqlite").exists():
        (store_dir / "store.sqlite").unlink()
    print(f"\nRecording a simulated lab day into {store_dir} (AADS 3 springs, knee hip 90/55/15°, "
          f"ankle knee 0/45/90°, replica leg; rooms in parallel) ...")
    store, outcomes = record_lab_day(store_dir, quick=quick)
    rows = summary_rows(store)
    print(f"{'trial':>5} {'protocol':<8} {'status':<10} {'samples':<42} condition")
    for r in rows:
        samples = " ".join(f"{n}={c}" for n, c in r["samples"].items())
        print(f"{r['trial']:>5} {r['protocol']:<8} {r['status']:<10} {samples:<42} {r['condition']}")
    exports = out / "exports"
    exports.mkdir(exist_ok=True)
    done = set()
    for t in store.trials():
        if t.protocol in done:
            continue
        done.add(t.protocol)
        trial = read_trial(t.path)
        fmt = "c3d" if t.protocol == "aads" else "csv"
        files = export_trial(trial, fmt, exports / f"trial{t.id}-{t.protocol}.{fmt}", store.subject(t.subject_code).as_dict())
        print(f"  exported trial {t.id} ({t.protocol}) -> {files[0]}")
    ok = all(r["status"] == "recorded" and not any(r["lost"].values()) for r in rows)
    store.close()
    return rows, ok


def main(seconds: float = 4.0, out: Path | None = None, faults: bool = True, quick: bool = True) -> int:
    """Run the demo; returns a process exit code (0 when every device streamed cleanly)."""
    print(f"Simulated lab: force plate (serial framing over TCP), dynamometer (CAN, virtual bus), "
          f"torque sensor (Modbus RTU, {LabConfig().torque_baud} baud emulated); {seconds:.0f} s each run.")
    clean, lab = run_streams(seconds)
    rows = [_row(n, r, lab) for n, r in clean.items()]
    _print_table(rows, "Clean links (every sample should arrive):")
    phys = physics_summary(clean)
    print(f"  plate Fz {phys['plate_fz_min_n']:.1f}..{phys['plate_fz_max_n']:.1f} N while the operator bends the AFO; "
          f"dynamometer at {phys['dyno_position_end_deg']:.1f}° after {seconds:.0f} s of a 5°/s knee flexion "
          f"(torque range {phys['dyno_torque_range_nm']:.2f} N·m); replica-leg torque {phys['torque_sensor_mean_nm']:.2f} N·m")
    report: dict[str, Any] = {"clean": rows, "physics": phys}
    ok = all(r["lost_samples"] == 0 and r["crc_errors"] == 0 for r in rows)
    if faults:
        bad = FaultConfig(drop_rate=0.01, corrupt_rate=0.01, garbage_rate=0.01, truncate_rate=0.005)
        drill, lab = run_streams(seconds, LabConfig(plate_faults=bad, dyno_faults=bad, torque_faults=bad, seed=1))
        frows = [_row(n, r, lab) for n, r in drill.items()]
        _print_table(frows, "Fault drill (1% dropped, 1% corrupted, 1% garbage, 0.5% truncated frames):")
        print("  every bad frame is counted and skipped; lost samples are gaps in the device counter.")
        report["fault_drill"] = frows
        ok = ok and all(r["samples"] > 0 for r in frows)
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        report["lab_day"], day_ok = lab_day(out, quick)
        ok = ok and day_ok
        (out / "demo.json").write_text(json.dumps(report, indent=2, default=float))
        print(f"\nwrote {out / 'demo.json'}")
    return 0 if ok else 1
