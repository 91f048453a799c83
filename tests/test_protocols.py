"""Trial protocols: named sequences of phases with their settings, one registry entry each."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from test_trial import handle_grasp

from simgrasp.assets.model import model_for
from simgrasp.config.fields import field_spec
from simgrasp.errors import SimgraspError
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig
from simgrasp.grasping.trials.phases import PHASES, phase_sequence
from simgrasp.grasping.trials.protocol import (
    PROTOCOLS,
    TrialProtocol,
    default_phases,
    get_protocol,
    protocol_names,
)
from simgrasp.grasping.trials.trial_config import FAST_TRIAL, TrialConfig

ROOT = Path(__file__).resolve().parents[1]
HOLD_ONLY = TrialProtocol(
    "hold-only",
    "the fast protocol without the tugs",
    ("settle", "pregrasp", "approach", "close", "lift", "hold"),
    FAST_TRIAL,
    "docs/results/grasp-sets/",
)


def test_every_protocol_runs_registered_phases_and_names_its_results() -> None:
    for name, protocol in PROTOCOLS.items():
        assert protocol.name == name
        assert [phase.name for phase in phase_sequence(protocol.phases)] == list(protocol.phases)
        assert protocol.phases == default_phases(protocol.config)
        assert "\n" not in protocol.summary
        assert (ROOT / protocol.results).is_dir(), protocol.results
        assert set(protocol.phases) <= set(PHASES)


def test_the_docs_table_lists_each_protocol_with_its_phases_and_summary() -> None:
    page = (ROOT / "docs" / "concepts" / "trials.md").read_text(encoding="utf-8")
    rows = re.findall(
        r"^\| `([\w-]+)` \| ([a-z]+(?: → [a-z]+)+) \| (.+?) \|", page, flags=re.MULTILINE
    )
    documented = {name: (phases, summary.replace("`", "")) for name, phases, summary in rows}
    registered = {n: (" → ".join(p.phases), p.summary) for n, p in PROTOCOLS.items()}
    assert documented == registered


def test_the_protocol_choices_are_the_registry() -> None:
    field = LabelConfig.__dataclass_fields__["protocol"]
    choices = field_spec(field).choices
    assert callable(choices) and choices() == protocol_names() == tuple(PROTOCOLS)
    assert LabelConfig("gen_hammer", protocol="acronym").trial == get_protocol("acronym").config


def test_unknown_protocols_phases_and_mismatched_entries_are_refused_in_one_line() -> None:
    with pytest.raises(SimgraspError, match="'slow' is not one of full, fast, acronym"):
        LabelConfig("gen_hammer", protocol="slow")
    with pytest.raises(SimgraspError, match="^unknown protocol 'slow'; use one of full, fast"):
        get_protocol("slow")
    with pytest.raises(SimgraspError, match="^unknown trial phase 'wiggle'; the phases are"):
        phase_sequence(("settle", "wiggle"))
    with pytest.raises(SimgraspError, match="a shake phase needs the config's shake settings"):
        TrialProtocol("shaken", "no shake settings", ("settle", "shake"), TrialConfig(), "")


def test_a_protocol_registered_as_one_entry_labels_grasps(monkeypatch) -> None:
    """A protocol added to the registry at run time (the fast one without its tugs) labels a
    grasp on the label-grasps code path: its phases run, bit for bit as the fast protocol's up
    to the hold, and the tugs do not."""
    monkeypatch.setitem(PROTOCOLS, HOLD_ONLY.name, HOLD_ONLY)
    model = model_for("gen_hammer_s1")  # the hammer and scene of tests/test_trial.py
    records = {}
    for protocol in ("hold-only", "fast"):
        labeler = GraspLabeler(model, LabelConfig("gen_hammer_s1", protocol=protocol, seed=3))
        grasp = handle_grasp(labeler.scene)
        object_T_tcp = grasp.object_T_tcp(labeler.scene.world_T_object)
        records[protocol] = labeler.label(0, object_T_tcp, grasp.width)
    ours, fast = records["hold-only"], records["fast"]
    assert ours["protocol"] == "hold-only" and ours["success"] is True, ours["failure"]
    assert ours["slip_perturb"] is None and fast["slip_perturb"] is not None
    assert "tugs" not in ours["timings_s"] and "tugs" in fast["timings_s"]
    for key in ("lift_height", "slip_lift", "handle_fraction", "contact_points_object"):
        assert ours[key] == fast[key], key
