"""rclpy programs in the styles of ros2/examples (tests/ros_programs/) run unchanged with `hri-lab
run` against a real lab (`serve --exercises`): `with rclpy.init():` and ExternalShutdownException,
an `async def` action server whose cancels are accepted or rejected (the client told which), a
coroutine on the executor awaiting `call_async`, a MultiThreadedExecutor's mutually exclusive
group, a package's own modules and service type found by its package.xml's name (run and launch),
the camera handout's image server answering its service while images stream in, and the graph's
counts and matched events as another client subscribes and leaves, and service introspection's events."""

import signal
from base64 import b64decode

import roslibpy

from tests.e2e.serving import running_server, served_lab
from tests.http_client import http
from tests.lab_zygote import run_command
from tests.ros_running import PROGRAMS, Program, run
from tests.waiting import wait_for

lab = served_lab("--exercises")

WORKSPACE = PROGRAMS / "ros2_ws"
PACKAGE = WORKSPACE / "src" / "greeting_package"  # package.xml says: greetings


def test_with_rclpy_init_programs_talk_and_end_on_ctrl_c_or_sigterm(lab):
    listener = run(lab.url, "listener_rclpy.py")
    talker = run(lab.url, "talker_rclpy.py")
    try:
        listener.wait_for_line('I heard: "Hello World: 1"')
    finally:
        assert talker.interrupt() == 0, talker.output  # KeyboardInterrupt, caught as the example does
        listener.proc.send_signal(signal.SIGTERM)  # a launch system's stop: the context shuts down
        assert listener.wait() == 0, listener.output
    assert "listener: shut down cleanly" in listener.output  # ExternalShutdownException out of spin


def _cancel_run(lab, accept: bool) -> Program:
    server = run(
        lab.url,
        "fibonacci_action_server_rclpy.py",
        "--ros-args",
        "-p",
        f"accept_cancel:={str(accept).lower()}",
        "-p",
        "period:=0.3",
    )
    try:
        wait_for(lambda: "/fibonacci" in http.get(f"{lab.url}/actions").text)
        client = run(lab.url, "fibonacci_action_client_cancel_rclpy.py")
        assert client.wait(timeout=120) == 0, client.output + "\n--- server:\n" + server.output
    finally:
        server.interrupt()
    assert "Goal accepted :)" in client.output
    assert "Received feedback: array('i', [0, 1, 1" in client.output  # rclpy's typed sequence
    return client


def test_an_async_action_server_accepts_a_cancel_and_the_client_is_told(lab):
    client = _cancel_run(lab, accept=True)
    assert "Goal successfully canceled" in client.output


def test_an_async_action_server_rejects_a_cancel_and_the_client_is_told(lab):
    client = _cancel_run(lab, accept=False)
    assert "Goal failed to cancel" in client.output


def test_an_async_execute_callback_succeeds_over_http(lab):
    server = run(lab.url, "fibonacci_action_server_rclpy.py", "--ros-args", "-p", "period:=0.01")
    try:
        wait_for(lambda: "/fibonacci" in http.get(f"{lab.url}/actions").text)
        goal = http.post(f"{lab.url}/actions/fibonacci/goals", json={"order": 6}, timeout=30)
        assert goal.status_code == 202, goal.text
        goal_id = goal.json()["goal_id"]
        ended = wait_for(
            lambda: (
                (g := http.get(f"{lab.url}/actions/fibonacci/goals/{goal_id}").json())["status"]
                in ("succeeded", "aborted", "preempted", "rejected")
                and g
            )
        )
        assert ended["status"] == "succeeded", ended  # not aborted at once, as an unawaited coroutine was
        assert ended["result"]["sequence"] == [0, 1, 1, 2, 3, 5, 8]
        info = run_command("action", "info", "-t", "/fibonacci", "--url", lab.url, timeout=60)  # ros2action's form
        assert info.stdout == (
            "Action: /fibonacci\nAction clients: 0\nAction servers: 1\n"
            "    /minimal_action_server [example_interfaces/action/Fibonacci]\n"
        ), info.stdout + info.stderr
        node = run_command("node", "info", "/minimal_action_server", "--url", lab.url, timeout=60)
        assert "  Action Servers:\n    /fibonacci: example_interfaces/action/Fibonacci\n" in node.stdout, node.stderr
    finally:
        server.interrupt()


def test_a_coroutine_on_the_executor_awaits_call_async(lab):
    server = run(lab.url, "add_two_ints_server_rclpy.py")
    try:
        server.wait_for_line("Ready to add two ints.")
        client = run(lab.url, "add_two_ints_client_task_rclpy.py", "2", "3")
        assert client.wait() == 0, client.output
    finally:
        server.interrupt()
    assert "for 2 + 3 = 5" in client.output
    assert "for 5 + 3 = 8" in client.output
    assert "task done: True, result 8" in client.output


