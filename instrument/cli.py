"""The ``instrument`` command line."""

from __future__ import annotations

import argparse
import json
import logging
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from drivers.errors import DriverError, LimitViolationError

from . import kinds
from .errors import InstrumentError, ProtocolError, StoreError
from .kinds.base import Parameter
from .offline.loading import LoadedTrial, is_store_id, load_trials
from .store import SessionStore, Subject, default_store_dir, file_sha256, open_store, remembered


def _bounded(low: float, high: float, unit: str) -> Callable[[str], float]:
    """An argparse type: a finite number in ``low..high`` (a usage error, exit 2, otherwise)."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        if not (math.isfinite(value) and low <= value <= high):
            raise argparse.ArgumentTypeError(f"{text} is outside {low:g}..{high:g} {unit}")
        return value
    return parse


def _option_of(p: Parameter) -> dict[str, Any]:
    """argparse's keywords for a trial kind's parameter (its default is the kind's: None here means "not given")."""
    used_by = ", ".join(k.name for k in kinds.KINDS if p in k.parameters)
    help_text = f"{p.help} [{used_by}; default {p.text_of(p.default)}]"
    if p.value_type is bool:
        return {"action": argparse.BooleanOptionalAction, "help": help_text}
    if p.choices:
        return {"type": p.value_type, "choices": p.choices, "help": help_text}
    if p.low is not None and p.high is not None:
        parse = _bounded(p.low, p.high, p.unit)
        return {"type": (lambda text: int(parse(text))) if p.value_type is int else parse,
                "help": f"{help_text} ({p.low:g}–{p.high:g} {p.unit})".replace(" )", ")")}
    return {"type": p.value_type, "help": help_text}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="instrument", description="AFO stiffness and passive muscle-tendon lab instrument")
    parser.add_argument("-v", "--verbose", action="store_true", help="log driver events")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run the simulated lab through the real drivers (no hardware)")
    demo.add_argument("--seconds", type=float, default=4.0, help="streaming time per run (s)")
    demo.add_argument("--out", type=Path, default=Path("out"), help="output folder")
    demo.add_argument("--no-faults", action="store_true", help="skip the fault drill")
    demo.add_argument("--cohort", type=int, default=0, metavar="N",
                      help="also record a simulated study of N subjects and run the cohort analysis on it")

    rec = sub.add_parser("record", help="record one trial into a session store")
    rec.add_argument("--simulate", action="store_true", help="use the simulated lab")
    rec.add_argument("--lab", type=Path, default=None, metavar="LAB.toml",
                     help="the lab's devices by URL and the subject's envelope (see docs/hardware.md): record on them")
    rec.add_argument("--protocol", choices=kinds.names(aliases=True), required=True,
                     help="; ".join(f"{k.name}: {k.summary}" for k in kinds.KINDS))
    rec.add_argument("--store", type=Path, default=None, help="store folder (default: the user's data folder)")
    rec.add_argument("--subject", default="SIM01", help="pseudonymous subject code")
    rec.add_argument("--operator", default="operator-1")
    for p in kinds.all_parameters():  # every kind's parameters, generated (a shared one is one option)
        rec.add_argument(p.option, dest=p.dest, default=None, **_option_of(p))
    rec.add_argument("--seed", type=int, default=0)

    imp = sub.add_parser("import-xdf", help="a LabRecorder XDF file (the instrument's outlets beside EMG, goniometers, "
                         "...) as a trial of the store")
    imp.add_argument("file", type=Path, help="the .xdf file")
    imp.add_argument("--protocol", choices=kinds.names(aliases=True), required=True,
                     help="the trial's kind (its condition from the options below, as for record)")
    imp.add_argument("--store", type=Path, default=None, help="store folder (default: the user's data folder)")
    imp.add_argument("--subject", required=True, help="pseudonymous subject code (added to the store if new)")
    imp.add_argument("--operator", default="operator-1")
    for p in kinds.all_parameters():
        imp.add_argument(p.option, dest=p.dest, default=None, **_option_of(p))

    serve = sub.add_parser("simulate-lab", help="the simulated lab as its own process: its devices reached as real "
                           "ones (CiA 402 drive over slcan on a pty, Modbus RTU and the plate over TCP, LSL senders), "
                           "named in a lab file")
    serve.add_argument("--lab-file", type=Path, default=Path("simulated_lab.toml"), help="the lab file to write")
    serve.add_argument("--protocol", choices=kinds.names(aliases=True), default="knee",
                       help="whose rig and subject to simulate (default knee)")
    serve.add_argument("--seconds", type=float, default=None, help="serve this long (default: until Ctrl-C)")
    serve.add_argument("--no-streams", action="store_true", help="no LSL goniometer and EMG senders")
    serve.add_argument("--seed", type=int, default=0)

    probe_cmd = sub.add_parser("devices", help="probe the lab file's devices: which answer, at what rate, with what limits")
    probe_cmd.add_argument("--lab", type=Path, required=True, metavar="LAB.toml")
    ses = sub.add_parser("sessions", help="list subjects, sessions and trials of a store")
    ses.add_argument("--store", type=Path, default=None)
    ses.add_argument("--json", action="store_true")

    exp = sub.add_parser("export", help="export one trial (sto, csv with JSON sidecar, c3d)")
    exp.add_argument("trial_id", type=int)
    exp.add_argument("--store", type=Path, default=None)
    exp.add_argument("--format", choices=("sto", "csv", "c3d"), required=True)
    exp.add_argument("-o", "--output", type=Path, required=True)

    gui = sub.add_parser("gui", help="the operator window (PySide6): guided protocols, live checks, e-stop")
    gui.add_argument("--simulate", action="store_true", help="use the simulated lab instead of hardware")
    gui.add_argument("--store", type=Path, default=None, help="store folder (default: the user's data folder)")
    gui.add_argument("--subject", default="SIM01")
    gui.add_argument("--operator", default="operator-1")
    for dev in ("force_plate", "dynamometer", "torque_sensor", "mocap"):
        gui.add_argument(f"--{dev.replace('_', '-')}", dest=dev, default=None, metavar="URL", help=f"{dev} URL (hardware)")
    gui.add_argument("--lab", type=Path, default=None, metavar="LAB.toml", help="the lab file's devices and envelope")
    gui.add_argument("--close-after", type=float, default=None, help=argparse.SUPPRESS)
    ana = sub.add_parser("analyze", help="analyse recorded trials")
    analyses = ana.add_subparsers(dest="analysis", required=True)
    afo = analyses.add_parser("afo", help="AFO stiffness by the AADS test (static optimisation, theory, ANOVA)")
    afo.set_defaults(run=cmd_analyze_afo)
    afo.add_argument("trials", nargs="+", help="store trial ids, .h5 trial files or .c3d files")
    afo.add_argument("--model", type=Path, default=None, help="jig/AFO model (.toml or .json); default: the dissertation's jig")
    afo.add_argument("--store", type=Path, default=None, help="store folder for trial ids")
    afo.add_argument("--spring", type=int, default=None, help="C3D input: spring number of the model")
    afo.add_argument("--spring-n-per-m", type=float, default=None, help="C3D input: spring stiffness (N/m)")
    afo.add_argument("--out", type=Path, default=Path("afo_report"), help="folder for the JSON report and PNG plots")
    afo.add_argument("--json", action="store_true", help="print the JSON report instead of the tables")
    afo.add_argument("--recompute", action="store_true", help="analyse again even if the store holds this analysis")
    afo.add_argument("--diagnose-model", action="store_true",
                     help="also diagnose the AFO model across the trials (hinge friction, shell compliance, axis "
                          "misalignment; each trial left out once; needs >= 3 trials of one AFO with the spring hooks)")

    dia = sub.add_parser("diagnose", help="what the model of a trial gets wrong, and why")
    dia.add_argument("file", type=Path, help="a store trial id, a trial CSV (with its .json sidecar) or an "
                     "instrument trial file (.h5); a store id brings the subject's anthropometrics (limb weight "
                     "and inertia)")
    dia.add_argument("--store", type=Path, default=None, help="store folder for a trial id")
    dia.add_argument("--kind", choices=kinds.table_kinds(), default=None,
                     help="trial kind (default: the sidecar's or the recording's)")
    dia.add_argument("--json", action="store_true", help="print the JSON result")
    dia.add_argument("--plot", type=Path, default=None, help="write the diagnosis plot (PNG) here")
    cohort = analyses.add_parser("cohort", help="every subject of a store: passive parameters with bootstrap "
                              "intervals, on Dask (results kept in the store)")
    cohort.set_defaults(run=cmd_analyze_cohort)
    cohort.add_argument("--store", type=Path, required=True)
    cohort.add_argument("--subjects", nargs="+", default=None, help="subject codes (default: every subject)")
    cohort.add_argument("--bootstrap", type=int, default=20, help="bootstrap refits per subject")
    cohort.add_argument("--scheduler", default=None, help="a Dask scheduler (tcp://host:8786); default: a "
                        "LocalCluster on this machine")
    cohort.add_argument("--workers", type=int, default=None, help="LocalCluster worker processes (default: cores)")
    cohort.add_argument("--intervals", type=int, default=12, help="collocation intervals per trial")
    cohort.add_argument("--seed", type=int, default=0, help="seed of the bootstrap resamples")
    cohort_model = cohort.add_mutually_exclusive_group()
    cohort_model.add_argument("--diagnose-model", action="store_true",
                              help="diagnose each subject's model first (as analyze pmp --diagnose-model) and fit "
                                   "the extension it names, its bootstrap refits too")
    cohort_model.add_argument("--extension", default=None, metavar="NAME",
                              help="fit every subject with the model extended by NAME (as analyze pmp --extension)")
    cohort.add_argument("--out", type=Path, default=Path("cohort_report"))
    cohort.add_argument("--json", action="store_true")
    pmp = analyses.add_parser("pmp", help="passive muscle-tendon parameters from knee and ankle trials (collocation)")
    pmp.set_defaults(run=cmd_analyze_pmp)
    pmp.add_argument("trials", nargs="+", help="store trial ids, .h5 trial files or trial CSVs (with sidecars)")
    pmp.add_argument("--subject", type=Path, default=None,
                     help="subject JSON (mass_kg, shank_length_m, foot_length_m; thigh_length_m if measured); "
                          "default: the first sidecar's subject block")
    pmp.add_argument("--store", type=Path, default=None)
    pmp.add_argument("--intervals", type=int, default=24, help="collocation intervals per trial")
    pmp.add_argument("--out", type=Path, default=Path("pmp_report"))
    pmp.add_argument("--json", action="store_true")
    pmp.add_argument("--recompute", action="store_true", help="fit again even if the store holds this analysis")
    pmp.add_argument("--diagnose-model", action="store_true",
                     help="also fit each candidate model extension (damping, friction, limb-mass error, torque offset, "
                          "axis misalignment, end-range structures, a tonic activation, compliant knee tendons) inside "
                          "the estimator, judge it by held-out prediction across trials, and a second one beside the "
                          "winner (about 5 fits per candidate: minutes)")
    pmp.add_argument("--extension", default=None, metavar="NAME",
                     help="fit the model extended with NAME directly (what an earlier --diagnose-model of this subject "
                          "named, e.g. end_range_structures or tonic_activation+knee_tendon_compliance): seconds")
    rep = analyses.add_parser("replica", help="spring stiffness and rest length of the replica leg from its static holds")
    rep.set_defaults(run=cmd_analyze_replica)
    rep.add_argument("trials", nargs="+", help="store trial ids, .h5 trial files or replica trial CSVs (with sidecars)")
    rep.add_argument("--model", type=Path, default=None, help="replica-leg drawing (TOML; default: the built-in rig)")
    rep.add_argument("--store", type=Path, default=None)
    rep.add_argument("--out", type=Path, default=Path("replica_report"))
    rep.add_argument("--json", action="store_true")
    rep.add_argument("--recompute", action="store_true", help="analyse again even if the store holds this analysis")
    return parser


