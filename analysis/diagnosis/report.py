"""The diagnosis plot: what the baseline got wrong, and how the named extension fixes it (PNG, no Qt)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .result import Diagnosis


def write_diagnosis_plot(d: Diagnosis, path: str | Path) -> Path:
    """Torque against angle (measured, baseline, extended); the baseline's residual against angle by branch
    with its systematic regions shaded; the residuals of both against time."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    prep = d.prepared
    if prep is None:
        raise ValueError("the diagnosis carries no data to plot")
    path = Path(path)
    fig = Figure(figsize=(15, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    a1, a3, a2 = fig.subplots(1, 3)
    deg = np.rad2deg(prep.theta)
    base = d.fits["none"].prediction
    ext = d.fits[d.cause].prediction
    a1.plot(deg, prep.torque, ".", ms=1.5, color="0.6", label="measured")
    a1.plot(deg, base, lw=0.8, color="C3", label="baseline")
    if d.cause != "none":
        a1.plot(deg, ext, lw=0.8, color="C0", label=f"+ {d.cause}")
    a1.set_xlabel("angle (°)")
    a1.set_ylabel("torque (N·m)")
    a1.legend(fontsize=7)
    resid = prep.torque - base
    moving = np.deg2rad(1.0)
    for name, mask, color in (("loading", prep.omega > moving, "C1"), ("unloading", prep.omega < -moving, "C2"),
                              ("still", np.abs(prep.omega) <= moving, "0.5")):
        a3.plot(deg[mask], resid[mask], ".", ms=1.5, color=color, label=name)
    for r in d.systematic:
        a3.axvspan(*r["angle_deg"], color={"loading": "C1", "unloading": "C2"}.get(r["branch"], "0.5"), alpha=0.12)
    a3.axhline(0, color="k", lw=0.5)
    a3.set_xlabel("angle (°)")
    a3.set_ylabel("baseline residual (N·m)")
    a3.set_title("shaded: systematic (|mean| > 3 SE)" if d.systematic else "no systematic region (|mean| > 3 SE)",
                 fontsize=8)
    a3.legend(fontsize=7, markerscale=4)
    a2.plot(prep.t, prep.torque - base, lw=0.6, color="C3", label=f"baseline (RMSE {d.baseline_rmse_nm:.3f} N·m)")
    if d.cause != "none":
        a2.plot(prep.t, prep.torque - ext, lw=0.6, color="C0", label=f"+ {d.cause} (RMSE {d.extended_rmse_nm:.3f} N·m)")
    a2.axhline(0, color="k", lw=0.5)
    a2.set_xlabel("time (s)")
    a2.set_ylabel("residual (N·m)")
    a2.legend(fontsize=7)
    # every cause the text names: the first, any found with it, and what the data cannot tell it from
    named = " + ".join([d.cause, *(a["cause"] for a in d.also)])
    fig.suptitle(f"{d.kind}: {named}" + (f" (or {', '.join(d.ambiguous_with)})" if d.ambiguous_with else ""))
    fig.savefig(path, dpi=110)
    return path
