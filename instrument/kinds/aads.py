"""The AADS test: the operator bends an AFO on the force plate while motion capture tracks the jig.

Static optimisation recovers the AFO torque; its slope against the hinge angle over the jig's fit
window (6–20°, a hinge stop at 21°) is the stiffness in N·m/°.
"""

from __future__ import annotations

import random
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from analysis.aads.experiment import AadsExperiment, TrialInput, analyze_experiment, write_report
from analysis.aads.model import default_jig_model, load_jig_model
from analysis.aads.pipeline import analyze_trial
from analysis.c3d import write_c3d
from analysis.errors import AnalysisError
from analysis.trial_csv import TrialTable
from drivers import StreamingDevice
from drivers.simulation.aads_jig import AfoProperties

from ..errors import InstrumentError, ProtocolError
from ..live.motion import motion_trial
from .base import (
    AFO_STIFFNESS,
    Action,
    Curves,
    LiveView,
    Parameter,
    SetAnalysis,
    TrialKind,
    TrialProtocol,
    wait_or_stop,
)

#: the AADS springs of the dissertation (N/m), numbered as in Table 2.1
AADS_SPRINGS_N_PER_M = {1: 9910.0, 2: 15600.0, 3: 25200.0}
#: from the operator's cue to the first bend sample in the simulated lab (s)
BEND_LEAD_S = 0.05
#: the model-level diagnosis leaves one trial out at a time: it needs this many of one AFO
MIN_TRIALS_FOR_MODEL_DIAGNOSIS = 3


@dataclass
class AadsProtocol(TrialProtocol):
    """One AADS trial: spring 1–3 (or a stiffness in N/m), operator 1–4, trial number; ``duration_s`` of bending."""

    name: ClassVar[str] = "aads"
    devices: ClassVar[tuple[str, ...]] = ("force_plate", "mocap")
    spring: int = 2
    operator: int = 1
    trial: int = 1
    duration_s: float = 6.0
    afo: str = "hinged AFO (default jig)"
    #: False where the motion-capture system has no public real-time stream: the trial is guided by
    #: the plate alone and the angle comes afterwards from the lab's C3D export
    live_markers: bool = True
    #: the operator's hand: ``unload(True)`` lifts the AFO off the plate for zeroing, ``unload(False)``
    #: puts it back; a GUI prompt on the bench, the simulator in simulation
    unload: Callable[[bool], None] | None = field(default=None, repr=False, compare=False)
    #: the operator's cue to start bending (a prompt on the bench; the simulated operator starts one
    #: pass of its bends, anchored to the plate's counter, in simulation)
    begin_bends: Callable[[], float] | None = field(default=None, repr=False, compare=False)
    plate_zero_v: list[float] | None = None
    #: the stiffness fit window and the hinge stop (°), from the jig model (`analysis/aads/default_jig.toml`)
    fit_window_deg: tuple[float, float] = field(default_factory=lambda: default_jig_model().fit_window_deg)
    stop_deg: float = field(default_factory=lambda: default_jig_model().stop_deg)

    def __post_init__(self) -> None:
        if self.spring not in AADS_SPRINGS_N_PER_M:
            raise ProtocolError(f"spring must be one of {sorted(AADS_SPRINGS_N_PER_M)}, got {self.spring}")
        if not 1 <= self.operator <= 4:
            raise ProtocolError(f"operator must be 1..4, got {self.operator}")
        if not self.live_markers:
            self.devices = ("force_plate",)  # type: ignore[misc]  # this trial's devices, not the class's

    @property
    def spring_n_per_m(self) -> float:
        return AADS_SPRINGS_N_PER_M[self.spring]

    def condition(self) -> dict[str, Any]:
        return {"spring": self.spring, "spring_n_per_m": self.spring_n_per_m, "operator": self.operator,
                "trial": self.trial, "fit_window_deg": list(self.fit_window_deg), "stop_deg": self.stop_deg, "afo": self.afo,
                "live_markers": self.live_markers, "plate_zeroed_unloaded": self.plate_zero_v is not None}

    def condition_text(self) -> str:
        return f"spring {self.spring}, operator {self.operator}, trial {self.trial}"

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:
        """Zero the plate with the AFO lifted off, when the operator's hand is available; the
        zeroing samples are dropped, not recorded."""
        if self.unload is None:
            return
        plate = devices["force_plate"]
        self.unload(True)
        try:
            plate.start()
            time.sleep(0.05)  # the lifted AFO settles
            self.plate_zero_v = [float(v) for v in plate.tare(samples=200)]  # type: ignore[attr-defined]  # a plate
        finally:
            self.unload(False)
        time.sleep(0.05)
        plate.read_available()  # the zeroing stream is not part of the trial

    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        if self.begin_bends is not None:
            self.begin_bends()
        mark("bend_start", operator=self.operator)
        wait_or_stop(stop, self.duration_s)
        mark("bend_end")

    def expected_duration_s(self) -> float:
        return self.duration_s

    live_aads_loop: ClassVar[bool] = True

    def checklist(self) -> list[str]:
        return ["force plate zeroed with the AFO unloaded",
                "AFO foot strapped to the plate (no heel lift or slip)",
                f"spring {self.spring} fitted, hinge moves freely to the {self.stop_deg:g}° stop",
                "markers on foot, shank and spring hooks visible to the cameras"]

    def live_hint(self, snapshot: Any) -> str | None:
        if not self.live_markers:
            return ("Recording AADS, force-guided: bend until the plate's load peaks and return; the angle comes "
                    "from the motion-capture system's C3D export (instrument analyze afo FILE.c3d).")
        if not snapshot.aads_angle_deg.size:
            return None
        if snapshot.aads_past_stop:
            return (f"WARNING: bent to {snapshot.aads_peak_deg:.1f}°, past the {self.stop_deg:g}° stop: ease off (the "
                    "stop adds its own stiffness).")
        lo, hi = self.fit_window_deg
        return (f"Recording AADS … peak {snapshot.aads_peak_deg:.1f}°; fit window {lo:g}–{hi:g}° "
                + ("covered." if snapshot.aads_covers_window else "not covered yet: push further."))

    def incomplete_because(self, snapshot: Any) -> str | None:
        if self.live_markers and not snapshot.aads_covers_window:
            return f"bend did not cover the {self.fit_window_deg[0]:g}–{self.fit_window_deg[1]:g}° fit window"
        return None


