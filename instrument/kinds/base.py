"""What a trial kind is: its parameters, its protocol, its table, its set analysis, its simulated rig, its view.

A :class:`TrialKind` is the only place a kind is described. The command line's ``record`` options
and the operator window's form are generated from :attr:`TrialKind.parameters`; the export, the
set analysis, the simulated lab and the live plots ask the kind, never its name. Each kind lives
in its own module of :mod:`instrument.kinds` and is found there by the registry.

:class:`TrialProtocol` is the procedure one trial runs (as pymeasure's ``Procedure``: prepare,
drive, shutdown); a kind builds it from the parameters' values. Angles are degrees at this edge
(as operators set them); everything recorded is SI.
"""

from __future__ import annotations

import math
import threading
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from analysis.diagnosis import diagnose, from_table, write_diagnosis_plot
from drivers import StreamingDevice

from ..errors import ExportError, ProtocolError
from ..live.relaxation import LIVE_DETECTION_FLOOR_NM

#: telemetry periods recorded after the halt, so the trial shows the arm at rest
HALT_RECORD_PERIODS = 10
#: positioning speed between trials (deg/s)
POSITIONING_SPEED_DEG_S = 30.0

#: the offline analyses a kind's trials feed (what the demo, the cohort and the CLI group trials by)
AFO_STIFFNESS = "afo_stiffness"
PASSIVE_PARAMETERS = "passive_parameters"
REPLICA_SPRINGS = "replica_springs"


class TrialProtocol(ABC):
    """One trial of a kind. ``condition()`` is what the store indexes; ``drive()`` runs the trial."""

    name: ClassVar[str]
    devices: ClassVar[tuple[str, ...]]

    @abstractmethod
    def condition(self) -> dict[str, Any]:
        """The trial's condition (JSON), units in the keys."""

    def prepare(self, devices: dict[str, StreamingDevice]) -> None:  # noqa: B027 - an optional hook; doing nothing is the default
        """Set the devices up before recording starts (positioning, limits). Default: nothing."""

    @abstractmethod
    def drive(self, devices: dict[str, StreamingDevice], mark: Any, stop: threading.Event) -> None:
        """Run the trial while recording; ``mark(kind, **fields)`` writes an event into the trial."""

    def shutdown(self, devices: dict[str, StreamingDevice], mark: Any) -> None:  # noqa: B027 - an optional hook; doing nothing is the default
        """Leave the devices safe; runs after every trial, however it ended (operator stop, error,
        e-stop, normal end), while the recording still runs. Must not raise. Default: nothing."""

    def expected_duration_s(self) -> float:
        return float("nan")

    def condition_text(self) -> str:
        """The condition in a few words, for progress lines and titles (default: the fixed joint, if any)."""
        fixed = getattr(self, "fixed_joint_text", None)
        return fixed() if callable(fixed) else ""

    # what a trial asks of the runner, the GUI and the CLI (no isinstance chains there)
    #: the live relaxation check runs on this kind's dynamometer sweep
    relaxation_monitored: ClassVar[bool] = False
    #: the live AADS loop (angle from markers, torque from the plate) is computed for this kind
    live_aads_loop: ClassVar[bool] = False

    def sweep_deg(self) -> tuple[float, float, float] | None:
        """(start °, end °, speed °/s) of the dynamometer motion this trial commands, or None."""
        return None

    def checklist(self) -> list[str]:
        """The set-up items the operator confirms before a trial."""
        return []

    def live_hint(self, snapshot: Any) -> str | None:
        """The operator's guidance while this trial runs (from the runner's live state), or None."""
        return None

    def incomplete_because(self, snapshot: Any) -> str | None:
        """Why a finished trial of this kind should be repeated even without an alarm, or None."""
        return None


def wait_or_stop(stop: threading.Event, seconds: float) -> bool:
    """Sleep ``seconds`` unless stopped; True if stopped."""
    return stop.wait(seconds)


