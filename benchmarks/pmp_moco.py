"""The single-trial problem this estimator and OpenSim Moco both solve, for ``python -m benchmarks pmp``.

One degree of freedom (a knee pin, gravity along −y), one DeGroote–Fregly muscle with a rigid
tendon on a straight two-point path, a coordinate actuator standing for the dynamometer. The
"measured" trial: the knee moved 0→60° at 5 °/s, the torque that holds the passive muscle and
the shank's weight plus 0.3 N·m noise. Unknown: the tendon slack length. Both sides track angle,
velocity and torque with the same weights (eq 3.8: 1/σ² with σ_q = 0.5°, σ_v = 2 °/s,
σ_u = 0.5 N·m) on Hermite–Simpson collocation with 50 intervals. Ours is ``estimate`` with
this model plugged in; Moco is ``MocoStudy`` + ``MocoParameter`` + ``MocoStateTrackingGoal`` +
``MocoControlTrackingGoal`` with ``MocoCasADiSolver`` (``parameters_require_initsystem`` off, its
fastest setting), in a subprocess: OpenSim's bundled CasADi cannot share a process with ours.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tempfile
import textwrap
import time
from typing import Any

import numpy as np

from analysis.constants import GRAVITY_M_S2

MASS_KG = 3.5
COM_M = 0.25              # below the knee pin along the shank
INERTIA_COM_KGM2 = 0.06
ORIGIN_M = (0.0, 0.30)    # muscle origin on the ground (thigh), relative to the knee pin
INSERTION_M = (0.04, -0.12)  # insertion in the shank frame
F_MAX_N = 3000.0
FIBRE_OPT_M = 0.10
PASSIVE_STRAIN = 0.6
SLACK_TRUE_M = 0.280
SLACK_GENERIC_M = 0.270
INTERVALS = 50
G = GRAVITY_M_S2


def path_length(q: Any, backend: Any = np) -> Any:
    """Origin-to-insertion distance (m) at knee angle ``q`` (rad)."""
    px, py = INSERTION_M
    x = px * backend.cos(q) - py * backend.sin(q)
    y = px * backend.sin(q) + py * backend.cos(q)
    return backend.sqrt((x - ORIGIN_M[0]) ** 2 + (y - ORIGIN_M[1]) ** 2)


def trial(seed: int = 0) -> dict[str, np.ndarray]:
    """The simulated measurement (SI), quasi-static at 5 °/s."""
    from analysis.pmp.curves import passive_fiber_force

    t = np.linspace(0.0, 12.0, 241)
    q = np.deg2rad(5.0 * t)
    h = 1e-6
    dl = (path_length(q + h) - path_length(q - h)) / (2 * h)
    force = F_MAX_N * passive_fiber_force((path_length(q) - SLACK_TRUE_M) / FIBRE_OPT_M, PASSIVE_STRAIN)
    muscle = -force * dl                        # moment toward positive angle
    gravity = -MASS_KG * G * COM_M * np.sin(q)  # toward positive angle
    u = -(muscle + gravity) + np.random.default_rng(seed).normal(0.0, 0.3, t.size)
    return {"time_s": t, "angle_rad": q, "velocity_rad_s": np.full(t.size, np.deg2rad(5.0)), "torque_nm": u}


def solve_ours(data: dict[str, np.ndarray]) -> dict[str, Any]:
    import casadi as ca

    from analysis.pmp.curves import passive_fiber_force
    from analysis.pmp.estimator import ParameterSet, PmpTrial, Subject, estimate

    class Pendulum(Subject):
        def inertia_kgm2(self, joint: str) -> float:
            return INERTIA_COM_KGM2 + MASS_KG * COM_M**2

        def gravity_moment_nm(self, joint: str, q: Any, fixed: dict[str, float], cos: Any = np.cos) -> Any:
            return -MASS_KG * G * COM_M * cos(q - math.pi / 2)  # −m g d sin q

    def moment(tr: PmpTrial, q: Any, par: dict[str, Any]) -> tuple[Any, list[Any], list[Any]]:
        length = path_length(q, ca)
        force = F_MAX_N * passive_fiber_force((length - par["muscle.tendon_slack_length_m"]) / FIBRE_OPT_M,
                                              PASSIVE_STRAIN)
        return -force * ca.jacobian(length, q), [], []

    shortest = float(np.min(path_length(data["angle_rad"])))
    pset = ParameterSet(["muscle.tendon_slack_length_m"], np.array([SLACK_GENERIC_M]),
                        np.array([0.6 * SLACK_GENERIC_M]), np.array([shortest - 1e-3]))
    tr = PmpTrial("knee", {}, data["time_s"], data["angle_rad"], data["velocity_rad_s"], data["torque_nm"],
                  "toy")
    t0 = time.perf_counter()
    res = estimate([tr], Pendulum(), intervals=INTERVALS, parameters=pset, moment=moment)
    wall = time.perf_counter() - t0
    return {"slack_m": res.parameters["muscle.tendon_slack_length_m"], "wall_s": wall, "iterations": res.nit}


MOCO_SCRIPT = r"""
import json, math, time, sys
import numpy as np
import opensim as osim
cfg = json.loads(sys.argv[1])
m = osim.Model()
m.setName("toy_knee")
m.setGravity(osim.Vec3(0, -9.81, 0))
body = osim.Body("shank", cfg["mass"], osim.Vec3(0, -cfg["com"], 0),
                 osim.Inertia(cfg["icom"], cfg["icom"], cfg["icom"]))
