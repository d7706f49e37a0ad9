"""A simulated study: N subjects with different, known passive muscle parameters, recorded through the drivers.

Each subject gets anthropometrics and muscle parameters drawn from a seed (mass 60–90 kg, shank
0.38–0.45 m, foot 0.23–0.28 m; slack lengths ×U(0.95, 1.05) of the scaled model's, ε₀ of the
non-calf muscles and ε_T0 of the calf tendons ×U(0.85, 1.15)). The simulated dynamometer's
subject then resists with that muscle model's passive moment (a table over the sweep, in place
of Riener & Edrich's equations), and the six trials (knee at hip 90/55/15°, ankle at knee
0/45/90°) go through the same drivers, acquisition and store as a real session. A sweep starts
where the passive moment is below :data:`SWEEP_TORQUE_LIMIT_NM` (a knee at hip 90° cannot be
straightened against tight hamstrings). The truth rides in each trial's metadata
(``study_truth``), for validation only: the analysis never reads it to fit.

A study may instead be given its subjects (:class:`StudyDraw`: the store's subject, the true parameters and
the moment table of each sweep), e.g. drawn from an independent model (``benchmarks.cohort`` draws them from
OpenSim, realistic subjects included); they go through the same drivers and store.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..kinds.ankle import AnkleProtocol
from ..kinds.isokinetic import IsokineticProtocol
from ..kinds.knee import KneeProtocol
from ..live.session import record_trial
from ..store import SessionStore, Subject
from .simulate import lab_config_for, simulated_devices, simulation_metadata

#: a sweep starts where the subject's passive moment (plus limb weight) is below this (N·m)
SWEEP_TORQUE_LIMIT_NM = 100.0
#: rooms recording at once (each trial is its own simulated lab)
ROOMS = 4


#: (sweep protocol) -> (angles deg ascending, passive moment N·m toward positive angles) over its range ±3°
MomentTable = Callable[[IsokineticProtocol], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class StudyDraw:
    """One subject of a simulated study: the store's record (what the lab entered), the true parameters
    (``muscle.parameter`` -> SI value, kept in the trials' metadata for validation only), the subject's passive
    moments per sweep and a name for where they came from (``variant``)."""

    subject: Subject
    truth: dict[str, float]
    moment_table: MomentTable
    variant: str = "muscle model"
    #: the body's true shank length (m) where the entered one is off (a tape error); None: as entered
    true_shank_length_m: float | None = None


def muscle_model_draw(index: int, seed: int = 0) -> StudyDraw:
    """Subject ``index`` of ``seed`` whose passive moments are the estimator's own muscle model's."""
    subject, truth = draw_subject(index, seed)
    leg = true_leg(subject, truth)
    return StudyDraw(subject, truth, lambda proto: passive_table(proto, leg))


def draw_subject(index: int, seed: int = 0) -> tuple[Subject, dict[str, float]]:
    """Subject ``index`` of the study drawn from ``seed``: the store's subject and the true parameters."""
    from analysis.pmp.estimator import PmpTrial, free_parameters
    from analysis.pmp.geometry import model_segment_lengths_m
    from analysis.pmp.muscles import COMPLIANT, LegMuscles, scale_for_subject

    rng = np.random.default_rng([seed, index, 20])
    mass = float(rng.uniform(60.0, 90.0))
    shank = float(rng.uniform(0.38, 0.45))
    foot = float(rng.uniform(0.23, 0.28))
    leg = LegMuscles(length_scale=scale_for_subject(shank))
    probe = [PmpTrial(p.joint, {}, np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3))
             for p in (KneeProtocol, AnkleProtocol)]  # the study's two sweeps
    truth: dict[str, float] = {}
    for name in free_parameters(leg, probe).names:
        m, what = name.split(".")
        generic = float(getattr(leg.params[m], what))
        if what == "tendon_slack_length_m":
            truth[name] = generic * float(rng.uniform(0.95, 1.05))
        elif what == "tendon_strain" and m in COMPLIANT or what == "passive_strain" and m not in COMPLIANT:
            truth[name] = generic * float(rng.uniform(0.85, 1.15))
        else:
            truth[name] = generic
    code = f"SIM{index + 1:02d}"
    # the body is the generic leg scaled by one factor: the lab's tape reads its thigh in that proportion
    segments = model_segment_lengths_m()
    thigh = segments["thigh_length_m"] * shank / segments["shank_length_m"]
    return Subject(code, "unknown", None, mass, None, thigh, shank, None, foot), truth


def true_leg(subject: Subject, truth: dict[str, float]) -> Any:
    """The muscle model of ``subject`` with its true parameters."""
    from analysis.pmp.muscles import LegMuscles, MuscleParameters, scale_for_subject

    leg = LegMuscles(length_scale=scale_for_subject(float(subject.shank_length_m or 0.42)))
    for m, p in list(leg.params.items()):
        leg.params[m] = MuscleParameters(truth.get(f"{m}.tendon_slack_length_m", p.tendon_slack_length_m),
                                         truth.get(f"{m}.passive_strain", p.passive_strain),
                                         truth.get(f"{m}.tendon_strain", p.tendon_strain))
    return leg


