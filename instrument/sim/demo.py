"""``instrument demo``: the simulated lab, streamed through the real drivers (no hardware)."""

from __future__ import annotations

import json
import math
import sys
import threading
from pathlib import Path
from typing import Any

import numpy as np

from drivers import Dynamometer, open_dynamometer, open_force_plate, open_torque_sensor
from drivers.dynamometer import protocol as dyn_protocol
from drivers.forceplate import protocol as fp_protocol
from drivers.simulation.faults import FaultConfig
from drivers.simulation.lab import LabConfig, SimulatedLab
from drivers.torque import registers

from .. import kinds
from ..live.stream import StreamResult, stream_devices


def _progress(line: str) -> None:
    """A progress line: on stderr, so that stdout holds only the results (two runs print the same)."""
    print(line, file=sys.stderr, flush=True)


def _measured(line: str) -> None:
    """A measurement of this host (stream rates, recorded sample counts, latencies, solve times): on
    stderr with the progress, so that stdout holds only what the seeds determine."""
    print(line, file=sys.stderr, flush=True)


def _wire_limit_hz(name: str, lab: SimulatedLab) -> float:
    if name == "force_plate":
        return fp_protocol.max_sample_rate_hz(921600)
    if name == "dynamometer":  # a CiA 402 drive sends two TPDOs per sample, the frame set one frame
        return dyn_protocol.max_frame_rate_hz() / (2 if lab.config.dynamometer_protocol == "cia402" else 1)
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
        assert isinstance(dyno, Dynamometer)
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


#: devices read by polling: a poll unanswered in time on a loaded host is a counted gap, not a failure
POLLED_DEVICES = frozenset({"torque_sensor"})


def _row(name: str, res: StreamResult, lab: SimulatedLab) -> dict[str, Any]:
    st = res.stats
    rate = float(st["rate_hz"])  # type: ignore[arg-type]  # the stream's stats mix counts and a rate
    return {"device": name, "samples": res.samples, "rate_hz": rate, "gaps": st["gaps"],
            "lost_samples": st["lost_samples"], "crc_errors": st["crc_errors"],
            "malformed_frames": st["malformed_frames"], "poll_timeouts": st["poll_timeouts"],
            "command_retries": st["command_retries"],
            "errors_reported": len(res.errors),
            "wire_limit_ratio": rate / _wire_limit_hz(name, lab) if math.isfinite(rate) else float("nan")}


def _drill_counted(row: dict[str, Any]) -> bool:
    """Under injected faults, did the driver count them? A streamed device shows bad frames and gaps in
    its sample counter; a polled device shows bad replies and unanswered polls (a lost reply is a poll
    that times out, not a gap: the next poll reads the current value)."""
    bad = row["crc_errors"] + row["malformed_frames"]
    if row["device"] in POLLED_DEVICES:
        return row["samples"] > 0 and bad + row["poll_timeouts"] > 0
    return row["samples"] > 0 and row["gaps"] > 0 and bad > 0


