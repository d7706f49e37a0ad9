"""Ankle from full dorsiflexion (15°) to plantarflexion (−30°) at 5°/s with the knee at 0, 45 or 90°."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from analysis.constants import GRAVITY_M_S2

from ..errors import ProtocolError
from .isokinetic import ARM_COM, ARM_MASS, KNEE, SPEED, IsokineticKind, IsokineticProtocol


@dataclass
class AnkleProtocol(IsokineticProtocol):
    """Ankle from full dorsiflexion to plantarflexion at 5°/s; knee at 0, 45 or 90°."""

    name: ClassVar[str] = "ankle"
    joint: ClassVar[str] = "ankle"
    start_deg: float = 15.0
    end_deg: float = -30.0
    knee_flexion_deg: float = 0.0
    hip_flexion_deg: float = 90.0

    def __post_init__(self) -> None:
        if self.knee_flexion_deg not in KNEE.choices:
            raise ProtocolError(f"knee angle must be 0, 45 or 90°, got {self.knee_flexion_deg}")

    def fixed_joint_text(self) -> str:
        return f"knee at {self.knee_flexion_deg:g}°"

    def fixed_angles_deg(self) -> dict[str, float]:
        return {"hip_flexion_deg": self.hip_flexion_deg, "knee_flexion_deg": self.knee_flexion_deg}

    @property
    def set_angle_deg(self) -> float:
        return self.knee_flexion_deg


class AnkleKind(IsokineticKind):
    name = AnkleProtocol.name
    title = "Ankle isokinetic"
    order = 30
    summary = "ankle dorsiflexion 15° to plantarflexion −30° at 5°/s with the knee at 0, 45 or 90°, relaxed"
    table_kind = "ankle"
    opensim_coordinate = "ankle_angle_r"
    parameters = (KNEE, SPEED, ARM_MASS, ARM_COM)

    def build(self, **values: Any) -> AnkleProtocol:
        return AnkleProtocol(**values)

    def instructions(self) -> str:
        return ("Ankle: knee as set, relaxed. The dynamometer moves the ankle from full dorsiflexion to "
                "plantarflexion at the set speed. Red crosses mark activation.")

    def arm_gravity_nm(self, angle_deg: np.ndarray, arm_mass_kg: float, arm_com_m: float,
                       condition: dict[str, Any]) -> np.ndarray:
        """The footplate's elevation above horizontal is dorsiflexion + 90° − knee flexion; gravity plantarflexes."""
        th = np.deg2rad(np.asarray(angle_deg, dtype=float))
        knee = float(condition.get("knee_flexion_deg", 0.0))
        return -arm_mass_kg * GRAVITY_M_S2 * arm_com_m * np.cos(th + np.deg2rad(90.0 - knee))


KIND = AnkleKind()

__all__ = ["KIND", "AnkleKind", "AnkleProtocol"]
