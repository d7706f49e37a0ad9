"""A study's passive-parameter fits as independent work items: one subject's fit, or one bootstrap refit.

Every work item (:class:`FitTask`) is plain data (numpy arrays, floats, strings): it crosses
process boundaries by pickling, and the CasADi problem is built inside :func:`run_fit_task`, in
the process that solves it. A task's :attr:`FitTask.key` is a SHA-256 of everything that decides
its result (the trials' samples, the subject, the settings, the resample's seed and this module's
:data:`METHOD_VERSION`), so the same task always has the same key: a stored result is re-used, a
changed trial gives a new key.

Bootstrap (:func:`bootstrap_trials`): replicate ``b ≥ 1`` of a subject resamples its sweeps.

* A condition (joint and fixed angles) recorded two or more times: that many trials drawn with
  replacement from its repeats (whole trials, so the interval carries trial-to-trial variability).
* A condition recorded once: its residual about the subject's fit (sample-level, quasi-static
  model torque) is resampled in circular moving blocks of twice the residual's integrated
  autocorrelation time (at least 1 s) and added back to the fitted torque (a block bootstrap of
  the sweep: serial correlation and model misfit kept, trial-to-trial variability not seen).

The 95 % interval of a parameter is the subject's estimate ± (√((t(0.975, B−1) · SD of its B
bootstrap estimates)² + (1.96 · the SE its measured inputs cause, ``identifiability(...).measurement_se_rel``)²)
+ the bound on the bias the muscle model's own error can cause, ``identifiability(...).model_error_bound_rel``):
resampling sees the noise, not the tape's, goniometer's or scale's error, nor the model's systematic error. Without
the measured inputs' share, a tape-error subject's slack length 0.48 % off lay outside its interval (`benchmarks
cohort`, seed 20000). The percentile interval of the bootstrap estimates is reported beside it. A parameter counts as
*determined* when the subject's fit says so (:func:`analysis.pmp.estimator.identifiability`) and
the bootstrap interval is within ±3.5 % (the dissertation's accuracy).

A model extension (:attr:`FitTask.extension`): every fit of the subject (its own and each resample's) has the
extension's terms beside the muscles' (:mod:`analysis.pmp.model_diagnosis`), and the resamples are drawn about
the extended model's torque. :data:`DIAGNOSED` asks for the model-level diagnosis of the subject's trials first:
the extension it names, if any, is then the subject's, and its resamples are fitted with it (the diagnosis's
choice is not resampled: the intervals are conditional on it).
"""

from __future__ import annotations

import hashlib
import math
import os
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .identifiability import autocorrelation_time, identifiability, smoothed
from .model import PmpTrial, Subject, moment_function, with_set_angles
from .muscles import LegMuscles
from .problem import estimate
from .workers import mapped

#: bumped when a change to the fit or the resampling changes results (invalidates stored results)
METHOD_VERSION = "cohort-7"  # cohort-7: the refit also from the diagnosis's fit, plausible models in the intervals
#: half-width limit of a determined parameter's bootstrap interval (relative): the dissertation's 3.5 %
DETERMINED_HALF_WIDTH_REL = 0.035
#: shortest residual block of the sweep bootstrap (s)
MIN_BLOCK_S = 1.0
#: :attr:`FitTask.extension` asking for each subject's model-level diagnosis first (its named extension fitted)
DIAGNOSED = "diagnosed"