def _print_table(rows: list[dict[str, Any]], title: str) -> None:
    """The streams' table: a measurement of this host's timing (on stderr, see :func:`_measured`)."""
    _measured(f"\n{title} (measured on this host)")
    _measured(f"{'device':<14}{'samples':>9}{'rate Hz':>10}{'gaps':>6}{'lost':>7}{'CRC err':>9}{'malformed':>11}"
              f"{'no reply':>10}{'repeats':>9}{'wire use':>10}")
    for r in rows:
        _measured(f"{r['device']:<14}{r['samples']:>9}{r['rate_hz']:>10.1f}{r['gaps']:>6}{r['lost_samples']:>7}"
                  f"{r['crc_errors']:>9}{r['malformed_frames']:>11}{r['poll_timeouts']:>10}{r['command_retries']:>9}"
                  f"{r['wire_limit_ratio']:>10.3f}")


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
    from ..live.recording import read_trial
    from ..offline.export import export_trial
    from .lab_day import record_lab_day, summary_rows

    store_dir = out / "store"
    if (store_dir / "store.sqlite").exists():
        (store_dir / "store.sqlite").unlink()
    print(f"\nRecording a simulated lab day into {store_dir} (AADS 3 springs, knee hip 90/55/15°, "
          f"ankle knee 0/45/90°, replica leg; rooms in parallel) ...")
    store, outcomes = record_lab_day(store_dir, quick=quick, progress=_progress)
    rows = summary_rows(store)
    print(f"{'trial':>5} {'protocol':<8} {'status':<10} condition")
    _measured("  lab day: samples recorded per trial (recordings start and stop by the host's clock)")
    for r in rows:
        print(f"{r['trial']:>5} {r['protocol']:<8} {r['status']:<10} {r['condition']}")
        _measured(f"  {r['trial']:>5} {r['protocol']:<8} " + " ".join(f"{n}={c}" for n, c in r["samples"].items()))
    exports = out / "exports"
    exports.mkdir(exist_ok=True)
    done = set()
    for t in store.trials():
        if t.protocol in done:
            continue
        done.add(t.protocol)
        trial = read_trial(t.path)
        fmt = kinds.get(t.protocol).export_format
        files = export_trial(trial, fmt, exports / f"trial{t.id}-{t.protocol}.{fmt}", store.subject(t.subject_code).as_dict())
        print(f"  exported trial {t.id} ({t.protocol}) -> {files[0]}")
    def streamed_losses(r: dict[str, Any]) -> dict[str, int]:
        return {n: k for n, k in r["lost"].items() if k and n not in POLLED_DEVICES}

    ok = all(r["status"] == "recorded" and not streamed_losses(r) for r in rows)
    for r in rows:
        if r["status"] != "recorded" or streamed_losses(r):
            print(f"  PROBLEM: lab-day trial {r['trial']} {r['status']}, lost samples {r['lost']}")
        elif any(r["lost"].values()):
            print(f"  NOTE: lab-day trial {r['trial']}: unanswered polls {r['lost']} (counted as gaps)")
    store.close()
    return rows, ok


def _agreement(difference_nm: float) -> str:
    """A difference at rounding level as a bound (its digits are the float arithmetic's, not the data's)."""
    return "< 1e-9" if abs(difference_nm) < 1e-9 else f"{difference_nm:.1e}"


