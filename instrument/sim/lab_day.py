"""A small simulated lab day recorded into a store: AADS set, knee and ankle isokinetic sets, replica leg.

The trials of different rigs are independent simulated labs, so they are recorded concurrently
(each on its own threads, own virtual CAN channel and own ports), as separate rooms of a lab would.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..kinds.aads import AadsProtocol
from ..kinds.ankle import AnkleProtocol
from ..kinds.base import TrialProtocol
from ..kinds.knee import KneeProtocol
from ..kinds.replica import ReplicaProtocol
from ..live.session import TrialOutcome, record_trial
from ..store import SessionStore, Subject
from .simulate import lab_config_for, simulated_devices, simulation_metadata

#: the simulated body is Rajagopal 2016's unscaled (tools/make_demo_subject.py: hip to knee 0.408 m, knee to
#: ankle 0.3965 m); the lab's tape reads its thigh 2 mm and its shank 3.5 mm long
SUBJECT = Subject("SIM01", "male", 1.78, 75.0, 0.92, 0.41, 0.40, 0.28, 0.26, 0.52, 0.37)


def plan(quick: bool) -> list[tuple[str, TrialProtocol]]:
    """(room, protocol) of the day in the order the store numbers them: the first trial of every room,
    then the second of every room, and so on; ``quick`` runs the sweeps at 15°/s instead of 5°/s
    and short holds."""
    speed = 15.0 if quick else 5.0
    rooms: dict[str, list[TrialProtocol]] = {
        # long enough for the operator's whole pass of bends (6.5–11 s), recorded whole
        AadsProtocol.name: [AadsProtocol(spring=s, operator=1 + (s % 4), trial=1, duration_s=12.0) for s in (1, 2, 3)]}
    # each knee sweep in its own room: the three are the day's longest trials (recorded side by side)
    rooms.update({f"knee-hip{h:g}": [KneeProtocol(hip_flexion_deg=h, speed_deg_s=speed)] for h in (90.0, 55.0, 15.0)})
    rooms[AnkleProtocol.name] = [AnkleProtocol(knee_flexion_deg=k, speed_deg_s=speed) for k in (0.0, 45.0, 90.0)]
    rooms[ReplicaProtocol.name] = [ReplicaProtocol(hold_s=0.5 if quick else 2.0)]
    rounds = max(len(v) for v in rooms.values())
    return [(room, trials[k]) for k in range(rounds) for room, trials in rooms.items() if k < len(trials)]


class _Turns:
    """Store registrations in plan order while the rooms record at once: trial ``i`` registers after
    trials ``0 … i−1`` have registered (or ended without registering), so the trial ids do not depend
    on which room's host thread happened to be quicker."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._done: set[int] = set()
        self._next = 0

    def wait(self, i: int) -> None:
        with self._cond:
            self._cond.wait_for(lambda: self._next >= i)

    def done(self, i: int) -> None:
        with self._cond:
            self._done.add(i)
            while self._next in self._done:
                self._next += 1
            self._cond.notify_all()


class _InTurn:
    """The store as one trial of the day sees it: ``begin_trial`` waits for the trial's turn."""

    def __init__(self, store: SessionStore, turns: _Turns, index: int) -> None:
        self._store, self._turns, self._index = store, turns, index

    def begin_trial(self, *args: Any, **kwargs: Any) -> Any:
        self._turns.wait(self._index)
        try:
            return self._store.begin_trial(*args, **kwargs)
        finally:
            self._turns.done(self._index)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._store, name)


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
    turns = _Turns()

    def room(name: str) -> None:
        for i, (r, proto) in enumerate(trials):
            if r != name:
                continue
            try:
                with simulated_devices(proto, lab_config_for(proto, seed=i)) as (lab, devices):
                    outcomes[i] = record_trial(_InTurn(store, turns, i), sessions[r], proto,  # type: ignore[arg-type]  # _InTurn forwards every store call in turn (a proxy, not a SessionStore)
                                               devices, operator=f"{r}-operator", trial_number=1,
                                               extra_metadata=simulation_metadata(lab))
                if progress is not None:
                    with lock:
                        done[0] += 1
                        o = outcomes[i]
                        progress(f"  lab day: {done[0]}/{len(trials)} trials recorded ({r} room: {proto.name} "
                                 f"{proto.condition_text()}, {o.status if o else '?'}, {o.duration_s if o else 0:.1f} s)")
            except BaseException as err:
                errors.append(err)
            finally:
                turns.done(i)  # a trial that failed before registering does not hold the others up

    threads = [threading.Thread(target=room, args=(r,), name=f"room-{r}") for r in sessions]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return store, [o for o in outcomes if o is not None]


def record_repeat(store: SessionStore, protocol: TrialProtocol, seed: int, note: str) -> TrialOutcome:
    """Record one more trial of ``protocol`` for the day's subject in a session of its own (``note`` says why: the
    operator repeats a trial whose data fell short), on a simulated lab drawn from ``seed``."""
    session = store.new_session(SUBJECT.code, operator=f"{protocol.name}-operator", notes=note)
    with simulated_devices(protocol, lab_config_for(protocol, seed=seed)) as (lab, devices):
        return record_trial(store, session, protocol, devices, operator=f"{protocol.name}-operator", trial_number=2,
                            extra_metadata=simulation_metadata(lab))


def summary_rows(store: SessionStore) -> list[dict[str, Any]]:
    return [{"trial": t.id, "protocol": t.protocol, "status": t.status,
             "condition": {k: v for k, v in t.condition.items() if k in ("spring", "operator", "hip_flexion_deg",
                                                                          "knee_flexion_deg", "speed_deg_s")},
             "samples": {n: c["samples"] for n, c in t.devices.items()},
             "lost": {n: c["lost_samples"] for n, c in t.devices.items()}} for t in store.trials()]
