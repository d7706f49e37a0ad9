"""The simulated lab's seated subject: passive joint moments OpenSim computed (``data/demo_subject.json``).

Made by ``tools/make_demo_subject.py`` (OpenSim, Rajagopal 2016's muscles with drawn parameters, the
muscles the estimator does not model, CoordinateLimitForce at the range's ends): a subject the
passive-parameter estimator was not built from, with a known truth to validate it against. One table of
the moment (N·m toward positive angle) against the moving joint's angle (deg) per protocol condition:
knee at hip 90/55/15°, ankle at knee 0/45/90°. Other conditions have no table (the simulator then uses
Riener & Edrich's moments).
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

DATA = Path(__file__).with_name("data") / "demo_subject.json"
#: how close (deg) a fixed angle must be to a table's condition to use it
CONDITION_TOLERANCE_DEG = 0.5


@cache
def demo_subject() -> dict[str, Any]:
    """The whole record: tables, the truth (muscle parameters, limit forces) and the model's shank length (m)."""
    return json.loads(DATA.read_text(encoding="utf-8"))


def passive_table(joint: str, fixed_deg: float) -> tuple[tuple[float, ...], tuple[float, ...]] | None:
    """(angles deg ascending, moments N·m toward positive angle) of ``joint`` with the other joint (hip for
    the knee, knee for the ankle) at ``fixed_deg``; None when the subject has no table for that condition."""
    other = "hip_deg" if joint == "knee" else "knee_deg"
    for table in demo_subject()["tables"]:
        if table["joint"] == joint and abs(float(table[other]) - fixed_deg) <= CONDITION_TOLERANCE_DEG:
            return tuple(table["angle_deg"]), tuple(table["moment_nm"])
    return None


def shank_length_m() -> float:
    """The subject's true shank length (m): the OpenSim model's, whose paths made the tables."""
    return float(demo_subject()["shank_length_m"])
