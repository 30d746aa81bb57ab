"""Python and YAML launch files (rosclient/pylaunch.py, the launch / launch_ros layer of
rosclient/site): a description's evaluation (the processes it starts, with their ROS arguments),
arguments, conditions, includes, groups, refusals by name; and a run of real processes with a
timer, event handlers and a Shutdown event; roslaunch's search of a whole package."""

import os
import sys
import threading
from pathlib import Path

import pytest
import yaml

from rosclient import launch as xml_launch
from rosclient import pylaunch
from tests.ros_running import PROGRAMS

COURSE = PROGRAMS / "course_ws"
LAB8 = COURSE / "src" / "lab8" / "launch" / "lab8.launch.py"


def _ros_args(plan) -> list[str]:
    return plan.args[plan.args.index("--ros-args") + 1 :]


def _params(plan) -> dict:
    args = _ros_args(plan)
    values: dict = {}
    for i, flag in enumerate(args):
        if flag == "--params-file":
            values.update(yaml.safe_load(Path(args[i + 1]).read_text())["/**"]["ros__parameters"])
    return values


def test_the_lab8_launch_file_starts_its_server_with_name_namespace_parameter_and_remap():
    runner = pylaunch.evaluate(LAB8, {"offset": "7"}, workspace=str(COURSE))
    (server,) = runner.plans  # the client comes from an event handler's timer, later
    assert server.label == "myServer-1"
    assert server.entry == "lab8.my_server:main"
    args = _ros_args(server)
    assert args[:2] == ["-r", "__node:=lab8_server"]
    assert "__ns:=/lab8" in args
    assert "add_two_ints:=adder" in args
    assert _params(server) == {"offset": 7}  # a substitution's text read as YAML: an integer
    assert server.output == "screen"
    assert len(runner.handlers) == 2


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


PACKAGE_XML = "<package format='3'><name>{}</name></package>"


@pytest.fixture
def workspace(tmp_path):
    ws = tmp_path / "ws"
    pkg = ws / "src" / "demo"
    _write(pkg, "package.xml", PACKAGE_XML.format("demo"))
    _write(
        pkg,
        "setup.py",
        "from setuptools import setup\nsetup(entry_points={'console_scripts': ['talker = demo.talker:main']})\n",
    )
    _write(pkg, "demo/__init__.py", "")
    _write(pkg, "demo/talker.py", "def main():\n    pass\n")
    _write(pkg, "config/params.yaml", "/**:\n  ros__parameters:\n    rate: 5\n")
    _write(
        pkg,
        "launch/inner.launch.py",
        """
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('who'),
        Node(package='demo', executable='talker', name=LaunchConfiguration('who'), namespace='inner'),
    ])
""",
    )
    return ws


def test_includes_groups_conditions_and_package_paths(workspace, tmp_path, monkeypatch):
    monkeypatch.setenv("HRI_LAB_WORKSPACE", str(workspace))  # as `hri-lab launch --workspace` sets it
    top = _write(
        tmp_path,
        "top.launch.py",
        """
import os
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription, SetLaunchConfiguration
from launch.conditions import IfCondition, UnlessCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution, PythonExpression
from launch_ros.actions import Node, PushRosNamespace, SetParameter
from launch_ros.substitutions import FindPackageShare

def generate_launch_description():
    params = os.path.join(get_package_share_directory('demo'), 'config', 'params.yaml')
    return LaunchDescription([
        DeclareLaunchArgument('fast', default_value='false'),
        SetParameter(name='use_sim_time', value=True),
        GroupAction([
            PushRosNamespace('robot1'),
            SetLaunchConfiguration('scoped', 'yes'),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource(PathJoinSubstitution([FindPackageShare('demo'), 'launch', 'inner.launch.py'])),
                launch_arguments={'who': 'alice'}.items(),
            ),
        ]),
        Node(package='demo', executable='talker', name='fast', parameters=[params], condition=IfCondition(LaunchConfiguration('fast'))),
        Node(package='demo', executable='talker', name='slow', parameters=[params, {'rate': PythonExpression(['2 * 3'])}],
             condition=UnlessCondition(LaunchConfiguration('fast'))),
        Node(package='demo', executable='talker', name='leak', condition=IfCondition(LaunchConfiguration('scoped', default='false'))),
    ])
""",
    )
    runner = pylaunch.evaluate(top, {}, workspace=str(workspace))
    inner, slow = runner.plans
    assert inner.label == "talker-1" and slow.label == "talker-2"
    assert _ros_args(inner)[:4] == ["-r", "__node:=alice", "-r", "__ns:=/robot1/inner"]
    assert _params(inner) == {"use_sim_time": True}  # SetParameter: every node after it
    assert "__node:=slow" in _ros_args(slow)
    assert _params(slow) == {"use_sim_time": True, "rate": 6}
    assert str(workspace / "src/demo/config/params.yaml") in _ros_args(slow)
    assert "__ns:=/robot1" not in " ".join(_ros_args(slow))  # the group's namespace stayed in the group
    assert runner.context.launch_configurations.get("scoped") is None
    fast = pylaunch.evaluate(top, {"fast": "true"}, workspace=str(workspace))
    assert [p.args[p.args.index("-r") + 1] for p in fast.plans] == ["__node:=alice", "__node:=fast"]


