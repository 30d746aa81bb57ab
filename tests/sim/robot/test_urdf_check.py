"""`hri-lab urdf check`: a student's pan-tilt URDF prints check_urdf's tree; broken ones give their
error with its line and exit 1 (sim/robot/urdf_check.py, app/cli/urdf.py)."""

import math
from pathlib import Path

import pytest

from sim.robot.assets import panda_urdf
from sim.robot.urdf_check import MAX_INDENT, UrdfError, parse_urdf, parse_urdf_file, tree_text

from app.cli.main import main

ROOT = Path(__file__).resolve().parents[3]
PAN_TILT = ROOT / "examples/urdf/pan_tilt.urdf"
BROKEN = Path(__file__).resolve().parents[2] / "data/urdf"

# check_urdf's output for the pan-tilt file, as urdfdom's check_urdf.cpp prints it
PAN_TILT_TREE = """robot name is: pan_tilt
---------- Successfully Parsed XML ---------------
root Link: base_link has 1 child(ren)
    child(1):  pan_link
        child(1):  tilt_link
"""


def test_pan_tilt_checks_with_check_urdfs_output(capsys):
    assert main(["urdf", "check", str(PAN_TILT), "--tree-only"]) == 0
    assert capsys.readouterr().out == PAN_TILT_TREE


def test_the_joints_follow_with_their_types_limits_and_lines(capsys):
    assert main(["urdf", "check", str(PAN_TILT)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(PAN_TILT_TREE)
    assert "pan_joint (revolute): base_link -> pan_link  [-3.14, 3.14] rad  line 28" in out
    assert "tilt_joint (revolute): pan_link -> tilt_link  [-0.79, 0.79] rad  line 36" in out


def test_the_model_holds_the_files_limits():
    model = parse_urdf_file(PAN_TILT)
    assert [j.name for j in model.movable_joints()] == ["pan_joint", "tilt_joint"]
    assert model.joints[1].slider_range() == (-0.79, 0.79)
    assert model.joints[1].axis == (0.0, 1.0, 0.0)


@pytest.mark.parametrize(
    ("name", "line", "words"),
    [
        (
            "bad_parent.urdf",
            36,
            "its parent link 'pan_lnk' does not exist: expected one of base_link, pan_link, tilt_link",
        ),
        ("bad_limit.urdf", 41, "lower=0.79 is above upper=-0.79: expected lower <= upper"),
        ("nan_limit.urdf", 33, "joint 'pan_joint' <limit>: upper=\"pi\" is not a number"),
        ("no_limit.urdf", 36, "joint 'tilt_joint' is revolute but has no <limit>"),
        ("no_robot.urdf", 4, "the root element is <model>: expected <robot"),
        ("not_xml.urdf", 42, "not XML: Opening and ending tag mismatch: axis"),
        ("two_roots.urdf", 28, "two root links: 'base_link' (line 5) and 'camera_link' (line 28)"),
        ("cycle.urdf", 43, "the joints make a cycle: base_link -[pan_joint, line 28]-> pan_link"),
        ("duplicate_link.urdf", 20, "link 'pan_link' is not unique: it is also at line 12"),
    ],
)
def test_a_broken_file_names_its_line_and_exits_1(capsys, name, line, words):
    path = BROKEN / name
    assert main(["urdf", "check", str(path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert "\n" not in err
    assert "Traceback" not in err
    assert err.startswith(f"error: {path}:{line}: ")
    assert words in err


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("", "not XML"),
        ("<robot/>", "<robot> has no name"),
        ('<robot name="r"/>', "no <link> in the robot"),
        ('<robot name="r"><link/></robot>', "<link> has no name"),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="hinge"><parent link="a"/><child link="b"/></joint></robot>',
            'unknown type "hinge"',
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/></joint></robot>',
            "has no child link",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="0" upper="1" velocity="1"/></joint></robot>',
            "has no effort",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0"/></joint></robot>',
            'xyz="0 0" is not three numbers',
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="nan" upper="1" effort="1" velocity="1"/></joint></robot>',
            "not a finite number",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><link name="c"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint><joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint></robot>',
            "joint 'j' is not unique",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><link name="c"/><joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint><joint name="k" type="fixed"><parent link="b"/><child link="c"/></joint></robot>',
            "link 'c' has two parents",
        ),
        (
            '<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]><robot name="&x;"><link name="a"/></robot>',
            "external entity",
        ),
    ],
)
def test_urdfdoms_rules(text, words):
    with pytest.raises(UrdfError) as refused:
        parse_urdf(text)
    assert words in refused.value.message


def test_a_continuous_joint_slides_over_plus_minus_pi_and_children_go_in_joint_name_order():
    model = parse_urdf(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="z" type="fixed"><parent link="a"/><child link="b"/></joint>'
        '<joint name="w" type="continuous"><parent link="a"/><child link="c"/></joint></robot>'
    )
    assert model.joints[1].slider_range() == (-math.pi, math.pi)
    assert tree_text(model).splitlines()[3:] == ["    child(1):  c", "    child(2):  b"]  # urdfdom: by joint name


def test_the_pandas_urdf_checks():
    model = parse_urdf_file(panda_urdf())
    assert model.name == "panda"
    assert model.root == "panda_link0"
    assert len(model.movable_joints()) == 9  # 7 arm joints and the two fingers


def test_a_40000_link_chain_is_checked_and_printed_without_recursion(tmp_path, capsys):
    """The issue's 7.3 MB chain passed the check, then crashed with RecursionError printing the tree."""
    count = 40_000
    links = "".join(f'<link name="l{i}"/>' for i in range(count))
    joints = "".join(
        f'<joint name="j{i}" type="fixed"><parent link="l{i}"/><child link="l{i + 1}"/></joint>'
        for i in range(count - 1)
    )
    path = tmp_path / "chain.urdf"
    path.write_text(f'<robot name="chain">{links}{joints}</robot>')
    assert main(["urdf", "check", str(path), "--tree-only"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 3 + count - 1
    assert lines[-1] == "  " * (2 * MAX_INDENT) + f"child(1):  l{count - 1} (depth {count - 1})"


def test_a_xacro_file_is_named_as_unsupported():
    xacro = (
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="leg" params="n"><link name="${n}"/></xacro:macro>\n'
        '  <xacro:leg n="a"/>\n</robot>\n'
    )
    with pytest.raises(UrdfError) as refused:
        parse_urdf(xacro)
    assert "a xacro file" in refused.value.message
    assert "xacro robot.urdf.xacro > robot.urdf" in refused.value.message