@contextmanager
def _store_for(specs: list[str], path: Path | None) -> Iterator[SessionStore | None]:
    """The command's one store handle, opened (for reading: read-only where the medium cannot be
    written) when a trial is named by its store id, and closed when the command ends."""
    if not any(is_store_id(s) for s in specs):
        yield None
        return
    with _store(path, reading=True) as store:
        yield store


def _analysed(args: argparse.Namespace, kind: str, settings: dict,
              compute: Callable[[list[LoadedTrial]], dict]) -> dict:
    """``compute(trials)``'s payload (``text``, ``json``, ``files``, ``exit_code``) for the trials the
    command names, each loaded once through one store handle. When every trial is a store trial,
    the payload is kept in the store and read back when the same trials and settings were analysed before."""
    if getattr(args, "model", None):
        settings = {**settings, "model_sha256": file_sha256(Path(args.model))}
    with _store_for(args.trials, args.store) as store:
        loaded = load_trials(args.trials, store)
        records = [t.record for t in loaded if t.record is not None]
        if store is None or store.read_only or len(records) != len(loaded):  # a read-only medium: keep nothing
            return compute(loaded)
        payload, read_back = remembered(store, kind, records, settings, lambda: compute(loaded),
                                        recompute=bool(getattr(args, "recompute", False)))
    if read_back:
        print(f"(read back from the store: these trials and settings were analysed before; its files are "
              f"{', '.join(payload.get('files', [])) or 'not kept'}; --recompute runs it again)", file=sys.stderr)
    return payload