def test_a_mutually_exclusive_group_never_runs_two_callbacks_at_once(lab):
    program = run(lab.url, "exclusive_group_rclpy.py")
    try:
        program.wait_for_line("groups ready")
        report = wait_for(
            lambda: (
                (r := http.post(f"{lab.url}/services/group_report", json={}, timeout=30)).status_code == 200
                and int(r.json()["message"].split()[2]) >= 6
                and r.json()
            )
        )
    finally:
        program.interrupt()
    assert report["message"].endswith("at most 1 at once"), report


def test_a_package_imports_its_own_modules_and_srv_by_its_package_xml_name(lab):
    server = run(lab.url, str(PACKAGE / "greetings" / "hello_server.py"))
    try:
        server.wait_for_line("hello server ready")
        answer = http.post(f"{lab.url}/services/say_hello", json={"name": "Ada"}, timeout=30)
        assert answer.json() == {"greeting": "Hello, Ada!"}, answer.text
        assert http.get(f"{lab.url}/services/say_hello").json()["type"] == "greetings/srv/SayHello"
    finally:
        assert server.interrupt() == 0, server.output


def test_launch_finds_a_node_by_its_packages_name_in_the_workspace(lab, tmp_path):
    launch_file = tmp_path / "hello.launch.xml"  # outside the workspace: only --workspace finds the package
    launch_file.write_text((PACKAGE / "launch" / "hello.launch.xml").read_text())
    launched = Program(lab.url, "launch", "--workspace", str(WORKSPACE), str(launch_file), terminal=True)
    try:
        launched.wait_for_line("hello server ready")
        answer = http.post(f"{lab.url}/services/say_hello", json={"name": "launch"}, timeout=30)
        assert answer.json() == {"greeting": "Hello, launch!"}
    finally:
        launched.interrupt()


def test_the_image_server_answers_its_service_while_images_stream():
    """The handout's ImageSubscriber: every image callback is longer than the camera's period, so
    images are always waiting; each request is still answered (it used to wait behind the images
    until the lab gave up: 504)."""
    with running_server("--view", "none", "--exercises") as camera_lab:
        program = run(camera_lab.url, "image_subscriber_rclpy.py")
        try:
            wait_for(lambda: sum("Receiving video frame" in line for line in program.lines) >= 10, timeout=120)
            answers = [
                http.post(f"{camera_lab.url}/services/get_target_position", json={"get": True}, timeout=30)
                for _ in range(10)
            ]
        finally:
            program.interrupt()
    assert [a.status_code for a in answers] == [200] * 10, [a.text for a in answers]
    assert all(a.json()["x"] > 0 and a.json()["y"] > 0 for a in answers)  # the box, detected


def _goal(lab, order: int) -> str:
    goal = http.post(f"{lab.url}/actions/fibonacci/goals", json={"order": order}, timeout=30)
    assert goal.status_code == 202, goal.text
    return goal.json()["goal_id"]


def _ended(lab, goal_id: str) -> dict:
    return wait_for(
        lambda: (
            (g := http.get(f"{lab.url}/actions/fibonacci/goals/{goal_id}").json())["status"]
            in ("succeeded", "aborted", "preempted", "rejected")
            and g
        ),
        timeout=120,
    )


def test_a_queued_action_server_runs_goals_sent_together_one_after_the_other(lab):
    server = run(lab.url, "fibonacci_queue_server_rclpy.py")
    try:
        wait_for(lambda: "/fibonacci" in http.get(f"{lab.url}/actions").text)
        first, second = _goal(lab, 5), _goal(lab, 4)  # the second while the first executes: both taken
        assert _ended(lab, first)["result"]["sequence"] == [0, 1, 1, 2, 3, 5]
        assert _ended(lab, second)["result"]["sequence"] == [0, 1, 1, 2, 3]
        server.wait_for_line("Returning result of order 4")
    finally:
        server.interrupt()
    order = [line for line in server.lines if "of order" in line or "queue" in line]
    assert [
        "queue" in order[1],
        "Returning result of order 5" in order[2],
        "Executing goal of order 4" in order[3],
    ] == [True] * 3, order


def test_a_single_goal_action_server_aborts_the_goal_a_new_one_replaces(lab):
    server = run(lab.url, "fibonacci_single_goal_server_rclpy.py")
    try:
        wait_for(lambda: "/fibonacci" in http.get(f"{lab.url}/actions").text)
        first = _goal(lab, 40)
        wait_for(lambda: http.get(f"{lab.url}/actions/fibonacci/goals/{first}").json()["feedback_count"] >= 1)
        second = _goal(lab, 3)
        assert _ended(lab, first)["status"] == "aborted"
        assert _ended(lab, second)["result"]["sequence"] == [0, 1, 1, 2]
    finally:
        server.interrupt()
    assert "Aborting previous goal" in server.output