@dataclass
class FitTask:
    """One solve: a subject's trials (as recorded, or a bootstrap resample) and the settings.

    :ivar replicate: 0 for the fit of the trials as recorded; b ≥ 1 for bootstrap replicate b.
    :ivar intervals: collocation intervals per trial.
    :ivar initial: parameters to start from (the subject's fit, for a bootstrap refit), or None.
    :ivar inputs: what the trials came from (store trial ids, file SHA-256), recorded with the result.
    :ivar extension: a model extension fitted beside the muscles (a name of
        :data:`analysis.pmp.model_diagnosis.EXTENSIONS`, two joined by ``+``), :data:`DIAGNOSED` (replicate 0
        only: the subject's model-level diagnosis chooses), or None (the muscle model alone).
    """

    subject_code: str
    replicate: int
    trials: list[PmpTrial]
    subject: Subject
    intervals: int = 12
    initial: dict[str, float] | None = None
    inputs: dict[str, Any] = field(default_factory=dict)
    extension: str | None = None

    @property
    def key(self) -> str:
        """SHA-256 of everything that decides the result (not of ``initial``: a start point)."""
        h = hashlib.sha256()
        h.update(f"{METHOD_VERSION}|{self.subject_code}|{self.replicate}|{self.intervals}|".encode())
        s = self.subject
        h.update(f"{s.mass_kg!r}|{s.shank_length_m!r}|{s.foot_length_m!r}|{s.arm_inertia_kgm2!r}|".encode())
        h.update(f"{s.shank_length_sd_m!r}|{s.set_angle_sd_rad!r}|{s.mass_sd_kg!r}|".encode())  # in the intervals
        if s.thigh_length_m is not None:  # (a subject without a thigh measurement keeps its earlier keys)
            h.update(f"thigh={s.thigh_length_m!r}|{s.thigh_length_sd_m!r}|".encode())
        if self.extension:  # (the muscle model alone keeps the keys it had before extensions were offered)
            h.update(f"extension={self.extension}|".encode())
        for t in self.trials:
            h.update(f"{t.joint}|{sorted(t.fixed_rad.items())!r}|".encode())
            for a in (t.time_s, t.angle_rad, t.velocity_rad_s, t.torque_nm):
                h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
        return h.hexdigest()


def condition_of(trial: PmpTrial) -> tuple[str, tuple[tuple[str, float], ...]]:
    """The trial's condition: the moving joint and its fixed angles (rounded to 0.1°)."""
    return trial.joint, tuple(sorted((k, round(math.degrees(v), 1)) for k, v in trial.fixed_rad.items()))


def fitted_torque_nm(trial: PmpTrial, subject: Subject, parameters: dict[str, float], leg: LegMuscles) -> np.ndarray:
    """The quasi-static model's dynamometer torque at the trial's (smoothed) angles (N·m)."""
    f = mapped(moment_function(leg, trial, parameters), trial.angle_rad.size)
    q = smoothed(trial.angle_rad)
    moment = np.asarray(f(q.reshape(1, -1))).ravel()
    return -(moment + subject.gravity_moment_nm(trial.joint, q, trial.fixed_rad))