def _show(args: argparse.Namespace, payload: dict) -> int:
    if args.json:
        print(json.dumps(payload["json"], indent=2, default=float))
    else:
        print(payload["text"])
        for f in payload.get("files", []):
            print(f"wrote {f}")
    return int(payload.get("exit_code", 0))


def cmd_analyze_replica(args: argparse.Namespace) -> int:
    from analysis.pmp.replica import text, to_json

    from .kinds.replica import analyze_replica

    def compute(trials: list[LoadedTrial]) -> dict:
        tables, metas = [t.table() for t in trials], [t.metadata for t in trials]
        result, truth, files = analyze_replica(tables, metas, args.model, args.out)
        return {"json": to_json(result, truth), "text": text(result, truth), "files": [str(f) for f in files]}

    return _show(args, _analysed(args, "replica", {}, compute))


def cmd_analyze_cohort(args: argparse.Namespace) -> int:
    from analysis.pmp.cohort import DIAGNOSED
    from analysis.pmp.cohort_report import text

    from .offline.cohort import analyze_cohort, default_every, engine_account, progress_printer

    if args.bootstrap < 2:
        raise InstrumentError("--bootstrap must be at least 2 (an interval needs a spread)")
    if args.extension:
        from analysis.pmp.report import named_extension

        named_extension(args.extension)  # an unknown name refused in one line before any fit
    extension = DIAGNOSED if args.diagnose_model else args.extension
    with SessionStore(args.store) as store:
        n_subjects = len(args.subjects) if args.subjects else len(store.subjects())
        show = progress_printer(sys.stderr if args.json else sys.stdout,
                                every=default_every(n_subjects * (1 + args.bootstrap)))
        run, files = analyze_cohort(store, args.out, codes=args.subjects, bootstrap=args.bootstrap,
                                    intervals=args.intervals, seed=args.seed, scheduler=args.scheduler,
                                    workers=args.workers, progress=show, extension=extension)
    if args.json:
        print(json.dumps({"engine": engine_account(run, len(run.summaries)), "subjects": run.summaries,
                          "afo_sets": {k: v["json"] for k, v in run.afo_sets.items()}}, indent=2, default=float))
    else:
        if run.summaries:
            print(text(run.summaries, engine_account(run, len(run.summaries))))
        for afo, res in run.afo_sets.items():
            print(f"\nAFO set {afo!r}" + (" (read back from the store)" if res["read_back"] else "") + ":")
            print(res["text"])
        for f in files:
            print(f"wrote {f}")
    return 0 if not run.failed else 1