def afo_experiment(out: Path, store_dir: Path | None = None) -> tuple[dict[str, Any], bool]:
    """The full AADS experiment on the simulator (3 springs × 4 operators × 5 trials): Tables 2.1 and 2.2.

    The 60 trials are sampled offline from the same jig physics the device simulators serve (an
    hour of bending in a few seconds); the AADS trials of the recorded lab day, which went through
    the real drivers, are analysed from the store by the same pipeline.
    """
    from analysis.aads.experiment import TrialInput, analyze_experiment, write_report
    from analysis.aads.model import load_jig_model

    from ..offline.afo import resolve_trials
    from ..store import SessionStore
    from .simulate import synthesize_aads_trial

    model = load_jig_model()
    print("\nAADS experiment on the simulator: springs 9,910 / 15,600 / 25,200 N/m, 4 operators, 5 trials each "
          "(hinge friction and shell compliance on, as in the dissertation's AFO) ...")
    inputs = []
    for spring in (1, 2, 3):
        for operator in (1, 2, 3, 4):
            for trial in range(1, 6):
                motion, _ = synthesize_aads_trial(spring, operator, trial)
                inputs.append(TrialInput(motion, {"spring": spring, "operator": operator, "trial": trial}))
    experiment = analyze_experiment(inputs, model)
    text = experiment.text()
    print(text[text.index("Table 2.1"):])
    files = write_report(experiment, out / "afo", model.fit_window_deg)
    print(f"  wrote {', '.join(str(f) for f in files)}")
    from analysis.diagnosis.aads_case import explain_stiffness_error

    print("\n  Why SOP misses the spring (diagnosis against the known springs; loading-branch error %, mean of 20 trials):")
    print(f"  {'spring':<8}{'raw':>8}{'−friction':>11}{'−shell':>9}{'−both':>8}{'friction N·m':>14}{'μ':>7}{'shell N·m/°':>13}")
    explained = []
    for spring in (1, 2, 3):
        rows = []
        for r in experiment.results:
            if r.factors.get("spring") == spring and r.theory is not None:
                e = explain_stiffness_error(r.angle_deg, r.velocity_deg_s, r.afo_torque_nm, r.theory.torque_nm,
                                            r.theory.angle_deg, model.fit_window_deg)
                rows.append(e.as_dict())
        mean = {k: float(np.mean([x[k] for x in rows])) for k in rows[0]}
        explained.append({"spring": spring, **mean})
        print(f"  {spring:<8}{mean['error_raw_pct']:>8.1f}{mean['error_without_friction_pct']:>11.1f}"
              f"{mean['error_without_compliance_pct']:>9.1f}{mean['error_without_both_pct']:>8.1f}"
              f"{mean['friction_nm']:>14.2f}{mean['friction_per_spring_torque']:>7.3f}"
              f"{1.0 / mean['compliance_deg_per_nm']:>13.1f}")
    print("  hinge friction lifts the loading branch (softest spring over); the shell's bending stretches the "
          "angle more the stiffer the spring (stiffest under).")
    from analysis.diagnosis.aads_model import AfoTrialData, diagnose_afo_model

    picked = [r for r in experiment.results
              if r.factors.get("operator") in (3, 4) and r.factors.get("trial") == 1 and r.theory is not None]
    _progress(f"  model-level diagnosis of the AFO model on {len(picked)} trials (3 springs × operators 3, 4), "
              "each left out once ...")
    afo_model = diagnose_afo_model(
        [AfoTrialData.from_result(r, f"spring {r.factors['spring']} operator {r.factors['operator']}") for r in picked],
        window_deg=model.fit_window_deg)
    print("\n".join("  " + line for line in afo_model.text().splitlines()))
    summary: dict[str, Any] = {"explained": explained, "table_2_1": [r.as_dict() for r in experiment.springs],
                               "table_2_2": [r.as_dict() for r in experiment.anova or []],
                               "model_diagnosis": afo_model.as_dict(), "failed": experiment.failed}
    ok = not experiment.failed and experiment.anova is not None
    if not ok:
        print(f"  PROBLEM: failed trials {experiment.failed}; ANOVA {experiment.anova_error or 'ok'}")
    if store_dir is not None and (store_dir / "store.sqlite").exists():
        store = SessionStore(store_dir, read_only=True)
        ids = [str(t.id) for t in store.trials() if t.protocol in kinds.names_feeding(kinds.AFO_STIFFNESS)
               and t.status == "recorded"]
        recorded = analyze_experiment(resolve_trials(ids, store), model)
        store.close()
        print("  AADS trials of the recorded lab day (through the drivers), same pipeline:")
        for r in recorded.results:
            print(f"    trial {r.factors.get('store_trial_id')}: spring {r.factors.get('spring')}, "
                  f"SOP {r.stiffness_nm_per_deg:.3f} N·m/° vs theory {r.theoretical_stiffness_nm_per_deg:.3f}, "
                  f"SOP − bottom-up {_agreement(r.summary()['sop_vs_bottom_up_max_nm'])} N·m")
        summary["recorded"] = [r.summary() for r in recorded.results]
        if recorded.failed or len(recorded.results) != len(ids):
            print(f"  PROBLEM: recorded AADS trials that failed: {recorded.failed}")
            ok = False
    return summary, ok


def diagnose_recordings(out: Path) -> list[dict[str, Any]]:
    """The demo's last step: diagnose the trials it recorded and exported, and print the findings."""
    from analysis.diagnosis import diagnose, from_table, write_diagnosis_plot

    from ..offline.loading import load_trials
    from ..store import SessionStore

    print("\nDiagnosis of the recorded trials (what the model gets wrong, and why):")
    found = []
    store = SessionStore(out / "store", read_only=True)
    picked: dict[str, Any] = {}
    for t in store.trials():
        picked.setdefault(t.protocol, t)
    loaded = dict(zip(picked, load_trials(list(picked.values()), store)))
    store.close()
    (out / "diagnosis").mkdir(exist_ok=True)
    for protocol, t in picked.items():
        table = loaded[protocol].table()  # built from the recording once: the diagnosis and the truth line read it
        d = diagnose(from_table(table))
        plot = write_diagnosis_plot(d, out / "diagnosis" / f"trial{t.id}-{protocol}.png")
        amb = f" (or {', '.join(d.ambiguous_with)})" if d.ambiguous_with else ""
        def listed(p: dict[str, float]) -> str:
            return ", ".join(f"{k} {v:.3g}" for k, v in p.items())
        params = listed(d.parameters) + "".join(f" + {a['cause']} {listed(a['parameters'])}" for a in d.also)
        print(f"  trial {t.id} {protocol:<8} → {d.cause}{amb} {params}; RMSE {d.baseline_rmse_nm:.3f} → "
              f"{d.extended_rmse_nm:.3f} N·m, held-out ratio {d.heldout_rmse_ratio:.2f}  [{plot.name}]")
        truth = kinds.get(protocol).simulated_truth(table.sidecar)
        if truth:
            print(f"      the simulated subject: {truth}")
        for n in d.notes[:2]:
            print(f"      note: {n}")
        found.append({"trial": t.id, "protocol": protocol, **d.as_dict(), "simulated_truth": truth})
    return found


