"""What the store's index holds per subject and per trial, and the rule a subject code must follow."""

from __future__ import annotations

import os
import re
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..errors import SubjectCodeError

#: what a subject code must look like unless ``INSTRUMENT_SUBJECT_CODE_PATTERN`` says otherwise:
#: 1–6 capital letters, an optional hyphen, 1–6 digits (``S01``, ``AFO-12``). A name, an e-mail
#: address or a national identity number does not match, so it can never enter the store.
DEFAULT_SUBJECT_CODE_PATTERN = r"[A-Z]{1,6}-?[0-9]{1,6}"


@dataclass
class Subject:
    """A pseudonymous subject with anthropometrics (SI units; lengths as the dissertation measures them).

    :ivar thigh_length_m: greater trochanter to lateral epicondyle.
    :ivar shank_length_m: fibula head to lateral malleolus.
    :ivar hip_width_m: ASIS to ASIS.
    :ivar foot_length_m: calcaneus to 5th metatarsal tuberosity.
    """

    code: str
    sex: str = "unknown"
    height_m: float | None = None
    mass_kg: float | None = None
    leg_length_m: float | None = None
    thigh_length_m: float | None = None
    shank_length_m: float | None = None
    hip_width_m: float | None = None
    foot_length_m: float | None = None
    thigh_circumference_m: float | None = None
    shank_circumference_m: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class TrialRecord:
    """One row of the trial index."""

    id: int
    session_id: int
    subject_code: str
    protocol: str
    condition: dict[str, Any]
    operator: str | None
    trial_number: int | None
    status: str
    reason: str | None
    repeated_by: int | None
    path: Path
    started_at: float
    ended_at: float | None
    software_version: str | None
    devices: dict[str, dict[str, int]]

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["path"] = str(self.path)
        return d


def subject_code_pattern() -> str:
    """The pseudonym pattern in force (``INSTRUMENT_SUBJECT_CODE_PATTERN`` or the default)."""
    return os.environ.get("INSTRUMENT_SUBJECT_CODE_PATTERN") or DEFAULT_SUBJECT_CODE_PATTERN


def check_subject_code(code: str) -> None:
    """Refuse a subject code that is not a pseudonym.

    :raises SubjectCodeError: names the pattern and how to change it.
    """
    pattern = subject_code_pattern()
    if not isinstance(code, str) or re.fullmatch(pattern, code) is None:
        raise SubjectCodeError(
            f"subject code {code!r} is not a pseudonym: codes match {pattern} (e.g. S01); names, e-mail addresses "
            "and identity numbers are never stored (set INSTRUMENT_SUBJECT_CODE_PATTERN to change the pattern)")


__all__ = ["DEFAULT_SUBJECT_CODE_PATTERN", "Subject", "TrialRecord", "check_subject_code", "subject_code_pattern"]
