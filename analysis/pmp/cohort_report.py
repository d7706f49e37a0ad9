"""A cohort's passive parameters: Figures 3.15–3.17 as box plots, Table 3.3, the parameter table, CSV and JSON.

Input: the per-subject summaries of :func:`analysis.pmp.cohort.subject_summary`, each with the
subject's anthropometrics under ``"subject"`` (``mass_kg``, ``shank_length_m``, ``foot_length_m``).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import numpy as np

from .muscles import LegMuscles, scale_for_subject, thigh_over_shank_for_subject
from .stiffness import representative_values


def parameter_rows(summaries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per subject and parameter: estimate, 95 % interval, determined, generic (and truth, error)."""
    rows = []
    for s in summaries:
        for name, r in s["parameters"].items():
            ci = r.get("ci95") or [None, None]
            rows.append({"subject": s["subject_code"], "parameter": name, "estimate": r["estimate"],
                         "ci95_low": ci[0], "ci95_high": ci[1], "determined": r["determined"],
                         "generic": r["generic"], "bootstrap_n": r["bootstrap_n"],
                         "truth": r.get("truth"), "error_pct": r.get("error_pct"), "covered": r.get("covered")})
    return rows


def table_3_3(summaries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per subject: forward-dynamics RMSE of every trial, motion (deg) and torque (N·m/kg), and their means."""
    out = []
    for s in summaries:
        fd = s.get("forward_dynamics") or []
        angle = [f["angle_rmse_deg"] for f in fd]
        torque = [f["torque_rmse_nm_per_kg"] for f in fd]
        out.append({"subject": s["subject_code"], "trials": len(fd),
                    "angle_rmse_deg": {f["trial"]: f["angle_rmse_deg"] for f in fd},
                    "torque_rmse_nm_per_kg": {f["trial"]: f["torque_rmse_nm_per_kg"] for f in fd},
                    "mean_angle_rmse_deg": float(np.nanmean(angle)) if angle else None,
                    "mean_torque_rmse_nm_per_kg": float(np.nanmean(torque)) if torque else None})
    return out


def physiological_values(summary: dict[str, Any], which: str = "estimate") -> dict[str, dict[str, float]]:
    """Figures 3.15–3.17's quantities of one subject: slack length per shank length, tendon stiffness
    (kN/m) and muscle stiffness (N/m), from its estimates (``which="estimate"``) or the generic model's."""
    shank = float(summary["subject"]["shank_length_m"])
    thigh = summary["subject"].get("thigh_length_m")  # the muscles scaled as the subject's fit scaled them
    leg = LegMuscles(length_scale=scale_for_subject(shank),
                     thigh_over_shank=thigh_over_shank_for_subject(None if thigh is None else float(thigh), shank))
    return representative_values(leg, {n: float(r[which]) for n, r in summary["parameters"].items()}, shank)


_FIGURES = (("slack_per_shank", "tendon_slack_length_m", "slack length / shank length", "tendon slack length (Fig. 3.15)"),
            ("tendon_kN_per_m", "tendon_strain", "kN/m", "tendon stiffness (Fig. 3.16)"),
            ("muscle_N_per_m", "passive_strain", "N/m", "muscle stiffness (Fig. 3.17)"))


def cohort_figure(summaries: list[dict[str, Any]]) -> Any:
    """Figures 3.15–3.17 for the cohort: a box per muscle over the subjects whose parameter is
    determined, every subject's value as a dot (hollow grey: not determined), the generic model's
    value (for the cohort's mean shank length) as a red bar."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15, 4.6), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3)
    fitted = [physiological_values(s) for s in summaries]
    generic = [physiological_values(s, "generic") for s in summaries]
    for ax, (key, suffix, unit, title) in zip(axes, _FIGURES):
        muscles = sorted({m for f in fitted for m in f[key]})
        for i, m in enumerate(muscles):
            det = [f[key][m] for f, s in zip(fitted, summaries) if s["parameters"][f"{m}.{suffix}"]["determined"]]
            und = [f[key][m] for f, s in zip(fitted, summaries) if not s["parameters"][f"{m}.{suffix}"]["determined"]]
            if len(det) >= 2:
                ax.boxplot([det], positions=[i], widths=0.5, showfliers=False)
            jitter = np.linspace(-0.12, 0.12, max(len(det), 1))[: len(det)]
            ax.plot(i + jitter, det, "o", ms=4, color="C0")
            jitter = np.linspace(-0.12, 0.12, max(len(und), 1))[: len(und)]
            ax.plot(i + jitter, und, "o", ms=4, mfc="none", color="0.6")
            g = float(np.mean([gg[key][m] for gg in generic]))
            ax.plot([i - 0.3, i + 0.3], [g, g], color="C3", lw=2)
        ax.set_xticks(range(len(muscles)), muscles, rotation=60, fontsize=8)
        ax.set_xlim(-0.7, len(muscles) - 0.3)
        ax.set_ylabel(unit)
        ax.set_title(f"{title}: {len(summaries)} subjects", fontsize=10)
    axes[0].plot([], [], "o", color="C0", label="determined")
    axes[0].plot([], [], "o", mfc="none", color="0.6", label="not determined")
    axes[0].plot([], [], color="C3", label="generic (Rajagopal 2016)")
    axes[0].legend(fontsize=7)
    return fig


def text(summaries: list[dict[str, Any]], engine: dict[str, Any] | None = None, *, timings: bool = True) -> str:
    """The cohort's report as text: Table 3.3, determined parameters with intervals, coverage if known
    (``timings=False`` leaves out the wall time, the host's and not the data's)."""
    lines = []
    if engine:
        took = f" in {engine['wall_s']:.1f} s" if timings else ""
        lines.append(f"{engine['subjects']} subjects, {engine['solves']} solves ({engine['solved_now']} now, "
                     f"{engine['read_back']} read back from the store, {len(engine['failed'])} failed) on "
                     f"{engine['scheduler']}{took}")
        for f in engine["failed"]:
            lines.append(f"  FAILED {f}")
        for f in engine.get("left_out", []):
            lines.append(f"  left out: {f}")
    lines.append("\nTable 3.3: forward-dynamics RMSE per subject (mean over its trials)")
    lines.append(f"  {'subject':<8} {'trials':>6} {'motion (deg)':>13} {'torque (N·m/kg)':>16}")
    for r in table_3_3(summaries):
        a, t = r["mean_angle_rmse_deg"], r["mean_torque_rmse_nm_per_kg"]
        lines.append(f"  {r['subject']:<8} {r['trials']:>6} {a if a is not None else float('nan'):>13.3f} "
                     f"{t if t is not None else float('nan'):>16.4f}")
    lines.append("\nDetermined parameters (estimate, 95 % interval: bootstrap ± model-error bound)")
    for s in summaries:
        det = [(n, r) for n, r in s["parameters"].items() if r["determined"]]
        why = "; ".join(s.get("not_determined_because") or [])
        ext = s.get("extension")
        model = f" with {ext} ({', '.join(f'{k} {v:.3g}' for k, v in (s.get('extension_parameters') or {}).items())})" \
            if ext else ""
        head = f"  {s['subject_code']}{model}: {len(det)} of {len(s['parameters'])} determined"
        lines.append(head + (f" ({why})" if why and not det else ""))
        if s.get("model_diagnosis"):
            lines.append(f"    model-level diagnosis: {s['model_diagnosis']['message']}")
        for n, r in det:
            extra = f"  truth {r['truth']:.4g} ({r['error_pct']:+.2f} %)" if "truth" in r else ""
            lines.append(f"    {n:<32} {r['estimate']:.4g} [{r['ci95'][0]:.4g}, {r['ci95'][1]:.4g}]{extra}")
    return "\n".join(lines)


def write_cohort(out_dir: str | Path, summaries: list[dict[str, Any]], engine: dict[str, Any],
                 extra: dict[str, Any] | None = None) -> list[Path]:
    """cohort.json (everything), cohort_parameters.csv, table_3_3.csv and cohort_parameters.png."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "cohort.json", out / "cohort_parameters.csv", out / "table_3_3.csv", out / "cohort_parameters.png"]
    doc = {"engine": engine, "subjects": summaries, "table_3_3": table_3_3(summaries), **(extra or {})}
    files[0].write_text(json.dumps(doc, indent=2, default=float))
    rows = parameter_rows(summaries)
    with open(files[1], "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]) if rows else ["subject"])
        w.writeheader()
        w.writerows(rows)
    with open(files[2], "w", newline="", encoding="utf-8") as fh:
        plain = csv.writer(fh)
        plain.writerow(["subject", "trial", "angle_rmse_deg", "torque_rmse_nm_per_kg"])
        for r in table_3_3(summaries):
            for trial, a in r["angle_rmse_deg"].items():
                plain.writerow([r["subject"], trial, a, r["torque_rmse_nm_per_kg"][trial]])
    cohort_figure(summaries).savefig(files[3], dpi=100)
    return files