def passive_parameters(out: Path) -> tuple[dict[str, Any], bool]:
    """Fit the passive muscle-tendon parameters to the lab day's knee (hip 90/55/15°) and ankle (knee 0/45/90°)
    trials, let the model-level diagnosis name what the muscle model lacks, and hold the determined
    parameters against the simulated subject's truth (OpenSim's, not the estimator's model)."""
    from analysis.errors import AnalysisError
    from analysis.pmp.report import analyse, subject_from, text, to_json, trial_from_table, write_plots
    from drivers.simulation.demo_subject import demo_subject

    from ..kinds.isokinetic import MODEL_CANDIDATES
    from ..offline.loading import load_trials
    from ..store import SessionStore

    with SessionStore(out / "store", read_only=True) as store:
        tables = [t.table() for t in load_trials([t for t in store.trials() if t.status == "recorded" and
                                                  t.protocol in kinds.names_feeding(kinds.PASSIVE_PARAMETERS)], store)]
    print(f"\nPassive muscle-tendon parameters from the {len(tables)} recorded knee and ankle trials (direct "
          "collocation, CasADi). The simulated subject's moments are OpenSim's (Rajagopal 2016's muscles with their own "
          "parameters, muscles the estimator does not model, ligaments at the range's ends): a subject the estimator "
          "was not built from ...")
    try:
        print("  ... and the model-level diagnosis: end-range structures, a limb-mass error and a torque offset fitted "
              "inside the estimator, each judged by predicting held-out blocks of every trial", flush=True)
        report = analyse([trial_from_table(t) for t in tables], subject_from(tables[0].sidecar.get("subject") or {}),
                         intervals=16, diagnose_model=len(tables) >= 3, model_intervals=12,
                         model_candidates=list(MODEL_CANDIDATES),
                         progress=lambda line: _progress(f"    {line}"))
    except AnalysisError as err:
        print(f"  PROBLEM: {err}")
        return {"error": str(err)}, False
    _measured(f"  passive fit solved in {report.result.solve_time_s:.1f} s")
    print("  " + text(report, timings=False).replace("\n", "\n  "))
    truth = demo_subject()["truth"]
    idf, res = report.identifiability, report.result
    checked = []
    for name in idf.determined:
        muscle, what = name.split(".")
        true = float(truth[muscle][what])
        lo, hi = idf.ci95[name]
        checked.append({"parameter": name, "truth": true, "estimate": res.parameters[name], "held": lo <= true <= hi})
        print(f"  against the simulated subject's truth: {name} {res.parameters[name]:.4g} (truth {true:.4g}, "
              f"{100 * (res.parameters[name] / true - 1):+.2f} %), 95 % interval [{lo:.4g}, {hi:.4g}] "
              f"{'holds it' if lo <= true <= hi else 'MISSES it'}")
    files = write_plots(report, out / "pmp")
    print("  figures: " + ", ".join(str(f) for f in files))
    result = to_json(report)
    result["against_truth"] = checked
    return result, True


