"""The trial kinds: one module per kind, each with its ``KIND`` (a :class:`~instrument.kinds.base.TrialKind`).

The registry finds every module of this package that defines ``KIND``; adding a kind is adding its
module (and its tests). Everything else asks the registry::

    from instrument import kinds

    kind = kinds.get("knee")               # or an alias: kinds.get("afo") is the AADS test
    proto = kind.protocol(hip_flexion_deg=55.0)
    [k.name for k in kinds.feeding(kinds.PASSIVE_PARAMETERS)]
"""

from __future__ import annotations

import importlib
import pkgutil

from ..errors import ProtocolError
from .base import (
    AFO_STIFFNESS,
    PASSIVE_PARAMETERS,
    REPLICA_SPRINGS,
    Action,
    LiveView,
    Parameter,
    TrialKind,
    TrialProtocol,
)


def _discover() -> tuple[TrialKind, ...]:
    found = []
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        kind = getattr(module, "KIND", None)
        if isinstance(kind, TrialKind):
            found.append(kind)
    return tuple(sorted(found, key=lambda k: (k.order, k.name)))


#: every kind, in the form's order
KINDS: tuple[TrialKind, ...] = _discover()
_BY_NAME = {n: k for k in KINDS for n in (k.name, *k.aliases)}


def get(name: str) -> TrialKind:
    """The kind called ``name`` (or one of its aliases).

    :raises ProtocolError: no such kind.
    """
    try:
        return _BY_NAME[name]
    except KeyError:
        raise ProtocolError(f"no trial kind {name!r}; one of {', '.join(names())}") from None


def names(*, aliases: bool = False) -> tuple[str, ...]:
    """The kinds' names (and their aliases), in the form's order."""
    return tuple(n for k in KINDS for n in ((k.name, *k.aliases) if aliases else (k.name,)))


def feeding(analysis: str) -> tuple[TrialKind, ...]:
    """The kinds whose trials feed ``analysis`` (``AFO_STIFFNESS``, ``PASSIVE_PARAMETERS``, ``REPLICA_SPRINGS``)."""
    return tuple(k for k in KINDS if k.analysis == analysis)


def names_feeding(analysis: str) -> tuple[str, ...]:
    """The names of the kinds whose trials feed ``analysis`` (what the store's index holds)."""
    return tuple(k.name for k in feeding(analysis))


def table_kinds() -> tuple[str, ...]:
    """What the kinds' tables measure, as the analysis layer names it (the trial CSV's ``kind``)."""
    return tuple(dict.fromkeys(k.table_kind for k in KINDS))


def all_parameters() -> tuple[Parameter, ...]:
    """Every kind's parameters, each once (a parameter kinds share is one option and one form field).

    :raises ProtocolError: two kinds describe the same parameter differently.
    """
    out: dict[str, Parameter] = {}
    for k in KINDS:
        for p in k.parameters:
            same = out.setdefault(p.name, p)
            if same != p:
                raise ProtocolError(f"parameter {p.name} is described differently by two kinds")
    return tuple(out.values())


__all__ = ["AFO_STIFFNESS", "KINDS", "PASSIVE_PARAMETERS", "REPLICA_SPRINGS", "Action", "LiveView", "Parameter",
           "TrialKind", "TrialProtocol", "all_parameters", "feeding", "get", "names", "names_feeding", "table_kinds"]
