"""The trial-kind registry: one home per kind, used by the CLI, the GUI's form, the export and the simulated lab."""

from __future__ import annotations

import ast
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from analysis.diagnosis import diagnose, from_table
from instrument import kinds
from instrument.cli import build_parser
from instrument.errors import ProtocolError
from instrument.kinds.base import TrialKind
from instrument.kinds.knee_return import KneeReturnProtocol
from instrument.live.recording import read_trial
from instrument.live.session import record_trial
from instrument.offline.export import trial_table
from instrument.sim.simulate import lab_config_for, simulated_devices, simulation_metadata
from instrument.store import SessionStore, Subject

ROOT = Path(__file__).resolve().parents[2]
#: every name a kind goes by, and what its table measures
KIND_NAMES = set(kinds.names(aliases=True)) | set(kinds.table_kinds())


def kind_name_branches(path: Path) -> list[str]:
    """Lines of ``path`` that branch on a trial kind's name: a comparison with one (``==``, ``!=``,
    ``in``), a dispatch table keyed by one, or a ``match`` case on one."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))

    def named(node: ast.AST) -> bool:
        if isinstance(node, ast.Constant) and node.value in KIND_NAMES:
            return True
        return isinstance(node, (ast.Tuple, ast.List, ast.Set)) and any(named(e) for e in node.elts)

    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare) and any(named(x) for x in (node.left, *node.comparators)):
            out.append(f"{path.relative_to(ROOT)}:{node.lineno}")
        elif isinstance(node, ast.Dict) and sum(named(k) for k in node.keys if k is not None) >= 2:
            out.append(f"{path.relative_to(ROOT)}:{node.lineno}")
        elif isinstance(node, ast.match_case) and isinstance(node.pattern, ast.MatchValue) and named(node.pattern.value):
            out.append(f"{path.relative_to(ROOT)}:{node.pattern.lineno}")
    return out


def test_no_module_outside_a_kinds_home_branches_on_its_name() -> None:
    files = [f for f in sorted((ROOT / "instrument").rglob("*.py")) if "kinds" not in f.relative_to(ROOT).parts]
    assert len(files) > 20
    assert [b for f in files for b in kind_name_branches(f)] == []


def test_the_branch_finder_sees_each_form_of_branch(tmp_path: Path) -> None:
    (ROOT / "instrument" / "_probe_tmp").mkdir(exist_ok=True)
    probe = ROOT / "instrument" / "_probe_tmp" / "m.py"
    try:
        probe.write_text('if k == "knee":\n    pass\nx = k in ("aads", "replica")\n'
                         'TABLE = {"ankle": 1, "afo": 2}\nmatch k:\n    case "replica":\n        pass\n'
                         'fine = {"hip": 1}\nalso_fine = kinds.get("knee")\n')
        assert [b.rsplit(":", 1)[1] for b in kind_name_branches(probe)] == ["1", "3", "4", "6"]
    finally:
        probe.unlink()
        probe.parent.rmdir()


def test_every_kind_is_complete_and_builds_its_protocol_from_its_defaults() -> None:
    assert kinds.names() == ("aads", "knee", "ankle", "replica", "knee_return")
    for kind in kinds.KINDS:
        assert isinstance(kind, TrialKind) and kind.title and kind.summary and kind.instructions()
        assert kind.analysis in (kinds.AFO_STIFFNESS, kinds.PASSIVE_PARAMETERS, kinds.REPLICA_SPRINGS)
        proto = kind.protocol()
        assert proto.name == kind.name
        assert proto.devices and proto.checklist()
        assert kinds.get(kind.name) is kind
    assert kinds.get("afo") is kinds.get("aads")  # the AADS test's other name
    with pytest.raises(ProtocolError, match="no trial kind 'hip'"):
        kinds.get("hip")
    with pytest.raises(ProtocolError, match="no parameter spring"):
        kinds.get("knee").protocol(spring=2)


def test_the_record_command_takes_every_parameter_of_every_kind() -> None:
    parser = build_parser()
    for kind in kinds.KINDS:
        for p in kind.parameters:
            args = parser.parse_args(["record", "--simulate", "--protocol", kind.name, p.option,
                                      *([] if p.value_type is bool else [str(p.choices[-1] if p.choices else p.default)])])
            assert getattr(args, p.dest) is not None, (kind.name, p.name)
    args = parser.parse_args(["record", "--protocol", "knee_return", "--hip", "55", "--speed", "20"])
    proto = kinds.get(args.protocol).protocol(**{p.name: getattr(args, p.dest) for p in kinds.get(args.protocol).parameters
                                                 if getattr(args, p.dest) is not None})
    assert isinstance(proto, KneeReturnProtocol) and proto.hip_flexion_deg == 55.0 and proto.speed_deg_s == 20.0
    with pytest.raises(SystemExit):  # outside the parameter's range: a usage error
        parser.parse_args(["record", "--protocol", "knee", "--speed", "500"])


@given(st.sampled_from([p for p in kinds.all_parameters() if p.low is not None and p.high is not None]),
       st.floats(allow_nan=True, allow_infinity=True, width=32))
def test_a_parameter_takes_exactly_its_range(p: kinds.Parameter, value: float) -> None:
    inside = np.isfinite(value) and p.low <= value <= p.high and (p.value_type is float or value == int(value))
    if inside:
        assert p.check(value) == p.value_type(value)
    else:
        with pytest.raises(ProtocolError, match=p.label):
            p.check(value)


def test_kinds_that_share_a_parameter_describe_it_once() -> None:
    shared = [p for p in kinds.all_parameters() if sum(p in k.parameters for k in kinds.KINDS) > 1]
    assert {p.name for p in shared} >= {"speed_deg_s", "arm_mass_kg", "arm_com_m", "hip_flexion_deg"}


def test_the_knee_out_and_back_records_both_legs_and_the_diagnosis_reads_them(tmp_path: Path) -> None:
    """The fifth kind, added as one module: recorded through the CAN driver, its table holds the sweep
    out and back (both directions of motion), and the trial CSV's kind is the knee's."""
    store = SessionStore(tmp_path / "store")
    store.add_subject(Subject("S01", mass_kg=75.0, shank_length_m=0.40, foot_length_m=0.26))
    session = store.new_session("S01")
    proto = kinds.get("knee_return").protocol(end_deg=30.0, speed_deg_s=15.0, hip_flexion_deg=90.0)
    with simulated_devices(proto, lab_config_for(proto, seed=3)) as (lab, devices):
        out = record_trial(store, session, proto, devices, extra_metadata=simulation_metadata(lab))
    assert out.status == "recorded"
    assert store.trial(out.trial_id).protocol == "knee_return"
    trial = read_trial(out.path)
    assert [e["kind"] for e in trial.events if e["kind"].startswith("sweep")] == ["sweep_start", "sweep_turn", "sweep_end"]
    table = trial_table(trial, store.subject("S01").as_dict())
    assert table.sidecar["kind"] == "knee" and table.sidecar["movement"] == "out_and_back"
    v = table.columns["velocity_deg_s"]
    assert (v > 10.0).sum() > 50 and (v < -10.0).sum() > 50  # both legs at the set speed
    peak = int(np.argmax(table.angle_deg))
    assert table.angle_deg[peak] == pytest.approx(30.0, abs=1.0)
    assert table.angle_deg[0] < 2.0 and table.angle_deg[-1] < 2.0  # out from 0° and back to it
    d = diagnose(from_table(table))
    assert d.text()  # the diagnosis reads a return sweep (its cause is not asserted: the subject is realistic)


_cell = st.text(st.characters(blacklist_categories=("Cs", "Cc", "Zl", "Zp"), blacklist_characters="\x85"), max_size=12)


@given(st.integers(0, 5).flatmap(lambda n: st.tuples(
    st.lists(_cell, min_size=n, max_size=n), st.lists(st.lists(_cell, min_size=n, max_size=n), max_size=6))))
def test_a_set_analysis_reads_as_text_and_round_trips_whatever_its_table(table: tuple[list[str], list[list[str]]]) -> None:
    """Any table (no rows at all, empty cells, a column title longer than its cells) prints aligned, one line per
    row under the headline, and comes back from its JSON form unchanged (the store keeps it that way)."""
    from instrument.kinds.base import SetAnalysis

    columns, rows = table
    a = SetAnalysis("headline", tuple(columns), tuple(tuple(r) for r in rows), ("/x/fig.png",), "details")
    lines = a.as_text().splitlines()
    assert lines[0] == "headline" and lines[-1] == "details"
    assert len(lines) == 2 + (1 + len(rows) if columns else 0)
    assert SetAnalysis.from_dict(json.loads(json.dumps(a.as_dict()))) == a


def test_a_replica_hold_short_of_its_readings_asks_for_a_repeat_and_repeats_fill_it() -> None:
    """A hold is short when no trial read half of its conversions (a stalled host): repeats at the same angle pool."""
    from analysis.trial_csv import TrialTable
    from instrument.kinds.replica import holds_short_of_readings

    def table(readings: list[list[float]]) -> TrialTable:
        return TrialTable({"time_s": np.zeros(0), "angle_deg": np.zeros(0), "torque_Nm": np.zeros(0)},
                          {"kind": "replica", "hold_readings": readings})

    first = table([[0.0, 30, 30], [8.0, 3, 30], [16.0, 15, 30], [24.0, 14, 30]])
    assert holds_short_of_readings([first]) == [8.0, 24.0]
    assert holds_short_of_readings([first, table([[8.0, 30, 30], [24.0, 2, 30]])]) == [24.0]
    no_counter = TrialTable({"time_s": np.zeros(0), "angle_deg": np.zeros(0), "torque_Nm": np.zeros(0)}, {})
    assert holds_short_of_readings([no_counter]) == []