m.addBody(body)
joint = osim.PinJoint("knee", m.getGround(), osim.Vec3(0), osim.Vec3(0), body, osim.Vec3(0), osim.Vec3(0))
coord = joint.updCoordinate()
coord.setName("knee_angle")
coord.setRangeMin(-1.0); coord.setRangeMax(2.0)
m.addJoint(joint)
mus = osim.DeGrooteFregly2016Muscle()
mus.setName("muscle")
mus.set_max_isometric_force(cfg["fmax"]); mus.set_optimal_fiber_length(cfg["lo"])
mus.set_tendon_slack_length(cfg["ls0"]); mus.set_pennation_angle_at_optimal(0.0)
mus.set_ignore_tendon_compliance(True); mus.set_ignore_activation_dynamics(True)
mus.set_passive_fiber_strain_at_one_norm_force(cfg["eps0"]); mus.set_fiber_damping(0.0)
mus.set_max_contraction_velocity(10.0)
mus.addNewPathPoint("origin", m.getGround(), osim.Vec3(cfg["origin"][0], cfg["origin"][1], 0))
mus.addNewPathPoint("insertion", body, osim.Vec3(cfg["insertion"][0], cfg["insertion"][1], 0))
m.addForce(mus)
act = osim.CoordinateActuator("knee_angle")
act.setName("dyno"); act.setOptimalForce(1.0); act.setMinControl(-300); act.setMaxControl(300)
m.addForce(act)
m.finalizeConnections()
t = np.array(cfg["t"]); q = np.array(cfg["q"]); v = np.array(cfg["v"]); u = np.array(cfg["u"])
states = osim.TimeSeriesTable(list(t))
states.appendColumn("/jointset/knee/knee_angle/value", osim.Vector(list(q)))
states.appendColumn("/jointset/knee/knee_angle/speed", osim.Vector(list(v)))
states.addTableMetaDataString("inDegrees", "no")
controls = osim.TimeSeriesTable(list(t))
controls.appendColumn("/forceset/dyno", osim.Vector(list(u)))
controls.addTableMetaDataString("inDegrees", "no")
study = osim.MocoStudy()
problem = study.updProblem()
problem.setModel(m)
problem.setTimeBounds(float(t[0]), float(t[-1]))
problem.setStateInfo("/jointset/knee/knee_angle/value", [-0.5, 1.6])
problem.setStateInfo("/jointset/knee/knee_angle/speed", [-2.0, 2.0])
problem.setControlInfo("/forceset/muscle", [0.0, 0.01])  # passive: excitation ~0
problem.setControlInfo("/forceset/dyno", [-300.0, 300.0])
par = osim.MocoParameter("slack", "/forceset/muscle", "tendon_slack_length", osim.MocoBounds(cfg["lsmin"], cfg["lsmax"]))
problem.addParameter(par)
track = osim.MocoStateTrackingGoal("states", 1.0)
track.setReference(osim.TableProcessor(states))
w = osim.MocoWeightSet()
w.cloneAndAppend(osim.MocoWeight("/jointset/knee/knee_angle/value", cfg["wq"]))
w.cloneAndAppend(osim.MocoWeight("/jointset/knee/knee_angle/speed", cfg["wv"]))
track.setWeightSet(w)
problem.addGoal(track)
ctrack = osim.MocoControlTrackingGoal("torque", cfg["wu"])
ctrack.setReference(osim.TableProcessor(controls))
problem.addGoal(ctrack)
solver = study.initCasADiSolver()
solver.set_num_mesh_intervals(cfg["intervals"])
solver.set_transcription_scheme("hermite-simpson")
solver.set_parameters_require_initsystem(False)
solver.set_optim_convergence_tolerance(1e-6)
solver.set_optim_constraint_tolerance(1e-6)
solver.set_verbosity(0)
solver.set_optim_hessian_approximation("exact") if cfg.get("exact") else None
guess = solver.createGuess()
guess.setTime(osim.Vector(list(np.linspace(t[0], t[-1], guess.getNumTimes()))))
tg = np.linspace(t[0], t[-1], guess.getNumTimes())
guess.setState("/jointset/knee/knee_angle/value", osim.Vector(list(np.interp(tg, t, q))))
guess.setState("/jointset/knee/knee_angle/speed", osim.Vector(list(np.interp(tg, t, v))))
guess.setControl("/forceset/dyno", osim.Vector(list(np.interp(tg, t, u))))
guess.setControl("/forceset/muscle", osim.Vector([0.0] * guess.getNumTimes()))
solver.setGuess(guess)
t0 = time.perf_counter()
sol = study.solve()
wall = time.perf_counter() - t0
ok = sol.success()
sol.unseal()
print(json.dumps({"slack_m": float(sol.getParameter("slack")), "wall_s": wall, "success": bool(ok),
                  "iterations": int(sol.getNumIterations()), "status": sol.getStatus()}))
