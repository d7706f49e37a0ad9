"""OpenSim as the independent truth of passive joint moments (run in its own interpreter).

    python -m benchmarks.opensim_passive < request.json > answer.json

Imports only OpenSim, NumPy and the standard library: OpenSim's bundled CasADi cannot share a
process with the ``casadi`` wheel, and nothing of the estimator's model may leak into its truth.

The request names the ``.osim`` model, the muscles' parameters, the poses and the variant:

* Rajagopal 2016's muscles replaced by ``DeGrooteFregly2016Muscle`` (OpenSim's own curves and
  pennation model);
* ``parameters``: per muscle (``bflh`` …), any of ``tendon_slack_length_m``, ``passive_strain``
  (ε₀) and ``tendon_strain`` (ε_T0); the others keep the model's values;
* ``compliant_knee_tendons``: False (default) makes every muscle but the calf ones rigid-tendoned;
* ``activation``: the muscles' activation (0 for a relaxed subject; 0.01 is DGF's minimum);
* ``poses``: list of ``{"hip": rad, "knee": rad, "ankle": rad}``;
* ``unmodelled_muscles``: True adds the passive forces of every other right-leg muscle crossing the
  knee or the ankle (gracilis, sartorius, tensor fasciae latae, the toe extensors and flexors, the
  peronei, tibialis anterior and posterior: :data:`OTHER_MUSCLES`) at the model's own parameters;
* ``limit_forces``: OpenSim's own ``CoordinateLimitForce`` per coordinate, ``{"knee": {"upper_deg",
  "upper_stiffness_Nm_per_deg", "lower_deg", "lower_stiffness_Nm_per_deg", "transition_deg"}, ...}``
  (capsule and ligaments at the range's ends); their generalized force (``calcLimitForce``) is added
  to the coordinate's moment;
* ``segment_scales``: per body (``femur_r``, ``tibia_r``, ``talus_r`` …), an isotropic scale factor applied
  with OpenSim's own ``Model.scale`` (what the Scale Tool does with manual factors; the muscles' optimal fibre
  and tendon slack lengths follow their paths, as OpenSim scales them). ``parameters``' slack lengths are
  then taken relative to the unscaled model's (the subject's draw about the generic muscle) and applied to the
  scaled ones; the answer's ``tendon_slack_length_m`` holds every muscle's slack length as simulated.

At each pose the coordinates are set and the pose assembled; each muscle's tendon force at rest
comes from OpenSim's own curves (``calcPassiveForceMultiplier``, ``calcTendonForceMultiplier``,
``calcActiveForceLengthMultiplier``), its path length (``getLength``) and pennation, the
fibre–tendon equilibrium solved by bisection (``Model.equilibrateMuscles`` cannot bracket a slack
muscle); the passive joint moment about each of the hip, knee and ankle coordinates is
Σ tendon force × ``computeMomentArm``. The answer holds those moments
(N·m, toward positive coordinate) and, per muscle, the path length and moment arms (m), so the
estimator's path model can be held against OpenSim's at the same poses.
"""

from __future__ import annotations

import json
import sys
from typing import Any

MUSCLES = ("bflh", "bfsh", "gaslat", "gasmed", "soleus", "semimem", "semiten", "vasint", "vaslat", "vasmed", "recfem")
CALF = ("soleus", "gasmed", "gaslat")
COORDINATES = {"hip": "hip_flexion_r", "knee": "knee_angle_r", "ankle": "ankle_angle_r"}
#: the line before the JSON answer on stdout (OpenSim's log lines may come first)
ANSWER_MARKER = "@@opensim-passive-answer@@"
#: muscles of Rajagopal 2016 crossing the knee or ankle that the estimator does not model
OTHER_MUSCLES = ("grac", "sart", "tfl", "edl", "ehl", "fdl", "fhl", "perbrev", "perlong", "tibant", "tibpost")


