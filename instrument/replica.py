"""The replica-leg analysis from recorded trials: holds → spring estimates, compared with the rig's truth when known."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from analysis.errors import InputError
from analysis.pmp.replica import (
    Holds,
    ReplicaResult,
    estimate_replica,
    holds_from_samples,
    load_replica_model,
    write_plots,
)
from analysis.trial_csv import TrialTable


def holds_of(tables: list[TrialTable]) -> Holds:
    """The holds of one or more replica trials (repeats at the same angle are pooled).

    :raises InputError: a table is not a replica trial, or there are too few holds.
    """
    for t in tables:
        if t.sidecar.get("kind") != "replica":
            raise InputError(f"{t.sidecar.get('source', 'a trial')}: not a replica-leg trial ({t.sidecar.get('kind')!r})")
    angle = np.concatenate([t.angle_deg for t in tables])
    torque = np.concatenate([t.torque_nm for t in tables])
    return holds_from_samples(angle, torque)


def analyze_replica(tables: list[TrialTable], metadata: list[dict[str, Any]], model_path: Path | None,
                    out: Path | None) -> tuple[ReplicaResult, dict[str, float] | None, list[Path]]:
    """Fit the springs; the simulator's truth (from the first simulated recording) is compared, never used."""
    model = load_replica_model(model_path)
    # a sensor tared with the shank off reads zero at no load; otherwise its zero is fitted too
    tared = all(t.sidecar.get("sensor_tared_unloaded") for t in tables)
    result = estimate_replica(holds_of(tables), model, sensor_offset_nm=0.0 if tared else None)
    truth = next((m["simulation"]["replica_springs"] for m in metadata
                  if m.get("simulated") and "replica_springs" in m.get("simulation", {})), None)
    files = write_plots(result, out, truth) if out is not None else []
    return result, truth, files