def run_fit_task(task: FitTask) -> dict[str, Any]:
    """Solve one task (in whatever process runs it); a JSON-able result, never an exception for a
    fit that did not converge (``success`` False, with the solver's message).

    The fit of the trials as recorded (replicate 0) also carries what the study reports and the
    bootstrap needs: the identifiability analysis, the forward-dynamics errors per trial and the
    fitted torque of every trial.
    """
    from .identifiability import with_plausible_models
    from .model_diagnosis import diagnose_model, fit_extended, fit_plausible, get_extension, predict_torque_nm
    from .verify import forward_dynamics

    started = time.perf_counter()
    leg = task.subject.leg()
    name = task.extension
    diagnosis = None
    if name == DIAGNOSED or (name and task.replicate == 0):
        plain = estimate(task.trials, task.subject, leg=leg, intervals=task.intervals, initial=task.initial)
        if name == DIAGNOSED:
            # one process: a study's subjects are already fitted side by side
            diagnosis = diagnose_model(task.trials, task.subject, leg=leg, intervals=task.intervals, plain=plain,
                                       workers=1)
            name = None if diagnosis.cause == "none" else diagnosis.cause
    extension = get_extension(name) if name else None
    if extension is None:
        res = plain if diagnosis is not None else estimate(task.trials, task.subject, leg=leg,
                                                           intervals=task.intervals, initial=task.initial)
    elif task.replicate == 0:  # as the single-subject report refits: from the plain fit, the generic model and
        # the diagnosis's own fit of the named model
        res = fit_extended(task.trials, task.subject, extension, leg=leg, intervals=task.intervals, plain=plain,
                           found=diagnosis.named_fit if diagnosis is not None else None)
    else:  # a resample, from the subject's extended fit
        res = estimate(task.trials, task.subject, leg=leg, intervals=task.intervals, initial=task.initial,
                       extension=extension)
    out: dict[str, Any] = {
        "key": task.key, "subject_code": task.subject_code, "replicate": task.replicate,
        "parameters": dict(res.parameters), "generic": dict(res.generic), "success": bool(res.success),
        "status": res.solver_status, "message": res.message, "iterations": int(res.nit),
        "solve_time_s": float(res.solve_time_s), "inputs": task.inputs, "intervals": task.intervals,
        "method_version": METHOD_VERSION, "extension": name,
        "extension_parameters": {k: float(v) for k, v in res.extension_parameters.items()},
    }
    if diagnosis is not None:
        out["model_diagnosis"] = {"cause": diagnosis.cause, "message": diagnosis.message,
                                  "conclusive": diagnosis.conclusive, "ambiguous_with": list(diagnosis.ambiguous_with),
                                  "plausible": list(diagnosis.plausible)}
    if task.replicate == 0:
        idf = identifiability(res, task.trials, task.subject, leg=leg, extension=extension)
        if diagnosis is not None and diagnosis.plausible:  # model uncertainty, as the single-subject report has it
            alternatives = fit_plausible(task.trials, task.subject, diagnosis.plausible, leg=leg,
                                         intervals=task.intervals, plain=plain, named=res, named_extension=extension)
            idf = with_plausible_models(idf, res, [(n, r, identifiability(r, task.trials, task.subject, leg=leg,
                                                                          extension=e)) for n, r, e in alternatives])
        out["identifiability"] = {k: getattr(idf, k) for k in ("determined", "undetermined", "ci95", "misfit_ratio",
                                                       "residual_rms_nm", "noise_nm", "not_determined_because",
                                                       "at_bound", "model_error_bound_rel", "measurement_se_rel",
                                                       "model_alternatives")}
        # the extended model simulated at the set angles its fit found, as the single-subject report does
        fd_trials = with_set_angles(task.trials, res.set_angle_offsets_rad) if extension is not None else task.trials
        fd = [forward_dynamics(t, task.subject, res.parameters, leg=leg, extension=extension,
                               extension_parameters=res.extension_parameters) for t in fd_trials]
        out["forward_dynamics"] = [{"trial": v.name, "angle_rmse_deg": float(v.angle_rmse_deg),
                                    "torque_rmse_nm_per_kg": float(v.torque_rmse_nm_per_kg)} for v in fd]
        if extension is None:
            out["fitted_torque_nm"] = [fitted_torque_nm(t, task.subject, res.parameters, leg).tolist()
                                       for t in task.trials]
        else:  # the extended model's torque (its terms included): the resamples are drawn about it
            out["fitted_torque_nm"] = [predict_torque_nm(res, t, task.subject, leg, extension,
                                                         indices=np.arange(t.time_s.size))[1].tolist()
                                       for t in task.trials]
        out["trial_names"] = [t.name for t in task.trials]
    out["task_seconds"] = time.perf_counter() - started
    out["worker_pid"] = os.getpid()
    return out


def _block_resample(residual: np.ndarray, block: int, rng: np.random.Generator) -> np.ndarray:
    """A circular moving-block resample of ``residual`` (same length)."""
    n = residual.size
    block = max(1, min(block, n))
    starts = rng.integers(0, n, size=math.ceil(n / block))
    idx = (starts[:, None] + np.arange(block)[None, :]).ravel()[:n] % n
    return residual[idx]


def bootstrap_trials(trials: list[PmpTrial], fitted_torque: list[np.ndarray], replicate: int,
                     seed: int = 0) -> list[PmpTrial]:
    """Replicate ``replicate`` (≥ 1) of a subject's trials (see the module docstring for the scheme).

    :param fitted_torque: the subject's fitted torque per trial (N·m), from its replicate-0 result.
    """
    if replicate < 1:
        raise ValueError("bootstrap replicates are numbered from 1")
    rng = np.random.default_rng([seed, replicate])
    groups: dict[Any, list[int]] = {}
    for i, t in enumerate(trials):
        groups.setdefault(condition_of(t), []).append(i)
    out: list[PmpTrial] = []
    for members in groups.values():
        if len(members) >= 2:
            for pick in rng.choice(members, size=len(members), replace=True):
                t = trials[int(pick)]
                out.append(PmpTrial(t.joint, dict(t.fixed_rad), t.time_s, t.angle_rad, t.velocity_rad_s,
                                    t.torque_nm, f"{t.name} (drawn)"))
            continue
        t = trials[members[0]]
        fit = np.asarray(fitted_torque[members[0]], dtype=float)
        residual = t.torque_nm - fit
        dt = float(np.median(np.diff(t.time_s))) if t.time_s.size > 1 else 1.0
        block = max(int(round(2.0 * autocorrelation_time(residual))), int(math.ceil(MIN_BLOCK_S / dt - 1e-9)))
        torque = fit + _block_resample(residual, block, rng)
        out.append(PmpTrial(t.joint, dict(t.fixed_rad), t.time_s, t.angle_rad, t.velocity_rad_s, torque,
                            f"{t.name} (residual blocks of {block})"))
    return out


