"""An AADS experiment: many trials through the pipeline, Tables 2.1 and 2.2, a JSON report and PNG plots."""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import AnalysisError, FitError
from ..motion import MotionTrial
from .model import JigModel
from .pipeline import AadsTrialResult, analyze_trial
from .statistics import (
    AnovaRow,
    SpringRow,
    StiffnessRecord,
    anova_table,
    format_anova_table,
    format_spring_table,
    spring_table,
)


@dataclass
class TrialInput:
    """A trial to analyse: the data, what is known of its factors, and the spring stiffness if known (N/m)."""

    motion: MotionTrial
    factors: dict[str, Any] = field(default_factory=dict)
    spring_n_per_m: float | None = None


@dataclass
class AadsExperiment:
    """Results of every trial, the trials that failed (with why), and the two tables where they apply."""

    results: list[AadsTrialResult]
    failed: dict[str, str]
    springs: list[SpringRow]
    anova: list[AnovaRow] | None
    anova_error: str = ""

    def records(self) -> list[StiffnessRecord]:
        return records_of(self.results)

    def as_dict(self) -> dict[str, Any]:
        return {"trials": [r.summary() for r in self.results], "failed": self.failed,
                "table_2_1": [r.as_dict() for r in self.springs],
                "table_2_2": [r.as_dict() for r in self.anova] if self.anova else None,
                "anova_error": self.anova_error}

    def text(self) -> str:
        """The per-trial table, Table 2.1 and Table 2.2, as printed by ``instrument analyze afo``."""
        lines = [f"{'trial':<28}{'spring':>7}{'oper.':>6}{'#':>3}{'SOP Nm/°':>10}{'R²':>7}{'theory':>8}{'peak °':>8}"
                 f"{'>stop':>6}{'hyst J':>8}{'mk RMS mm':>10}  flags"]
        for r in self.results:
            s = r.summary()
            fit = r.stiffness.fits.get(r.stiffness.reported_branch)
            # a store's trial by its id (its file name is a random token); a file by its name
            label = (f"trial {r.factors['store_trial_id']}" if r.factors.get("store_trial_id") is not None
                     else Path(r.source).name[:27])
            lines.append(f"{label:<28}{str(s.get('spring', '')):>7}{str(s.get('operator', '')):>6}"
                         f"{str(s.get('trial', '')):>3}{s['stiffness_nm_per_deg']:>10.3f}"
                         f"{(fit.r_squared if fit else float('nan')):>7.3f}{s['theoretical_stiffness_nm_per_deg']:>8.3f}"
                         f"{r.stiffness.peak_angle_deg:>8.1f}{r.stiffness.frames_past_stop:>6}"
                         f"{r.stiffness.hysteresis_area_j:>8.3f}{s['marker_rms_mm']:>10.2f}  {len(r.flags)}")
        for name, why in self.failed.items():
            lines.append(f"{Path(name).name[:27]:<28} FAILED: {why}")
        if self.springs:
            lines += ["", "Table 2.1: stiffness per spring (SOP mean ± SD over trials, theory from the spring hooks)",
                      format_spring_table(self.springs)]
        if self.anova:
            lines += ["", "Table 2.2: multi-factor ANOVA of the SOP stiffness", format_anova_table(self.anova)]
        elif self.anova_error:
            lines += ["", f"no ANOVA: {self.anova_error}"]
        return "\n".join(lines)


def records_of(results: Iterable[AadsTrialResult], *, complete: bool = True) -> list[StiffnessRecord]:
    """Trials as statistics records: those with spring, operator and trial numbers (``complete``), or a spring only."""
    out = []
    for r in results:
        f = r.factors
        needed = ("spring", "operator", "trial") if complete else ("spring",)
        if all(f.get(k) is not None for k in needed):
            out.append(StiffnessRecord(int(f["spring"]), int(f.get("operator") or 0), int(f.get("trial") or 0),
                                       r.stiffness_nm_per_deg, r.theoretical_stiffness_nm_per_deg))
    return out


def analyze_experiment(trials: Iterable[TrialInput], model: JigModel) -> AadsExperiment:
    """Analyse every trial; a trial that cannot be analysed is listed in ``failed``, never dropped silently."""
    results: list[Any] = []
    failed: dict[str, str] = {}
    for t in trials:
        try:
            results.append(analyze_trial(t.motion, model, spring_n_per_m=t.spring_n_per_m, factors=t.factors))
        except AnalysisError as err:
            failed[t.motion.source or f"trial {len(results) + len(failed) + 1}"] = str(err)
    with_spring = records_of(results, complete=False)
    springs = spring_table(with_spring) if with_spring else []
    recs = records_of(results)
    anova, why = None, ""
    if recs:
        try:
            anova = anova_table(recs)
        except FitError as err:
            why = str(err)
    else:
        why = "no trial has its spring, operator and trial number"
    return AadsExperiment(results, failed, springs, anova, why)


def _json_default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o).__name__)