def cohort(out: Path, subjects: int = 0, bootstrap: int = 3) -> tuple[dict[str, Any], bool]:
    """The cohort analysis on Dask: the lab day's subject (a few bootstrap refits, then the re-run
    read back from the store), or with ``subjects`` a simulated study of that many subjects with
    known muscle parameters, recorded through the drivers and checked against its truth."""
    from analysis.pmp.cohort_report import text

    from ..offline.cohort import analyze_cohort, default_every, engine_account, local_client, progress_printer
    from ..store import SessionStore
    from .study import record_study

    if subjects:
        print(f"\nRecording a simulated study of {subjects} subjects (known muscle parameters; knee at hip "
              f"90/55/15°, ankle at knee 0/45/90°, 15°/s) into {out / 'study'} ...", flush=True)
        if (out / "study" / "store.sqlite").exists():
            import shutil

            shutil.rmtree(out / "study")
        store = record_study(out / "study", subjects, speed_deg_s=15.0, progress=_progress)
        where = out / "cohort_study"
    else:
        store = SessionStore(out / "store")
        where = out / "cohort"
    client, cluster, _ = local_client(workers=2)  # one cluster for the run and its re-run
    try:
        n = len(store.subjects())
        print(f"\nCohort analysis on Dask (LocalCluster, 2 worker processes): {n} subject(s) x (1 fit + "
              f"{bootstrap} bootstrap refits), results kept in the store ...", flush=True)
        if not subjects:
            print("  (the lab day's subject resists with Riener & Edrich's moments, not the muscle model's: the "
                  "report should say the model does not fit well enough to determine anything)", flush=True)
        show = progress_printer(sys.stderr, every=default_every(n * (1 + bootstrap)))
        run, files = analyze_cohort(store, where, bootstrap=bootstrap, progress=show, client=client)
        _measured(f"  cohort analysis took {engine_account(run, n)['wall_s']:.1f} s")
        print("  " + text(run.summaries, engine_account(run, n), timings=False).replace("\n", "\n  "))
        for afo, res in run.afo_sets.items():
            print(f"  AFO set {afo!r} ({len(res['json']['trials'])} trials):")
            print("    " + res["text"].replace("\n", "\n    "))
        again, _ = analyze_cohort(store, where, bootstrap=bootstrap, client=client)
        print(f"  re-run with the same trials and settings: {again.read_back} of {again.solves} results read back "
              f"from the store, {again.solved_now} solved")
    finally:
        store.close()
        client.close()
        cluster.close()
    for f in files:
        print(f"  wrote {f}")
    ok = not run.failed and again.solved_now == 0
    report = {"engine": engine_account(run, n), "rerun_read_back": again.read_back, "coverage": run.coverage}
    return report, ok


def replica_leg(out: Path) -> tuple[dict[str, Any], bool]:
    """Fit the replica leg's four springs to the lab day's replica trial and compare with the rig's truth."""
    from analysis.errors import AnalysisError
    from analysis.pmp.replica import text, to_json

    from ..kinds.replica import ReplicaProtocol, analyze_replica, holds_short_of_readings
    from ..offline.loading import load_trials
    from ..store import SessionStore
    from .lab_day import record_repeat

    def replica_trials() -> list[Any]:
        with SessionStore(out / "store", read_only=True) as store:
            return load_trials([t for t in store.trials() if t.status == "recorded" and
                                t.protocol in kinds.names_feeding(kinds.REPLICA_SPRINGS)], store)

    trials = replica_trials()
    tables = [t.table() for t in trials]
    short = holds_short_of_readings(tables)
    if short:
        # a host stalled past the transmitter's history lost a hold's readings (counted in the trial): the operator
        # repeats the trial, as a lab would, and the repeats' holds are pooled
        print(f"  the replica trial's hold(s) at {', '.join(f'{a:g}' for a in short)}° read fewer than half of their "
              "conversions (a stalled host; counted in the trial): recording it again")
        first = trials[0].metadata["protocol"]["condition"]
        with SessionStore(out / "store") as store:
            record_repeat(store, ReplicaProtocol(hold_s=float(first["hold_s"])), seed=1000,
                          note="repeat: a hold lost its readings")
        trials = replica_trials()
        tables = [t.table() for t in trials]
    print(f"\nReplica leg: four springs (BFLH, BFSH, VASINT, RECFEM) from {len(trials)} trial(s) of static holds "
          "every 8°, hip 90° (sensor tared with the shank off) ...")
    try:
        result, truth, _ = analyze_replica(tables, [t.metadata for t in trials], None, out / "replica")
    except AnalysisError as err:
        print(f"  PROBLEM: {err}")
        return {"error": str(err)}, False
    print("  " + text(result, truth).replace("\n", "\n  "))
    missed = sum(int(t.sidecar.get("hold_conversions_missed", 0)) for t in tables)
    if missed:
        # the holds are the transmitter's numbered conversions; one no poll read moves these figures
        print(f"  ({missed} conversion(s) inside the holds were not read by any poll: these figures can differ "
              "from another run's in their last digits)")
    return to_json(result, truth), True


