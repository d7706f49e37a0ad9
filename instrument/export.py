"""Export a recorded trial: OpenSim ``.sto``/``.mot``, the trial CSV with its JSON sidecar, and C3D.

Sign conventions are the trial CSV's (:mod:`analysis.trial_csv`). For dynamometer trials the
export is the isokinetic sweep (between the protocol's ``sweep_start`` and ``sweep_end`` marks, narrowed to the arm's movement),
with the dynamometer arm's weight removed from the torque using the arm mass and centre of mass
entered at set-up; for replica-leg trials it is the samples inside each hold, with the hold angle.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from analysis.c3d import write_c3d
from analysis.constants import GRAVITY_M_S2
from analysis.sto import write_sto
from analysis.trial_csv import TrialTable, write_trial_csv

from .errors import RecordingError
from .motion import motion_trial
from .recording import TrialFile

G = GRAVITY_M_S2
FORMATS = ("sto", "csv", "c3d")


class ExportError(RecordingError):
    """The trial cannot be exported in the format asked for."""


def arm_gravity_moment_nm(joint: str, angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float,
                          knee_flexion_deg: float = 0.0) -> np.ndarray:
    """Gravity moment of the dynamometer arm toward positive angles (N·m).

    Knee: the arm is horizontal at 0° flexion and hangs at 90°. Ankle: the footplate's elevation
    above horizontal is dorsiflexion + 90° − knee flexion; gravity plantarflexes.
    """
    th = np.deg2rad(np.asarray(angle_deg, dtype=float))
    if joint == "knee":
        return arm_mass_kg * G * arm_com_m * np.cos(th)
    return -arm_mass_kg * G * arm_com_m * np.cos(th + np.deg2rad(90.0 - knee_flexion_deg))


def _event_time(trial: TrialFile, kind: str) -> float | None:
    for e in trial.events:
        if e.get("kind") == kind:
            return float(e["time_s"])
    return None


#: a dynamometer sample is part of the movement when its speed is at least this fraction of the sweep's
MOVING_FRACTION_OF_SWEEP_SPEED = 0.01


def _sweep_speed_rad_s(trial: TrialFile) -> float:
    for e in trial.events:
        if e.get("kind") == "sweep_start" and e.get("speed_deg_s"):
            return float(np.deg2rad(float(e["speed_deg_s"])))
    return 0.0


def _movement(keep: np.ndarray, velocity_rad_s: np.ndarray, sweep_speed_rad_s: float) -> np.ndarray:
    """The movement that the sweep marks ``keep`` overlap, by the arm's velocity: from the first
    moving sample to the first at rest after the arm stops (its arrival at the end angle).

    The marks are stamped by the host when it commands the move and hears it end, a tick or two
    either side of the movement and differently every run; the movement itself is counted in the
    device's ticks, so the table — and every analysis of it — is the same for the same device
    behaviour."""
    if sweep_speed_rad_s <= 0.0:
        return keep
    moving = np.abs(velocity_rad_s) >= MOVING_FRACTION_OF_SWEEP_SPEED * sweep_speed_rad_s
    inside = np.flatnonzero(keep & moving)
    if len(inside) == 0:
        return keep
    first, last = int(inside[0]), int(inside[-1])
    while first > 0 and moving[first - 1]:
        first -= 1
    while last < len(moving) - 1 and moving[last + 1]:
        last += 1
    out = np.zeros_like(keep)
    out[first:min(last + 2, len(keep))] = True
    return out


def _device_time_s(device: Any, keep: np.ndarray) -> np.ndarray:
    """Time in the sweep (s) from the device's sample counter at its telemetry rate when the recording
    has both (the device's clock spaces the samples; the host's stamps jitter), else the host stamps."""
    rate = float((device.identity or {}).get("telemetry_rate_hz") or 0.0)
    counter = device.channels.get("counter")
    if rate > 0.0 and counter is not None and len(counter) == len(keep):
        c = np.asarray(counter, dtype=np.int64)[keep]
        return (c - c[0]).astype(float) / rate
    t = device.channels["time_s"][keep]
    return t - t[0]


def _subject_block(subject: dict[str, Any] | None) -> dict[str, Any]:
    return {k: v for k, v in (subject or {}).items() if v is not None}


def trial_table(trial: TrialFile, subject: dict[str, Any] | None = None) -> TrialTable:
    """The trial as ``time_s, angle_deg, torque_Nm`` columns with its sidecar.

    :raises ExportError: the protocol has no such table (AADS needs the analysis) or no data.
    """
    proto = trial.metadata["protocol"]
    name, cond = proto["name"], proto["condition"]
    if name in ("knee", "ankle"):
        d = trial.devices["dynamometer"].channels
        t = d["time_s"]
        t0 = _event_time(trial, "sweep_start")
        t1 = _event_time(trial, "sweep_end")
        keep = (t >= (t0 if t0 is not None else -np.inf)) & (t <= (t1 if t1 is not None else np.inf))
        if not keep.any():
            raise ExportError(f"{trial.path}: no dynamometer samples inside the sweep")
        keep = _movement(keep, d["velocity_rad_s"], _sweep_speed_rad_s(trial))
        angle = np.rad2deg(d["position_rad"][keep])
        torque = d["torque_nm"][keep] + arm_gravity_moment_nm(
            name, angle, cond["arm_mass_kg"], cond["arm_com_m"], cond.get("knee_flexion_deg", 0.0))
        cols = {"time_s": _device_time_s(trial.devices["dynamometer"], keep), "angle_deg": angle, "torque_Nm": torque,
                "velocity_deg_s": np.rad2deg(d["velocity_rad_s"][keep])}
        fixed = {"hip_flexion_deg": cond["hip_flexion_deg"],
                 "knee_flexion_deg": cond.get("knee_flexion_deg"),
                 "ankle_dorsiflexion_deg": cond.get("ankle_dorsiflexion_deg")}
        return TrialTable(cols, {"kind": name, **{k: v for k, v in fixed.items() if v is not None},
                                 "subject": _subject_block(subject), "source": trial.path.name,
                                 "trial_status": trial.status,
                                 # the arm turns with the limb: its inertia is in the torque (its weight is not)
                                 "arm_inertia_kgm2": float(cond["arm_mass_kg"]) * float(cond["arm_com_m"]) ** 2})
    if name == "replica":
        sensor = trial.devices["torque_sensor"]
        d = sensor.channels
        t = d["time_s"]
        # a transmitter that numbers its samples: each hold is its conversions, taken by the counter
        # and timed by its clock (the host's stamps of the same samples differ from run to run)
        rate = float((sensor.identity or {}).get("output_rate_hz") or 0.0)
        counter = np.asarray(d["counter"], dtype=np.int64) if "counter" in d else None
        by_counter = rate > 0.0 and counter is not None and len(counter) == len(t)
        parts = []
        missed = 0
        # time in the trial from the first hold's first conversion (or, host-timed, its first sample),
        # counted in whole conversions so that the same conversion has the same time in every run
        first = next((e for e in trial.events if e.get("kind") == "hold"), {})
        origin_sample = int(first["first_sample"]) if by_counter and "first_sample" in first else None
        for e in trial.events:
            if e.get("kind") == "hold":
                if origin_sample is not None and "first_sample" in e:
                    assert counter is not None
                    m = (counter >= int(e["first_sample"])) & (counter <= int(e["last_sample"]))
                    missed += int(e["last_sample"]) - int(e["first_sample"]) + 1 - int(m.sum())
                    when = (counter[m] - origin_sample).astype(float) / rate
                else:
                    m = (t >= e["t_start_s"]) & (t <= e["t_end_s"])
                    when = t[m]
                parts.append((when, np.full(m.sum(), float(e["knee_flexion_deg"])), d["torque_nm"][m]))
        if not parts or sum(len(p[0]) for p in parts) == 0:
            holds = [e for e in trial.events if e.get("kind") == "hold"]
            t0 = float(t[0]) if len(t) else (holds[0]["t_start_s"] if holds else 0.0)  # times in the trial
            span = f"samples {t[0] - t0:.2f}–{t[-1] - t0:.2f} s" if len(t) else "no samples"
            hold_span = (f"holds {holds[0]['t_start_s'] - t0:.2f}–{holds[-1]['t_end_s'] - t0:.2f} s" if holds
                         else "no holds")
            raise ExportError(f"{trial.path}: no torque samples inside any hold ({len(t)} {span}; "
                              f"{len(holds)} {hold_span}, from the first sample)")
        tt, aa, qq = (np.concatenate(x) for x in zip(*parts))
        origin = 0.0 if origin_sample is not None else float(tt[0])
        return TrialTable({"time_s": tt - origin, "angle_deg": aa, "torque_Nm": qq},
                          {"kind": "replica", "hip_flexion_deg": 90.0, "ankle_dorsiflexion_deg": 0.0,
                           "sensor_tared_unloaded": bool(cond.get("sensor_tared_unloaded", False)),
                           "subject": _subject_block(subject), "source": trial.path.name,
                           "trial_status": trial.status,
                           # conversions inside the holds that no poll read (the counter shows them)
                           **({"hold_conversions_missed": missed} if by_counter else {})})
    if name == "aads":
        return aads_table(trial, subject)
    raise ExportError(f"{trial.path}: no table export for {name!r} trials")


def aads_table(trial: TrialFile, subject: dict[str, Any] | None = None, model_path: str | Path | None = None) -> TrialTable:
    """An AADS trial's AFO torque (static optimisation) against the hinge angle, with the default or given jig model."""
    from analysis.aads.model import load_jig_model
    from analysis.aads.pipeline import analyze_trial

    cond = trial.metadata["protocol"]["condition"]
    model = load_jig_model(model_path)
    res = analyze_trial(motion_trial(trial), model, spring_n_per_m=cond.get("spring_n_per_m"),
                        factors={k: cond.get(k) for k in ("spring", "operator", "trial")})
    ok = res.sop.valid
    cols = {"time_s": res.time_s[ok], "angle_deg": res.angle_deg[ok], "torque_Nm": res.afo_torque_nm[ok],
            "velocity_deg_s": res.velocity_deg_s[ok], "bottom_up_torque_Nm": res.bottom_up_torque_nm[ok],
            **{f"operator_force_{a}_N": res.sop.operator_force_n[ok, i] for i, a in enumerate("xyz")},
            **{f"operator_moment_{a}_Nm": res.sop.operator_moment_nm[ok, i] for i, a in enumerate("xyz")}}
    if res.theory is not None:
        cols["spring_torque_Nm"] = res.theory.torque_nm[ok]
        cols["hook_angle_deg"] = res.theory.angle_deg[ok]
    return TrialTable(cols, {"kind": "afo", "jig_model": model.source, "stiffness": res.summary(),
                             "subject": _subject_block(subject), "source": trial.path.name,
                             "trial_status": trial.status})


