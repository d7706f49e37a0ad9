"""A small simulated lab day recorded into a store: AADS set, knee and ankle isokinetic sets, replica leg.

The trials of different rigs are independent simulated labs, so they are recorded concurrently
(each on its own threads, own virtual CAN channel and own ports), as separate rooms of a lab would.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .protocols import AadsProtocol, AnkleProtocol, KneeProtocol, ReplicaProtocol, TrialProtocol
from .session import TrialOutcome, record_trial
from .simulate import lab_config_for, simulated_devices, simulation_metadata
from .store import SessionStore, Subject

SUBJECT = Subject("SIM01", "male", 1.78, 75.0, 0.92, 0.43, 0.42, 0.28, 0.26, 0.52, 0.37)


def plan(quick: bool) -> list[tuple[str, TrialProtocol]]:
    """(room, protocol) of the day; ``quick`` runs the sweeps at 15°/s instead of 5°/s and short holds."""
    speed = 15.0 if quick else 5.0
    trials: list[tuple[str, TrialProtocol]] = [
        ("aads", AadsProtocol(spring=s, operator=1 + (s % 4), trial=1, duration_s=3.0 if quick else 8.0))
        for s in (1, 2, 3)]
    # each knee sweep in its own room: the three are the day's longest trials (recorded side by side)
    trials += [(f"knee-hip{h:g}", KneeProtocol(hip_flexion_deg=h, speed_deg_s=speed)) for h in (90.0, 55.0, 15.0)]
    trials += [("ankle", AnkleProtocol(knee_flexion_deg=k, speed_deg_s=speed)) for k in (0.0, 45.0, 90.0)]
    trials += [("replica", ReplicaProtocol(hold_s=0.5 if quick else 2.0))]
    return trials


def record_lab_day(store_dir: Path, quick: bool = True,
                   progress: Callable[[str], None] | None = None) -> tuple[SessionStore, list[TrialOutcome]]:
    """Record the day's trials into ``store_dir``; returns the store and the outcomes in plan order.

    :param progress: called with a line after each trial (rooms record at once, so in finishing order).
    """
    store = SessionStore(store_dir)
    store.add_subject(SUBJECT)
    sessions = {room: store.new_session(SUBJECT.code, operator=f"{room}-operator", notes="simulated lab day")
                for room in dict.fromkeys(r for r, _ in plan(quick))}
    trials = plan(quick)
    outcomes: list[TrialOutcome | None] = [None] * len(trials)
    errors: list[BaseException] = []
    lock = threading.Lock()
    done = [0]

    def room(name: str) -> None:
        for i, (r, proto) in enumerate(trials):
            if r != name:
                continue
            try:
                with simulated_devices(proto, lab_config_for(proto, seed=i)) as (lab, devices):
                    outcomes[i] = record_trial(store, sessions[r], proto, devices, operator=f"{r}-operator",
                                               trial_number=1, extra_metadata=simulation_metadata(lab))
                if progress is not None:
                    with lock:
                        done[0] += 1
                        o = outcomes[i]
                        progress(f"  lab day: {done[0]}/{len(trials)} trials recorded ({r} room: {proto.name} "
                                 f"{proto.condition_text()}, {o.status if o else '?'}, {o.duration_s if o else 0:.1f} s)")
            except BaseException as err:  # noqa: BLE001 - reported after the other rooms finish
                errors.append(err)

    threads = [threading.Thread(target=room, args=(r,), name=f"room-{r}") for r in sessions]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return store, [o for o in outcomes if o is not None]


def summary_rows(store: SessionStore) -> list[dict[str, Any]]:
    return [{"trial": t.id, "protocol": t.protocol, "status": t.status,
             "condition": {k: v for k, v in t.condition.items() if k in ("spring", "operator", "hip_flexion_deg",
                                                                          "knee_flexion_deg", "speed_deg_s")},
             "samples": {n: c["samples"] for n, c in t.devices.items()},
             "lost": {n: c["lost_samples"] for n, c in t.devices.items()}} for t in store.trials()]
