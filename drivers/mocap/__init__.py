"""Motion capture: labelled marker positions streamed as :class:`~drivers.blocks.MarkerBlock`.

Open by URL::

    open_marker_stream("sim://aads-1?rate=100")   # a MarkerSimulator registered under that name

Real labs record markers in their own system (Vicon Nexus, Qualisys, ...) and hand the trial over
as C3D (:mod:`instrument.c3d`); a live back end is a new entry in :data:`BACKENDS`.
"""

from __future__ import annotations

from typing import Any, ClassVar

from ..base import StreamingDevice
from ..blocks import MarkerBlock
from ..url import DeviceUrl, load_backend

#: scheme -> (module, class); imported only when asked for
BACKENDS: dict[str, tuple[str, str]] = {"sim": ("drivers.mocap.simulated", "SimulatedMarkerStream")}


class MarkerStream(StreamingDevice):
    """A motion-capture stream with a fixed, ordered set of marker labels."""

    kind: ClassVar[str] = "mocap"
    block_type = MarkerBlock
    labels: tuple[str, ...] = ()

    def channel_layout(self) -> dict[str, tuple[tuple[int, ...], str]]:
        layout = dict(MarkerBlock.LAYOUT)
        layout["position_m"] = ((len(self.labels), 3), "f8")
        return layout


def open_marker_stream(url: str, **kwargs: Any) -> MarkerStream:
    """Make (not yet open) the marker stream for ``url``.

    :raises DeviceNotAvailableError: unknown scheme or no such simulated source.
    """
    parsed = DeviceUrl.parse(url)
    cls = load_backend(BACKENDS, parsed, "motion capture")
    return cls.from_url(parsed, **kwargs)  # type: ignore[attr-defined]  # every backend has one