def export_targets(fmt: str, out: str | Path) -> list[Path]:
    """The files an export of ``fmt`` to ``out`` writes (a CSV brings its JSON sidecar)."""
    out = Path(out)
    return [out, out.with_suffix(".json")] if fmt == "csv" else [out]


def check_export_targets(fmt: str, out: str | Path, *, store_root: Path | None, inputs: list[Path]) -> None:
    """Refuse an export that would write inside the store or over one of its own inputs.

    :raises ExportError: names the file and why.
    """
    targets = [t.resolve() for t in export_targets(fmt, out)]
    if len(set(targets)) != len(targets):
        raise ExportError(f"{out}: a {fmt} export writes {Path(out).with_suffix('.json').name} beside it; "
                          "choose a name that does not end in .json")
    root = store_root.resolve() if store_root is not None else None
    sources = {p.resolve() for p in inputs}
    for t in targets:
        if t in sources:
            raise ExportError(f"{t}: is an input of this export; exports never overwrite their inputs")
        if root is not None and (t == root or root in t.parents):
            raise ExportError(f"{t}: is inside the store {root}; exports are written outside it")


def export_trial(trial: TrialFile, fmt: str, out: str | Path, subject: dict[str, Any] | None = None) -> list[Path]:
    """Write ``trial`` as ``fmt`` to ``out``; returns the files written.

    :raises ExportError: unknown format, or this trial has no such export.
    """
    out = Path(out)
    if fmt not in FORMATS:
        raise ExportError(f"unknown export format {fmt!r}; one of {FORMATS}")
    name = trial.metadata["protocol"]["name"]
    if fmt == "c3d":
        cond = trial.metadata["protocol"].get("condition", {})
        factors: dict[str, Any] = {k: cond.get(k) for k in ("spring", "operator", "trial")}
        if cond.get("spring") is not None:  # the theory's stiffness of that spring, from the jig model
            from .protocols import default_jig_model

            try:
                factors["spring_n_per_m"] = default_jig_model().spring_n_per_m(int(cond["spring"]))
            except (KeyError, IndexError, ValueError):
                pass  # a spring the built-in jig does not have: the file carries its number only
        write_c3d(out, motion_trial(trial), factors=factors)
        return [out]
    if fmt == "sto":
        if name == "aads":
            m = motion_trial(trial)
            ok = ~np.isnan(m.force_n[:, 0])
            write_sto(out, {"time": m.plate_time_s[ok],
                            **{f"ground_force_v{a}": m.force_n[ok, i] for i, a in enumerate("xyz")},
                            **{f"ground_force_p{a}": np.nan_to_num(m.cop_m[ok, i]) for i, a in enumerate("xyz")},
                            "ground_torque_x": np.zeros(ok.sum()), "ground_torque_y": np.zeros(ok.sum()),
                            "ground_torque_z": m.free_moment_nm[ok]}, name=f"aads trial {trial.path.stem}",
                      in_degrees=False)
            return [out]
        table = trial_table(trial, subject)
        coord = {"knee": "knee_angle_r", "ankle": "ankle_angle_r", "replica": "knee_angle_r"}[name]
        cols = {"time": table.time_s, coord: table.angle_deg, f"{coord}_moment": table.torque_nm}
        if "velocity_deg_s" in table.columns:
            cols[f"{coord}_speed"] = table.columns["velocity_deg_s"]
        write_sto(out, cols, name=f"{name} trial {trial.path.stem}", in_degrees=True)
        return [out]
    write_trial_csv(out, trial_table(trial, subject))
    return [out, out.with_suffix(".json")]
