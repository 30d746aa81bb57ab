"""The course's ROS 2 packages (tests/ros_programs/course_ws) started as their handouts start them,
against one real lab: `hri-lab run PKG EXE` (setup.py's console_scripts entry points, the workspace
found through $ROS_PACKAGE_PATH or above the working folder, its interface package found too), the
adder server's file whose main() nothing calls, and lab8's Python launch file."""

import subprocess
import sys

from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.ros_running import PROGRAMS, Program
from tests.waiting import wait_for

lab = served_lab("--exercises")

COURSE = PROGRAMS / "course_ws"
ADDER = COURSE / "src" / "learning_service" / "learning_service" / "service_adder_server.py"


def _add(lab, a: int, b: int) -> dict:
    answer = http.post(f"{lab.url}/services/add_two_ints", json={"a": a, "b": b}, timeout=30)
    assert answer.status_code == 200, answer.text
    return answer.json()


def test_the_seed_programs_run_as_ros2_run_starts_them(lab):
    server = Program(
        lab.url, "run", "learning_service", "service_adder_server", env={"ROS_PACKAGE_PATH": str(COURSE / "src")}
    )
    try:
        server.wait_for_line("adder server ready")
        client = Program(lab.url, "run", "--workspace", str(COURSE), "lab8", "myClient", "2", "40")
        assert client.wait(timeout=120) == 0, client.output
        assert "sum: 42" in client.output
        assert "a: 2 b: 40" in server.wait_for_line("a: 2 b: 40")  # learning_interface/srv/AddTwoInts, served
    finally:
        server.interrupt()
    mine = Program(lab.url, "run", "--workspace", str(COURSE), "lab8", "myServer", "--ros-args", "-p", "offset:=1")
    try:
        mine.wait_for_line("myServer ready, offset 1")
        assert _add(lab, 2, 40) == {"sum": 43}
    finally:
        assert mine.interrupt() == 0, mine.output
    missing = Program(lab.url, "run", "--workspace", str(COURSE), "lab8", "myserver")
    assert missing.wait() == 1
    assert "No executable found: 'myserver' in package 'lab8'" in missing.output


def test_a_file_whose_main_nothing_calls_runs_its_main_and_says_so(lab):
    server = Program(lab.url, "run", str(ADDER))
    try:
        server.wait_for_line("adder server ready")
        assert _add(lab, 20, 22) == {"sum": 42}
    finally:
        server.interrupt()
    assert 'defines main() and has no `if __name__ == "__main__":` block: calling main()' in server.output


def test_a_python_launch_file_starts_its_nodes_with_parameters_remaps_and_event_handlers(lab):
    launch = Program(lab.url, "launch", "--workspace", str(COURSE), "lab8", "lab8.launch.py", "offset:=100")
    try:
        assert launch.wait(timeout=180) == 0, launch.output
    finally:
        launch.stop()
    out = launch.output
    assert "[myServer-1] " in out and "myServer ready, offset 100" in out  # output='screen', the argument passed
    assert "[myClient-1] sum: 142" in out  # /lab8/adder: namespace and remap on both sides
    assert "[INFO] [launch.user]: client done" in out  # OnProcessExit, then EmitEvent(Shutdown)
    assert "[INFO] [myServer-1]: process has finished cleanly" in out


def test_rclpy_graph_queries_name_the_programs_topics_services_and_node(lab):
    program = Program(lab.url, "run", str(PROGRAMS / "graph_queries_rclpy.py"))
    assert program.wait(timeout=120) == 0, program.output
    out = program.lines
    assert "topic ['std_msgs/msg/String']" in out
    assert "service ['example_interfaces/srv/AddTwoInts']" in out
    assert "node True" in out
    assert "by node ['std_msgs/msg/String']" in out
    assert "parameter 3" in out
    assert "liveliness AUTOMATIC" in out


def test_roslib_tf_msg_and_the_labs_own_subscriber_counted(lab):
    program = Program(lab.url, "run", str(PROGRAMS / "roslib_tf_rospy.py"))
    assert program.wait(timeout=120) == 0, program.output
    assert "class std_msgs/String None" in program.lines
    assert "tf tf/tfMessage []" in program.lines
    assert "connections 1" in program.lines  # the lab subscribes to its command topic