def is_aads_trial(metadata: dict[str, Any]) -> bool:
    """Whether recorded ``metadata`` is an AADS trial's."""
    return bool(metadata.get("protocol", {}).get("name") == AadsProtocol.name)


def trial_input(trial: Any) -> TrialInput:
    """An instrument trial file (read), with its spring, operator and trial from the recorded condition.

    :raises InstrumentError: the trial is not an AADS trial.
    """
    proto = trial.metadata.get("protocol", {})
    if not is_aads_trial(trial.metadata):
        raise InstrumentError(f"not an AADS trial (protocol {proto.get('name')!r})")
    cond = proto.get("condition", {})
    return TrialInput(motion_trial(trial), {k: cond.get(k) for k in ("spring", "operator", "trial")},
                      cond.get("spring_n_per_m"))


def aads_table(trial: Any, subject: dict[str, Any] | None = None, model_path: str | Path | None = None) -> TrialTable:
    """An AADS trial's AFO torque (static optimisation) against the hinge angle, with the default or given jig model."""
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
    return TrialTable(cols, {"kind": AadsKind.table_kind, "jig_model": model.source, "stiffness": res.summary(),
                             "subject": {k: v for k, v in (subject or {}).items() if v is not None},
                             "source": trial.path.name, "trial_status": trial.status})


def afo_model_diagnosis(experiment: AadsExperiment, window_deg: tuple[float, float]) -> tuple[dict[str, Any] | None, str]:
    """The AFO model-level diagnosis of an analysed set (one AFO's trials, each left out once):
    (its JSON, or ``None`` when it cannot run; its text, or one line saying why not)."""
    from analysis.diagnosis.aads_model import AfoTrialData, diagnose_afo_model

    with_theory = [r for r in experiment.results if r.theory is not None]
    try:
        d = diagnose_afo_model([AfoTrialData.from_result(r, Path(r.source).name) for r in with_theory],
                               window_deg=window_deg)
    except AnalysisError as err:
        return None, f"AFO model-level diagnosis not run: {err}"
    return d.as_dict(), d.text()