def write_report(experiment: AadsExperiment, out_dir: str | Path,
                 window_deg: tuple[float, float] = (6.0, 20.0)) -> list[Path]:
    """Write ``afo_report.json``, ``torque_angle.png`` (Figure 2.4's layout, fit window shaded) and ``sop_vs_theory.png``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "afo_report.json"]
    files[0].write_text(json.dumps(experiment.as_dict(), indent=2, default=_json_default, allow_nan=True))
    if not experiment.results:
        return files
    springs = sorted({r.factors.get("spring") for r in experiment.results}, key=lambda s: (s is None, s or 0))
    operators = sorted({r.factors.get("operator") for r in experiment.results}, key=lambda s: (s is None, s or 0))
    colors = {op: f"C{i}" for i, op in enumerate(operators)}
    # Figure 2.4's layout: one panel per spring, the torque–angle loops of every trial (coloured by operator),
    # the spring theory overlaid, the fit window shaded and the spring's mean fit line drawn across it
    fig = Figure(figsize=(4.2 * len(springs), 4.4), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(springs), squeeze=False, sharey=True)[0]
    for ax, spring in zip(axes, springs, strict=True):
        mine = [r for r in experiment.results if r.factors.get("spring") == spring]
        seen = set()
        for r in mine:
            op = r.factors.get("operator")
            ax.plot(r.angle_deg, r.afo_torque_nm, color=colors[op], lw=0.8, alpha=0.8, zorder=3,
                    label=f"operator {op} (SOP)" if op not in seen else None)
            seen.add(op)
        theory = next((r.theory for r in mine if r.theory is not None and r.theory.angle_deg.size), None)
        if theory is not None:
            order = np.argsort(theory.angle_deg)
            ax.plot(theory.angle_deg[order], theory.torque_nm[order], "--", color="0.45", lw=1.0, zorder=2,
                    label="theory (eqs 2.1–2.9)")
        fits = [f for r in mine if (f := r.stiffness.fits.get(r.stiffness.reported_branch)) is not None]
        k = np.array([f.slope_nm_per_deg for f in fits])
        if fits:
            x = np.array(window_deg, dtype=float)
            b = float(np.mean([f.intercept_nm for f in fits]))
            ax.plot(x, float(np.mean(k)) * x + b, color="k", lw=1.4, alpha=0.85, zorder=4,
                    label=f"mean {mine[0].stiffness.reported_branch} fit ({window_deg[0]:g}–{window_deg[1]:g}°)")
        ax.axvspan(*window_deg, color="0.9", zorder=0)
        ax.grid(alpha=0.3)
        th = np.array([r.theoretical_stiffness_nm_per_deg for r in mine])
        th_text = f", theory {np.mean(th[np.isfinite(th)]):.3f}" if np.isfinite(th).any() else ""
        spread = f" ± {np.std(k, ddof=1):.3f}" if k.size > 1 else ""  # one trial has no spread to show
        ax.set_title(f"spring {spring}: {np.mean(k):.3f}{spread} N·m/° ({k.size} trial{'s' * (k.size != 1)}{th_text})"
                     if k.size else f"spring {spring}: no fit", fontsize=9)
        ax.set_xlabel("dorsiflexion (°)")
        ax.legend(fontsize=6, loc="upper left")
    axes[0].set_ylabel("AFO torque (N·m)")
    files.append(out / "torque_angle.png")
    fig.savefig(files[-1], dpi=110)
    # SOP against theory: every trial (by operator), each spring's mean ± SD with its label, the identity line
    fig2 = Figure(figsize=(5.2, 4.6), layout="constrained")
    FigureCanvasAgg(fig2)
    ax = fig2.subplots()
    k_all = np.array([r.stiffness_nm_per_deg for r in experiment.results])
    th_all = np.array([r.theoretical_stiffness_nm_per_deg for r in experiment.results])
    ops = [r.factors.get("operator") for r in experiment.results]
    for op in operators:
        sel = np.array([o == op for o in ops])
        ax.scatter(th_all[sel], k_all[sel], s=10, color=colors[op], alpha=0.5, label=f"operator {op}")
    for spring in springs:
        sel = np.array([r.factors.get("spring") == spring for r in experiment.results]) & np.isfinite(k_all) \
            & np.isfinite(th_all)
        if not sel.any():
            continue
        mk, sk = float(np.mean(k_all[sel])), float(np.std(k_all[sel], ddof=1)) if sel.sum() > 1 else 0.0
        mt = float(np.mean(th_all[sel]))
        ax.errorbar(mt, mk, yerr=sk, fmt="s", color="k", ms=5, capsize=4, zorder=5)
        ax.annotate(f"spring {spring}\n{100 * (mk / mt - 1):+.1f} %", (mt, mk), textcoords="offset points",
                    xytext=(8, -14), fontsize=8)
    finite = np.isfinite(th_all) & np.isfinite(k_all)
    if finite.any():
        lim = [0.0, 1.15 * float(max(th_all[finite].max(), k_all[finite].max()))]
        ax.plot(lim, lim, "k--", lw=0.8, label="identity")
    ax.set_xlabel("theoretical stiffness (N·m/°)")
    ax.set_ylabel("SOP stiffness (N·m/°), mean ± SD per spring")
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    files.append(out / "sop_vs_theory.png")
    fig2.savefig(files[-1], dpi=110)
    return files