def live_check_agreement(diagnosis: Any) -> str:
    """What the operator needs when the offline diagnosis names an activation on an accepted trial,
    which the live relaxation check let through: the two checks' sizes, so they do not contradict
    each other on screen ("" when the diagnosis names no activation)."""
    named = [(diagnosis.cause, diagnosis.parameters)] + [(a["cause"], a["parameters"]) for a in diagnosis.also]
    burst = next((p for c, p in named if c == "activation_burst"), None)
    if burst is None:
        return ""
    amplitude = abs(float(burst["burst_amplitude_Nm"]))
    start, duration = float(burst["burst_start_s"]), float(burst["burst_duration_s"])
    if amplitude < LIVE_DETECTION_FLOOR_NM:
        why = (f"below the {LIVE_DETECTION_FLOOR_NM:g} N·m the live relaxation check catches, so it raised no alarm "
               "while the diagnosis, fitting the whole trial, can see it")
    else:
        why = "large enough for the live relaxation check: if it raised no alarm, the operator accepted the trial over it"
    return (f"\n  the trial was accepted, yet the diagnosis fits an activation of {amplitude:.2f} N·m at "
            f"{start:.1f}–{start + duration:.1f} s into the trial: {why}. Look at the torque there; repeat the "
            "trial if the subject was not relaxed, or the passive fit includes it")


def diagnosis_line(tables: Sequence[Any], figures_dir: Path | None = None) -> tuple[str, list[Path]]:
    """The diagnosis of the set's newest trial, in one line for the set analysis ("" without trials), and
    its figure (written into ``figures_dir`` when given)."""
    if not tables:
        return "", []
    d = diagnose(from_table(tables[-1]))
    figures = [write_diagnosis_plot(d, figures_dir / "diagnosis.png")] if figures_dir is not None else []
    return "\ndiagnosis: " + d.text().splitlines()[0] + live_check_agreement(d), figures


@dataclass(frozen=True)
class SetAnalysis:
    """A set's analysis as the operator reads it: a headline, a table, the figures and the full text.

    :ivar headline: one or two lines, the result first (``spring 2: 0.699 N·m/° (1 trial)``)
    :ivar columns: the table's column titles (units in them)
    :ivar rows: the table's cells, as text
    :ivar figures: the PNG files written for this set (paths as text)
    :ivar details: the full report (what the command line prints)
    """

    headline: str
    columns: tuple[str, ...] = ()
    rows: tuple[tuple[str, ...], ...] = ()
    figures: tuple[str, ...] = ()
    details: str = ""

    def as_text(self) -> str:
        """Headline, table and details as plain text."""
        lines = [self.headline]
        if self.columns:
            width = [max([len(c), *(len(r[i]) for r in self.rows)]) for i, c in enumerate(self.columns)]
            lines += ["  ".join(c.ljust(w) for c, w in zip(row, width)).rstrip()
                      for row in (self.columns, *self.rows)]
        return "\n".join(lines + ([self.details] if self.details else []))

    def as_dict(self) -> dict[str, Any]:
        return {"headline": self.headline, "columns": list(self.columns), "rows": [list(r) for r in self.rows],
                "figures": list(self.figures), "details": self.details}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> SetAnalysis:
        return cls(str(d["headline"]), tuple(d.get("columns", ())), tuple(tuple(r) for r in d.get("rows", ())),
                   tuple(d.get("figures", ())), str(d.get("details", "")))


