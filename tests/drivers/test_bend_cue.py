"""The simulated AADS operator's cue: at rest until it, and a late cue never splits sent samples."""

from __future__ import annotations

import numpy as np

from drivers.simulation.lab import LabConfig, SimulatedLab


def test_the_operator_rests_until_the_cue() -> None:
    with SimulatedLab(LabConfig(seed=3)) as lab:
        lab.hold_bends()
        plate, cams = lab.force_plate, lab.mocap
        rest = lab.jig.state(np.zeros(1))
        # ten seconds of the stream at any phase of the free-running operator's pass: the rest state
        loads = plate.loads_at(np.arange(0, 10_000, 7))
        noise_sd = plate.noise_n * plate.faults.noise_scale
        assert np.all(np.abs(loads[:, :3] - rest.force_n[0]) < 6 * noise_sd)
        markers = cams.frames(0, 1000)
        at_rest = np.stack([rest.markers_m[k][0] for k in cams.labels])
        assert np.nanmax(np.abs(markers - at_rest)) < 6 * cams.noise_m


def test_a_cue_the_host_sets_late_starts_after_every_sample_already_sent() -> None:
    """A host stalled past the cue's lead (here by 10 s) starts the bends after what the drivers have
    already read (else those samples would show the free-running operator beside resting ones)."""
    with SimulatedLab(LabConfig(seed=3)) as lab:
        lab.hold_bends()
        plate, cams = lab.force_plate, lab.mocap
        per_frame = plate.rate_hz // cams.rate_hz
        cams.frames(0, 300)  # a driver has read the cameras' first 3 s
        sent = plate.counter
        first_bend_s = lab.begin_bends(lead_s=-10.0)
        origin = plate.bend_origin
        assert origin is not None and origin >= max(sent, 300 * per_frame) and origin % per_frame == 0
        assert cams.bend_origin == origin // per_frame
        assert first_bend_s == plate.time_origin_s + origin / plate.rate_hz
        # the frames before the start rest, the start's frame is the pass's first
        n = 5
        before, after = cams.frames(cams.bend_origin - n, n), cams.frames(cams.bend_origin, n)
        rest = np.stack([lab.jig.state(np.zeros(1)).markers_m[k][0] for k in cams.labels])
        assert np.nanmax(np.abs(before - rest)) < 6 * cams.noise_m
        assert np.nanmax(np.abs(after[0] - rest)) < 6 * cams.noise_m
