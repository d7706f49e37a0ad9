"""The passive-parameter report: parameter table with intervals, stiffness table, forward-dynamics RMSE, plots."""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..trial_csv import SUBJECT_RANGES, TrialTable
from .estimator import MEASUREMENT_SD, PmpResult, PmpTrial, Subject, estimate, identifiability
from .geometry import path_ranges_deg
from .identifiability import SHAPE_ONLY_SHARE, Identifiability
from .model import moment_function, with_set_angles
from .muscles import COMPLIANT, LegMuscles
from .stiffness import FIGURE_QUANTITIES, achilles_stiffness_kn_per_m, representative_values
from .verify import Verification, forward_dynamics
from .workers import mapped

if TYPE_CHECKING:
    from .model_diagnosis import Extension

#: how far (deg) a trial may leave the muscle paths' fitted range
RANGE_MARGIN_DEG = 2.0
#: the least sweep (deg) a trial must cover to fit passive moments
MIN_SWEEP_DEG = 5.0


@dataclass(frozen=True)
class ExtendedModel:
    """The model extended with what the model-level diagnosis named, refitted (beside the plain fit).

    Attributes
    ----------
    extension, description : the extension's name and what it models
    contribution_nm : per trial, (angle in degrees, the extension's moment in N·m toward positive angle)
    parameters : the extension's fitted parameters (their own units)
    plain_misfit_ratio, misfit_ratio : residual over noise, plain and extended
    plain_residual_rms_nm, residual_rms_nm : residual RMS (N·m), plain and extended
    plain_determined, determined : parameters determined, plain and extended
    plain_result : the plain model's fit
    """

    extension: str
    description: str
    contribution_nm: list[tuple[list[float], list[float]]]
    parameters: dict[str, float]
    plain_misfit_ratio: float
    misfit_ratio: float
    plain_residual_rms_nm: float
    residual_rms_nm: float
    plain_determined: list[str]
    determined: list[str]
    plain_result: PmpResult

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (the plain result left out: its table is in the text)."""
        return {"extension": self.extension, "description": self.description, "contribution_nm": self.contribution_nm,
                "parameters": dict(self.parameters), "plain_misfit_ratio": self.plain_misfit_ratio,
                "misfit_ratio": self.misfit_ratio, "plain_residual_rms_Nm": self.plain_residual_rms_nm,
                "residual_rms_Nm": self.residual_rms_nm, "plain_determined": list(self.plain_determined),
                "determined": list(self.determined)}


@dataclass(frozen=True)
class PmpReport:
    """Everything :func:`analyse` found: the fit, what it determined, the physiological quantities of the
    determined parameters, forward dynamics, and with the model-level diagnosis the extended model.

    Attributes
    ----------
    result : the (final) fit; with an extension named, the extended model's
    identifiability : what the trials determine, with 95 % intervals
    stiffness : ``tendon_kN_per_m`` and ``muscle_N_per_m`` per determined muscle (and ``achilles_kN_per_m``)
    slack_per_shank_length : determined slack lengths over the shank length (dimensionless)
    forward_dynamics : per trial, the fitted model simulated from the measured torque
    leg : the scaled muscle model
    shank_length_m : the entered shank length (m)
    model_diagnosis : the model-level diagnosis, when asked for
    extended : the extended model, when the diagnosis named an extension
    """

    result: PmpResult
    identifiability: Identifiability
    stiffness: dict[str, Any]
    slack_per_shank_length: dict[str, float]
    forward_dynamics: list[Verification]
    leg: LegMuscles
    shank_length_m: float
    model_diagnosis: Any = None
    extended: ExtendedModel | None = None


def trial_from_table(table: TrialTable) -> PmpTrial:
    """A knee or ankle trial CSV (with its sidecar) as an estimator trial; the CSV torque is the dynamometer's u.

    Rows with a missing (NaN/inf) angle or torque are left out and counted in the trial's name; a
    rejected or interrupted trial, a missing fixed joint angle or a sweep of under 5° is refused.

    :raises InputError: one line naming what is wrong.
    """
    side = table.sidecar
    kind = side.get("kind")
    where = f"{side['source']}: " if side.get("source") else ""
    if kind is None:
        raise InputError(f"{where}no kind in its sidecar (is the .json sidecar beside the CSV?); passive parameters "
                         "come from knee or ankle trials")
    if kind not in ("knee", "ankle"):
        raise InputError(f"{where}passive parameters come from knee or ankle trials, not {kind} trials")
    status = side.get("trial_status")
    if status in ("rejected", "interrupted", "failed"):
        raise InputError(f"a {status} trial is not fitted (the operator or the recording ended it); "
                         "repeat it, or export it as CSV and fit it knowingly")
    required = "hip_flexion_deg" if kind == "knee" else "knee_flexion_deg"
    if side.get(required) is None:
        raise InputError(f"{kind} trial without {required} in its sidecar: the fixed joint angle is needed")
    # a goniometer's measured angle, where one was recorded, in place of the chair's setting
    fixed = {"hip": math.radians(float(side.get("hip_flexion_measured_deg", side.get("hip_flexion_deg", 90.0))))}
    if kind == "knee":
        fixed["ankle"] = math.radians(float(side.get("ankle_dorsiflexion_deg") or 0.0))
    else:
        fixed["knee"] = math.radians(float(side.get("knee_flexion_measured_deg", side[required])))
    ok = np.isfinite(table.angle_deg) & np.isfinite(table.torque_nm) & np.isfinite(table.time_s)
    if ok.sum() < 10:
        raise InputError(f"{kind} trial has {int(ok.sum())} rows with a finite angle and torque; at least 10 needed")
    lo, hi = path_ranges_deg()[kind]
    outside = (table.angle_deg[ok] < lo - RANGE_MARGIN_DEG) | (table.angle_deg[ok] > hi + RANGE_MARGIN_DEG)
    if outside.any():
        raise InputError(f"{kind} trial reaches {table.angle_deg[ok][outside][0]:.1f}°, outside the muscle paths' "
                         f"fitted range {lo:g}..{hi:g}° (tools/fit_muscle_paths.py): cut the trial to it")
    t = table.time_s[ok]
    q = np.deg2rad(table.angle_deg[ok])
    sweep_deg = float(np.ptp(table.angle_deg[ok]))
    if sweep_deg < MIN_SWEEP_DEG:
        raise InputError(f"{kind} trial sweeps {sweep_deg:.2f}° (constant angle?): at least {MIN_SWEEP_DEG:g}° "
                         "is needed to fit passive moments")
    v = (np.deg2rad(table.columns["velocity_deg_s"][ok]) if "velocity_deg_s" in table.columns
         and np.isfinite(table.columns["velocity_deg_s"][ok]).all() else np.gradient(q, t))
    name = f"{kind} " + (f"hip {float(side['hip_flexion_deg']):.3g}°" if kind == "knee"
                         else f"knee {float(side['knee_flexion_deg']):.3g}°")
    dropped = int((~ok).sum())
    if dropped:
        name += f" ({dropped} rows without angle or torque left out)"
    if table.rows_without_time:
        name += f" ({table.rows_without_time} rows without a time left out)"
    return PmpTrial(kind, fixed, t, q, v, table.torque_nm[ok], name)


def subject_from(data: dict[str, Any]) -> Subject:
    """The subject's mass (kg), shank and foot length (m), each given and physiological; the thigh's (m) if given.

    :raises InputError: names the missing or out-of-range field and the allowed range.
    """
    values: dict[str, float | None] = {}
    # the thigh is optional (it scales the thigh's muscles; without it they follow the shank, and the intervals
    # carry adults' spread of thigh to shank proportions)
    for key in ("mass_kg", "shank_length_m", "foot_length_m", "thigh_length_m"):
        lo, hi = SUBJECT_RANGES[key]
        value = data.get(key) if isinstance(data, dict) else None
        if value is None:
            if key == "thigh_length_m":
                values[key] = None
                continue
            raise InputError(f"subject {key} is missing: enter it for the subject (store) or in --subject JSON "
                             f"({lo:g}..{hi:g})")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                or not lo <= value <= hi:
            raise InputError(f"subject {key} = {value!r} is outside the allowed range {lo:g}..{hi:g}")
        values[key] = float(value)
    # how well each was measured (one SD), if the record says; else the defaults (MEASUREMENT_SD)
    sd = {key: float(data[key]) for key in ("shank_length_sd_m", "thigh_length_sd_m", "set_angle_sd_deg", "mass_sd_kg")
          if isinstance(data.get(key), (int, float)) and not isinstance(data.get(key), bool)
          and math.isfinite(data[key]) and data[key] > 0}
    mass, shank, foot = (float(values[k] or 0.0) for k in ("mass_kg", "shank_length_m", "foot_length_m"))
    return Subject(mass, shank, foot,
                   shank_length_sd_m=sd.get("shank_length_sd_m", MEASUREMENT_SD["shank_length_m"]),
                   set_angle_sd_rad=math.radians(sd["set_angle_sd_deg"]) if "set_angle_sd_deg" in sd
                   else MEASUREMENT_SD["set_angle_rad"],
                   mass_sd_kg=sd.get("mass_sd_kg", MEASUREMENT_SD["mass_kg"]),
                   thigh_length_m=values["thigh_length_m"],
                   thigh_length_sd_m=sd.get("thigh_length_sd_m", MEASUREMENT_SD["thigh_length_m"]))


def named_extension(name: str) -> Extension:
    """The model extension ``name`` (:data:`analysis.pmp.model_diagnosis.EXTENSIONS`, or two joined by ``+``).

    :raises InputError: no extension has that name.
    """
    from .model_diagnosis import EXTENSIONS, JOIN, get_extension

    try:
        return get_extension(name)
    except KeyError as err:
        raise InputError(f"no model extension {name!r}; known: {', '.join(EXTENSIONS)} (two joined by {JOIN!r})") from err


def analyse(trials: list[PmpTrial], subject: Subject, intervals: int = 24, diagnose_model: bool = False,
            model_candidates: list[str] | None = None, model_intervals: int | None = None,
            progress: Callable[[str], None] | None = None, extension: str | None = None) -> PmpReport:
    """Fit, identifiability, physiological stiffness of the determined parameters, and forward dynamics;
    with ``diagnose_model``, the model-level diagnosis too (:mod:`analysis.pmp.model_diagnosis`: every
    candidate extension fitted inside the estimator, judged by held-out prediction across trials) and the
    model extended with what it named; with ``extension`` (a name of
    :data:`analysis.pmp.model_diagnosis.EXTENSIONS`, or two joined by ``+``: what an earlier diagnosis of
    this subject named) the model extended with it directly, without the diagnosis.

    :raises InputError: ``extension`` names no extension, or is given with ``diagnose_model``.
    """
    if extension is not None:
        if diagnose_model:
            raise InputError("give an extension to fit or ask for the model-level diagnosis, not both")
        named_extension(extension)  # refused before any fit
    named = extension
    leg = subject.leg()

    def iteration(i: int, objective: float) -> None:
        if progress is not None and i % 5 == 0:
            progress(f"IPOPT iteration {i}: objective {objective:.4g}")

    res = estimate(trials, subject, leg=leg, intervals=intervals, progress=iteration if progress else None)
    if progress is not None:
        progress(f"fit done: {res.nit} iterations, {res.solve_time_s:.1f} s ({res.message}); "
                 f"identifiability and forward dynamics ...")
    idf = identifiability(res, trials, subject, leg=leg)
    model = None
    extended: ExtendedModel | None = None
    if diagnose_model:
        from .model_diagnosis import diagnose_model as run_model_diagnosis

        if progress is not None:
            progress("model-level diagnosis: each candidate fitted and judged on held-out blocks ...")
        model = run_model_diagnosis(trials, subject, leg=leg, intervals=model_intervals or intervals,
                                    plain=res if not model_intervals or model_intervals == intervals else None,
                                    candidates=model_candidates)
        named = None if model.cause == "none" else model.cause
    fitted_extension = None
    if named is not None:
        # extend the model with what the diagnosis named (or the caller gave), refit, and report the extended
        # model's parameters with the extension's parameters as nuisances in their intervals; the plain fit is
        # kept beside it
        fitted_extension = named_extension(named)
        if progress is not None:
            progress(f"refit with {fitted_extension.name} ...")
        from .model_diagnosis import fit_extended

        plain_res, plain_idf = res, idf
        res = fit_extended(trials, subject, fitted_extension, leg=leg, intervals=intervals, plain=plain_res,
                           found=model.named_fit if model is not None else None)
        idf = identifiability(res, trials, subject, leg=leg, extension=fitted_extension)
        values = [float(res.extension_parameters[n]) for n in fitted_extension.parameters]
        contribution = []
        for t in with_set_angles(trials, res.set_angle_offsets_rad):  # the extension's own moment over each
            # trial (N·m toward positive angle), plotted
            every = max(t.angle_rad.size // 200, 1)
            q, v = t.angle_rad[::every], t.velocity_rad_s[::every]
            moment = np.array([float(fitted_extension.moment(t, float(a), float(w), values,
                                                      float(subject.gravity_moment_nm(t.joint, a, t.fixed_rad))))
                               for a, w in zip(q, v)])
            options = fitted_extension.muscle_options(t, values)
            if options:  # what it changes in the muscles: the extended muscles' moment less the plain ones'
                moment = moment + (np.asarray(mapped(moment_function(leg, t, res.parameters, **options), q.size)(
                    q[None, :])).ravel() - np.asarray(mapped(moment_function(leg, t, res.parameters), q.size)(
                        q[None, :])).ravel())
            contribution.append((np.rad2deg(q).tolist(), moment.tolist()))
        extended = ExtendedModel(extension=fitted_extension.name, description=fitted_extension.description,
                                 contribution_nm=contribution, parameters=dict(res.extension_parameters),
                                 plain_misfit_ratio=plain_idf.misfit_ratio, misfit_ratio=idf.misfit_ratio,
                                 plain_residual_rms_nm=plain_idf.residual_rms_nm,
                                 residual_rms_nm=idf.residual_rms_nm,
                                 plain_determined=list(plain_idf.determined), determined=list(idf.determined),
                                 plain_result=plain_res)
    if model is not None and model.plausible:
        # models the held-out test could not reject beside the named one: each fitted, and the intervals made to
        # hold the parameters' estimates under them (model uncertainty)
        from .identifiability import with_plausible_models
        from .model_diagnosis import fit_plausible

        alternatives = fit_plausible(trials, subject, model.plausible, leg=leg, intervals=intervals,
                                     plain=plain_res if extended is not None else res, named=res,
                                     named_extension=fitted_extension, progress=progress)
        idf = with_plausible_models(idf, res, [(n, r, identifiability(r, trials, subject, leg=leg, extension=e))
                                               for n, r, e in alternatives])
        if extended is not None:
            extended = dataclasses.replace(extended, determined=list(idf.determined))
    # the physiological quantities of the determined parameters only (Figures 3.15–3.17's, eq 3.13/3.16)
    rep = representative_values(leg, res.parameters, subject.shank_length_m)
    determined = set(idf.determined)
    stiff: dict[str, Any] = {key: {m: v for m, v in rep[key].items() if f"{m}.{FIGURE_QUANTITIES[key]}" in determined}
                             for key in ("tendon_kN_per_m", "muscle_N_per_m")}
    if all(m in stiff["tendon_kN_per_m"] for m in COMPLIANT):
        stiff["achilles_kN_per_m"] = achilles_stiffness_kn_per_m({m: 1e3 * stiff["tendon_kN_per_m"][m] for m in COMPLIANT})
    slack_norm = {m: v for m, v in rep["slack_per_shank"].items() if f"{m}.tendon_slack_length_m" in determined}
    # simulated at the set angles the fit found (the chair's setting plus its fitted offset)
    fd = [forward_dynamics(t, subject, res.parameters, leg=leg, extension=fitted_extension,
                           extension_parameters=res.extension_parameters)
          for t in with_set_angles(trials, res.set_angle_offsets_rad)]
    return PmpReport(result=res, identifiability=idf, stiffness=stiff, slack_per_shank_length=slack_norm,
                     forward_dynamics=fd, leg=leg, shank_length_m=subject.shank_length_m, model_diagnosis=model,
                     extended=extended)


def text(report: PmpReport, *, timings: bool = True) -> str:
    """The fit's report as text; ``timings=False`` leaves out the solve time (the host's, not the data's)."""
    res: PmpResult = report.result
    idf = report.identifiability
    took = f"{res.solve_time_s:.1f} s, " if timings else ""
    head = (f"fit: {res.solver_status}, {res.nit} iterations, {took}cost {res.fun:.3f}" if res.success
            else f"fit DID NOT CONVERGE: {res.message}; the values below are the last iterate, not estimates")
    lines = [head, f"residual {idf.residual_rms_nm:.3g} N·m RMS against measurement noise {idf.noise_nm:.3g} "
                   f"N·m ({idf.misfit_ratio:.1f}×; {idf.effective_samples:.0f} effective of {idf.samples} "
                   "samples)",
             f"{'parameter':<34}{'generic':>9}{'estimate':>10}   95 % interval / status"]
    for n, v in res.parameters.items():
        if n in idf.determined:
            lo, hi = idf.ci95[n]
            status = f"[{lo:.4g}, {hi:.4g}]"
        elif n in idf.at_bound:
            status = "not determined: at its bound"
        else:
            status = "not determined by these trials (the fit's value, not a measurement)"
        lines.append(f"{n:<34}{res.generic[n]:>9.4g}{v:>10.4g}   {status}")
    for label, offset in res.set_angle_offsets_rad.items():  # "hip_set_angle_55deg (knee trials)"
        joint, entered = label.split("_set_angle_")
        lines.append(f"{joint} set angle {entered.replace('deg', '°')}: fitted {math.degrees(offset):+.1f}° off the "
                     "entered angle (a nuisance with the measurement's prior; the intervals include it)")
    for why in idf.not_determined_because:
        lines.append(f"NOTHING DETERMINED: {why}")
    if idf.thigh_would_determine:
        lines.append("the thigh was not measured, so its muscles' intervals carry adults' spread of thigh to shank "
                     "proportions; its length (hip to knee joint centre, by tape: thigh_length_m) would also determine "
                     + ", ".join(idf.thigh_would_determine))
    if idf.model_misfit and report.model_diagnosis is None and report.extended is None:
        from .model_diagnosis import EXTENSIONS

        lines.append("  next: the muscle model lacks something these trials show; diagnosing the model (the command "
                     "line's --diagnose-model, about a minute on two cores; the GUI's set analysis does it once three "
                     "conditions or repeats are in) fits each extension inside the estimator "
                     f"({', '.join(n.replace('_', ' ') for n in EXTENSIONS)}), names the one that predicts left-out "
                     "data better and reports the parameters beside it")
    for c in idf.free_combinations[:4]:
        comp = " ".join(f"{w:+.2f}·{k}" for k, w in c["components"].items())
        lines.append(f"  free combination: {comp}")
    st = report.stiffness
    for m, k in st["tendon_kN_per_m"].items():
        lines.append(f"tendon stiffness {m}: {k:.0f} kN/m")
    if "achilles_kN_per_m" in st:
        lines.append(f"Achilles (calf tendons in parallel): {st['achilles_kN_per_m']:.0f} kN/m")
    for m, k in st["muscle_N_per_m"].items():
        lines.append(f"muscle stiffness {m}: {k:.0f} N/m")
    for fd in report.forward_dynamics:
        why = ("" if np.isfinite(fd.angle_rmse_deg) else
               " (the simulation left the range where the calf tendons have an equilibrium: the fitted "
               "parameters do not reproduce this trial's motion)")
        lines.append(f"forward dynamics {fd.name}: angle RMSE {fd.angle_rmse_deg:.2f}°, torque RMSE "
                     f"{fd.torque_rmse_nm_per_kg:.4f} N·m/kg{why}")
    if report.model_diagnosis is not None:
        lines.append(report.model_diagnosis.text())
    ext = report.extended
    if ext:
        lines.append(f"the model extended with {ext.extension} ({ext.description}): residual "
                     f"{ext.plain_residual_rms_nm:.3g} → {ext.residual_rms_nm:.3g} N·m "
                     f"({ext.plain_misfit_ratio:.1f}× → {ext.misfit_ratio:.1f}× the noise); determined "
                     f"{len(ext.plain_determined)} → {len(ext.determined)} parameters (the table above is the "
                     "extended model's, its intervals with the extension's parameters fitted jointly)")
        from .model_diagnosis import protocol_to_separate

        traded = sorted(set(ext.plain_determined) - set(ext.determined))
        if traded:
            lines.append("  trade with the extension (determined by the plain model, not beside it): " + ", ".join(traded)
                         + "; " + protocol_to_separate(ext.extension))
        if idf.shape_limited:
            lines.append("  told from the extension by its shape only, which the data do not fix (determined within the "
                         "extension's family, not once its shape may differ): " + ", ".join(idf.shape_limited) + "; "
                         + ("what would separate them: as above" if traded else protocol_to_separate(ext.extension)))
        shape_only = [n for n in idf.determined if idf.extension_share.get(n, 0.0) > SHAPE_ONLY_SHARE]
        if shape_only:
            lines.append("  told from the extension by the curves' shapes only (its terms reproduce "
                         + ", ".join(f"{100 * idf.extension_share[n]:.0f} % of {n}'s effect" for n in shape_only)
                         + "): their intervals hold if the extension's shape is the structure's; "
                         + protocol_to_separate(ext.extension))
    return "\n".join(lines)