@dataclass(frozen=True)
class Parameter:
    """One setting of a trial kind, as the operator enters it (degrees, seconds, kilograms at this edge).

    :ivar name: the protocol's field it sets (``hip_flexion_deg``)
    :ivar label: the form's label (``Hip flexion``)
    :ivar unit: shown after the value (``°``, ``°/s``, ``s``, ``kg``, ``m``; empty for counts and names)
    :ivar default: the value when none is given; its type is the parameter's (bool, int, float, str)
    :ivar choices: the only values allowed (empty: any in ``low..high``)
    :ivar low, high: the allowed range (inclusive), for numbers without choices
    :ivar flag: the command-line option (default ``--`` and the name with dashes)
    :ivar help: one line for the command line's help and the form's tooltip
    :ivar choice_text: how the form names a choice (default ``str``)
    """

    name: str
    label: str
    default: Any
    unit: str = ""
    choices: tuple[Any, ...] = ()
    low: float | None = None
    high: float | None = None
    flag: str = ""
    help: str = ""
    choice_text: Callable[[Any], str] | None = None

    @property
    def option(self) -> str:
        """The command-line option."""
        return self.flag or "--" + self.name.replace("_", "-")

    @property
    def dest(self) -> str:
        """The attribute argparse stores the option in."""
        return self.option.lstrip("-").replace("-", "_")

    @property
    def value_type(self) -> type:
        return type(self.default)

    def text_of(self, value: Any) -> str:
        """A choice as the form names it."""
        return self.choice_text(value) if self.choice_text is not None else f"{value:g}" if isinstance(
            value, float) else str(value)

    def check(self, value: Any) -> Any:
        """``value`` as this parameter's type, if allowed.

        :raises ProtocolError: not of the type, not a choice, outside the range or not finite.
        """
        kind = self.value_type
        try:
            typed = kind(value) if kind is not bool else bool(value)
            if kind is int and float(value) != typed:  # 2.5 is not a trial number
                raise ValueError(value)
        except (TypeError, ValueError, OverflowError):
            raise ProtocolError(f"{self.label}: {value!r} is not a {kind.__name__}") from None
        if isinstance(typed, str):
            return typed.strip() or self.default
        if isinstance(typed, float) and not math.isfinite(typed):
            raise ProtocolError(f"{self.label}: {value!r} is not a finite number")
        if self.choices and typed not in self.choices:
            raise ProtocolError(f"{self.label} must be one of {', '.join(self.text_of(c) for c in self.choices)}"
                                f"{' ' + self.unit if self.unit else ''}, got {value!r}")
        if kind is not bool and (self.low is not None and typed < self.low or self.high is not None and typed > self.high):
            raise ProtocolError(f"{self.label} {typed:g} is outside {self.low:g}..{self.high:g} {self.unit}".rstrip())
        return typed


@dataclass(frozen=True)
class Action:
    """A button of a kind's form: ``run(values)`` returns the values it sets and a line to show."""

    label: str
    run: Callable[[dict[str, Any]], tuple[dict[str, Any], str]]


class Curves:
    """What a kind's live view draws on (the GUI's pyqtgraph items; anything with ``setData``)."""

    a: Any
    b: Any
    c: Any
    alarms: Any


@dataclass(frozen=True)
class LiveView:
    """A kind's live plots: axis labels of the upper (``a``) and lower (``b``) plot, whether the AADS
    fit window and hinge stop are marked on the upper one, and ``draw(curves, rings, snapshot)``,
    called on the GUI's timer with the ring buffers and the runner's snapshot (or None)."""

    a_labels: tuple[str, str]
    b_labels: tuple[str, str]
    draw: Callable[[Curves, dict[str, Any], Any], None]
    marks_fit_window: bool = False
    #: the expected band on the upper plot for a protocol and the entered subject (``mass_kg``,
    #: ``shank_length_m``, ``foot_length_m``): (x, low, high) arrays, or None where a kind has none
    band: Callable[[Any, dict[str, float]], tuple[Any, Any, Any] | None] | None = None