def test_a_second_server_of_a_provided_service_raises_rclerror(lab):
    first = run(lab.url, "add_two_ints_server_rclpy.py")
    try:
        first.wait_for_line("Ready to add two ints.")
        second = run(lab.url, "add_two_ints_server_rclpy.py")
        assert second.wait() == 1, second.output
        # the same node name: its parameter services are the first one's (a warning, as ROS 2 warns)
        assert "this one's parameters are not served" in second.output
        assert "rclpy.exceptions.RCLError: Failed to create service /add_two_ints" in second.output
        assert "already provided by node" in second.output
        assert http.post(f"{lab.url}/services/add_two_ints", json={"a": 1, "b": 2}, timeout=30).json() == {"sum": 3}
    finally:
        assert first.interrupt() == 0, first.output


def test_a_publishers_matched_events_and_counts_follow_the_graph(lab, ros):
    program = run(lab.url, "graph_counts_rclpy.py")
    try:
        program.wait_for_line("graph counts ready")
        assert program.wait_for_line("joint_states publishers:").endswith(": 1")  # the lab's node
        got: list[dict] = []
        topic = roslibpy.Topic(ros, "/counted", "std_msgs/String")
        topic.subscribe(got.append)
        try:
            assert program.wait_for_line("matched current=1").endswith("change=1 total=1 count=1")
            wait_for(lambda: got)  # still advertised: its spare publisher's destruction left it to the other
        finally:
            topic.unsubscribe()
        assert program.wait_for_line("matched current=0").endswith("change=-1 total=1 count=0")
    finally:
        program.interrupt()


def test_service_introspection_publishes_each_step_of_a_call(lab, ros):
    program = run(lab.url, "introspection_rclpy.py")
    events: list[dict] = []
    topic = roslibpy.Topic(ros, "/introspected_sum/_service_event", "example_interfaces/srv/AddTwoInts_Event")
    topic.subscribe(events.append)
    try:
        program.wait_for_line("sum 5")

        def a_whole_call() -> dict[int, dict] | None:  # ServiceEventInfo's steps of one client call and one served
            client = {e["info"]["event_type"]: e for e in events if any(b64decode(e["info"]["client_gid"]))}
            served = {e["info"]["event_type"]: e for e in events if not any(b64decode(e["info"]["client_gid"]))}
            return {**client, **served} if {0, 3} <= set(client) and {1, 2} <= set(served) else None

        steps = wait_for(a_whole_call)
    finally:
        topic.unsubscribe()
        program.interrupt()
    assert steps[0]["request"] == [{"a": 2, "b": 3}]
    assert steps[3]["response"] == [{"sum": 5}]
    assert steps[1]["request"] == []
    assert steps[2]["response"] == []
    assert len(b64decode(steps[0]["info"]["client_gid"])) == 16  # char[16], base64 as rosbridge sends it


def test_a_late_transient_local_subscription_hears_all_a_publisher_kept_and_a_volatile_one_none(lab):
    talker = run(lab.url, "transient_talker_rclpy.py")
    try:
        talker.wait_for_line("published 10")
        listener = run(lab.url, "transient_listener_rclpy.py")
        assert listener.wait(timeout=120) == 0, listener.output
    finally:
        talker.interrupt()
    heard = ", ".join(f"message {i}" for i in range(10))
    assert f"transient_local heard: {heard}" in listener.output
    assert "volatile heard 0" in listener.output


def test_a_late_subscription_hears_only_messages_within_their_lifespan_and_topic_info_shows_the_qos(lab):
    """The lifespan demo's behaviour through the real lab (its history and `lifespan`), and `hri-lab
    topic info -v` of the running program: its publisher's node and QoS as ros2 prints them."""
    import subprocess
    import sys

    program = run(lab.url, "lifespan_rclpy.py")
    try:
        program.wait_for_line("late subscriptions made")
        program.wait_for_line("heard: long_lived 2")
        info = subprocess.run(
            [sys.executable, "-m", "app.cli", "topic", "info", "-v", "/long_lived", "--url", lab.url],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert info.returncode == 0, info.stderr
    finally:
        program.interrupt()
    heard = [line for line in program.output.splitlines() if line.startswith("heard: ")]
    assert heard == ["heard: long_lived 0", "heard: long_lived 1", "heard: long_lived 2"]
    assert info.stdout.startswith("Type: std_msgs/msg/String\n\nPublisher count: 1\n\nNode name: lifespan_talker\n")
    assert "  Durability: TRANSIENT_LOCAL\n  Lifespan: 3600000000000 nanoseconds\n" in info.stdout
    assert "Subscription count: 1\n\nNode name: lifespan_talker\n" in info.stdout  # its late subscription