def cmd_analyze_pmp(args: argparse.Namespace) -> int:
    from analysis.errors import DataFileError, InputError
    from analysis.pmp.report import analyse, subject_from, text, to_json, trial_from_table, write_plots

    given_subject = None
    if args.subject:
        try:
            given_subject = json.loads(args.subject.read_text(encoding="utf-8"))
        except (OSError, ValueError) as err:
            raise DataFileError(args.subject, f"subject JSON cannot be read: {err}") from err

    def fitted(t: LoadedTrial, table: Any) -> Any:
        try:
            return trial_from_table(table)
        except InputError as err:  # a CSV without its sidecar has no source to name: the spec names it
            raise InputError(str(err) if t.path.name in str(err) else f"{t.spec}: {err}") from err

    def compute(trials: list[LoadedTrial]) -> dict:
        tables = [t.table() for t in trials]
        subject_data = given_subject if given_subject is not None else tables[0].sidecar.get("subject") or {}
        report = analyse([fitted(t, table) for t, table in zip(trials, tables)], subject_from(subject_data), args.intervals,
                         diagnose_model=args.diagnose_model, extension=args.extension)
        files = write_plots(report, args.out)
        return {"json": to_json(report), "text": text(report), "files": [str(f) for f in files]}

    settings = {"intervals": args.intervals, "diagnose_model": args.diagnose_model, "subject": given_subject}
    if args.extension:
        settings["extension"] = args.extension
    return _show(args, _analysed(args, "pmp_subject", settings, compute))


