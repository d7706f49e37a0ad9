"""Knee flexion from full extension to 90° at 5°/s with the hip at 90, 55 or 15° (the subject relaxed)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import ProtocolError
from .isokinetic import ARM_COM, ARM_MASS, HIP, KNEE_END, SPEED, IsokineticKind, IsokineticProtocol, knee_arm_gravity_nm


@dataclass
class KneeProtocol(IsokineticProtocol):
    """Knee flexion from full extension to 90° at 5°/s; hip at 90, 55 or 15°."""

    name: ClassVar[str] = "knee"
    joint: ClassVar[str] = "knee"
    hip_flexion_deg: float = 90.0
    ankle_dorsiflexion_deg: float = 0.0

    def fixed_joint_text(self) -> str:
        return f"hip at {self.hip_flexion_deg:g}°"

    def __post_init__(self) -> None:
        if self.hip_flexion_deg not in HIP.choices:
            raise ProtocolError(f"hip angle must be 90, 55 or 15°, got {self.hip_flexion_deg}")

    def fixed_angles_deg(self) -> dict[str, float]:
        return {"hip_flexion_deg": self.hip_flexion_deg, "ankle_dorsiflexion_deg": self.ankle_dorsiflexion_deg}

    @property
    def set_angle_deg(self) -> float:
        return self.hip_flexion_deg


class KneeKind(IsokineticKind):
    name = KneeProtocol.name
    title = "Knee isokinetic"
    order = 20
    summary = "knee flexion 0→90° at 5°/s with the hip at 90, 55 or 15°, the subject relaxed"
    table_kind = "knee"
    opensim_coordinate = "knee_angle_r"
    parameters = (HIP, SPEED, KNEE_END, ARM_MASS, ARM_COM)

    def build(self, **values: Any) -> KneeProtocol:
        return KneeProtocol(**values)

    def instructions(self) -> str:
        return ("Knee: subject seated, hip as set, relaxed. The dynamometer moves the knee from full extension to "
                "flexion at the set speed. The torque is drawn against the angle beside the green band a relaxed "
                "subject is expected in; red crosses mark torque the passive tissue cannot make (activation).")

    def arm_gravity_nm(self, angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float,
                       condition: dict[str, Any]) -> np.ndarray:
        return knee_arm_gravity_nm(angle_deg, arm_mass_kg, arm_com_m)


KIND = KneeKind()

__all__ = ["KIND", "KneeKind", "KneeProtocol"]
