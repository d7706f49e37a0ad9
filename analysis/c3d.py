"""C3D in and out with ezc3d: markers and one force platform, as Vicon and other labs exchange them.

Reading uses ezc3d's own force-platform extraction (types 1–4: channels, scales, offsets,
calibration matrix, corners and origin from the ``FORCE_PLATFORM`` group), which gives the load
*on the plate* in the lab frame; the analysis wants the reaction on the specimen, so the force
and free moment are negated. Writing produces a type-2 platform (Fx Fy Fz Mx My Mz channels,
N and N·mm) in the plate's own frame as the corners define it (x = c1→c0, y = c4→c1; with the
default corners z points down, as AMTI plates do), and ``ORIGIN`` the plate centre relative to the
transducer origin in that frame, z ≤ 0 (the C3D type-2 convention, which ezc3d enforces).
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import Any

import numpy as np

from .errors import DataFileError, InputError
from .motion import MotionTrial, cop_from_moment

_UNIT_TO_M = {"mm": 1e-3, "m": 1.0, "cm": 1e-2}


def _scale(unit: str, what: str, path: Path) -> float:
    u = unit.strip().lower()
    if u in _UNIT_TO_M:
        return _UNIT_TO_M[u]
    raise DataFileError(path, f"unknown {what} unit {unit!r}")


def _declared_frames(path: Path) -> int | None:
    """Frames the C3D header declares (words 4–5), read from the raw bytes: ezc3d shortens its own
    header to what a truncated file holds. None when the header cannot be decoded."""
    try:
        with path.open("rb") as fh:
            head = fh.read(512)
            param_block = head[0] if head else 0
            fh.seek(max(param_block - 1, 0) * 512)
            param_head = fh.read(4)
    except OSError:
        return None
    if len(head) < 10 or len(param_head) < 4:
        return None
    order = ">" if param_head[3] == 86 else "<"  # 84 Intel, 85 DEC (little-endian words), 86 MIPS
    first, last = struct.unpack(order + "HH", head[6:10])
    return last - first + 1 if last >= first else None


def read_c3d(path: str | Path, *, plate: int = 0, require_plate: bool = True) -> MotionTrial:
    """Read markers and force platform ``plate`` of a C3D file.

    :raises DataFileError: the file cannot be read, or it has no force platform (when required).
    """
    import ezc3d

    path = Path(path)
    if not path.exists():
        raise DataFileError(path, "file does not exist")
    try:
        c = ezc3d.c3d(str(path), extract_forceplat_data=True)
    except Exception as err:
        raise DataFileError(path, f"not a readable C3D file: {err}") from err
    declared = _declared_frames(path)
    held = int(np.asarray(c["data"]["points"]).shape[-1])
    if declared is not None and held < declared:
        raise DataFileError(path, f"truncated: the header declares {declared} frames, the file holds {held}")
    params = c["parameters"]
    try:
        rate = float(params["POINT"]["RATE"]["value"][0])
    except (KeyError, IndexError) as err:
        raise DataFileError(path, "no POINT:RATE parameter") from err
    labels = [str(s).strip() for s in params["POINT"]["LABELS"]["value"]]
    units = params["POINT"].get("UNITS", {}).get("value", [])
    unit = str(units[0]) if len(units) else "mm"
    pts = np.asarray(c["data"]["points"], dtype=float)  # (4, markers, frames)
    markers = np.transpose(pts[:3], (2, 1, 0)) * _scale(unit, "point", path)
    if "meta_points" in c["data"] and c["data"]["meta_points"]["residuals"].size:
        res = c["data"]["meta_points"]["residuals"][0].T  # (frames, markers); < 0 marks an invalid point
        markers[res < 0] = np.nan
    first = int(c["header"]["points"]["first_frame"])
    marker_t = (first + np.arange(markers.shape[0])) / rate
    platforms = c["data"].get("platform", [])
    if len(platforms) <= plate:
        if require_plate:
            raise DataFileError(path, f"no force platform {plate + 1} (FORCE_PLATFORM group has {len(platforms)})")
        empty = np.zeros((0, 3))
        return MotionTrial(marker_t, markers, labels, np.zeros(0), empty, empty, np.zeros(0), str(path))
    pf = platforms[plate]
    f_scale = 1.0 if pf["unit_force"].strip() in ("N", "") else float("nan")
    m_unit = pf["unit_moment"].strip().lower().replace("·", "")
    m_scale = {"nmm": 1e-3, "nm": 1.0}.get(m_unit, float("nan"))
    p_scale = _scale(pf["unit_position"] or "mm", "force-platform position", path)
    if not np.isfinite(f_scale * m_scale):
        raise DataFileError(path, f"unknown force-platform units {pf['unit_force']!r}, {pf['unit_moment']!r}")
    force_on_plate = pf["force"].T * f_scale
    analog_rate = float(c["header"]["analogs"]["frame_rate"]) or rate
    plate_t = first / rate + np.arange(force_on_plate.shape[0]) / analog_rate
    cop = pf["center_of_pressure"].T * p_scale
    tz = pf["Tz"].T[:, 2] * m_scale
    low = np.abs(force_on_plate[:, 2]) < 5.0
    cop[low] = np.nan
    corners = pf["corners"].T * p_scale
    meta = {"plate_corners_m": corners.tolist(), "plate_origin_m": (pf["origin"] * p_scale).tolist(),
            "marker_rate_hz": rate, "analog_rate_hz": analog_rate, "aads_factors": _aads_factors(params)}
    _check_plausible(path, markers, labels, rate, force_on_plate)
    return MotionTrial(marker_t, markers, labels, plate_t, -force_on_plate, cop, -np.where(low, 0.0, tz),
                       str(path), meta)


#: what no motion-capture volume or force plate records: a coordinate farther than this from the origin (m),
#: a marker moving faster than this between frames (m/s), a force larger than this (N). C3D carries no
#: checksum; a damaged float's exponent shows as such a value, and the file is refused rather than analysed
PLAUSIBLE_COORDINATE_M, PLAUSIBLE_MARKER_SPEED_M_S, PLAUSIBLE_FORCE_N = 20.0, 30.0, 50_000.0


def _check_plausible(path: Path, markers: np.ndarray, labels: list[str], rate_hz: float, force_n: np.ndarray) -> None:
    """Refuse data no lab can have recorded (a corrupted file): names the marker or channel and the frame."""
    with np.errstate(invalid="ignore"):
        far = np.abs(markers) > PLAUSIBLE_COORDINATE_M
        if far.any():
            frame, marker, _ = np.argwhere(far)[0]
            distance = float(np.nanmax(np.abs(markers[frame, marker])))
            raise DataFileError(path, f"corrupt data: marker {labels[marker]} at {distance:.3g} m from the origin in "
                                      f"frame {frame}")
        if markers.shape[0] > 1:
            speed = np.linalg.norm(np.diff(markers, axis=0), axis=2) * rate_hz
            fast = speed > PLAUSIBLE_MARKER_SPEED_M_S
            if fast.any():
                frame, marker = np.argwhere(fast)[0]
                raise DataFileError(path, f"corrupt data: marker {labels[marker]} jumps {speed[frame, marker] / rate_hz:.3g} m "
                                          f"between frames {frame} and {frame + 1}")
        big = ~(np.abs(force_n) <= PLAUSIBLE_FORCE_N) & np.isfinite(force_n) | np.isinf(force_n)
        if big.any():
            sample = int(np.argwhere(big)[0][0])
            raise DataFileError(path, f"corrupt data: a force of {np.max(np.abs(force_n[sample])):.3g} N at analog sample "
                                      f"{sample}")


#: the AADS factors a C3D file carries (parameter group ``AADS``), so a re-analysis needs no flags
AADS_FACTORS = ("SPRING", "OPERATOR", "TRIAL")


def _aads_factors(params: Any) -> dict[str, Any]:
    """The ``AADS`` parameter group (spring, operator, trial, spring_n_per_m), where the file has one."""
    group = params["AADS"] if "AADS" in params else {}
    out: dict[str, Any] = {}
    for key in AADS_FACTORS:
        if key in group and len(group[key]["value"]):
            out[key.lower()] = int(group[key]["value"][0])
    if "SPRING_N_PER_M" in group and len(group["SPRING_N_PER_M"]["value"]):
        out["spring_n_per_m"] = float(group["SPRING_N_PER_M"]["value"][0])
    return out


def write_c3d(path: str | Path, trial: MotionTrial, *, corners_m: np.ndarray | None = None,
              transducer_origin_m: np.ndarray | None = None, factors: dict[str, Any] | None = None) -> None:
    """Write markers (mm) and the force plate as a type-2 platform (N, N·mm).

    ``factors``: the AADS test's ``spring``, ``operator``, ``trial`` (integers) and
    ``spring_n_per_m`` (the spring's theoretical stiffness, N/m), written to the ``AADS``
    parameter group (read back by :func:`read_c3d` into ``meta["aads_factors"]``).

    The plate rate must be an integer multiple of the marker rate, and both streams must cover
    the same frames (cut to the shorter). ``corners_m`` (4, 3): plate corners in the lab frame
    (default: a 600 × 400 mm plate centred at the origin); ``transducer_origin_m`` (3,): the
    point the moment channels refer to, in the lab frame (default 40 mm below the surface).

    :raises InputError: rates not commensurate, or no samples.
    """
    import ezc3d
    from ezc3d import ezc3d as core

    path = Path(path)
    n_m = trial.markers_m.shape[0]
    marker_rate = 1.0 / float(np.median(np.diff(trial.marker_time_s))) if n_m > 1 else 100.0
    plate_rate = 1.0 / float(np.median(np.diff(trial.plate_time_s))) if trial.plate_time_s.size > 1 else marker_rate
    marker_rate, plate_rate = round(marker_rate), round(plate_rate)
    if plate_rate % marker_rate:
        raise InputError(f"plate rate {plate_rate} Hz is not a multiple of the marker rate {marker_rate} Hz")
    ratio = plate_rate // marker_rate
    n = min(n_m, trial.plate_time_s.size // ratio)
    if n == 0:
        raise InputError("nothing to write: no frame has both markers and force-plate samples")
    corners = np.array([[0.3, -0.2, 0.0], [-0.3, -0.2, 0.0], [-0.3, 0.2, 0.0], [0.3, 0.2, 0.0]]) \
        if corners_m is None else np.asarray(corners_m, dtype=float)
    origin = np.array([0.0, 0.0, -0.040]) if transducer_origin_m is None else np.asarray(transducer_origin_m)
    centre = corners.mean(axis=0)
    ex, ey = corners[0] - corners[1], corners[0] - corners[3]
    ez = np.cross(ex, ey)
    ey = np.cross(ez, ex)
    rot = np.column_stack([ex / np.linalg.norm(ex), ey / np.linalg.norm(ey), ez / np.linalg.norm(ez)])  # plate→lab
    c = ezc3d.c3d()
    p = c["parameters"]
    p["POINT"]["RATE"]["value"] = [float(marker_rate)]
    p["POINT"]["LABELS"]["value"] = list(trial.marker_labels)
    p["POINT"]["UNITS"]["value"] = ["mm"]
    p["ANALOG"]["RATE"]["value"] = [float(plate_rate)]
    p["ANALOG"]["LABELS"]["value"] = ["Fx1", "Fy1", "Fz1", "Mx1", "My1", "Mz1"]
    p["ANALOG"]["UNITS"]["value"] = ["N", "N", "N", "Nmm", "Nmm", "Nmm"]
    pts = np.ones((4, len(trial.marker_labels), n))
    pts[:3] = np.transpose(trial.markers_m[:n] * 1e3, (2, 1, 0))
    c["data"]["points"] = pts
    k = n * ratio
    f_plate = -trial.force_n[:k] @ rot  # load on the plate, in the plate frame
    m_plate = -trial.moment_about_nm(origin)[:k] @ rot
    an = np.vstack([f_plate.T, m_plate.T * 1e3])[None]
    c["data"]["analogs"] = np.nan_to_num(an)
    for name, value in (("USED", [1]), ("TYPE", [2]), ("CHANNEL", np.arange(1, 7).reshape(6, 1))):
        c.add_parameter("FORCE_PLATFORM", name, np.asarray(value, dtype=float))
        p["FORCE_PLATFORM"][name]["type"] = core.INT
    c.add_parameter("FORCE_PLATFORM", "CORNERS", (corners.T * 1e3).reshape(3, 4, 1))
    c.add_parameter("FORCE_PLATFORM", "ORIGIN", (rot.T @ (centre - origin) * 1e3).reshape(3, 1))
    for key, value in (factors or {}).items():
        if value is None:
            continue
        if key.upper() in AADS_FACTORS:
            c.add_parameter("AADS", key.upper(), np.asarray([int(value)], dtype=float))
            p["AADS"][key.upper()]["type"] = core.INT
        elif key == "spring_n_per_m":
            c.add_parameter("AADS", "SPRING_N_PER_M", np.asarray([float(value)]))
    c["header"]["points"]["first_frame"] = int(round(trial.marker_time_s[0] * marker_rate)) if n_m else 0
    try:
        c.write(str(path))
    except Exception as err:
        raise DataFileError(path, f"cannot write C3D: {err}") from err


def write_analog_c3d(path: str | Path, rate_hz: float, channels: list[tuple[str, str, np.ndarray]], *,
                     start_s: float = 0.0, events: list[tuple[str, float]] | None = None,
                     group: str = "", parameters: dict[str, float | str] | None = None) -> None:
    """Write evenly sampled channels as C3D analog channels, as motion-capture software stores a
    dynamometer's (Vicon Nexus: torque, angle and velocity as analog channels with their units).

    ``channels``: ``(label, unit, values)`` with equal lengths (units as C3D writes them: ``Nm``, ``deg``,
    ``deg/s``); ``events``: ``(label, time s from the first sample)`` written to the ``EVENT`` group;
    ``group``/``parameters``: a parameter group of numbers and texts describing the trial (its condition).
    The file has no markers (``POINT:USED`` 0). NaN values are refused: fill or cut them first.

    :raises InputError: no channel, unequal lengths, a NaN, or a rate that is not positive.
    """
    import ezc3d

    path = Path(path)
    if not channels:
        raise InputError("nothing to write: no analog channel")
    n = len(channels[0][2])
    if n == 0 or any(len(v) != n for _, _, v in channels):
        raise InputError("analog channels must be non-empty and of equal length")
    data = np.vstack([np.asarray(v, dtype=float) for _, _, v in channels])
    if not np.all(np.isfinite(data)):
        raise InputError("analog channels hold NaN or infinite values; fill or cut them before writing C3D")
    if not rate_hz > 0:
        raise InputError(f"analog rate must be positive, got {rate_hz}")
    c = ezc3d.c3d()
    p = c["parameters"]
    p["POINT"]["RATE"]["value"] = [float(rate_hz)]
    p["ANALOG"]["RATE"]["value"] = [float(rate_hz)]
    p["ANALOG"]["LABELS"]["value"] = [label for label, _, _ in channels]
    p["ANALOG"]["UNITS"]["value"] = [unit for _, unit, _ in channels]
    c["data"]["points"] = np.ones((4, 0, n))
    c["data"]["analogs"] = data[None]
    if events:
        c.add_parameter("EVENT", "USED", np.asarray([len(events)], dtype=float))
        c.add_parameter("EVENT", "LABELS", [label for label, _ in events])
        c.add_parameter("EVENT", "CONTEXTS", ["General"] * len(events))
        times = np.array([[0.0, float(t)] for _, t in events]).T  # (minutes, seconds) per event
        c.add_parameter("EVENT", "TIMES", times)
    for key, value in (parameters or {}).items():
        if isinstance(value, str):
            c.add_parameter(group, key.upper(), [value])
        else:
            c.add_parameter(group, key.upper(), np.asarray([float(value)]))
    c["header"]["points"]["first_frame"] = int(round(start_s * rate_hz))
    try:
        c.write(str(path))
    except Exception as err:
        raise DataFileError(path, f"cannot write C3D: {err}") from err


__all__ = ["read_c3d", "write_analog_c3d", "write_c3d", "cop_from_moment"]