def cmd_diagnose(args: argparse.Namespace) -> int:
    from analysis.diagnosis import diagnose, from_table, write_diagnosis_plot

    def compute(trials: list[LoadedTrial]) -> dict:
        result = diagnose(from_table(trials[0].table(), args.kind))
        files = [str(write_diagnosis_plot(result, args.plot))] if args.plot else []
        return {"json": result.as_dict(), "text": f"{args.file}:\n{result.text()}", "files": files}

    # a store trial's diagnosis is kept with its inputs, like every analysis (read back on a re-run)
    args.trials = [str(args.file)]
    return _show(args, _analysed(args, "diagnosis", {"kind": args.kind}, compute))


def cmd_gui(args: argparse.Namespace) -> int:
    from .gui.app import run

    urls = {d: getattr(args, d) for d in ("force_plate", "dynamometer", "torque_sensor", "mocap") if getattr(args, d)}
    if not args.simulate and not urls and args.lab is None:
        print("instrument gui: give --simulate, --lab LAB.toml, or the device URLs (--dynamometer URL, ...)",
              file=sys.stderr)
        return 2
    return run(simulate=args.simulate, store_dir=args.store, urls=urls, subject=args.subject, operator=args.operator,
               seconds=args.close_after, lab_file=args.lab)


def cmd_analyze(args: argparse.Namespace) -> int:
    """The analysis the ``analyze`` sub-command names (each sub-parser sets its ``run``)."""
    return int(args.run(args))


def cmd_analyze_afo(args: argparse.Namespace) -> int:
    from analysis.aads.experiment import write_report
    from analysis.aads.model import load_jig_model

    from .offline.afo import afo_model_diagnosis, analyze_afo

    def compute(trials: list[LoadedTrial]) -> dict:
        model = load_jig_model(args.model)
        inputs = [t.afo_input(spring=args.spring, spring_n_per_m=args.spring_n_per_m, model=model) for t in trials]
        experiment = analyze_afo(inputs, model)
        files = write_report(experiment, args.out, model.fit_window_deg)
        payload = {"json": json.loads(files[0].read_text()), "text": experiment.text(), "files": [str(f) for f in files],
                   "exit_code": 0 if experiment.results and not experiment.failed else 1}
        if args.diagnose_model:
            payload["json"]["model_diagnosis"], line = afo_model_diagnosis(experiment, model.fit_window_deg)
            payload["text"] += "\n\n" + line
        return payload

    settings = {"spring": args.spring, "spring_n_per_m": args.spring_n_per_m}
    if args.diagnose_model:
        settings["diagnose_model"] = True
    return _show(args, _analysed(args, "afo_set", settings, compute))