def _randomise_springs(values: dict[str, Any]) -> tuple[dict[str, Any], str]:
    order = random.sample(sorted(AADS_SPRINGS_N_PER_M), len(AADS_SPRINGS_N_PER_M))
    return {"spring": order[0]}, "spring order: " + " → ".join(str(s) for s in order)


def _draw(curves: Curves, rings: dict[str, Any], snapshot: Any) -> None:
    if snapshot is not None and snapshot.aads_angle_deg.size:
        curves.a.setData(snapshot.aads_angle_deg, snapshot.aads_torque_nm)
    if "force_plate" in rings:
        f = rings["force_plate"].latest(5000)
        if len(f["time_s"]):
            curves.b.setData(f["time_s"] - f["time_s"][0], f["force_n"][:, 2])


class AadsKind(TrialKind):
    name = AadsProtocol.name
    aliases = ("afo",)
    title = "AADS test"
    order = 10
    summary = "AFO stiffness: the operator bends the AFO on the force plate, motion capture tracks it"
    analysis = AFO_STIFFNESS
    table_kind = "afo"
    export_format = "c3d"
    parameters = (
        Parameter("afo", "AFO", "hinged AFO (default jig)", help="the AFO's name (the set it belongs to)"),
        Parameter("live_markers", "live markers (else force-guided; angle from the C3D export)", True,
                  help="the motion-capture system streams markers live"),
        Parameter("spring", "Spring", 2, choices=tuple(AADS_SPRINGS_N_PER_M),
                  choice_text=lambda s: f"{s}: {AADS_SPRINGS_N_PER_M[s]:.0f} N/m",
                  help="AADS spring (" + ", ".join(f"{v:.0f}" for v in AADS_SPRINGS_N_PER_M.values()) + " N/m)"),
        Parameter("operator", "Operator", 1, choices=(1, 2, 3, 4), flag="--aads-operator",
                  help="the AADS operator (1–4, a factor of the ANOVA)"),
        Parameter("trial", "Trial", 1, low=1, high=99, help="trial number of this spring and operator"),
        Parameter("duration_s", "Bend time", 6.0, unit="s", low=1.0, high=120.0, flag="--seconds",
                  help="bending time (s)"),
    )
    actions = (Action("Randomise spring order", _randomise_springs),)
    view = LiveView(("AFO torque (N·m)", "dorsiflexion (°)"), ("vertical force (N)", "time (s)"), _draw,
                    marks_fit_window=True)

    def build(self, **values: Any) -> AadsProtocol:
        return AadsProtocol(**values)

    def instructions(self) -> str:
        (lo, hi), stop = default_jig_model().fit_window_deg, default_jig_model().stop_deg
        return (f"AADS: with the AFO unloaded, zero the plate. Then push the AFO down past {hi:g}° (not beyond "
                f"the {stop:g}° stop) and return it to neutral. The loop must cover the green {lo:g}–{hi:g}° window.")

    def table(self, trial: Any, subject: dict[str, Any] | None = None) -> TrialTable:
        return aads_table(trial, subject)

    def sto_columns(self, trial: Any, subject: dict[str, Any] | None = None) -> tuple[dict[str, Any], bool]:
        m = motion_trial(trial)
        ok = ~np.isnan(m.force_n[:, 0])
        return {"time": m.plate_time_s[ok],
                **{f"ground_force_v{a}": m.force_n[ok, i] for i, a in enumerate("xyz")},
                **{f"ground_force_p{a}": np.nan_to_num(m.cop_m[ok, i]) for i, a in enumerate("xyz")},
                "ground_torque_x": np.zeros(ok.sum()), "ground_torque_y": np.zeros(ok.sum()),
                "ground_torque_z": m.free_moment_nm[ok]}, False

    def write_c3d(self, trial: Any, out: Path) -> None:
        cond = trial.metadata["protocol"].get("condition", {})
        factors: dict[str, Any] = {k: cond.get(k) for k in ("spring", "operator", "trial")}
        if cond.get("spring") is not None:  # the theory's stiffness of that spring, from the jig model
            try:
                factors["spring_n_per_m"] = default_jig_model().spring_n_per_m(int(cond["spring"]))
            except (KeyError, IndexError, ValueError):
                pass  # a spring the built-in jig does not have: the file carries its number only
        write_c3d(out, motion_trial(trial), factors=factors)

    def analyse_set(self, protocol: TrialProtocol, trials: Sequence[Any], subject: dict[str, float], *,
                    figures_dir: Path | None = None,
                    progress: Callable[[str], None] | None = None) -> SetAnalysis:
        assert isinstance(protocol, AadsProtocol)
        if not protocol.live_markers:
            return SetAnalysis("force-guided AADS trial recorded; its stiffness needs the markers: export the C3D "
                               "from the motion-capture system and run `instrument analyze afo FILE.c3d`.")
        model = load_jig_model()
        every = analyze_experiment([t.afo_input(model=model) for t in trials], model)
        lo, hi = model.fit_window_deg
        columns = ("spring", "trials", f"k {lo:g}–{hi:g}° (N·m/°)", "SD", "theory", "Δ theory (%)")
        rows = []
        for spring in sorted({r.factors.get("spring") for r in every.results}, key=lambda s: (s is None, s or 0)):
            mine = [r for r in every.results if r.factors.get("spring") == spring]
            k = np.array([r.stiffness_nm_per_deg for r in mine], dtype=float)
            th = np.array([r.theoretical_stiffness_nm_per_deg for r in mine], dtype=float)
            ok = k[np.isfinite(k)]
            theory = float(np.nanmean(th)) if np.isfinite(th).any() else float("nan")
            rows.append((str(spring), str(len(mine)), f"{ok.mean():.3f}" if ok.size else "no fit",
                         f"{ok.std(ddof=1):.3f}" if ok.size > 1 else "one trial",  # never "± 0.000"
                         f"{theory:.3f}" if np.isfinite(theory) else "—",
                         f"{100 * (ok.mean() / theory - 1):+.1f}" if ok.size and np.isfinite(theory) else "—"))
        k_now = [r.stiffness_nm_per_deg for r in every.results if r.factors.get("spring") == protocol.spring]
        head = (f"spring {protocol.spring}: {np.nanmean(k_now):.3f} N·m/° from {len(k_now)} accepted "
                f"trial{'s' * (len(k_now) != 1)} (fit {lo:g}–{hi:g}°)" if k_now else f"spring {protocol.spring}: no fit")
        figures = ([f for f in write_report(every, figures_dir, model.fit_window_deg) if f.suffix == ".png"]
                   if figures_dir is not None else [])
        # the session's AFO, all its springs: what its spring model misses, once a trial can be left out
        if len(every.results) < MIN_TRIALS_FOR_MODEL_DIAGNOSIS:
            details = (f"AFO model-level diagnosis: from {MIN_TRIALS_FOR_MODEL_DIAGNOSIS} accepted trials of "
                       f"this AFO (has {len(every.results)})")
        else:
            details = afo_model_diagnosis(every, model.fit_window_deg)[1]
        return SetAnalysis(head, columns, tuple(rows), tuple(str(f) for f in figures), details)

    def simulated_rig(self, protocol: TrialProtocol, subject: dict[str, float], afo: Any) -> dict[str, Any]:
        assert isinstance(protocol, AadsProtocol)
        return {"afo": afo or AfoProperties(spring_n_per_m=protocol.spring_n_per_m), "operator": protocol.operator}

    def simulated_operator(self, protocol: TrialProtocol, lab: Any) -> None:
        assert isinstance(protocol, AadsProtocol)
        # the simulated operator lifts the AFO off the plate for zeroing (this lab's plate, every time)
        protocol.unload = lambda off: setattr(lab.force_plate, "specimen_on_plate", not off)
        # on the protocol's cue (at rest before it) the operator bends through one pass of its profile, then rests; a trial
        # asked to last at least the pass records all of it, so the same seed records the same bends
        # whatever the host's timing (the lab day's do)
        lab.hold_bends()  # at rest until the cue
        protocol.begin_bends = lambda: lab.begin_bends(lead_s=BEND_LEAD_S)
        protocol.duration_s = min(protocol.duration_s, lab.jig.profile.duration_s + BEND_LEAD_S + 0.2)


KIND = AadsKind()

__all__ = ["AADS_SPRINGS_N_PER_M", "KIND", "AadsKind", "AadsProtocol", "aads_table", "afo_model_diagnosis",
           "is_aads_trial", "trial_input"]