"""


def solve_moco(data: dict[str, np.ndarray], timeout_s: float = 900.0) -> dict[str, Any]:
    """Moco on the same problem (subprocess); raises RuntimeError with Moco's message if it fails."""
    shortest = float(np.min(path_length(data["angle_rad"])))
    cfg = {"mass": MASS_KG, "com": COM_M, "icom": INERTIA_COM_KGM2, "fmax": F_MAX_N, "lo": FIBRE_OPT_M,
           "ls0": SLACK_GENERIC_M, "eps0": PASSIVE_STRAIN, "origin": ORIGIN_M, "insertion": INSERTION_M,
           "lsmin": 0.6 * SLACK_GENERIC_M, "lsmax": shortest - 1e-3, "intervals": INTERVALS,
           "wq": 1.0 / math.radians(0.5) ** 2, "wv": 1.0 / math.radians(2.0) ** 2, "wu": 1.0 / 0.5**2,
           "t": data["time_s"].tolist(), "q": data["angle_rad"].tolist(), "v": data["velocity_rad_s"].tolist(),
           "u": data["torque_nm"].tolist()}
    with tempfile.TemporaryDirectory() as work:  # OpenSim writes opensim.log where it runs
        out = subprocess.run([sys.executable, "-c", textwrap.dedent(MOCO_SCRIPT), json.dumps(cfg)],
                             capture_output=True, text=True, timeout=timeout_s, cwd=work)
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-1500:])
    return json.loads(out.stdout.strip().splitlines()[-1])


__all__ = ["trial", "solve_ours", "solve_moco", "SLACK_TRUE_M"]
