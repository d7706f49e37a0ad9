"""Isokinetic trials whose passive moments OpenSim made, from known, perturbed parameters.

The protocol's sweeps (knee 0→90° at hip 90/55/15°, ankle 15→−30° dorsiflexion at knee 0/45/90°,
5 °/s, 100 Hz) of a subject whose muscles are Rajagopal 2016's with perturbed tendon slack
lengths, passive fibre strains and tendon strains. The passive moments come from OpenSim in a
subprocess (:mod:`benchmarks.opensim_passive`: its DeGrooteFregly2016 curves, ``getLength`` and
``computeMomentArm``) at 46 poses per sweep, interpolated by a cubic spline; the limb weight is
written here from Winter's segment table, independently of the estimator's code; sensor noise
is white on torque and angle. As on the instrument, no sweep goes past the dynamometer's
150 N·m torque ceiling: at hip 90° the generic hamstrings near full extension would need more,
so that sweep starts where the torque falls below it. Nothing of the estimator's path polynomials or curve code enters.

Variants (``variant=``): ``"base"`` (rigid knee tendons, relaxed), ``"realistic"`` (compliant
knee tendons and activation 0.01 — effects the estimator does not model).
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline


def _find_model() -> Path:
    """The generic model beside the repo (``../shared/models``), the workspace's shared copy, or
    ``INSTRUMENT_OSIM_MODEL``; the first that exists (else the first candidate, reported missing)."""
    import os

    candidates = [Path(os.environ["INSTRUMENT_OSIM_MODEL"])] if os.environ.get("INSTRUMENT_OSIM_MODEL") else []
    candidates += [Path(__file__).resolve().parents[2] / "shared" / "models" / "Rajagopal2016.osim",
                   Path("/work/shared/models/Rajagopal2016.osim")]
    return next((c for c in candidates if c.exists()), candidates[0])


MODEL = _find_model()
MUSCLES = ("bflh", "bfsh", "gaslat", "gasmed", "soleus", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem")
CALF = ("soleus", "gasmed", "gaslat")
KNEE_MUSCLES = tuple(m for m in MUSCLES if m not in ("soleus",))
RATE_HZ = 100.0
SPEED_DEG_S = 5.0
GRAVITY = 9.81
POSES_PER_SWEEP = 46


@dataclass
class TruthTrial:
    """One sweep (SI): the dynamometer torque u toward positive angle (arm weight removed)."""

    joint: str
    fixed_rad: dict[str, float]
    time_s: np.ndarray
    angle_rad: np.ndarray
    velocity_rad_s: np.ndarray
    torque_nm: np.ndarray
    passive_nm: np.ndarray  # OpenSim's passive muscle moment at the true angle (noise-free)
    name: str
    true_angle_rad: np.ndarray  # the angle without sensor noise


def model_path() -> Path:
    if not MODEL.exists():
        raise FileNotFoundError(f"{MODEL}: the generic model (shared, not in the repo) is needed for OpenSim truth")
    return MODEL


def opensim(request: dict[str, Any], timeout_s: float = 600.0) -> dict[str, Any]:
    """Ask :mod:`benchmarks.opensim_passive` in a child interpreter."""
    out = subprocess.run([sys.executable, "-m", "benchmarks.opensim_passive"], input=json.dumps(request),
                         capture_output=True, text=True, timeout=timeout_s, cwd=Path(__file__).resolve().parents[1])
    if out.returncode != 0:
        raise RuntimeError(f"OpenSim truth failed: {out.stderr[-2000:]}")
    from .opensim_passive import ANSWER_MARKER

    try:
        return json.loads(out.stdout.split(ANSWER_MARKER, 1)[-1])
    except json.JSONDecodeError as err:
        raise RuntimeError(f"OpenSim truth answered no JSON ({err}): {out.stdout[:300]!r} {out.stderr[-1000:]!r}") from err


#: OpenSim's answers kept by what was asked (see :func:`remembered_opensim`); written only with
#: ``INSTRUMENT_OPENSIM_ANSWERS=write``
ANSWERS = Path(__file__).resolve().parent / "data" / "opensim_answers"
#: the parts of an answer :func:`make_trials` and :func:`generic_parameters` read (the rest is not kept)
_KEPT = ("moments_nm", "tendon_slack_length_m", "limit_moments_nm", "muscles", "shank_length_m", "thigh_length_m")


def answer_key(request: dict[str, Any]) -> str:
    """What identifies an answer: the request without the model's path, the model file's content, the child's
    source (:mod:`benchmarks.opensim_passive`) and OpenSim's version (SHA-256, hex)."""
    import hashlib
    from importlib.metadata import PackageNotFoundError, version

    try:
        opensim_version = version("opensim")
    except PackageNotFoundError:
        opensim_version = "absent"
    digest = hashlib.sha256
    asked = {k: v for k, v in request.items() if k != "model"}
    body = {"request": asked, "model_sha256": digest(Path(request["model"]).read_bytes()).hexdigest(),
            "child_sha256": digest((Path(__file__).parent / "opensim_passive.py").read_bytes()).hexdigest(),
            "opensim": opensim_version}
    return digest(json.dumps(body, sort_keys=True).encode()).hexdigest()


