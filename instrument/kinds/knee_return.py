"""The knee swept out and back: flexion 0→90° and back to 0° at the same speed, the hip at 90, 55 or 15°.

The return movement is what the diagnosis asks for to separate the causes one direction cannot:
friction and damping change sign with the direction of motion, a torque offset and the passive
moment do not, so the two legs of one trial tell them apart. Everything else is the knee sweep's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from .knee import KneeKind, KneeProtocol


@dataclass
class KneeReturnProtocol(KneeProtocol):
    """Knee flexion from full extension to ``end_deg`` and back at ``speed_deg_s``; hip at 90, 55 or 15°."""

    name: ClassVar[str] = "knee_return"
    returns: ClassVar[bool] = True

    def fixed_joint_text(self) -> str:
        return f"hip at {self.hip_flexion_deg:g}°, out and back"


class KneeReturnKind(KneeKind):
    name = KneeReturnProtocol.name
    title = "Knee out and back"
    order = 45
    summary = ("knee flexion 0→90° and back to 0° at 5°/s, hip at 90, 55 or 15°: the return separates "
               "friction and damping from offsets")

    def build(self, **values: Any) -> KneeReturnProtocol:
        return KneeReturnProtocol(**values)

    def instructions(self) -> str:
        return ("Knee out and back: subject seated, hip as set, relaxed. The dynamometer flexes the knee from full "
                "extension at the set speed and brings it back. Red crosses mark activation on the way out.")


KIND = KneeReturnKind()

__all__ = ["KIND", "KneeReturnKind", "KneeReturnProtocol"]