def _store(path: Path | None, read_only: bool = False, reading: bool = False) -> SessionStore:
    """The store, named on stderr; ``reading`` commands fall back to read-only where the medium cannot be
    written, and never create one (a mistyped ``--store`` is an error, not an empty store).

    :raises StoreError: a reading command's store does not exist.
    """
    root = path or default_store_dir()
    if (reading or read_only) and not (root / "store.sqlite").exists():
        raise StoreError(f"{root}: no store here (store.sqlite missing); check --store, or record a trial first")
    store = open_store(root) if reading else SessionStore(root, read_only=read_only)
    for r in store.recovered:
        print(f"recovered interrupted trial file {r.path} ({r.samples} samples, {r.seconds * 1e3:.0f} ms)",
              file=sys.stderr)
    return store


def _protocol_from(args: argparse.Namespace) -> kinds.TrialProtocol:
    """The trial protocol the command line's options describe (unset options: the kind's defaults)."""
    kind = kinds.get(args.protocol)
    return kind.protocol(**{p.name: getattr(args, p.dest) for p in kind.parameters if getattr(args, p.dest) is not None})


def _new_session(store: SessionStore, args: argparse.Namespace, notes: str, new_subject: Subject | None = None) -> int:
    """A new session of ``args.subject`` by ``args.operator``; a subject the store does not know is added
    (as ``new_subject``, or with its code only)."""
    try:
        store.subject(args.subject)
    except KeyError:
        store.add_subject(new_subject or Subject(args.subject))
    return store.new_session(args.subject, args.operator, notes=notes)


def cmd_record(args: argparse.Namespace) -> int:
    from .live.session import record_trial
    from .sim.simulate import lab_config_for, simulated_devices, simulation_metadata
    if args.simulate == (args.lab is not None):
        print("instrument record: give --simulate (the simulated lab) or --lab LAB.toml (the lab's devices)",
              file=sys.stderr)
        return 2
    proto = _protocol_from(args)
    if args.lab is not None:
        return _record_on_lab(args, proto)
    with _store(args.store) as store:
        session = _new_session(store, args, "simulated",
                               Subject(args.subject, "unknown", 1.78, 75.0, shank_length_m=0.40, foot_length_m=0.26))
        print(f"store {store.root}, subject {args.subject}, session {session}")
        print(f"recording {proto.name}, {proto.condition_text() or 'default settings'} "
              f"(about {proto.expected_duration_s():.0f} s) ...")
        with simulated_devices(proto, lab_config_for(proto, seed=args.seed)) as (lab, devices):
            out = record_trial(store, session, proto, devices, operator=args.operator, trial_number=args.trial or 1,
                               extra_metadata=simulation_metadata(lab))
    counts = ", ".join(f"{n}: {r.samples} samples, {r.counts()['lost_samples']} lost" for n, r in out.devices.items())
    print(f"trial {out.trial_id} {out.status}{' (' + out.reason + ')' if out.reason else ''}: {counts}\n  {out.path}")
    return 0 if out.status == "recorded" else 1


def cmd_simulate_lab(args: argparse.Namespace) -> int:
    from .sim.lab_process import serve_lab

    try:
        serve_lab(kinds.get(args.protocol).protocol(), args.lab_file, seconds=args.seconds, streams=not args.no_streams,
                  seed=args.seed, say=lambda line: print(line, flush=True))
    except KeyboardInterrupt:  # Ctrl-C is how a served lab ends
        print("simulated lab stopped")
    return 0