def operator_drill(out: Path) -> tuple[dict[str, Any], bool]:
    """The operator's live checks through the trial runner the GUI uses: a burst flagged and the trial
    rejected (data kept), a relaxed repeat accepted, an emergency stop; then the GUI's screens, offscreen."""
    import os
    import time

    from drivers.dynamometer.protocol import State

    from ..kinds.knee import KneeProtocol
    from ..live.runner import TrialRunner
    from ..store import SessionStore, Subject
    from .source import SimulatedSource

    print("\nOperator drill (the GUI's trial runner): 3 N·m activation burst, relaxed repeat, emergency stop ...")
    store = SessionStore(out / "drill_store")
    store.add_subject(Subject("DRILL01", mass_kg=75.0, shank_length_m=0.42, foot_length_m=0.26))
    session = store.new_session("DRILL01", "drill-operator")
    source = SimulatedSource(seed=11)
    rows: dict[str, Any] = {}
    for case in ("burst", "relaxed", "estop"):
        proto = KneeProtocol(end_deg=25.0, speed_deg_s=10.0)
        with source.devices(proto) as devices:
            runner = TrialRunner(store, session, proto, devices, extra_metadata=source.metadata())
            runner.start()
            runner.sweep_started.wait(20.0)
            if case == "burst":
                source.inject_burst(3.0, at_movement_s=1.2)
            latency_ms, stopped = None, False
            if case == "estop":
                time.sleep(0.5)
                assert source.lab is not None
                sim = source.lab.dynamometer
                t0 = time.perf_counter()
                runner.emergency_stop("drill")
                while sim.state != State.ESTOP and time.perf_counter() - t0 < 1.0:
                    time.sleep(0.0005)
                latency_ms = (time.perf_counter() - t0) * 1e3
                stopped = sim.state == State.ESTOP
            runner.wait(30.0)
        snap = runner.snapshot()
        why = runner.suggested_rejection()
        if snap.outcome is not None:
            (runner.reject(why) if why else runner.accept())
        status = store.trial(snap.outcome.trial_id).status if snap.outcome else "failed"
        rows[case] = {"alarms": [a.angle_deg for a in snap.alarms], "status": status, "reason": why,
                      "estop_latency_ms": latency_ms}
        if latency_ms is not None:
            _measured(f"  e-stop reached the dynamometer in {latency_ms:.1f} ms")
        reached = (", the dynamometer latched its e-stop" if stopped else ", PROBLEM: the dynamometer did not stop") \
            if case == "estop" else ""
        flags = ", ".join(f"{a.angle_deg:.1f}°" for a in snap.alarms) or "none"
        print(f"  {case:<8} activation flags: {flags}; trial {status}" + (f" ({why})" if why else "") + reached)
    store.close()
    ok = bool(rows["burst"]["alarms"]) and rows["burst"]["status"] == "rejected" and \
        rows["relaxed"]["status"] == "accepted" and rows["estop"]["status"] == "rejected"
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    try:
        from ..gui.screens import save_screens

        rows["gui_screens"] = [p.name for p in save_screens(out / "gui_store", out / "gui", SimulatedSource())]
        print(f"  GUI screens (offscreen): {', '.join(rows['gui_screens'])} in {out / 'gui'}")
    except ImportError as err:  # the GUI is optional for the demo's numbers (no Qt on this machine)
        if err.name is None or not err.name.startswith(("PySide6", "shiboken6", "pyqtgraph")):
            raise  # the product's own import failing is a defect, never "not available"
        print(f"  GUI not available here: {err}")
    return rows, ok


def _devices_line(rows: list[dict[str, Any]], ok: bool) -> str:
    streamed = [r["device"] for r in rows if r["device"] not in POLLED_DEVICES]
    return (f"{', '.join(streamed)}: " + ("every sample arrived, no CRC error" if ok else
            "PROBLEM: samples lost or corrupted on a clean link") + f"; {', '.join(sorted(POLLED_DEVICES))}: polled")


