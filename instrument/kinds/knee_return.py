"""The knee swept out and back: flexion 0→90° and back to 0° at the same speed, the hip at 90, 55 or 15°.

The return movement is what the diagnosis asks for to separate the causes one direction cannot:
friction and damping change sign with the direction of motion, a torque offset and the passive
moment do not, so the two legs of one trial tell them apart.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import ProtocolError
from .isokinetic import ARM_COM, ARM_MASS, HIP, KNEE_END, SPEED, IsokineticKind, IsokineticProtocol, knee_arm_gravity_nm


@dataclass
class KneeReturnProtocol(IsokineticProtocol):
    """Knee flexion from full extension to ``end_deg`` and back at ``speed_deg_s``; hip at 90, 55 or 15°."""

    name: ClassVar[str] = "knee_return"
    joint: ClassVar[str] = "knee"
    returns: ClassVar[bool] = True
    hip_flexion_deg: float = 90.0
    ankle_dorsiflexion_deg: float = 0.0

    def __post_init__(self) -> None:
        if self.hip_flexion_deg not in HIP.choices:
            raise ProtocolError(f"hip angle must be 90, 55 or 15°, got {self.hip_flexion_deg}")

    def fixed_joint_text(self) -> str:
        return f"hip at {self.hip_flexion_deg:g}°, out and back"

    def fixed_angles_deg(self) -> dict[str, float]:
        return {"hip_flexion_deg": self.hip_flexion_deg, "ankle_dorsiflexion_deg": self.ankle_dorsiflexion_deg}

    @property
    def set_angle_deg(self) -> float:
        return self.hip_flexion_deg


class KneeReturnKind(IsokineticKind):
    name = KneeReturnProtocol.name
    title = "Knee out and back"
    order = 45
    summary = ("knee flexion 0→90° and back to 0° at 5°/s, hip at 90, 55 or 15°: the return separates "
               "friction and damping from offsets")
    table_kind = "knee"
    opensim_coordinate = "knee_angle_r"
    parameters = (HIP, SPEED, KNEE_END, ARM_MASS, ARM_COM)

    def build(self, **values: Any) -> KneeReturnProtocol:
        return KneeReturnProtocol(**values)

    def instructions(self) -> str:
        return ("Knee out and back: subject seated, hip as set, relaxed. The dynamometer flexes the knee from full "
                "extension at the set speed and brings it back. Red crosses mark activation on the way out.")

    def arm_gravity_nm(self, angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float,
                       condition: dict[str, Any]) -> np.ndarray:
        return knee_arm_gravity_nm(angle_deg, arm_mass_kg, arm_com_m)


KIND = KneeReturnKind()

__all__ = ["KIND", "KneeReturnKind", "KneeReturnProtocol"]
