"""Students' rospy and rclpy programs (tests/ros_programs/) run unchanged with `hri-lab run` against a
real lab (`serve --exercises`): their services answer HTTP and other programs, their clients call
the lab's services and each other's, topics reach each other, rclpy parameters are served with
the standard rcl_interfaces services, Ctrl+C ends spin, and bad programs get ROS's errors."""

import subprocess
import sys

import pytest

from app.grading.services import grade_services
from tests.e2e.serving import running_server, served_lab
from tests.http_client import http
from tests.ros_running import PROGRAMS, Program, run
from tests.waiting import wait_for

lab = served_lab("--exercises")  # the lab with its exercise services


def call(lab, name, body):
    return call_url(lab.url, name, body)


def call_url(url, name, body):
    return http.post(f"{url}/services/{name.strip('/')}", json=body, timeout=30)


@pytest.mark.parametrize("api", ["rospy", "rclpy"])
def test_add_two_ints_server_and_client(lab, api):
    server = run(lab.url, f"add_two_ints_server_{api}.py")
    try:
        server.wait_for_line("Ready to add two ints.")
        # the lab has the program's service once it is created, as rospy.Service returns once it is registered
        assert http.get(f"{lab.url}/services/add_two_ints").json()["node"] != "/hri_lab"
        client = run(lab.url, f"add_two_ints_client_{api}.py", "20", "22")
        assert client.wait() == 0, client.output
        assert ("20 + 22 = 42" if api == "rospy" else "for 20 + 22 = 42") in client.output
        assert call(lab, "add_two_ints", {"a": -5, "b": 2}).json() == {"sum": -3}  # HTTP, answered by the program
        line = server.wait_for_line("-5" if api == "rospy" else "a: -5 b: 2")  # its log line: the program served it
        node = "add_two_ints_server" if api == "rospy" else "minimal_service"
        logged = wait_for(
            lambda: [
                entry
                for entry in http.get(f"{lab.url}/log").json()
                if "-5" in entry["msg"] and entry["node"].strip("/") == node
            ]
        )
        assert logged[0]["msg"].splitlines()[-1] in line  # the same line on /rosout, under the node's name
    finally:
        assert server.interrupt() == 0, server.output  # Ctrl+C ends spin(), the program ends normally


def test_a_workspace_srv_types_the_programs_services(lab):
    server = run(lab.url, "multiply_divide_server_rclpy.py")
    try:
        server.wait_for_line("calculator ready")
        assert call(lab, "multiply_three", {"a": 2, "b": 3, "c": 7}).json() == {"product": 42}
        assert call(lab, "divide_ints", {"a": 7, "b": 2}).json() == {"result": 3.5, "message": "Division ok."}
        assert call(lab, "divide_ints", {"a": 7, "b": 0}).json()["message"] == "Division by zero!"
    finally:
        assert server.interrupt() == 0
    assert "calculator stopped by Ctrl+C" in server.output  # KeyboardInterrupt out of rclpy.spin, as in rclpy


def _fields(response) -> dict[str, str]:
    return {f["name"]: f["type"] for f in response["request_fields"]}


def _refused_naming(response, field: str) -> bool:
    return response.status_code == 422 and any(field in ".".join(map(str, e["loc"])) for e in response.json()["detail"])


