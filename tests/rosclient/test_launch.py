"""Launch files that are not what they claim (the attack suite, docs/operations.md): each is an
`hri-lab launch` error naming the file and the line, never a traceback; node names are ROS names
and programs are found inside their package only."""

import argparse
import os

import pytest

from rosclient import launch
from rosclient.launch import LaunchError, read

PROGRAM = "import rospy\n"


def _write(folder, name: str, text: str):
    path = folder / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("body", "says"),
    [
        (
            "<group>" * 10_000 + "</group>" * 10_000,
            r"self.launch, line 2: not a launch file \(Excessive depth in document: 256",
        ),
        ('<include file="self.launch"/>', r"self.launch, line 2: <include> of .*self.launch, which is including it"),
        ('<param name="n" type="int" value="abc"/>', r"line 2: <param name=\"n\" type=\"int\">: 'abc' is not an int"),
        (
            '<param name="x" type="double" value="1,5"/>',
            r"line 2: <param name=\"x\" type=\"double\">: '1,5' is not a double",
        ),
        (
            '<param name="t" textfile="/nonexistent/robot.urdf"/>',
            r"line 2: <param name=\"t\" textfile=...>: cannot read /nonexistent/robot.urdf",
        ),
        ('<rosparam file="missing.yaml"/>', r"line 2: <rosparam file=...>: cannot read missing.yaml"),
        ('<node pkg="p" type="talker.py" name="../../evil"/>', r"line 2: node name '../../evil' is not a ROS name"),
        (
            '<node pkg="p" type="../../bin/sh" name="shell"/>',
            r"line 2: node program '../../bin/sh' of package 'p': a program's file name",
        ),
        ('<node pkg=".." type="sh" name="shell"/>', r"line 2: node program 'sh' of package '..'"),
    ],
)
def test_a_malformed_launch_file_is_refused_with_its_line(tmp_path, body, says):
    _write(tmp_path, "talker.py", PROGRAM)
    path = _write(tmp_path, "self.launch", f"<launch>\n{body}\n</launch>\n")
    with pytest.raises(LaunchError, match=says):
        read(path)


def test_a_program_linked_from_outside_its_package_is_not_found(tmp_path):
    package = tmp_path / "pkg"
    package.mkdir()
    os.symlink("/bin/sh", package / "sh")
    path = _write(package, "run.launch", '<launch>\n<node pkg="pkg" type="sh" name="shell"/>\n</launch>\n')
    with pytest.raises(LaunchError, match=r"line 2: node program 'sh' of package 'pkg' not found"):
        read(path)


def test_includes_that_include_each_other_and_deep_chains_are_refused(tmp_path):
    _write(tmp_path, "a.launch", '<launch>\n<include file="b.launch"/>\n</launch>\n')
    _write(tmp_path, "b.launch", '<launch>\n<include file="a.launch"/>\n</launch>\n')
    with pytest.raises(LaunchError, match=r"b.launch, line 2: <include> of .*a.launch, which is including it"):
        read(tmp_path / "a.launch")
    for i in range(launch.MAX_INCLUDES + 2):
        _write(tmp_path, f"chain{i}.launch", f'<launch>\n<include file="chain{i + 1}.launch"/>\n</launch>\n')
    _write(tmp_path, f"chain{launch.MAX_INCLUDES + 2}.launch", "<launch/>\n")
    with pytest.raises(LaunchError, match=f"nest deeper than {launch.MAX_INCLUDES}"):
        read(tmp_path / "chain0.launch")


def test_hri_lab_launch_prints_the_refusal_not_a_traceback(tmp_path, capsys):
    path = _write(tmp_path, "bad.launch", '<launch>\n<param name="n" type="int" value="abc"/>\n</launch>\n')
    args = argparse.Namespace(file=str(path), args=[], url=None, workspace=None)
    assert launch.run(args, path, {}) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {path}, line 2:")
    assert "Traceback" not in err


def test_a_well_formed_file_still_reads(tmp_path):
    _write(tmp_path, "talker.py", PROGRAM)
    path = _write(
        tmp_path,
        "ok.launch",
        '<launch>\n<arg name="rate" default="10"/>\n<node pkg="p" type="talker.py" name="talker">\n'
        '<param name="rate" type="int" value="$(arg rate)"/>\n</node>\n</launch>\n',
    )
    (node,) = read(path).nodes
    assert node.name == "talker"
    assert node.params == {"rate": 10}
    assert node.program == tmp_path / "talker.py"


def test_logs_go_where_ros_2s_launch_puts_them(tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "logs"))
    first = launch.log_dir()
    assert first.parent == tmp_path / "logs" and first.is_dir()
    assert first.name.endswith(f"-{os.getpid()}")  # time-host-pid, as launch/logging names it
    second = launch.log_dir()
    assert second != first
    assert (tmp_path / "logs" / "latest").resolve() == second  # latest: the newest
    monkeypatch.setenv("ROS_LOG_DIR", "")  # empty: as unset
    monkeypatch.setenv("ROS_HOME", str(tmp_path / "home"))
    assert launch.log_dir().parent == tmp_path / "home" / "log"
    monkeypatch.delenv("ROS_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "user"))
    assert launch.log_dir().parent == tmp_path / "user" / ".ros" / "log"


def test_logs_in_a_temporary_folder_where_the_base_cannot_be_made(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("not a folder")
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "file"))
    folder = launch.log_dir()
    assert folder.is_dir() and folder.name.startswith("hri-lab-launch-")
    folder.rmdir()