def model_facts(model_path: str) -> dict[str, Any]:
    """The generic model's segment lengths (m) between joint centres, and the muscles' parameters."""
    import numpy as np
    import opensim as osim

    osim.Logger.setLevelString("error")
    model = osim.Model(model_path)
    osim.DeGrooteFregly2016Muscle.replaceMuscles(model)
    state = model.initSystem()
    model.realizePosition(state)
    joints = model.getJointSet()

    def at(frame: Any) -> Any:
        p = frame.getPositionInGround(state)
        return np.array([p.get(i) for i in range(3)])

    shank = float(np.linalg.norm(at(joints.get("walker_knee_r").getChildFrame()) - at(joints.get("ankle_r").getParentFrame())))
    thigh = float(np.linalg.norm(at(joints.get("hip_r").getChildFrame()) - at(joints.get("walker_knee_r").getParentFrame())))
    muscles = {}
    for name in MUSCLES:
        m = osim.DeGrooteFregly2016Muscle.safeDownCast(model.getMuscles().get(f"{name}_r"))
        muscles[name] = {"tendon_slack_length_m": m.getTendonSlackLength(),
                         "passive_strain": m.get_passive_fiber_strain_at_one_norm_force(),
                         "tendon_strain": m.get_tendon_strain_at_one_norm_force(),
                         "optimal_fiber_length_m": m.getOptimalFiberLength(),
                         "max_isometric_force_n": m.getMaxIsometricForce(),
                         "pennation_at_optimal_rad": m.getPennationAngleAtOptimalFiberLength()}
    return {"shank_length_m": shank, "thigh_length_m": thigh, "muscles": muscles}


def path_geometry(request: dict[str, Any]) -> dict[str, Any]:
    """Path lengths (``getLength``) and moment arms (``computeMomentArm`` about hip, knee and ankle), m,
    of the muscles in ``request["muscles"]`` (default all) at ``request["poses"]``: no forces."""
    import opensim as osim

    osim.Logger.setLevelString("error")
    model = osim.Model(request["model"])
    osim.DeGrooteFregly2016Muscle.replaceMuscles(model)
    state = model.initSystem()
    coords = {k: model.getCoordinateSet().get(v) for k, v in COORDINATES.items()}
    names = list(request.get("muscles") or MUSCLES)
    muscles = {n: model.getMuscles().get(f"{n}_r") for n in names}
    joints = request.get("joints") or {n: list(COORDINATES) for n in names}
    lengths: dict[str, list[float]] = {n: [] for n in names}
    arms: dict[str, dict[str, list[float]]] = {n: {k: [] for k in joints[n]} for n in names}
    for pose in request["poses"]:
        for k, c in coords.items():
            c.setValue(state, float(pose[k]), False)
        model.assemble(state)
        model.realizePosition(state)
        for n, m in muscles.items():
            lengths[n].append(m.getLength(state))
            for k in joints[n]:
                arms[n][k].append(m.computeMomentArm(state, coords[k]))
    return {"path_length_m": lengths, "moment_arm_m": arms}


#: the bodies each measured segment's scale factor applies to (as a Scale Tool setup would group them)
SEGMENT_BODIES = {"thigh": ("pelvis", "femur_r", "patella_r"), "shank": ("tibia_r",),
                  "foot": ("talus_r", "calcn_r", "toes_r")}


