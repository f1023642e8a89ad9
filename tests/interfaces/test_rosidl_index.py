"""Services and actions from an ament resource index: authored prefixes and the pinned set."""

from __future__ import annotations

from pathlib import Path

import pytest

from skillwright.interfaces.ros2msg import definition_from_text
from skillwright.interfaces.rosidl_index import (
    ENV_VARIABLE,
    expand,
    index_files,
    index_texts,
    interface_prefixes,
    top_block,
)


def _package(prefix: Path, package: str, files: dict[str, str]) -> None:
    """An interface package installed the way colcon and the PyPI wheels lay it out."""
    index = prefix / "share" / "ament_index" / "resource_index" / "rosidl_interfaces"
    index.mkdir(parents=True, exist_ok=True)
    listed = []
    for relative, text in files.items():
        path = prefix / "share" / package / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        listed += [relative, relative.rsplit(".", 1)[0] + ".idl"]
    (index / package).write_text("\n".join(listed) + "\n", encoding="utf-8")


@pytest.fixture
def prefix(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    root = tmp_path / "install"
    _package(
        root,
        "acme_msgs",
        {
            "msg/Cell.msg": "int32 x\nint32 y # column\n",
            "srv/Mark.srv": "Cell cell\ngeometry_msgs/Point at\n---\nuint8 OK=0\nuint8 result\n",
            "action/Sweep.action": "Cell[] cells\n---\nbool done\n---\nfloat32 left\n",
        },
    )
    monkeypatch.setenv(ENV_VARIABLE, str(root))
    monkeypatch.delenv("ROS_DISTRO", raising=False)
    return root


def test_the_index_lists_each_definition_file_by_type_name(prefix: Path) -> None:
    files = index_files("testdistro")
    assert set(files) == {"acme_msgs/msg/Cell", "acme_msgs/srv/Mark", "acme_msgs/action/Sweep"}
    assert files["acme_msgs/msg/Cell"].startswith("int32 x")


def test_services_and_actions_become_rosidl_parts_with_their_messages(prefix: Path) -> None:
    point = "float64 x\nfloat64 y\nfloat64 z\n"
    texts = index_texts("testdistro", {"geometry_msgs/msg/Point": point})
    assert {n for n in texts if "_" in n.rsplit("/", 1)[1]} == {
        "acme_msgs/srv/Mark_Request",
        "acme_msgs/srv/Mark_Response",
        "acme_msgs/action/Sweep_Goal",
        "acme_msgs/action/Sweep_Result",
        "acme_msgs/action/Sweep_Feedback",
    }
    request = definition_from_text(
        "acme_msgs/srv/Mark_Request", texts["acme_msgs/srv/Mark_Request"]
    )
    cell, at = request.fields or []
    assert (cell.base_type, [f.name for f in cell.fields]) == ("acme_msgs/msg/Cell", ["x", "y"])
    assert (at.base_type, [f.name for f in at.fields]) == ("geometry_msgs/msg/Point", list("xyz"))
    assert not request.notes
    response = definition_from_text(
        "acme_msgs/srv/Mark_Response", texts["acme_msgs/srv/Mark_Response"]
    )
    assert [(c.name, c.value) for c in response.constants] == [("OK", 0)]
    goal = definition_from_text("acme_msgs/action/Sweep_Goal", texts["acme_msgs/action/Sweep_Goal"])
    assert goal.fields is not None
    assert goal.fields[0].array == "unbounded"


def test_a_message_the_index_and_the_store_lack_stays_unresolved(prefix: Path) -> None:
    texts = index_texts("testdistro")
    request = definition_from_text(
        "acme_msgs/srv/Mark_Request", texts["acme_msgs/srv/Mark_Request"]
    )
    assert request.fields is not None
    assert not request.fields[1].resolved


def test_ament_prefix_path_counts_only_for_its_own_distribution(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = tmp_path / "opt" / "ros"
    _package(root, "acme_msgs", {"msg/Cell.msg": "int32 x\n"})
    monkeypatch.delenv(ENV_VARIABLE, raising=False)
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(root))
    monkeypatch.setenv("ROS_DISTRO", "humble")
    assert root not in interface_prefixes("testdistro")
    monkeypatch.setenv("ROS_DISTRO", "testdistro")
    assert root in interface_prefixes("testdistro")


def test_expand_appends_each_used_message_once_depth_first() -> None:
    blocks = {
        "p/msg/A": "B b\nB again\nstd_msgs/Header header\n",
        "p/msg/B": "int8 v\n",
        "std_msgs/msg/Header": "string frame_id\n",
    }
    text = expand("p/srv/S_Request", "A a\nA b\n", blocks.get)
    assert text.count("MSG: p/A") == 1
    assert text.count("MSG: p/B") == 1
    assert "MSG: std_msgs/Header" in text
    assert top_block(text) == "A a\nA b"


@pytest.mark.parametrize(
    ("service", "response_fields"),
    [
        ("nav_msgs/srv/GetMap", ["map"]),
        ("std_srvs/srv/Trigger", ["success", "message"]),
        ("rcl_interfaces/srv/GetParameters", ["values"]),
        ("lifecycle_msgs/srv/ChangeState", ["success"]),
    ],
)
def test_the_pinned_jazzy_packages_define_the_core_services(
    service: str, response_fields: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv(ENV_VARIABLE, raising=False)
    monkeypatch.delenv("ROS_DISTRO", raising=False)
    texts = index_texts("jazzy")
    response = definition_from_text(f"{service}_Response", texts[f"{service}_Response"])
    assert [f.name for f in response.fields or []] == response_fields
    assert all(f.resolved for f in response.fields or [])


def test_the_pinned_jazzy_packages_have_no_navigation_stack_types(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.delenv(ENV_VARIABLE, raising=False)
    monkeypatch.delenv("ROS_DISTRO", raising=False)
    packages = {name.split("/", 1)[0] for name in index_files("jazzy")}
    assert {"nav_msgs", "std_srvs", "rcl_interfaces", "action_msgs"} <= packages
    assert not packages & {"nav2_msgs", "slam_toolbox"}