def summary_table(report: PmpReport) -> tuple[str, tuple[str, ...], list[tuple[str, ...]]]:
    """The fit for a results view: a headline, column titles and rows (text). The determined parameters
    with their 95 % intervals first, the undetermined counted in one row (their values are the fit's, not
    measurements), then the determined parameters' stiffnesses and each trial's forward check."""
    res: PmpResult = report.result
    idf = report.identifiability
    det = [n for n in res.parameters if n in idf.determined]
    if not res.success:
        head = f"fit did not converge ({res.message}): nothing determined"
    elif not det:
        head = "NOTHING DETERMINED" + (f": {idf.not_determined_because[0]}" if idf.not_determined_because else "")
    else:
        head = (f"{len(det)} of {len(res.parameters)} parameters determined; residual {idf.misfit_ratio:.1f}× "
                "the measurement noise")
    if report.extended is not None:
        ext = report.extended
        head += (f"\nmodel extended with {ext.extension}: residual {ext.plain_misfit_ratio:.1f}× → "
                 f"{ext.misfit_ratio:.1f}× the noise, determined {len(ext.plain_determined)} → {len(ext.determined)}")
    elif report.model_diagnosis is not None:
        head += f"\nmodel-level diagnosis: {report.model_diagnosis.message}"
    columns: tuple[str, ...] = ("quantity", "generic", "estimate", "95 % interval")
    rows: list[tuple[str, ...]] = [
        (n, f"{res.generic[n]:.4g}", f"{res.parameters[n]:.4g}", "[{:.4g}, {:.4g}]".format(*idf.ci95[n])) for n in det]
    rest = [n for n in res.parameters if n not in idf.determined]
    if rest:
        at_bound = sum(n in idf.at_bound for n in rest)
        rows.append((f"not determined: {len(rest)} parameters", "", "",
                     f"{at_bound} at a bound" if at_bound else "free in these trials"))
    st = report.stiffness
    rows += [(f"tendon stiffness {m} (kN/m)", "", f"{k:.0f}", "") for m, k in st["tendon_kN_per_m"].items()]
    if "achilles_kN_per_m" in st:
        rows.append(("Achilles stiffness (kN/m)", "", f"{st['achilles_kN_per_m']:.0f}", ""))
    rows += [(f"muscle stiffness {m} (kN/m)", "", f"{k / 1e3:.2f}", "") for m, k in st["muscle_N_per_m"].items()]
    rows += [(f"forward dynamics {fd.name}: angle RMSE (°)", "", f"{fd.angle_rmse_deg:.2f}", "")
             for fd in report.forward_dynamics]
    return head, columns, rows