def cmd_import_xdf(args: argparse.Namespace) -> int:
    from .offline.xdf import import_xdf, read_xdf

    proto = _protocol_from(args)
    devices = read_xdf(args.file)  # refused before the store is touched; read once
    with _store(args.store) as store:
        session = _new_session(store, args, f"imported from {args.file.name}")
        trial_id = import_xdf(args.file, store, session, proto, operator=args.operator, devices=devices)
        trial = store.trial(trial_id)
    counts = ", ".join(f"{n}: {c['samples']} samples, {c['lost_samples']} lost" for n, c in trial.devices.items())
    print(f"trial {trial_id} ({proto.name}, {proto.condition_text() or 'default settings'}) imported from "
          f"{args.file.name}: {counts}")
    return 0


def _record_on_lab(args: argparse.Namespace, proto: kinds.TrialProtocol) -> int:
    """One trial on the lab file's devices, with the live checks the operator window runs: refused
    unless every device the trial needs answers and the dynamometer reports the lab's envelope."""
    from .live.acquisition import Sink
    from .live.lab import probe
    from .live.runner import TrialRunner
    from .live.sources import HardwareSource

    source = HardwareSource.from_lab_file(args.lab)
    assert source.lab is not None
    probes = probe(source.lab, [*proto.devices, *source.lab.streams])
    for p in probes:
        print(p.line())
    silent = [p for p in probes if not p.answered]
    if silent:
        print("error: not recording: " + "; ".join(f"{p.kind} {p.problem}" for p in silent), file=sys.stderr)
        return 1
    with _store(args.store) as store:
        session = _new_session(store, args, f"lab file {args.lab}")
        print(f"recording {proto.name} {proto.condition_text()} on {args.lab} (about {proto.expected_duration_s():.0f} s; "
              "Ctrl-C halts the arm and keeps the data) ...")
        with source.devices(proto) as devices:
            sinks: list[Sink] = []
            if source.lab.lsl_publish:  # LabRecorder records the instrument beside EMG and EEG
                from .live.lsl import LslPublisher

                sinks.append(LslPublisher(devices, session=f"{store.root.name}-{session}", subject_code=args.subject))
            runner = TrialRunner(store, session, proto, devices, operator=args.operator, trial_number=args.trial or 1,
                                 extra_metadata=source.metadata(), limits=source.lab.limits, sinks=sinks)
            runner.start()
            try:
                while not runner.wait(1.0):
                    snap = runner.snapshot()
                    flags = f", {len(snap.alarms)} activation flag(s)" if snap.alarms else ""
                    print(f"  {snap.elapsed_s:4.0f} s of about {proto.expected_duration_s():.0f} s{flags}", flush=True)
            except KeyboardInterrupt:
                runner.request_stop()  # the protocol's shutdown halts the arm; the data is kept
                runner.wait(30.0)
                print("stopped by the operator: the arm was halted, the data kept", file=sys.stderr)
        snap = runner.snapshot()
    if snap.outcome is None:
        print(f"error: trial failed: {snap.error}", file=sys.stderr)
        return 1
    out = snap.outcome
    why = runner.suggested_rejection()
    print(f"trial {out.trial_id} {out.status}{' (' + out.reason + ')' if out.reason else ''}"
          + (f"; suggest repeating it: {why}" if why else "") + f"\n  {out.path}")
    return 0 if out.status == "recorded" and not why else 1


def cmd_devices(args: argparse.Namespace) -> int:
    """Probe every device of the lab file; exit 0 only when every one answers."""
    from .live.lab import LabFile, probe

    lab = LabFile.load(args.lab)
    probes = probe(lab)
    for p in probes:
        print(p.line())
    return 0 if all(p.answered for p in probes) else 1


def cmd_sessions(args: argparse.Namespace) -> int:
    with _store(args.store, reading=True) as store:
        return _print_sessions(store, args.json)


def _iso(epoch_s: float | None) -> str | None:
    """A store time (epoch seconds) as ISO 8601 in UTC, as JSON readers expect."""
    import datetime

    return None if epoch_s is None else datetime.datetime.fromtimestamp(float(epoch_s), datetime.UTC).isoformat()