def segment_fractions(request: dict[str, Any]) -> dict[str, Any]:
    """How each muscle's path length follows each segment's scale: (ΔL/L)/δ when the segment's bodies are
    scaled by 1 + δ (``request["step"]``, default 0.02) with ``Model.scale``, at ``request["poses"]``. One
    segment's fractions of all three sum to about 1 (a uniform scale lengthens every path by δ)."""
    import opensim as osim

    osim.Logger.setLevelString("error")
    step = float(request.get("step", 0.02))
    names = list(request.get("muscles") or MUSCLES)

    def lengths(segment: str | None) -> list[list[float]]:
        model = osim.Model(request["model"])
        if segment is not None:
            scales = osim.ScaleSet()
            for body in SEGMENT_BODIES[segment]:
                scale = osim.Scale()
                scale.setSegmentName(body)
                scale.setScaleFactors(osim.Vec3(1.0 + step, 1.0 + step, 1.0 + step))
                scale.setApply(True)
                scales.cloneAndAppend(scale)
            state = model.initSystem()
            if not model.scale(state, scales, True, -1.0):
                raise RuntimeError("OpenSim could not scale the model")
        state = model.initSystem()
        coords = {k: model.getCoordinateSet().get(v) for k, v in COORDINATES.items()}
        out = []
        for pose in request["poses"]:
            for k, c in coords.items():
                c.setValue(state, float(pose[k]), False)
            model.assemble(state)
            model.realizePosition(state)
            out.append([model.getMuscles().get(f"{n}_r").getLength(state) for n in names])
        return out

    base = lengths(None)
    fractions: dict[str, dict[str, list[float]]] = {n: {} for n in names}
    for segment in SEGMENT_BODIES:
        scaled = lengths(segment)
        for i, n in enumerate(names):
            fractions[n][segment] = [(s[i] - b[i]) / b[i] / step for s, b in zip(scaled, base)]
    return {"step": step, "bodies": {k: list(v) for k, v in SEGMENT_BODIES.items()}, "fractions": fractions}


def passive_moments(request: dict[str, Any]) -> dict[str, Any]:
    """Answer one request (see the module docstring)."""
    import opensim as osim

    osim.Logger.setLevelString("error")
    model = osim.Model(request["model"])
    osim.DeGrooteFregly2016Muscle.replaceMuscles(model)
    slack_factor: dict[str, float] = {}
    if request.get("segment_scales"):
        generic = {n: model.getMuscles().get(f"{n}_r").getTendonSlackLength() for n in MUSCLES + OTHER_MUSCLES}
        scales = osim.ScaleSet()
        for body, factor in request["segment_scales"].items():
            scale = osim.Scale()
            scale.setSegmentName(body)
            scale.setScaleFactors(osim.Vec3(float(factor), float(factor), float(factor)))
            scale.setApply(True)
            scales.cloneAndAppend(scale)
        state = model.initSystem()
        if not model.scale(state, scales, True, -1.0):
            raise RuntimeError("OpenSim could not scale the model")
        slack_factor = {n: model.getMuscles().get(f"{n}_r").getTendonSlackLength() / generic[n] for n in generic}
    activation = float(request.get("activation", 0.0))
    compliant_knee = bool(request.get("compliant_knee_tendons", False))
    everyone = MUSCLES + (OTHER_MUSCLES if request.get("unmodelled_muscles") else ())
    limits = {}
    for key, spec in (request.get("limit_forces") or {}).items():
        clf = osim.CoordinateLimitForce(COORDINATES[key], float(spec["upper_deg"]), float(spec["upper_stiffness_Nm_per_deg"]),
                                        float(spec["lower_deg"]), float(spec["lower_stiffness_Nm_per_deg"]), 0.0,
                                        float(spec.get("transition_deg", 2.0)))
        clf.setName(f"{key}_limit")
        model.addForce(clf)
        limits[key] = clf
    for name in everyone:
        m = osim.DeGrooteFregly2016Muscle.safeDownCast(model.getMuscles().get(f"{name}_r"))
        p = request.get("parameters", {}).get(name, {})
        if "tendon_slack_length_m" in p:
            m.setTendonSlackLength(float(p["tendon_slack_length_m"]) * slack_factor.get(name, 1.0))
        if "passive_strain" in p:
            m.set_passive_fiber_strain_at_one_norm_force(float(p["passive_strain"]))
        if "tendon_strain" in p:
            m.set_tendon_strain_at_one_norm_force(float(p["tendon_strain"]))
        m.set_ignore_tendon_compliance(name not in CALF and not compliant_knee)
        m.set_min_control(0.0)
        m.set_default_activation(max(activation, 0.01))  # must be > 0; the state gets the asked value below
    state = model.initSystem()
    coords = {k: model.getCoordinateSet().get(v) for k, v in COORDINATES.items()}
    muscles = {name: osim.DeGrooteFregly2016Muscle.safeDownCast(model.getMuscles().get(f"{name}_r"))
               for name in everyone}
    moments: dict[str, list[float]] = {k: [] for k in COORDINATES}
    lengths: dict[str, list[float]] = {name: [] for name in everyone}
    arms: dict[str, dict[str, list[float]]] = {name: {k: [] for k in COORDINATES} for name in everyone}
    forces: dict[str, list[float]] = {name: [] for name in everyone}
    limit_moments: dict[str, list[float]] = {k: [] for k in limits}
    for pose in request["poses"]:
        for k, c in coords.items():
            c.setValue(state, float(pose[k]), False)
            c.setSpeedValue(state, 0.0)
        model.assemble(state)
        model.realizePosition(state)
        total = {k: 0.0 for k in COORDINATES}
        for name, m in muscles.items():
            path_length = m.getLength(state)
            f = _static_tendon_force(m, path_length, activation)
            forces[name].append(f)
            lengths[name].append(path_length)
            for k, c in coords.items():
                r = m.computeMomentArm(state, c)
                arms[name][k].append(r)
                total[k] += f * r
        model.realizeVelocity(state)
        for k, clf in limits.items():
            limit_moments[k].append(clf.calcLimitForce(state))
            total[k] += limit_moments[k][-1]
        for k in COORDINATES:
            moments[k].append(total[k])
    return {"moments_nm": moments, "path_length_m": lengths, "moment_arm_m": arms, "tendon_force_n": forces,
            "limit_moments_nm": limit_moments,
            "tendon_slack_length_m": {name: m.getTendonSlackLength() for name, m in muscles.items()}}