def _cli(lab, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args, "--url", lab.url], capture_output=True, text=True, timeout=120
    )


def test_the_ros2_cli_sees_a_programs_topic_and_calls_with_a_type(lab):
    talker = Program(lab.url, "run", str(PROGRAMS / "talker_rclpy.py"))
    server = Program(lab.url, "run", "--workspace", str(COURSE), "lab8", "myServer")
    try:
        talker.wait_for_line("Publishing")
        server.wait_for_line("myServer ready")
        listed = _cli(lab, "topic", "list", "-t").stdout.splitlines()
        assert "/topic [std_msgs/msg/String]" in listed
        assert listed == sorted(listed)  # as ros2 topic list sorts them
        echo = _cli(lab, "topic", "echo", "/topic", "-n", "1")  # rostopic's -n
        assert echo.returncode == 0, echo.stderr
        assert echo.stdout.startswith("data: 'Hello World: ") and echo.stdout.endswith("---\n")
        call = _cli(lab, "service", "call", "/add_two_ints", "example_interfaces/srv/AddTwoInts", "{a: 1, b: 2}")
        assert call.returncode == 0, call.stderr
        assert "AddTwoInts_Response(sum=3)" in call.stdout
        nodes = _cli(lab, "node", "list").stdout.splitlines()
        assert {"/hri_lab", "/minimal_publisher", "/my_server"} <= set(nodes)
        assert nodes == sorted(nodes) and not any("_hri_lab_cli" in n for n in nodes)  # its own node hidden
        info = _cli(lab, "node", "info", "/minimal_publisher").stdout
        assert "  Publishers:\n    /rosout: rcl_interfaces/msg/Log\n    /topic: std_msgs/msg/String\n" in info
        assert "/minimal_publisher/get_parameters: rcl_interfaces/srv/GetParameters" in info
        wrong = _cli(lab, "service", "call", "/add_two_ints", "std_srvs/srv/Empty", "{}")
        assert wrong.returncode == 1
        assert "the type 'std_srvs/srv/Empty' is not the srv's: example_interfaces/srv/AddTwoInts" in wrong.stderr
    finally:
        talker.interrupt()
        server.interrupt()


def test_a_lifecycle_node_is_driven_through_its_change_state_and_get_state_services(lab):
    talker = Program(lab.url, "run", str(PROGRAMS / "lifecycle_talker_rclpy.py"))

    def state() -> dict:
        answer = http.post(f"{lab.url}/services/lc_talker/get_state", json={}, timeout=30)
        assert answer.status_code == 200, answer.text
        return answer.json()["current_state"]

    def change(transition: int) -> bool:
        answer = http.post(f"{lab.url}/services/lc_talker/change_state", json={"transition": {"id": transition}})
        assert answer.status_code == 200, answer.text
        return answer.json()["success"]

    try:
        wait_for(lambda: "/lc_talker/get_state" in http.get(f"{lab.url}/services").text)
        assert state() == {"id": 1, "label": "unconfigured"}
        assert change(3) is False  # activate: not a transition of `unconfigured`
        assert change(1) is True
        talker.wait_for_line("on_configure() from unconfigured")
        talker.wait_for_line("active False")  # the publisher drops what it is given
        assert state() == {"id": 2, "label": "inactive"}
        assert change(3) is True
        talker.wait_for_line("on_activate() from inactive")
        talker.wait_for_line("active True")
        assert change(4) is False  # on_deactivate raised: errorprocessing, on_error's SUCCESS: unconfigured
        assert state() == {"id": 1, "label": "unconfigured"}
    finally:
        talker.interrupt()


def test_interface_show_prints_a_definition_as_its_file_has_it(lab):
    shown = _cli(lab, "interface", "show", "example_interfaces/srv/AddTwoInts")
    assert shown.stdout == "int64 a\nint64 b\n---\nint64 sum\n"
    unknown = _cli(lab, "interface", "show", "std_msgs/msg/Nope")
    assert unknown.returncode == 1
    assert "Unknown interface 'std_msgs/msg/Nope'" in unknown.stderr