def remembered_opensim(request: dict[str, Any]) -> dict[str, Any]:
    """OpenSim's answer to ``request`` as :func:`opensim` gives it (the parts in ``_KEPT``), read from
    :data:`ANSWERS` when the same request of the same model to the same child and OpenSim version was answered
    before: the tests' subjects cost an OpenSim start and 46 poses × 6 sweeps (≈ 14 s) each otherwise. Only
    OpenSim writes these files (``INSTRUMENT_OPENSIM_ANSWERS=write``); a changed model, child or OpenSim misses
    them and asks OpenSim again, and ``tests/benchmarks/test_opensim_answers.py`` asks it again for one of them
    and compares."""
    import os

    path = ANSWERS / f"{answer_key(request)}.json"
    if path.exists():
        return dict(json.loads(path.read_text()))
    answer = {k: v for k, v in opensim(request).items() if k in _KEPT}
    if os.environ.get("INSTRUMENT_OPENSIM_ANSWERS") == "write":
        ANSWERS.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(answer))
    return answer


def generic_parameters() -> dict[str, dict[str, float]]:
    """The model's own parameters (after ``replaceMuscles``), from OpenSim."""
    return remembered_opensim({"what": "facts", "model": str(model_path())})["muscles"]


def draw_truth(seed: int, generic: dict[str, dict[str, float]], slack_spread: float = 0.05,
               strain_spread: float = 0.25) -> dict[str, dict[str, float]]:
    """Perturbed parameters: slack lengths ×U(1±slack_spread), strains ×U(1±strain_spread)."""
    rng = np.random.default_rng(seed)
    out = {}
    for m in MUSCLES:
        g = generic[m]
        out[m] = {"tendon_slack_length_m": g["tendon_slack_length_m"] * float(rng.uniform(1 - slack_spread, 1 + slack_spread)),
                  "passive_strain": g["passive_strain"] * float(rng.uniform(1 - strain_spread, 1 + strain_spread)),
                  "tendon_strain": g["tendon_strain"] * float(rng.uniform(1 - strain_spread, 1 + strain_spread))}
    return out


def sweeps() -> list[tuple[str, dict[str, float], float, float, str]]:
    """(moving joint, fixed angles rad, start deg, end deg, name) of the protocol's six sweeps."""
    out = [("knee", {"hip": np.radians(h), "ankle": 0.0}, 0.0, 90.0, f"knee hip {h}°") for h in (90, 55, 15)]
    out += [("ankle", {"hip": np.radians(90.0), "knee": np.radians(k)}, 15.0, -30.0, f"ankle knee {k}°")
            for k in (0, 45, 90)]
    return out


def limb_weight_nm(joint: str, angle_rad: np.ndarray, fixed: dict[str, float], mass_kg: float, shank_m: float,
                   foot_m: float) -> np.ndarray:
    """Weight of the segments distal to ``joint`` toward positive angle (N·m), seated, thigh level.

    Winter (2009): shank 4.65 % of body mass with its COM 43.3 % down from the knee, foot 1.45 %
    at the ankle's distance and, for the ankle, at half the foot length forward of the ankle.
    """
    if joint == "knee":
        lever = 0.0465 * mass_kg * 0.433 * shank_m + 0.0145 * mass_kg * shank_m
        return lever * GRAVITY * np.cos(angle_rad)
    lever = 0.0145 * mass_kg * 0.5 * foot_m
    return -lever * GRAVITY * np.cos(angle_rad + np.pi / 2 - fixed.get("knee", 0.0))