class TrialKind(ABC):
    """Everything the product knows about one kind of trial.

    A subclass per kind, one instance (``KIND``) in its module. The registry
    (:mod:`instrument.kinds`) orders them by :attr:`order`.
    """

    #: the name the store indexes and the command line takes
    name: ClassVar[str]
    #: other names the command line accepts for this kind
    aliases: ClassVar[tuple[str, ...]] = ()
    #: the operator's name of the kind (the form's protocol list)
    title: ClassVar[str]
    #: position in the form's list and the command line's help
    order: ClassVar[int] = 100
    #: one line: what the trial is
    summary: ClassVar[str]
    #: the offline analysis its trials feed (``AFO_STIFFNESS``, ``PASSIVE_PARAMETERS``, ``REPLICA_SPRINGS``)
    analysis: ClassVar[str]
    #: what its table measures, as :mod:`analysis` names it (the trial CSV's ``kind``)
    table_kind: ClassVar[str]
    #: the format a trial of this kind is exported in for the lab's other tools
    export_format: ClassVar[str] = "csv"
    #: the subject's anthropometrics are needed before a trial (gravity, scaling)
    needs_anthropometrics: ClassVar[bool] = False
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    actions: ClassVar[tuple[Action, ...]] = ()
    view: ClassVar[LiveView]

    @abstractmethod
    def build(self, **values: Any) -> TrialProtocol:
        """The protocol for checked parameter values (every parameter present)."""

    def protocol(self, **values: Any) -> TrialProtocol:
        """The protocol for ``values`` (parameter name → value; missing ones take their default).

        :raises ProtocolError: an unknown parameter or a value it does not allow.
        """
        known = {p.name: p for p in self.parameters}
        unknown = sorted(set(values) - set(known))
        if unknown:
            raise ProtocolError(f"{self.name} trials have no parameter {', '.join(unknown)}")
        return self.build(**{n: p.check(values[n]) if n in values else p.default for n, p in known.items()})

    def instructions(self) -> str:
        """What the operator does in this trial, in a few sentences."""
        return self.summary

    # --------------------------------------------------------------- recorded trial → table and exports
    @abstractmethod
    def table(self, trial: Any, subject: dict[str, Any] | None = None) -> Any:
        """The recorded trial as a :class:`analysis.trial_csv.TrialTable` with its sidecar.

        :raises ExportError: the trial holds no data for a table.
        """

    #: the OpenSim coordinate its table's angle is (the ``.sto`` export's column name)
    opensim_coordinate: ClassVar[str] = ""

    def sto_columns(self, trial: Any, subject: dict[str, Any] | None = None) -> tuple[dict[str, Any], bool]:
        """The ``.sto`` export's columns and whether its angles are degrees."""
        table = self.table(trial, subject)
        coord = self.opensim_coordinate
        cols = {"time": table.time_s, coord: table.angle_deg, f"{coord}_moment": table.torque_nm}
        if "velocity_deg_s" in table.columns:
            cols[f"{coord}_speed"] = table.columns["velocity_deg_s"]
        return cols, True

    def write_c3d(self, trial: Any, out: Path) -> None:
        """Write the trial as C3D (motion-capture kinds)."""
        raise ExportError(f"{trial.path}: {self.title} trials have no motion capture to export as C3D")

    # --------------------------------------------------------------- analysis of an accepted set
    @abstractmethod
    def analyse_set(self, protocol: TrialProtocol, trials: Sequence[Any], subject: dict[str, float], *,
                    figures_dir: Path | None = None,
                    progress: Callable[[str], None] | None = None) -> SetAnalysis:
        """The analysis of a session's accepted trials of this kind, as the operator reads it.

        ``trials`` are loaded trials (:class:`instrument.offline.loading.LoadedTrial`): ``table()``,
        ``afo_input()``, ``metadata``. Figures go into ``figures_dir`` when given; ``progress`` hears
        what a long fit is doing."""

    # --------------------------------------------------------------- simulated lab
    @abstractmethod
    def simulated_rig(self, protocol: TrialProtocol, subject: dict[str, float], afo: Any) -> dict[str, Any]:
        """The simulated lab's configuration for ``protocol`` (keyword arguments of ``LabConfig``)."""

    def simulated_operator(self, protocol: TrialProtocol, lab: Any) -> None:  # noqa: B027 - an optional hook; doing nothing is the default
        """Give ``protocol`` the simulated operator's hand in ``lab`` (default: none needed)."""

    def simulated_truth(self, sidecar: dict[str, Any]) -> str | None:
        """What the simulated lab's subject or rig holds that a diagnosis of a trial with ``sidecar`` should
        find, in one line for the demo to print beside the finding (default: nothing to say)."""
        return None


__all__ = ["diagnosis_line", "live_check_agreement", "AFO_STIFFNESS", "HALT_RECORD_PERIODS", "PASSIVE_PARAMETERS",
           "POSITIONING_SPEED_DEG_S", "REPLICA_SPRINGS",
           "Action", "Curves", "LiveView", "Parameter", "SetAnalysis", "TrialKind", "TrialProtocol", "wait_or_stop"]
