"""Relevance verdicts of the rules engine, and their agreement with the paper's own filter."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from skillwright.interfaces.infrastructure import RULES
from skillwright.interfaces.inventory import (
    InfrastructureFlag,
    Interface,
    InterfaceKind,
    Relevance,
)
from skillwright.interfaces.relevance import (
    agreement,
    relevance_by_rules,
    relevance_by_rules_for,
)
from tests.conftest import REPO_ROOT


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "rule"),
    [
        ("topic", "/rosout", "rcl_interfaces/msg/Log", "rosout"),
        ("topic", "/clock", "rosgraph_msgs/msg/Clock", "clock"),
        ("topic", "/performance_metrics", "gazebo_msgs/msg/PerformanceMetrics", "performance"),
        ("topic", "/robot_description", "std_msgs/msg/String", "robot_model"),
        ("topic", "/bond", "bond/msg/Status", "bond"),
        ("topic", "/arm/transition_event", "lifecycle_msgs/msg/TransitionEvent", "lifecycle"),
        ("service", "/teleop/set_parameters", "rcl_interfaces/srv/SetParameters", "parameter"),
        (
            "service",
            "/controller_manager/load_controller",
            "controller_manager_msgs/srv/LoadController",
            "controller_bring_up",
        ),
        ("service", "/spawn_entity", "gazebo_msgs/srv/SpawnEntity", "simulator_services"),
        ("service", "/reset_world", "std_srvs/srv/Empty", "simulator_physics_services"),
    ],
)
def test_plumbing_is_infrastructure_with_the_rule_named_in_the_reason(
    kind: InterfaceKind, name: str, type_name: str, rule: str
) -> None:
    verdict = relevance_by_rules_for(kind, name, type_name)
    assert verdict.category == "infrastructure"
    assert verdict.relevant is False
    assert "(rule " + rule in verdict.reason
    assert verdict.engine == "rules"


@pytest.mark.parametrize(
    ("kind", "name", "type_name", "says"),
    [
        ("topic", "/cmd_vel", "geometry_msgs/msg/Twist", "commands the resource"),
        ("topic", "/scan", "sensor_msgs/msg/LaserScan", "senses"),
        ("action", "/navigate_to_pose", "nav2_msgs/action/NavigateToPose", "plans"),
        (
            "service",
            "/controller_manager/switch_controller",
            "controller_manager_msgs/srv/SwitchController",
            "controllers",
        ),
        # An Empty service that is not one of the simulator's is the robot's own.
        ("service", "/dock", "std_srvs/srv/Empty", "no infrastructure rule covers it"),
        ("topic", "/acme/widget", "acme_msgs/msg/Widget", "no infrastructure rule covers it"),
        ("action", "/acme/polish", "acme_msgs/action/Polish", "goal-directed behaviour"),
    ],
)
def test_everything_else_is_control_with_a_reason(
    kind: InterfaceKind, name: str, type_name: str, says: str
) -> None:
    verdict = relevance_by_rules_for(kind, name, type_name)
    assert verdict.category == "control"
    assert verdict.relevant is True
    assert says in verdict.reason


def test_a_stale_stored_flag_does_not_decide_the_verdict() -> None:
    interface = Interface(
        name="/cmd_vel",
        kind="topic",
        type_name="geometry_msgs/msg/Twist",
        infrastructure=InfrastructureFlag(rule="old", reason="written by an older rule table"),
    )
    assert relevance_by_rules(interface).category == "control"


def test_every_infrastructure_rule_has_a_reason() -> None:
    assert all(rule.reason and rule.reason[0].islower() for rule in RULES)


def _verdict(relevant: bool) -> Relevance:
    return Relevance(
        relevant=relevant,
        category="control" if relevant else "infrastructure",
        reason="test",
    )


def test_agreement_counts_both_kinds_of_disagreement() -> None:
    verdicts = {
        "a": _verdict(True),
        "b": _verdict(True),
        "c": _verdict(False),
        "d": _verdict(False),
    }
    result = agreement(verdicts, {"a", "c"})
    assert result.total == 4
    assert result.both == {"a"}
    assert result.only_ours == {"b"}
    assert result.only_reference == {"c"}
    assert result.disagreements == {"b", "c"}
    assert result.precision == 0.5
    assert result.recall == 0.5


def test_agreement_of_empty_selections_is_perfect() -> None:
    result = agreement({"a": _verdict(False)}, set())
    assert (result.precision, result.recall) == (1.0, 1.0)


def test_agreement_refuses_a_reference_name_without_a_verdict() -> None:
    with pytest.raises(ValueError, match="/missing"):
        agreement({"a": _verdict(True)}, {"a", "/missing"})


# ---------------------------------------------------------------- the paper's robot


def _script() -> ModuleType:
    path = REPO_ROOT / "bench" / "relevance_agreement.py"
    spec = importlib.util.spec_from_file_location("relevance_agreement", path)
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def script(shared_data: Path) -> ModuleType:
    return _script()


@pytest.fixture(scope="module")
def paper(script: ModuleType) -> tuple[list[Interface], set[str], dict[str, Any]]:
    return script.read_report(), script.kept_names(), script.load_labels()


def test_paper_reports_have_107_interfaces_of_which_33_are_kept(
    paper: tuple[list[Interface], set[str], dict[str, Any]],
) -> None:
    interfaces, kept, _ = paper
    assert len(interfaces) == 107
    assert len(kept) == 33
    assert kept <= {i.name for i in interfaces}


def test_rules_engine_disagrees_with_the_paper_exactly_where_documented(
    paper: tuple[list[Interface], set[str], dict[str, Any]],
) -> None:
    interfaces, kept, labels = paper
    verdicts = {i.name: relevance_by_rules(i) for i in interfaces}
    result = agreement(verdicts, kept)
    measured = {
        name: ("control" if name in result.only_ours else "infrastructure")
        for name in result.disagreements
    }
    documented = {name: label["rules"] for name, label in labels["disagreements"].items()}
    assert measured == documented


def test_every_documented_disagreement_is_judged(
    paper: tuple[list[Interface], set[str], dict[str, Any]],
) -> None:
    _, kept, labels = paper
    for name, label in labels["disagreements"].items():
        assert label["paper"] == ("control" if name in kept else "infrastructure"), name
        assert label["rules"] != label["paper"], name
        assert label["right"] in {"rules", "paper"}, name
        assert len(label["why"]) > 20, name


def test_rules_engine_against_the_judged_labels(
    script: ModuleType, paper: tuple[list[Interface], set[str], dict[str, Any]]
) -> None:
    interfaces, kept, labels = paper
    verdicts = {i.name: relevance_by_rules(i) for i in interfaces}
    judged = script.judged_control(interfaces, kept, labels)
    wrong = {name for name, label in labels["disagreements"].items() if label["right"] == "paper"}
    result = agreement(verdicts, judged)
    assert result.disagreements == wrong


def test_agreement_script_prints_precision_recall_and_every_disagreement(
    script: ModuleType, capsys: pytest.CaptureFixture[str]
) -> None:
    assert script.main([]) == 0
    out = capsys.readouterr().out
    assert "engine rules: 107 interfaces, the paper keeps 33" in out
    assert "precision 1.00  recall 0.45" in out
    assert "/spawn_entity" in out
    assert "not judged yet" not in out