def make_trials(truth: dict[str, dict[str, float]], seed: int, *, variant: str = "base", mass_kg: float = 75.0,
                shank_m: float = 0.3965, foot_m: float = 0.26, torque_noise_nm: float = 0.1,
                angle_noise_deg: float = 0.1, max_torque_nm: float = 150.0,
                limit_forces: dict[str, dict[str, float]] | None = None,
                unmodelled_muscles: bool = False, set_angle_errors_rad: list[float] | None = None,
                compliant_knee_tendons: bool | None = None, activation: float | None = None,
                segment_scales: dict[str, float] | None = None,
                simulated_slack_m: dict[str, float] | None = None) -> list[TruthTrial]:
    """The six sweeps of one subject with ``truth`` parameters (OpenSim-made passive moments); with
    ``limit_forces`` OpenSim's ``CoordinateLimitForce`` at those coordinates' range ends, with
    ``unmodelled_muscles`` the passive forces of every other muscle crossing knee or ankle
    (:mod:`benchmarks.opensim_passive`); with ``set_angle_errors_rad`` (one per sweep) the fixed joint (hip
    for the knee sweeps, knee for the ankle ones) truly sits that far from the angle the trial records;
    ``compliant_knee_tendons`` and ``activation`` (every muscle's) each on their own (default: the variant's);
    ``segment_scales`` (per OpenSim body, an isotropic factor) scales the model with OpenSim's ``Model.scale``
    first (``truth``'s slack lengths then count relative to the generic ones), and ``simulated_slack_m``, if
    given, receives every muscle's slack length as simulated. ``shank_m`` and ``foot_m`` are the subject's
    (the limb weight's lever arms)."""
    rng = np.random.default_rng(10_000 + seed)
    plan = sweeps()
    poses, spans = [], []
    true_fixed = []
    for i, (joint, fixed, start, end, _) in enumerate(plan):
        grid = np.radians(np.linspace(start, end, POSES_PER_SWEEP))
        spans.append(grid)
        actual = dict(fixed)
        if set_angle_errors_rad is not None:
            other = "hip" if joint == "knee" else "knee"
            actual[other] = fixed.get(other, 0.0) + float(set_angle_errors_rad[i])
        true_fixed.append(actual)
        for q in grid:
            pose = {"hip": actual.get("hip", 0.0), "knee": actual.get("knee", 0.0), "ankle": actual.get("ankle", 0.0)}
            pose[joint] = float(q)
            poses.append(pose)
    request = {"model": str(model_path()), "parameters": truth, "poses": poses,
               "compliant_knee_tendons": variant == "realistic" if compliant_knee_tendons is None else compliant_knee_tendons,
               "activation": (0.01 if variant == "realistic" else 0.0) if activation is None else activation,
               "limit_forces": limit_forces or {}, "unmodelled_muscles": unmodelled_muscles,
               "segment_scales": segment_scales or {}}
    answer = remembered_opensim(request)
    if simulated_slack_m is not None:
        simulated_slack_m.update(answer["tendon_slack_length_m"])
    trials = []
    for i, ((joint, fixed, start, end, name), grid) in enumerate(zip(plan, spans)):
        moments = np.array(answer["moments_nm"][joint][i * POSES_PER_SWEEP:(i + 1) * POSES_PER_SWEEP])
        order = np.argsort(grid)
        spline = CubicSpline(grid[order], moments[order])
        duration = abs(end - start) / SPEED_DEG_S
        t = np.arange(0.0, duration, 1.0 / RATE_HZ)
        q = np.radians(start + np.sign(end - start) * SPEED_DEG_S * t)
        v = np.full(t.size, np.radians(SPEED_DEG_S) * np.sign(end - start))
        passive = spline(q)
        u = -(passive + limb_weight_nm(joint, q, true_fixed[i], mass_kg, shank_m, foot_m))
        # the dynamometer's torque ceiling: where the generic hamstrings at hip 90° would need more
        # (tens of kN in semimembranosus near full extension), the sweep starts where it falls below
        inside = np.abs(u) <= max_torque_nm
        first = int(np.argmax(inside))
        last = first + int(np.argmin(inside[first:])) if not inside[first:].all() else t.size
        t, q, v, passive, u = t[first:last] - t[first], q[first:last], v[first:last], passive[first:last], u[first:last]
        trials.append(TruthTrial(joint, dict(fixed), t, q + np.radians(angle_noise_deg) * rng.standard_normal(t.size),
                                 v, u + torque_noise_nm * rng.standard_normal(t.size), passive, name, q))
    return trials


def path_geometry(poses: list[dict[str, float]]) -> dict[str, Any]:
    """OpenSim's path lengths and moment arms at ``poses`` (generic parameters)."""
    return opensim({"model": str(model_path()), "poses": poses})