def test_a_missing_argument_and_an_unsupported_name_are_refused_by_name(workspace, tmp_path):
    from launch._core import LaunchError, Unsupported

    inner = workspace / "src/demo/launch/inner.launch.py"
    with pytest.raises(LaunchError, match="missing required argument 'who'"):
        pylaunch.evaluate(inner, {}, workspace=str(workspace))
    container = _write(
        tmp_path,
        "composed.launch.py",
        "from launch_ros.actions import ComposableNodeContainer\ndef generate_launch_description():\n    pass\n",
    )
    with pytest.raises(Unsupported, match=r"does not support launch_ros\.actions\.ComposableNodeContainer"):
        pylaunch.evaluate(container, {}, workspace=str(workspace))
    missing = _write(
        tmp_path,
        "missing.launch.py",
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n"
        "def generate_launch_description():\n    return LaunchDescription([Node(package='demo', executable='nope')])\n",
    )
    with pytest.raises(LaunchError, match="No executable found: 'nope' in package 'demo'"):
        pylaunch.evaluate(missing, {}, workspace=str(workspace))


def test_a_yaml_launch_file_is_read_as_its_xml_twin(workspace, tmp_path):
    _write(workspace / "src/demo", "scripts/listener.py", "print('x')\n")
    path = _write(
        workspace / "src/demo/launch",
        "demo.launch.yaml",
        """
launch:
- arg: {name: who, default: bob}
- node:
    pkg: demo
    exec: talker
    name: $(var who)
    param: [{name: rate, value: 3}]
    remap: [{from: chatter, to: talk}]
- group:
    - push-ros-namespace: {namespace: ns1}
    - node: {pkg: demo, exec: listener.py, name: listener}
""",
    )
    read = xml_launch.Reader(path, {}).read()
    talker, listener = read.nodes
    assert talker.entry == "demo.talker:main" and talker.name == "bob"
    assert talker.argv()[-4:] == ["-p", "rate:=3", "-r", "chatter:=talk"]
    assert listener.program.name == "listener.py" and listener.namespace == "/ns1"


def test_roslaunch_finds_a_node_anywhere_in_its_package(tmp_path):
    pkg = tmp_path / "catkin_ws" / "src" / "turtles"
    _write(pkg, "package.xml", PACKAGE_XML.format("turtles"))
    _write(pkg, "nodes/mimic.py", "print('x')\n")
    path = _write(pkg, "launch/mimic.launch", '<launch><node pkg="turtles" type="mimic.py" name="mimic"/></launch>')
    (node,) = xml_launch.read(path).nodes
    assert node.program == (pkg / "nodes" / "mimic.py").resolve()