def to_json(report: PmpReport) -> dict[str, Any]:
    res: PmpResult = report.result
    return {"parameters": res.parameters, "generic": res.generic, "lower": res.lower, "upper": res.upper,
            "cost": res.fun, "iterations": res.nit, "solve_time_s": res.solve_time_s,
            "success": res.success, "message": res.message,
            "identifiability": report.identifiability.as_dict(), "stiffness": report.stiffness,
            "slack_per_shank_length": report.slack_per_shank_length,
            "forward_dynamics": [{"trial": v.name, "angle_rmse_deg": v.angle_rmse_deg,
                                  "torque_rmse_Nm_per_kg": v.torque_rmse_nm_per_kg} for v in report.forward_dynamics],
            "model_diagnosis": report.model_diagnosis.as_dict() if report.model_diagnosis else None,
            "extended": report.extended.as_dict() if report.extended else None}


def _parameter_figure(report: PmpReport) -> Any:
    """Figures 3.15–3.17 side by side: slack length per shank length, tendon stiffness (kN/m) and
    muscle stiffness (kN/m). The generic model's value (orange outline) beside the fit: a determined
    parameter blue with its 95 % interval, an undetermined one a grey, hatched bar (the fit's value, not a
    measurement). Each panel on a log scale when its values span more than a decade."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    res: PmpResult = report.result
    idf = report.identifiability
    det = set(idf.determined)
    leg, shank = report.leg, float(report.shank_length_m)
    fig = Figure(figsize=(14, 4.4), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3)
    fitted = representative_values(leg, res.parameters, shank)
    generic = representative_values(leg, res.generic, shank)
    # each determined parameter's interval carried to its figure quantity (both ends evaluated)
    bounds: dict[str, dict[str, tuple[float, float]]] = {k: {} for k in FIGURE_QUANTITIES}
    for name, (lo, hi) in idf.ci95.items():
        ends = [representative_values(leg, {**res.parameters, name: v}, shank) for v in (lo, hi)]
        muscle = name.split(".")[0]
        for key, what in FIGURE_QUANTITIES.items():
            if name.endswith(what) and muscle in ends[0][key]:
                a, b = ends[0][key][muscle], ends[1][key][muscle]
                bounds[key][muscle] = (min(a, b), max(a, b))
    for ax, (key, unit, title) in zip(axes, (("slack_per_shank", "slack length / shank length",
                                              "tendon slack length (Fig. 3.15)"),
                                             ("tendon_kN_per_m", "kN/m", "tendon stiffness (Fig. 3.16)"),
                                             ("muscle_N_per_m", "kN/m", "muscle stiffness (Fig. 3.17)"))):
        muscles = list(fitted[key])
        x = np.arange(len(muscles))
        ok = [f"{m}.{FIGURE_QUANTITIES[key]}" in det for m in muscles]
        unit_scale = 1e-3 if key == "muscle_N_per_m" else 1.0  # muscle stiffness in kN/m, as the tendons'
        values = [unit_scale * fitted[key][m] for m in muscles]
        bounds[key] = {m: (unit_scale * lo, unit_scale * hi) for m, (lo, hi) in bounds[key].items()}
        ax.bar(x - 0.2, [unit_scale * generic[key][m] for m in muscles], 0.4, facecolor="none", edgecolor="C1", lw=1.5)
        ax.bar(x + 0.2, values, 0.4, color=["C0" if o else "0.8" for o in ok],
               hatch=None, edgecolor=["C0" if o else "0.5" for o in ok])
        for i, (m, o) in enumerate(zip(muscles, ok)):
            if not o:
                ax.patches[len(muscles) + i].set_hatch("//")
            elif m in bounds[key]:
                lo, hi = bounds[key][m]
                ax.errorbar(x[i] + 0.2, values[i], yerr=[[values[i] - lo], [hi - values[i]]], color="k", capsize=3)
        spread = [v for v in values + [unit_scale * generic[key][m] for m in muscles] if v > 0]
        if spread and max(spread) / min(spread) > 10:
            ax.set_yscale("log")
        ax.set_xticks(x, muscles, rotation=60, fontsize=8)
        ax.set_ylabel(unit)
        ax.set_title(title, fontsize=10)
        ax.legend(handles=[Patch(facecolor="none", edgecolor="C1", label="generic (Rajagopal 2016)"),
                           Patch(color="C0", label="determined, with its 95 % interval"),
                           Patch(facecolor="0.8", edgecolor="0.5", hatch="//", label="not determined (the fit's value)")],
                  fontsize=7)
    return fig


def _fit_figure(report: PmpReport) -> Any:
    """Per trial: measured and fitted torque against angle (with a named extension's share, dashed), and
    measured and forward-simulated angle against time."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    res: PmpResult = report.result
    n = len(res.trials)
    width_in = 4.5 * n
    fig = Figure(figsize=(width_in, 6.5))
    FigureCanvasAgg(fig)
    # fixed margins (inches over the figure's size): a constrained layout drew the figure twice, 0.9 s of a report
    axes = fig.subplots(2, n, squeeze=False, gridspec_kw={"left": 0.8 / width_in, "right": 1 - 0.15 / width_in,
                                                            "bottom": 0.5 / 6.5, "top": 1 - 0.3 / 6.5,
                                                            "wspace": 0.9 / 4.5, "hspace": 0.75 / 3.25})
    for i, (tr, fd) in enumerate(zip(res.trials, report.forward_dynamics)):
        a, b = axes[0, i], axes[1, i]
        a.plot(np.rad2deg(tr["measured_angle_rad"]), tr["measured_torque_nm"], ".", ms=2, color="0.5", label="measured")
        a.plot(np.rad2deg(tr["angle_rad"]), tr["torque_nm"], color="C0", label="collocation fit")
        a.set_title(tr["name"])
        a.set_xlabel("angle (°)")
        a.set_ylabel("torque (N·m)")
        if report.extended is not None:  # what the named extension adds to this trial's model torque (u = −M)
            angle_deg, moment = report.extended.contribution_nm[i]
            a.plot(angle_deg, -np.asarray(moment), color="C3", lw=1, ls="--",
                   label=f"{report.extended.extension} (its share)")
        a.legend(fontsize=7)  # after every line, the extension's share included
        b.plot(tr["time_s"], np.rad2deg(tr["measured_angle_rad"]), ".", ms=2, color="0.5", label="measured")
        b.plot(fd.time_s, np.rad2deg(fd.simulated_angle_rad), color="C1", label="forward dynamics")
        b.set_xlabel("time (s)")
        b.set_ylabel("angle (°)")
        b.legend(fontsize=7)
    return fig


def write_plots(report: PmpReport, out_dir: str | Path) -> list[Path]:
    """Measured against simulated torque and angle per trial; parameters against the generic model."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "pmp_fit.png"]
    _fit_figure(report).savefig(files[0], dpi=100)
    files.append(out / "pmp_parameters.png")
    _parameter_figure(report).savefig(files[-1], dpi=100)
    (out / "pmp_report.json").write_text(json.dumps(to_json(report), indent=2, default=float))
    files.append(out / "pmp_report.json")
    return files