def subject_summary(main: dict[str, Any], replicates: list[dict[str, Any]],
                    truth: dict[str, float] | None = None) -> dict[str, Any]:
    """Every parameter of one subject with its bootstrap interval (and its error, given the truth).

    :param main: the replicate-0 result of :func:`run_fit_task`.
    :param replicates: the bootstrap results (failed fits are counted and left out).
    """
    from scipy import stats

    ok = [r for r in replicates if r["success"]]
    determined_fit = set(main.get("identifiability", {}).get("determined", []))
    bias_rel = main.get("identifiability", {}).get("model_error_bound_rel", {})
    measured_rel = main.get("identifiability", {}).get("measurement_se_rel", {})
    # with plausible models beside the named one, the fit's interval is the hull of the models' (model uncertainty,
    # identifiability.with_plausible_models): the bootstrap's, drawn about the named model only, is widened to hold it
    hull = main.get("identifiability", {}).get("ci95", {}) if main.get("identifiability", {}).get(
        "model_alternatives") else {}
    rows: dict[str, Any] = {}
    for name, value in main["parameters"].items():
        draws = np.array([r["parameters"][name] for r in ok])
        row: dict[str, Any] = {"estimate": value, "generic": main["generic"][name], "bootstrap_n": int(draws.size)}
        bias = float(bias_rel.get(name, 0.0)) * abs(value)
        if draws.size >= 2:
            sd = float(np.std(draws, ddof=1))
            measured = 1.96 * float(measured_rel.get(name, 0.0)) * abs(value)
            half = math.hypot(float(stats.t.ppf(0.975, draws.size - 1)) * sd, measured) + bias
            lo, hi = value - half, value + half
            if name in hull:
                lo, hi = min(lo, hull[name][0]), max(hi, hull[name][1])
                half = max(value - lo, hi - value)
            row.update(sd=sd, ci95=[lo, hi],
                       percentile95=[float(np.percentile(draws, 2.5)), float(np.percentile(draws, 97.5))])
            row["determined"] = bool(main["success"] and name in determined_fit
                                     and half <= DETERMINED_HALF_WIDTH_REL * abs(value))
        else:
            row.update(sd=None, ci95=None, percentile95=None, determined=False)
        if truth is not None and name in truth:
            row["truth"] = truth[name]
            row["error_pct"] = 100.0 * (value - truth[name]) / truth[name]
            if row["ci95"] is not None:
                row["covered"] = bool(row["ci95"][0] <= truth[name] <= row["ci95"][1])
        rows[name] = row
    fd = main.get("forward_dynamics", [])
    return {"subject_code": main["subject_code"], "success": main["success"], "message": main["message"],
            "parameters": rows, "bootstrap_failed": len(replicates) - len(ok),
            "forward_dynamics": fd,
            "misfit_ratio": main.get("identifiability", {}).get("misfit_ratio"),
            "extension": main.get("extension"), "extension_parameters": main.get("extension_parameters", {}),
            "model_diagnosis": main.get("model_diagnosis"),
            "not_determined_because": main.get("identifiability", {}).get("not_determined_because", [])}


def coverage(summaries: list[dict[str, Any]]) -> dict[str, Any]:
    """Coverage of the 95 % intervals and errors of the determined parameters against the truth."""
    covered, errors = [], []
    for s in summaries:
        for row in s["parameters"].values():
            if row.get("determined") and "covered" in row:
                covered.append(row["covered"])
                errors.append(abs(row["error_pct"]))
    return {"determined_with_truth": len(covered),
            "coverage_95": float(np.mean(covered)) if covered else None,
            "max_error_determined_pct": float(np.max(errors)) if errors else None,
            "median_error_determined_pct": float(np.median(errors)) if errors else None}