def _story(report: dict[str, Any], out: Path) -> list[str]:
    """What the demo found, one or two lines per part, with where its figures are (stdout's story)."""
    lines = []
    day = report.get("lab_day") or []
    recorded = sum(r["status"] == "recorded" for r in day)
    lines.append(f"[2/8] Lab day: {recorded}/{len(day)} trials recorded into {out / 'store'} (AADS 3 springs, knee at "
                 f"hip 90/55/15°, ankle at knee 0/45/90°, the replica leg); one export per kind in {out / 'exports'}")
    afo = report.get("afo") or {}
    springs = afo.get("table_2_1") or []
    if springs:
        lines.append("[3/8] AFO stiffness (AADS, static optimisation): " + "; ".join(
            f"spring {r['spring']} {r['sop_mean_nm_per_deg']:.3f} N·m/° (theory {r['theoretical_nm_per_deg']:.3f}, "
            f"{r['percent_difference']:+.1f} %)" for r in springs))
        named = (afo.get("model_diagnosis") or {}).get("named") or []
        lines.append(f"      why SOP misses the spring: {' + '.join(named) or 'nothing named'}; figures "
                     f"{out / 'afo' / 'torque_angle.png'}, {out / 'afo' / 'sop_vs_theory.png'}")
    pmp = report.get("pmp") or {}
    if "error" in pmp:
        lines.append(f"[4/8] Passive muscle-tendon parameters: PROBLEM: {pmp['error']}")
    elif pmp:
        ext = pmp.get("extended") or {}
        held = pmp.get("against_truth") or []
        lines.append("[4/8] Passive muscle-tendon parameters (collocation, 6 trials): "
                     + (f"the muscle model lacked {ext['extension']} (residual {ext['plain_misfit_ratio']:.1f}× → "
                        f"{ext['misfit_ratio']:.1f}× the noise); " if ext else "")
                     + f"{len(held)} determined, {sum(bool(c['held']) for c in held)} of them with the simulated "
                     f"subject's truth inside the 95 % interval (" + ", ".join(
                         f"{c['parameter']} {100 * (c['estimate'] / c['truth'] - 1):+.1f} %" for c in held) + ")")
        lines.append(f"      figures {out / 'pmp' / 'pmp_fit.png'}, {out / 'pmp' / 'pmp_parameters.png'}")
    rep = report.get("replica") or {}
    if rep.get("determined"):
        errors = rep.get("error_pct") or {}
        lines.append(f"[5/8] Replica leg (springs on a torque sensor): {len(rep['determined'])} spring parameters "
                     f"determined, worst {max(abs(errors[n]) for n in rep['determined']):.1f} % from the built springs")
    drill = report.get("operator_drill") or {}
    if drill:
        lines.append(f"[6/8] Operator drill: a 3 N·m burst flagged and the trial {drill['burst']['status']}; the relaxed "
                     f"repeat {drill['relaxed']['status']}; the e-stop's trial {drill['estop']['status']} "
                     f"(screens in {out / 'gui'})")
    found = report.get("diagnosis") or []
    if found:
        def stop_at(d: dict[str, Any]) -> str:
            angle = d["parameters"].get("stop_angle_deg") if d["cause"] == "hard_stop" else None
            return f" at {angle:.0f}°" if angle is not None else ""
        truths = [d for d in found if d.get("simulated_truth")]
        lines.append("[7/8] Diagnosis of each kind's trial: " + "; ".join(
            f"{d['protocol']} → {' + '.join([d['cause'], *(a['cause'] for a in d.get('also', []))])}{stop_at(d)}"
            for d in found) + (f" (the simulated subject's {' and '.join(d['protocol'] for d in truths)} hold OpenSim's "
                               "limit forces at their range ends: the report sets them beside each finding)"
                               if truths else ""))
    cohort = report.get("cohort") or {}
    if cohort:
        eng = cohort.get("engine") or {}
        lines.append(f"[8/8] Cohort analysis on Dask: {eng.get('solves', 0)} fits, failed {len(eng.get('failed', []))}; "
                     f"the re-run read {cohort.get('rerun_read_back', 0)} back from the store; figures in {out / 'cohort'}")
    return lines