def test_processes_timers_event_handlers_and_a_shutdown_event(tmp_path):
    path = _write(
        tmp_path,
        "events.launch.py",
        f"""
from launch import LaunchDescription
from launch.actions import EmitEvent, ExecuteProcess, LogInfo, RegisterEventHandler, TimerAction
from launch.event_handlers import OnProcessExit, OnProcessStart, OnShutdown
from launch.events import Shutdown
from launch.substitutions import LocalSubstitution

PY = {sys.executable!r}

def generate_launch_description():
    first = ExecuteProcess(cmd=[PY, '-c', 'print("first ran")'], name='first', output='screen')
    second = ExecuteProcess(cmd=[PY, '-c', 'import sys; sys.exit(3)'], name='second')
    sleeper = ExecuteProcess(cmd=[PY, '-c', 'import time; time.sleep(600)'], name='sleeper')
    return LaunchDescription([
        sleeper,
        first,
        RegisterEventHandler(OnProcessStart(target_action=first, on_start=[LogInfo(msg='first started')])),
        RegisterEventHandler(OnProcessExit(target_action=first, on_exit=[TimerAction(period=0.2, actions=[second])])),
        RegisterEventHandler(OnProcessExit(target_action=second, on_exit=lambda event, context: [
            LogInfo(msg=['second exited with ', LocalSubstitution('event.returncode')]),
            EmitEvent(event=Shutdown(reason='second ended')),
        ])),
        RegisterEventHandler(OnShutdown(on_shutdown=[LogInfo(msg=['shutting down: ', LocalSubstitution('event.reason')])])),
    ])
""",
    )
    runner = pylaunch.Runner("", logs=tmp_path)
    try:
        code = runner.run(path, {}, threading.Event())
    finally:
        pylaunch._stop_all(runner.processes)
    said = [line for line in runner.lines if "launch]" not in line]
    assert code == 1  # `second` died with status 3
    assert said.index("[INFO] [launch.user]: first started") > said.index(
        next(s for s in said if "[first-1]: process started" in s)
    )
    assert "[INFO] [launch.user]: second exited with 3" in said
    assert "[INFO] [launch.user]: shutting down: second ended" in said
    assert any(s.startswith("[ERROR] [second-1]: process has died [pid") and "exit code 3" in s for s in said)
    assert any(s.startswith("[INFO] [sleeper-1]: process has finished cleanly") for s in said)  # stopped by SIGINT
    assert (tmp_path / "first-1.log").read_text() == "first ran\n"
    assert all(p.proc.poll() is not None for p in runner.processes)


def test_execute_process_of_executable_in_package_runs_an_entry_point_and_a_script(workspace, tmp_path):
    """topic_monitor's launch files: `ExecuteProcess(cmd=[ExecutableInPackage(...), args...])` of a
    console_scripts entry point (no file of that name in the sources) and of a rosrun-found script:
    each runs as its installed lib/PKG/EXE would, with its arguments, labelled by the executable."""
    pkg = workspace / "src" / "demo"
    _write(pkg, "demo/shout.py", "import sys\n\ndef main():\n    print('shout', sys.argv[1:])\n    return 4\n")
    _write(pkg, "setup.cfg", "[options.entry_points]\nconsole_scripts =\n    shout = demo.shout:main\n")
    _write(pkg, "scripts/whisper.py", "import sys\nprint('whisper', sys.argv[1:])\n")
    path = _write(
        tmp_path,
        "exe.launch.py",
        """
from launch import LaunchDescription
from launch.actions import ExecuteProcess
from launch_ros.substitutions import ExecutableInPackage

def generate_launch_description():
    return LaunchDescription([
        ExecuteProcess(cmd=[ExecutableInPackage(package='demo', executable='shout'), 'small', '--depth', '1'],
                       output='screen'),
        ExecuteProcess(cmd=[ExecutableInPackage(package='demo', executable='whisper.py'), 'quiet'], output='screen'),
    ])
""",
    )
    runner = pylaunch.Runner("", logs=tmp_path / "logs", workspace=str(workspace))
    try:
        code = runner.run(path, {}, threading.Event())
    finally:
        pylaunch._stop_all(runner.processes)
    assert [p.plan.label for p in runner.processes] == ["shout-1", "whisper.py-1"]
    assert (tmp_path / "logs" / "shout-1.log").read_text() == "shout ['small', '--depth', '1']\n"
    assert (tmp_path / "logs" / "whisper.py-1.log").read_text() == "whisper ['quiet']\n"
    assert [p.proc.returncode for p in runner.processes] == [4, 0]  # the entry point's return: its status
    assert code == 1  # a process died (status 4), as launch reports it


def test_an_executable_installed_again_leaves_its_file_as_the_started_processes_read_it(workspace, tmp_path):
    """topic_monitor's depth demo starts four processes of one entry point: the second
    ExecutableInPackage must not rewrite the file the first process is reading (rewritten in place,
    a process reading it then saw an empty script and ran nothing)."""
    pkg = workspace / "src" / "demo"
    _write(pkg, "demo/shout.py", "def main():\n    return 0\n")
    _write(pkg, "setup.cfg", "[options.entry_points]\nconsole_scripts =\n    shout = demo.shout:main\n")
    runner = pylaunch.Runner("", logs=tmp_path / "logs", workspace=str(workspace))
    found = runner.executable("demo", "shout")
    script = runner.installed(found)
    before = script.stat()
    assert runner.installed(found) == script
    after = script.stat()
    assert (after.st_ino, after.st_mtime_ns, after.st_size) == (before.st_ino, before.st_mtime_ns, before.st_size)
    assert script.read_text().startswith("#!") and os.access(script, os.X_OK)
    assert list(script.parent.iterdir()) == [script]  # no temporary file left beside it