def test_a_programs_own_srv_travels_with_the_service_it_types(lab):
    """MultiplyThree.srv of the program's workspace: the lab shows its text and type (HTTP, CLI) while
    the program serves /multiply_three, checks requests before they reach the program, and shows its
    own declaration again when the program ends."""
    server = run(lab.url, "multiply_divide_server_rclpy.py")
    try:
        server.wait_for_line("calculator ready")
        info = wait_for(
            lambda: (
                (i := http.get(f"{lab.url}/services/multiply_three").json())["type"] != "hri_lab/MultiplyThree" and i
            )
        )
        assert info["type"] == "cpp_package/srv/MultiplyThree"
        assert info["srv"] == (PROGRAMS / "cpp_package/srv/MultiplyThree.srv").read_text().strip()
        assert _fields(info) == {"a": "int64", "b": "int64", "c": "int64"}
        shown = subprocess.run(
            [sys.executable, "-m", "app.cli", "service", "show", "/multiply_three", "--url", lab.url],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert shown.stdout.strip() == info["srv"], shown.stderr
        assert _refused_naming(call(lab, "multiply_three", {"a": 2, "b": 3}), "c")  # missing
        assert _refused_naming(call(lab, "multiply_three", {"a": 2, "b": 3, "c": 7, "d": 1}), "d")  # unknown
        assert _refused_naming(call(lab, "multiply_three", {"a": 2, "b": "three", "c": 7}), "b")  # wrong type
        assert call(lab, "multiply_three", {"a": 2, "b": 3, "c": 7}).json() == {"product": 42}
    finally:
        assert server.interrupt() == 0, server.output
    assert http.get(f"{lab.url}/services/multiply_three").json()["type"] == "hri_lab/MultiplyThree"


def test_a_service_the_lab_does_not_declare_is_checked_against_the_programs_srv(lab):
    """ScalePoint.srv (nested geometry_msgs/Point, the package's own Note, a default): the lab knows
    the type only from the text the program carried, refuses a bad request naming the field before
    it reaches the program, and the program answers a good one (the defaults filled in)."""
    server = run(lab.url, "scale_point_server_rospy.py")
    try:
        server.wait_for_line("Ready to scale points.")
        info = wait_for(lambda: (r := http.get(f"{lab.url}/services/scale_point")).status_code == 200 and r.json())
        assert info["type"] == "cpp_package/ScalePoint"
        assert info["srv"] == (PROGRAMS / "cpp_package/srv/ScalePoint.srv").read_text().strip()
        assert _fields(info) == {"point": "geometry_msgs/Point", "factor": "float64", "digits": "uint8"}
        assert {f["name"]: f.get("default") for f in info["request_fields"]}["digits"] == 2
        assert [f["type"] for f in info["response_fields"]] == ["geometry_msgs/Point", "cpp_package/Note"]
        point = {"x": 1.0, "y": 2.0, "z": 0.5}
        assert _refused_naming(call(lab, "scale_point", {"point": point}), "factor")  # missing
        assert _refused_naming(call(lab, "scale_point", {"point": {"x": "one"}, "factor": 2}), "point.x")
        assert _refused_naming(call(lab, "scale_point", {"point": point, "factor": "two"}), "factor")
        assert _refused_naming(call(lab, "scale_point", {"point": point, "factor": 2, "digits": 300}), "digits")
        assert _refused_naming(call(lab, "scale_point", {"point": point, "factor": 2, "scale": 1}), "scale")
        answer = call(lab, "scale_point", {"point": {"x": 1.0, "y": 2.0}, "factor": 1 / 3})  # z: its default
        assert answer.json() == {
            "scaled": {"x": 0.33, "y": 0.67, "z": 0.0},
            "note": {"text": "scaled by 0.333333", "level": 1},
        }, answer.text
    finally:
        assert server.interrupt() == 0, server.output
    assert [line for line in server.lines if "scaled (" in line] == [
        next(line for line in server.lines if "scaled (" in line)
    ]  # one request reached the program: the refused ones did not


def test_a_call_to_a_missing_service_times_out_with_ros_exception(lab):
    client = run(lab.url, "missing_service_client_rospy.py")
    assert client.wait() != 0
    assert "rospy.exceptions.ROSException: timeout exceeded while waiting for service /add_three_ints" in client.output


def test_a_wrong_request_field_is_an_error_naming_it(lab):
    server = run(lab.url, "add_two_ints_server_rospy.py")
    try:
        server.wait_for_line("Ready to add two ints.")
        client = run(lab.url, "bad_field_client_rospy.py")
        assert client.wait() != 0
        assert "TypeError: example_interfaces/AddTwoIntsRequest has no field 'c' (its fields: a, b)" in client.output
    finally:
        server.interrupt()


def test_the_lifting_servers_answer_the_lab_and_apply_the_band(lab):
    server = run(lab.url, "lifting_services_rospy.py")
    try:
        server.wait_for_line("lifting services ready")
        answer = call(lab, "start_cooperative_lifting", {"force": 11.5}).json()
        assert answer == {"message": "Cooperative lifting starts with 11.5 N"}
        server.wait_for_line("band 11.5 .. 16.5 N")
        state = http.get(f"{lab.url}/topics/lifting_state").json()
        assert state["started"]
        assert state["f_n_min"] == 11.5
        stopped = call(lab, "stop_cooperative_lifting", {}).json()  # the handler returned a bare string
        assert stopped == {"message": "Cooperative lifting stopped, f_n_min reset to 0 N"}
    finally:
        assert server.interrupt() == 0
    assert "spin returned" in server.output


def test_echo_with_a_keyword_field(lab):
    server = run(lab.url, "echo_server_rclpy.py")
    try:
        server.wait_for_line("echo ready")
        assert call(lab, "echo", {"in": "hello lab"}).json() == {"out": "hello lab"}
    finally:
        server.interrupt()


def test_the_login_chain_publishes_subscribes_and_calls(lab):
    programs = [run(lab.url, "login_server_rospy.py")]
    try:
        programs[0].wait_for_line("login server ready")
        programs.append(run(lab.url, "login_checker_rospy.py", "_user:=ada"))
        programs.append(run(lab.url, "magic_number_publisher_rospy.py"))
        assert "Welcome, ada!" in programs[1].wait_for_line("magic 42: success=True")
        programs[1].wait_for_line("success=False Login failed")
    finally:
        for program in programs:
            program.interrupt()


def test_rclpy_parameters_are_served_with_rclcpp_refusals(lab):
    node = run(lab.url, "keys_to_twist_rclpy.py", "wd", "--ros-args", "-p", "linear_speed:=0.25")
    try:
        node.wait_for_line("key w: linear.x=0.25")  # --ros-args -p overrides the declared default
        node.wait_for_line("key d: linear.x=0 angular.z=-0.5")

        def set_parameter(name, kind, value):
            field = {3: "double_value", 4: "string_value", 2: "integer_value"}[kind]
            body = {"parameters": [{"name": name, "value": {"type": kind, field: value}}]}
            return call(lab, "keytwist_param/set_parameters", body).json()["results"][0]

        assert set_parameter("linear_speed", 3, 1.5) == {"successful": True, "reason": ""}
        node.wait_for_line("key w: linear.x=1.5")  # the next get_parameter sees it
        assert set_parameter("linear_speed", 3, 9.0) == {
            "successful": False,
            "reason": "linear_speed above 5 m/s is unsafe",
        }
        assert set_parameter("linear_speed", 4, "fast")["reason"] == (
            "Wrong parameter type, parameter {linear_speed} is of type {double}, setting it to {string} is not allowed."
        )
        assert set_parameter("angular_speed", 3, 2.5)["reason"] == (
            "Parameter {angular_speed} doesn't comply with floating point range."
        )
        assert set_parameter("top_speed", 3, 1.0)["reason"] == (
            "parameter 'top_speed' cannot be set because it was not declared"
        )
        listed = call(lab, "keytwist_param/list_parameters", {"prefixes": [], "depth": 0}).json()
        assert listed["result"]["names"] == ["angular_speed", "linear_speed"]
        values = call(lab, "keytwist_param/get_parameters", {"names": ["linear_speed"]}).json()["values"]
        assert values[0]["type"] == 3
        assert values[0]["double_value"] == 1.5
        described = call(lab, "keytwist_param/describe_parameters", {"names": ["angular_speed"]}).json()
        assert described["descriptors"][0]["floating_point_range"][0]["to_value"] == 2.0
    finally:
        node.interrupt()


def test_the_lab_going_away_ends_the_program_with_a_message():
    with running_server("--view", "none") as own_lab:
        program = run(own_lab.url, "add_two_ints_server_rospy.py")
        program.wait_for_line("Ready to add two ints.")
    try:
        assert program.wait() == 1
    finally:
        program.stop()
    assert "[FATAL] lost the lab" in program.output


def test_ctrl_c_ends_an_rclpy_program_whose_parent_ignores_it(lab):
    """rclpy.init installs its SIGINT handler whatever the program inherited (Python leaves an
    inherited SIG_IGN alone): Ctrl+C is a KeyboardInterrupt out of spin, the program ends normally."""
    server = run(lab.url, "add_two_ints_server_rclpy.py", sigint_ignored=True)
    try:
        server.wait_for_line("Ready to add two ints.")  # printed in the node's constructor, before spin()
        assert call(lab, "add_two_ints", {"a": 1, "b": 2}).json() == {"sum": 3}  # answered: it spins now
    finally:
        assert server.interrupt() == 0, server.output


def test_a_connected_program_passes_its_interpreter_between_threads_every_half_millisecond(lab, tmp_path):
    """The connection's reader threads get their turn while a callback computes (a callback of 2 ms
    per 1 kHz message left them seconds behind at Python's 5 ms: rosclient/delivery.py)."""
    from rosclient.delivery import READER_SWITCH_S

    program = tmp_path / "switch_interval.py"
    program.write_text(
        "import sys\nprint('before', sys.getswitchinterval())\nimport rospy\n"
        "rospy.init_node('switch_interval')\nprint('after', sys.getswitchinterval(), flush=True)\n"
    )
    node = Program(lab.url, "run", str(program))
    try:
        assert node.wait() == 0, node.output
    finally:
        node.stop()
    assert "before 0.005" in node.output  # Python's own, until the program connects
    assert f"after {READER_SWITCH_S}" in node.output


def test_no_lab_to_reach_is_a_message_and_exit_1_not_a_traceback():
    from app.serving.launch import free_port

    program = run(f"http://127.0.0.1:{free_port()}", "add_two_ints_server_rospy.py")
    try:
        assert program.wait() == 1
    finally:
        program.stop()
    assert "[FATAL] cannot reach the lab at http://127.0.0.1:" in program.output
    assert "Traceback" not in program.output


def test_launch_starts_the_lab_and_three_nodes_ctrl_c_stops_all():
    launch = Program(None, "launch", str(PROGRAMS / "calculator.launch.xml"), "speed:=0.75", terminal=True)
    try:
        url = launch.wait_for_line("the lab: ").split("the lab: ")[1].strip()
        launch.wait_for_line("[calculator] ")
        launch.wait_for_line("[keytwist_param] key w: linear.x=0.75")  # <param> from the launch argument
        assert call_url(url, "multiply_three", {"a": 1, "b": 2, "c": 3}).json() == {"product": 6}
        wait_for(lambda: call_url(url, "echo", {"in": "up"}).status_code == 200)
    finally:
        code = launch.interrupt(timeout=60)
    assert code == 0, launch.output
    assert "calculator stopped by Ctrl+C" in launch.output
    assert "process has died" not in launch.output


def test_launch_reports_a_crashing_node_by_name_with_its_exit_status(lab):
    launch = Program(lab.url, "launch", str(PROGRAMS / "crashing.launch"))
    try:
        launch.wait_for_line("[lost_client-4] process has died [pid")
        assert "exit code 1" in launch.wait_for_line("[lost_client-4] process has died")
        launch.wait_for_line("[login_checker] ")  # the include's nodes run on, its <arg> passed
        wait_for(lambda: any("Welcome, lin!" in e["msg"] for e in http.get(f"{lab.url}/log").json()), timeout=60)
    finally:
        code = launch.interrupt(timeout=60)
    assert code == 1  # a node crashed


def test_grade_services_grades_rospy_and_rclpy_programs(lab):
    programs = [
        run(lab.url, name)
        for name in (
            "lifting_services_rospy.py",
            "add_two_ints_server_rclpy.py",
            "multiply_divide_server_rclpy.py",
            "echo_server_rclpy.py",
            "login_server_rospy.py",
        )
    ]
    try:
        for program, ready in zip(
            programs, ("lifting services ready", "Ready to add", "calculator ready", "echo ready", "login server ready")
        ):
            program.wait_for_line(ready)
        report = grade_services(lab.url, seed=5)
    finally:
        for program in programs:
            program.interrupt()
    points = {item.name.split(":")[0]: (item.points, item.max_points, item.detail) for item in report.items}
    for service in (
        "/start_cooperative_lifting",
        "/stop_cooperative_lifting",
        "/add_two_ints",
        "/echo",
        "/login",
        "/divide_ints",
        "/multiply_three",
    ):
        assert points[service][0] == points[service][1] > 0, points[service]  # start: its message states only the force
    assert points["/planar_torques"][0] == 0  # not provided by any program


def test_every_lab_topic_is_a_message_of_its_declared_type(lab):
    from app.lab.topics import TOPICS
    from interfaces.packages import Interfaces

    interfaces = Interfaces([])
    for topic in TOPICS:
        # /image_raw starts the camera's renderer and waits for its first image: slow on a loaded machine
        sample = http.get(f"{lab.url}/topics/{topic.name.strip('/')}", timeout=60).json()
        message = interfaces.message(topic.type)
        assert message.from_json(sample).to_json() == sample, topic.name  # the same fields, types and sizes


@pytest.mark.parametrize("api", ["rospy", "rclpy"])
def test_the_printed_templates_run_as_printed(lab, tmp_path, api):
    services, lifting = tmp_path / f"services_{api}.py", tmp_path / f"lifting_{api}.py"
    for path, kind in ((services, "services"), (lifting, "node")):
        printed = subprocess.run(
            [sys.executable, "-m", "app.cli", "template", kind, *(["--api", api] if api != "rospy" else [])],
            capture_output=True,
            text=True,
            timeout=60,
        )
        path.write_text(printed.stdout)
        assert f"import {api}" in printed.stdout
    # one after the other: both provide /start_cooperative_lifting, and a name another node provides
    # is refused (rospy.ServiceException, rclpy's error)
    program = run(lab.url, str(services))
    try:
        program.wait_for_line("node ready")
        assert call(lab, "add_two_ints", {"a": 2, "b": 3}).json() == {"sum": 5}
        assert call(lab, "divide_ints", {"a": 7, "b": 2}).status_code == 200  # TODO: wrong, well-formed
        assert call(lab, "compute_wrench", {"torques": [0.0] * 7}).status_code == 200
    finally:
        program.interrupt()
    wait_for(lambda: http.get(f"{lab.url}/services/start_cooperative_lifting").json()["node"] == "/hri_lab")
    program = run(lab.url, str(lifting))
    try:
        program.wait_for_line("node ready")
        wait_for(lambda: http.get(f"{lab.url}/params/cooperative_lifting/controller").json()["value"] == "node")
    finally:
        program.interrupt()
    wait_for(lambda: http.get(f"{lab.url}/services/start_cooperative_lifting").json()["node"] == "/hri_lab")
    http.post(f"{lab.url}/services/error_recovery")


def test_actionlib_and_rclpy_action_clients_of_the_lab_action(lab):
    preempting = run(lab.url, "count_client_actionlib.py")
    assert preempting.wait(timeout=120) == 0, preempting.output
    line = preempting.wait_for_line("state ")
    assert line.startswith("state 2 (PREEMPTED is 2), final_count ")
    assert 2 <= int(line.split()[-1]) < 30
    counting = run(lab.url, "count_client_rclpy.py")
    assert counting.wait(timeout=120) == 0, counting.output
    assert "Received feedback: 1" in counting.output
    assert "Result: final_count 2, status 4" in counting.output  # action_msgs/GoalStatus SUCCEEDED


@pytest.mark.parametrize(("api", "delay"), [("actionlib", "_delay:=0.3"), ("rclpy", "--ros-args -p delay:=0.3")])
def test_a_programs_action_is_served_to_the_lab_and_to_a_preempting_client(lab, api, delay):
    server = run(lab.url, f"counting_server_{api}.py", *delay.split())
    try:
        server.wait_for_line("counting server ready")
        assert "/counting" in [a["name"] for a in http.get(f"{lab.url}/actions").json()]
        client = run(lab.url, "counting_client_actionlib.py")
        assert client.wait(timeout=120) == 0, client.output
        line = client.wait_for_line("state ")
        assert line.startswith("state 2 reached ")
        assert int(line.split()[-1]) >= 2
        server.wait_for_line("counting preempted at")
        goal = http.post(f"{lab.url}/actions/counting/goals", json={"count": 2}, timeout=30)
        assert goal.status_code in (200, 201, 202), goal.text  # an HTTP goal, served by the program
        goal_id = goal.json()["goal_id"]
        done = wait_for(
            lambda: (lambda v: v if v["status"] == "succeeded" else None)(
                http.get(f"{lab.url}/actions/counting/goals/{goal_id}").json()
            ),
            timeout=60,
        )
        assert done["result"] == {"reached": 2}
        assert len(done["feedback"]) == 2
    finally:
        server.interrupt()


def test_a_failed_call_is_a_service_exception_or_the_futures_exception(lab):
    rospy_client = run(lab.url, "failed_call_rospy.py")
    assert rospy_client.wait() == 0, rospy_client.output
    assert (
        "Service call failed: service [/divide_ints] failed: service /divide_ints is not provided yet"
        in rospy_client.output
    )
    rclpy_client = run(lab.url, "failed_call_rclpy.py")
    assert rclpy_client.wait() == 0, rclpy_client.output
    assert "done before spin: False" in rclpy_client.output  # callbacks run inside spin, as in rclpy
    assert (
        "done: True, exception: service /divide_ints failed: service /divide_ints is not provided yet"
        in rclpy_client.output
    )


def test_rospy_reads_and_writes_the_parameter_server(lab):
    program = run(lab.url, "params_rospy.py")
    assert program.wait() == 0, program.output
    lines = program.output
    assert "gains: {'k_n': 0.005, 'k_t': [0.1, 0.2]}" in lines
    assert "private rate: 5 5" in lines  # ~rate is /param_talker/rate
    assert "has greeting: True" in lines
    assert "has greeting after delete: False" in lines
    assert "default: none" in lines
    assert "KeyError: 'greeting'" in lines
    assert "declared by the lab: 5.0" in lines  # the lab's declared ROS 2 parameter, by its ROS 1 name


def test_hri_lab_param_set_reaches_the_running_program(lab):
    node = run(lab.url, "keys_to_twist_rclpy.py", "w")

    def cli(*args):
        return subprocess.run(
            [sys.executable, "-m", "app.cli", *args, "--url", lab.url], capture_output=True, text=True, timeout=60
        )

    try:
        node.wait_for_line("key w: linear.x=0.1 ")
        listed = wait_for(
            lambda: (lambda out: out if "linear_speed" in out else None)(cli("param", "list", "/keytwist_param").stdout)
        )
        assert "angular_speed" in listed  # the program's declared parameters, in the lab's registry
        assert any(
            p["node"].strip("/") == "keytwist_param" and p["name"] == "linear_speed"
            for p in http.get(f"{lab.url}/params").json()
        )
        changed = cli("param", "set", "/keytwist_param", "linear_speed", "3.5")
        assert changed.returncode == 0, changed.stdout + changed.stderr
        node.wait_for_line("key w: linear.x=3.5 ")  # the published twist follows
        refused = cli("param", "set", "/keytwist_param", "linear_speed", "9.0")
        assert refused.returncode != 0
        assert "linear_speed above 5 m/s is unsafe" in refused.stdout + refused.stderr
        assert "3.5" in cli("param", "get", "/keytwist_param", "linear_speed").stdout
    finally:
        node.interrupt()