def main(seconds: float = 4.0, out: Path | None = None, faults: bool = True, quick: bool = True,
         cohort_subjects: int = 0) -> int:
    """Run the demo; returns a process exit code (0 when every device streamed cleanly).

    Stdout tells the story in a few lines per part (what was done, what was found, where the figures
    are); every detail goes to ``OUT/demo_report.txt`` and ``OUT/demo.json``; progress and this host's
    measurements (rates, latencies, solve times) go to stderr."""
    import contextlib

    story = sys.stdout
    detail_file = None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        detail_file = (out / "demo_report.txt").open("w", encoding="utf-8")
    details = contextlib.redirect_stdout(detail_file) if detail_file is not None else contextlib.nullcontext()

    def say(line: str) -> None:
        print(line, file=story, flush=True)

    say(f"Simulated lab, reached through the real drivers: force plate (serial framing over TCP), dynamometer "
        f"(a CiA 402 servo drive over CANopen), torque sensor (Modbus RTU, {LabConfig().torque_baud} baud); "
        f"{seconds:.0f} s of streaming each run.")
    try:
        with details:
            print(f"Simulated lab: force plate (serial framing over TCP), dynamometer (CiA 402 over CANopen, virtual "
                  f"bus), torque sensor (Modbus RTU, {LabConfig().torque_baud} baud emulated); {seconds:.0f} s each run.")
            clean, lab = run_streams(seconds)
            rows = [_row(n, r, lab) for n, r in clean.items()]
            _print_table(rows, "Clean links (every sample should arrive):")
            phys = physics_summary(clean)
            _measured(f"  plate Fz {phys['plate_fz_min_n']:.1f}..{phys['plate_fz_max_n']:.1f} N while the operator bends "
                      f"the AFO; dynamometer at {phys['dyno_position_end_deg']:.1f}° after {seconds:.0f} s of a 5°/s knee "
                      f"flexion (torque range {phys['dyno_torque_range_nm']:.2f} N·m); replica-leg torque "
                      f"{phys['torque_sensor_mean_nm']:.2f} N·m")
            report: dict[str, Any] = {"clean": rows, "physics": phys}
            ok = all(r["crc_errors"] == 0 and (r["lost_samples"] == 0 or r["device"] in POLLED_DEVICES) for r in rows)
            print(f"Clean links: {_devices_line(rows, ok)} (rates and counts, a measurement of this host, on stderr)")
            for r in rows:
                if r["device"] in POLLED_DEVICES and r["lost_samples"]:
                    print(f"  NOTE: {r['device']}: {r['lost_samples']} polls unanswered in time on the simulated link "
                          "(a loaded host); counted as gaps, not hidden")
            drill_text = ""
            if faults:
                bad = FaultConfig(drop_rate=0.01, corrupt_rate=0.01, garbage_rate=0.01, truncate_rate=0.005)
                drill, lab = run_streams(seconds, LabConfig(plate_faults=bad, dyno_faults=bad, torque_faults=bad, seed=1))
                frows = [_row(n, r, lab) for n, r in drill.items()]
                _print_table(frows, "Fault drill (1% dropped, 1% corrupted, 1% garbage, 0.5% truncated frames):")
                counted = all(_drill_counted(r) for r in frows)
                drill_text = ("on every device the bad frames were counted and skipped, lost samples are gaps in the "
                              "device counter and lost polls are counted" if counted
                              else "PROBLEM: a device's bad frames went uncounted")
                print(f"Fault drill (1% dropped, 1% corrupted, 1% garbage, 0.5% truncated frames): {drill_text}.")
                report["fault_drill"] = frows
                ok = ok and all(r["samples"] > 0 for r in frows)
        say(f"[1/8] Devices: {_devices_line(rows, ok)}" + (f"; fault drill: {drill_text}" if drill_text else ""))
        if out is None:
            return 0 if ok else 1
        with details:
            report["lab_day"], day_ok = lab_day(out, quick)
            report["afo"], afo_ok = afo_experiment(out, out / "store")
            report["pmp"], pmp_ok = passive_parameters(out)
            report["replica"], replica_ok = replica_leg(out)
            report["operator_drill"], drill_ok = operator_drill(out)
            replica_ok = replica_ok and drill_ok
            pmp_ok = pmp_ok and replica_ok
            report["diagnosis"] = diagnose_recordings(out)
            report["cohort"], cohort_ok = cohort(out)
            ok = ok and cohort_ok
            if cohort_subjects:
                report["cohort_study"], study_ok = cohort(out, cohort_subjects, bootstrap=10)
                ok = ok and study_ok
            ok = ok and pmp_ok and day_ok and afo_ok
            (out / "demo.json").write_text(json.dumps(report, indent=2, default=float))
        for line in _story(report, out):
            say(line)
        say(f"Every detail: {out / 'demo_report.txt'}; every number as JSON: {out / 'demo.json'}")
        return 0 if ok else 1
    finally:
        if detail_file is not None:
            detail_file.close()