def _print_sessions(store: SessionStore, as_json: bool) -> int:
    trials = store.trials()
    if not as_json:
        print(f"store {store.root}" + (" (read-only)" if store.read_only else ""))
    if as_json:
        print(json.dumps({"subjects": [s.as_dict() for s in store.subjects()],
                          "sessions": [{**s, "started_at": _iso(s.get("started_at"))} for s in store.sessions()],
                          "trials": [{**t.as_dict(), "started_at": _iso(t.started_at), "ended_at": _iso(t.ended_at)}
                                     for t in trials]}, indent=2))
        return 0
    for s in store.subjects():
        fields = [f"sex {s.sex}" if s.sex else "", f"height {s.height_m:g} m" if s.height_m else "",
                  f"mass {s.mass_kg:g} kg" if s.mass_kg else "", f"shank {s.shank_length_m:g} m" if s.shank_length_m else ""]
        print(f"subject {s.code}  " + "  ".join(f for f in fields if f) if any(fields) else f"subject {s.code}  "
              "(no anthropometrics entered)")
    print(f"{'trial':>5} {'session':>7} {'subject':<8} {'protocol':<8} {'status':<12} {'samples':<40} condition")
    for t in trials:
        samples = " ".join(f"{n}={c['samples']}" + (f"(-{c['lost_samples']})" if c["lost_samples"] else "")
                           for n, c in t.devices.items())
        cond = "  ".join(f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in t.condition.items()
                         if k in ("spring", "operator", "trial", "hip_flexion_deg", "knee_flexion_deg", "speed_deg_s"))
        print(f"{t.id:>5} {t.session_id:>7} {t.subject_code:<8} {t.protocol:<11} {t.status:<12} {samples:<40} {cond}"
              + (f"  [{t.reason}]" if t.reason else ""))
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    with _store(args.store, reading=True) as store:
        return _export(store, args)


def _export(store: SessionStore, args: argparse.Namespace) -> int:
    from .live.recording import read_trial
    from .offline.export import ExportError, check_export_targets, export_trial

    rec = store.trial(args.trial_id)
    if not Path(args.output).resolve().parent.is_dir():
        raise ExportError(f"{args.output}: its folder {Path(args.output).resolve().parent} does not exist")
    check_export_targets(args.format, args.output, store_root=store.root,
                         inputs=[rec.path, store.root / "store.sqlite"])
    trial = read_trial(rec.path)
    try:
        subject = store.subject(rec.subject_code).as_dict()
    except KeyError:
        subject = None
    files = export_trial(trial, args.format, args.output, subject)
    for f in files:
        if not store.read_only:
            store.add_file(rec.id, f"export-{f.suffix.lstrip('.')}", f.resolve())
        print(f"wrote {f} (trial {rec.id} of the store {store.root})")
    return 0


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING)
    try:
        if args.command == "demo":
            from .sim.demo import main as demo_main

            return demo_main(args.seconds, args.out, faults=not args.no_faults, cohort_subjects=args.cohort)
        return {"record": cmd_record, "import-xdf": cmd_import_xdf, "simulate-lab": cmd_simulate_lab,
                "devices": cmd_devices, "sessions": cmd_sessions, "export": cmd_export, "analyze": cmd_analyze,
                "diagnose": cmd_diagnose, "gui": cmd_gui}[args.command](args)
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    except (LimitViolationError, ProtocolError) as err:  # what was asked is outside what may be done
        print(f"error: {_one_line(err)}", file=sys.stderr)
        return 2
    except (InstrumentError, DriverError, OSError) as err:
        print(f"error: {_one_line(err)}", file=sys.stderr)
        return 1
    except Exception as err:
        from analysis.errors import AnalysisError

        if isinstance(err, AnalysisError):
            print(f"error: {_one_line(err)}", file=sys.stderr)
            return 1
        if args.verbose:
            raise
        print(f"error: internal error ({type(err).__name__}: {_one_line(err)}); nothing recorded was changed; "
              "rerun with -v for the traceback and report it", file=sys.stderr)
        return 1


def _one_line(err: BaseException) -> str:
    text = str(err).strip()
    return text.splitlines()[0] if text else type(err).__name__


if __name__ == "__main__":
    sys.exit(main())