def passive_table(protocol: IsokineticProtocol, leg: Any) -> tuple[np.ndarray, np.ndarray]:
    """(position deg, moment N·m toward positive angles) of the subject's muscles over the sweep's range."""
    lo, hi = sorted((protocol.start_deg, protocol.end_deg))
    deg = np.arange(lo - 3.0, hi + 3.0 + 1e-9, 0.1)  # linear between: 0.1° keeps it under 0.01 N·m
    fixed = protocol.fixed_angles_deg()
    set_rad = dict(hip=np.deg2rad(fixed.get("hip_flexion_deg", 0.0)), knee=np.deg2rad(fixed.get("knee_flexion_deg", 0.0)),
                   ankle=np.deg2rad(fixed.get("ankle_dorsiflexion_deg", 0.0)))  # the joints' angles (rad)
    nm = [leg.joint_moment_nm(protocol.joint, **{**set_rad, protocol.joint: np.deg2rad(d)}) for d in deg]
    return deg, np.asarray(nm, dtype=float)


def subject_protocols(table: MomentTable,
                      speed_deg_s: float) -> list[tuple[IsokineticProtocol, tuple[np.ndarray, np.ndarray]]]:
    """The six sweeps, each starting where the passive moment (``table``) is within :data:`SWEEP_TORQUE_LIMIT_NM`,
    each with its table."""
    out: list[tuple[IsokineticProtocol, tuple[np.ndarray, np.ndarray]]] = []
    for proto in [KneeProtocol(hip_flexion_deg=h, speed_deg_s=speed_deg_s) for h in (90.0, 55.0, 15.0)] + \
                 [AnkleProtocol(knee_flexion_deg=k, speed_deg_s=speed_deg_s) for k in (0.0, 45.0, 90.0)]:
        deg, nm = table(proto)
        inside = (deg >= min(proto.start_deg, proto.end_deg)) & (deg <= max(proto.start_deg, proto.end_deg))
        ok = inside & (np.abs(nm) <= SWEEP_TORQUE_LIMIT_NM)
        if not ok.any():
            continue
        # start at the first tolerable angle along the sweep's direction (1° inside it)
        along = deg[ok] if proto.end_deg > proto.start_deg else deg[ok][::-1]
        start = float(along[0]) + (1.0 if proto.end_deg > proto.start_deg else -1.0)
        if abs(proto.end_deg - start) < 20.0:
            continue
        out.append((replace(proto, start_deg=start), (deg, nm)))
    return out


def record_study(store_dir: Path, subjects: int, *, seed: int = 0, speed_deg_s: float = 5.0,
                 progress: Any = print, draws: Sequence[StudyDraw] | None = None) -> SessionStore:
    """Record ``subjects`` simulated subjects' knee and ankle sweeps into the store at ``store_dir``.

    :param draws: the subjects (default: ``subjects`` drawn by :func:`muscle_model_draw` from ``seed``).
    :raises RecordingError, StoreError: as :func:`instrument.live.session.record_trial`.
    """
    store = SessionStore(store_dir)
    if draws is None:
        draws = [muscle_model_draw(i, seed) for i in range(subjects)]
    jobs: list[tuple[StudyDraw, int, IsokineticProtocol, tuple[np.ndarray, np.ndarray]]] = []
    for draw in draws:
        store.add_subject(draw.subject)
        session = store.new_session(draw.subject.code, operator="study-operator", notes="simulated study")
        jobs += [(draw, session, proto, table) for proto, table in subject_protocols(draw.moment_table, speed_deg_s)]
    lock = threading.Lock()
    errors: list[BaseException] = []
    done = [0]

    def room(k: int) -> None:
        for j, (draw, session, proto, (deg, nm)) in enumerate(jobs):
            if j % ROOMS != k or errors:
                continue
            subject = draw.subject
            try:
                shank = draw.true_shank_length_m or float(subject.shank_length_m or 0.42)
                cfg = lab_config_for(proto, seed=seed * 1000 + j, body_mass_kg=float(subject.mass_kg or 75.0),
                                     shank_length_m=shank, foot_length_m=float(subject.foot_length_m or 0.26))
                cfg.leg = replace(cfg.leg, passive_table_deg=tuple(deg.tolist()), passive_table_nm=tuple(nm.tolist()))
                with simulated_devices(proto, cfg) as (lab, devices):
                    meta = {**simulation_metadata(lab), "study_truth": draw.truth, "study_truth_variant": draw.variant}
                    out = record_trial(store, session, proto, devices, operator="study-operator", trial_number=1,
                                       extra_metadata=meta)
                with lock:
                    done[0] += 1
                    progress(f"  study: {done[0]}/{len(jobs)} trials recorded ({subject.code} {proto.name} "
                             f"{proto.fixed_joint_text()}: {out.status})")
            except BaseException as err:
                errors.append(err)

    threads = [threading.Thread(target=room, args=(k,), name=f"study-room-{k}") for k in range(ROOMS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        store.close()
        raise errors[0]
    return store
