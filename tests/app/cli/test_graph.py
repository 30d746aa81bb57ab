"""The graph commands' pure parts (app/cli/graph.py): `interface show` as ros2interface's show verb
prints a definition: nested message types expanded one tab in, comments by level."""

import io

import pytest

from app.cli.graph import interface_text
from app.cli.main import main

TWIST = "Vector3 linear\n\tfloat64 x\n\tfloat64 y\n\tfloat64 z\nVector3 angular\n\tfloat64 x\n\tfloat64 y\n\tfloat64 z"
STAMP = "builtin_interfaces/Time stamp\n\tint32 sec\n\tuint32 nanosec"


def test_nested_types_expand_one_tab_in_at_every_level():
    assert interface_text("geometry_msgs/msg/Twist") == TWIST
    assert interface_text("geometry_msgs/Twist") == TWIST  # pkg/Name: any kind
    stamped = interface_text("geometry_msgs/msg/PoseStamped").splitlines()
    assert stamped[:6] == [
        "std_msgs/Header header",
        "\tbuiltin_interfaces/Time stamp",
        "\t\tint32 sec",
        "\t\tuint32 nanosec",
        "\tstring frame_id",
        "Pose pose",
    ]
    assert "\t\tfloat64 w 1" in stamped  # a default kept as written
    states = interface_text("sensor_msgs/msg/JointState").splitlines()
    assert states[-4:] == ["string[] name", "float64[] position", "float64[] velocity", "float64[] effort"]


def test_comments_of_the_top_level_by_default_of_all_or_of_none():
    header = "# ROS 2's Header (ROS 1's seq is gone); stamp answers rospy's secs/nsecs/to_sec()"
    assert interface_text("std_msgs/msg/Header") == f"{header}\n{STAMP}\nstring frame_id"
    assert interface_text("std_msgs/msg/Header", "none") == f"{STAMP}\nstring frame_id"
    nested = interface_text("geometry_msgs/msg/PoseStamped").splitlines()
    assert f"\t{header}" not in nested  # a nested definition's comments: only with --all-comments
    assert f"\t{header}" in interface_text("geometry_msgs/msg/PoseStamped", "all").splitlines()
    contact = interface_text("hri_lab/msg/ContactState", "none").splitlines()
    assert contact[0] == "std_msgs/Header header"  # the file's first line, a comment, left out
    assert "float64 normal_force" in contact  # its trailing comment cut
    assert "float64 normal_force            # N, plate" in interface_text("hri_lab/msg/ContactState").splitlines()


def test_a_service_and_an_action_keep_their_separators():
    assert interface_text("hri_lab/srv/AddTwoInts") == "int64 a\nint64 b\n---\nint64 sum"
    assert interface_text("hri_lab/action/Count", "none").count("---") == 2


@pytest.mark.parametrize(
    ("name", "reason"),
    [("x", "Invalid name 'x'"), ("std_msgs/msg/Nothing", "Unknown interface 'std_msgs/msg/Nothing'")],
)
def test_a_bad_name_is_refused_with_the_reason(name, reason):
    with pytest.raises(LookupError, match=reason):
        interface_text(name)


def test_the_command_reads_the_type_from_stdin_and_takes_the_comment_options(monkeypatch, capsys):
    monkeypatch.setattr("sys.stdin", io.StringIO("std_msgs/msg/Header\n"))  # `ros2 topic type X | ... show -`
    assert main(["interface", "show", "-", "--no-comments"]) == 0
    assert capsys.readouterr().out == f"{STAMP}\nstring frame_id\n"
    with pytest.raises(SystemExit):  # one of the two, as ros2interface's mutually exclusive group
        main(["interface", "show", "std_msgs/msg/Header", "--no-comments", "--all-comments"])


def test_interface_list_package_and_packages_as_ros2interface_prints_them(capsys):
    """ros2interface's list (each kind under its heading, `    pkg/kind/Name`, by package and name;
    -m -s -a pick kinds), package (`pkg/kind/Name`; an unknown package refused by name) and packages."""
    assert main(["interface", "list"]) == 0
    listed = capsys.readouterr().out.splitlines()
    headings = [line for line in listed if not line.startswith("    ")]
    assert headings == ["Messages:", "Services:", "Actions:"]
    messages = listed[1 : listed.index("Services:")]
    assert "    std_msgs/msg/String" in messages and "    geometry_msgs/msg/Twist" in messages
    assert messages == sorted(messages, key=lambda line: line.strip().split("/")[::2])  # by package, then name
    assert main(["interface", "list", "-a"]) == 0
    actions = capsys.readouterr().out.splitlines()
    assert actions[0] == "Actions:" and "    example_interfaces/action/Fibonacci" in actions
    assert "    hri_lab/action/Count" in actions and not any("/msg/" in line for line in actions)
    assert main(["interface", "package", "example_interfaces", "-s"]) == 0
    assert capsys.readouterr().out == (
        "example_interfaces/srv/AddTwoInts\nexample_interfaces/srv/SetBool\nexample_interfaces/srv/Trigger\n"
    )
    assert main(["interface", "packages", "-s"]) == 0
    packages = capsys.readouterr().out.splitlines()
    assert {"example_interfaces", "std_srvs", "hri_lab"} <= set(packages) and "geometry_msgs" not in packages
    assert packages == sorted(packages)
    assert main(["interface", "package", "no_such_package"]) == 1
    assert "Unknown package 'no_such_package'" in capsys.readouterr().err