def _static_tendon_force(m: Any, path_length_m: float, activation: float) -> float:
    """Tendon force (N) of a DGF muscle at rest at ``path_length_m``: OpenSim's own curves, its
    constant-thickness pennation, and the fibre–tendon equilibrium solved by bisection here
    (``Model.equilibrateMuscles`` fails to bracket slack muscles)."""
    import math

    l_opt, f_max = m.getOptimalFiberLength(), m.getMaxIsometricForce()
    slack = m.getTendonSlackLength()
    height = l_opt * math.sin(m.getPennationAngleAtOptimalFiberLength())

    def fibre_along(tendon_length: float) -> float:
        along = max(path_length_m - tendon_length, 1e-9)
        fibre = math.hypot(along, height)
        norm = fibre / l_opt
        multiplier = activation * m.calcActiveForceLengthMultiplier(norm) + m.calcPassiveForceMultiplier(norm)
        return f_max * multiplier * along / fibre

    if m.get_ignore_tendon_compliance():
        return max(fibre_along(slack), 0.0)
    lo, hi = slack * 0.98, min(path_length_m - 1e-9, slack * 1.3)
    if hi <= lo:  # the path is shorter than the slack tendon: nothing pulls
        return max(f_max * m.calcTendonForceMultiplier(max(path_length_m, 1e-9) / slack), 0.0)

    def residual(tendon_length: float) -> float:
        return f_max * m.calcTendonForceMultiplier(tendon_length / slack) - fibre_along(tendon_length)

    if residual(lo) > 0:
        return max(f_max * m.calcTendonForceMultiplier(lo / slack), 0.0)
    if residual(hi) < 0:
        return max(f_max * m.calcTendonForceMultiplier(hi / slack), 0.0)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if residual(mid) > 0:
            hi = mid
        else:
            lo = mid
    return max(f_max * m.calcTendonForceMultiplier(0.5 * (lo + hi) / slack), 0.0)


def main() -> int:
    request = json.load(sys.stdin)
    if request.get("what") == "facts":
        answer = model_facts(request["model"])
    elif request.get("what") == "paths":
        answer = path_geometry(request)
    elif request.get("what") == "segment_fractions":
        answer = segment_fractions(request)
    else:
        answer = passive_moments(request)
    # OpenSim's logger writes to stdout too (an assembly that misses its tolerance by 1e-9 at some pose):
    # the answer follows a marker line, and the reader takes what comes after it
    sys.stdout.write("\n" + ANSWER_MARKER + "\n")
    json.dump(answer, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
