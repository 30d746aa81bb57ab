"""app/cli/client.py: the ros2-like commands (service, param, action) against the real app, in this
process: the commands' own HTTP requests go to the app through FastAPI's TestClient (the same
httpx client class they make for a URL), so what they print is what a user sees."""

import argparse
import contextlib

import pytest

from app.cli import client as cli
from app.cli import graph
from app.cli.topic_stats import Bandwidth, Rate
from tests.waiting import within


class _Socket:
    """The app's rosbridge endpoint through the TestClient, as websockets' sync client answers."""

    def __init__(self, session) -> None:
        self.session = session

    def send(self, text: str) -> None:
        self.session.send_text(text)

    def recv(self, timeout: float | None = None) -> str:
        return self.session.receive_text()


@contextlib.contextmanager
def _rosbridge(client):
    with client.websocket_connect("/") as session:
        yield _Socket(session)


@pytest.fixture
def hri_lab(client, monkeypatch):
    """`hri-lab ARGS...` -> (exit code, stdout, stderr), its requests answered by the test's app."""
    monkeypatch.setattr(cli, "_client", lambda args: contextlib.nullcontext(client))
    monkeypatch.setattr(graph, "connect", lambda url, **options: _rosbridge(client))  # its rosbridge endpoint
    parser = argparse.ArgumentParser(prog="hri-lab")
    cli.add_parsers(parser.add_subparsers(dest="command", required=True))

    def run(*words: str) -> int:
        args = parser.parse_args(list(words))
        return cli.run(args.func, args)

    return run


def test_service_list_type_show_and_call(hri_lab, capsys):
    assert hri_lab("service", "list", "-t") == 0
    listed = capsys.readouterr().out.splitlines()
    assert "/add_two_ints [hri_lab/srv/AddTwoInts]" in listed  # ROS 2's names
    assert listed == sorted(listed) and len(listed) > 2  # by name, as the graph's names come from rmw
    assert hri_lab("service", "list", "--count-services") == 0
    assert capsys.readouterr().out == f"{len(listed)}\n"
    assert hri_lab("service", "type", "add_two_ints") == 0
    assert capsys.readouterr().out == "hri_lab/srv/AddTwoInts\n"
    assert hri_lab("service", "info", "/add_two_ints") == 0
    assert capsys.readouterr().out == "Type: hri_lab/srv/AddTwoInts\nClients count: 0\nServices count: 1\n"
    assert hri_lab("service", "find", "hri_lab/srv/AddTwoInts") == 0
    assert capsys.readouterr().out == "/add_two_ints\n"
    assert hri_lab("service", "find", "hri_lab/AddTwoInts", "-c") == 0
    assert capsys.readouterr().out == "1\n"
    assert hri_lab("service", "call", "/add_two_ints", "{a: 2, b: 40}") == 0
    assert capsys.readouterr().out == (  # ros2service's call verb: a blank line after each
        "requester: making request: hri_lab.srv.AddTwoInts_Request(a=2, b=40)\n\n"
        "response:\nhri_lab.srv.AddTwoInts_Response(sum=42)\n\n"
    )


def test_service_call_from_stdin_and_again_at_a_rate_until_ctrl_c(hri_lab, capsys, monkeypatch):
    """ros2service's `--stdin` (the request's YAML after the type) and `-r N` (the call again every
    1/N s until Ctrl+C, which ends the command with status 0)."""
    import io

    from app.cli import client as cli

    monkeypatch.setattr("sys.stdin", io.StringIO("{a: 1, b: 2}"))
    assert hri_lab("service", "call", "/add_two_ints", "hri_lab/srv/AddTwoInts", "--stdin") == 0
    assert capsys.readouterr().out.endswith("hri_lab.srv.AddTwoInts_Response(sum=3)\n\n")
    pauses: list[float] = []

    def sleep(seconds: float) -> None:  # the third pause is the user's Ctrl+C
        pauses.append(seconds)
        if len(pauses) == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(cli.time, "sleep", sleep)
    assert hri_lab("service", "call", "/add_two_ints", "{a: 1, b: 1}", "-r", "2") == 0
    assert capsys.readouterr().out.count("response:\nhri_lab.srv.AddTwoInts_Response(sum=2)\n\n") == 3
    assert all(0.0 <= p <= 0.5 for p in pauses)
    with pytest.raises(SystemExit):  # argparse's refusal, naming the option
        hri_lab("service", "call", "/add_two_ints", "{a: 1, b: 1}", "-r", "0")
    assert "argument -r/--rate: must be a positive number, got 0" in capsys.readouterr().err


def test_a_failed_call_names_the_field_and_a_missing_service_says_so(hri_lab, capsys):
    assert hri_lab("service", "call", "/add_two_ints", "{a: one, b: 2}") == 1
    assert "service call failed: a: Input should be a valid integer" in capsys.readouterr().err
    assert hri_lab("service", "call", "/add_two_ints", "[1, 2]") == 1
    assert "the request must be a YAML mapping" in capsys.readouterr().err
    assert hri_lab("service", "type", "/nothing_here") == 1
    assert capsys.readouterr().err.startswith("error: service '/nothing_here' is not available")


def test_param_get_set_describe_as_ros2_prints_them(hri_lab, capsys):
    assert hri_lab("param", "get", "/cooperative_lifting", "mu") == 0
    assert capsys.readouterr().out.startswith("Double value is: ")
    assert hri_lab("param", "set", "/cooperative_lifting", "mu", "fast") == 1
    assert capsys.readouterr().out == (
        "Setting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, "
        "setting it to {string} is not allowed.\n"
    )
    assert hri_lab("param", "describe", "/cooperative_lifting", "mu") == 0
    out = capsys.readouterr().out
    assert out.startswith("Parameter name: mu\n  Type: double\n")
    assert "  Constraints:\n    Min value:" in out
    assert hri_lab("param", "get", "/cooperative_lifting", "no_such") == 1


def test_param_dump_then_load_sets_each(hri_lab, capsys, tmp_path):
    assert hri_lab("param", "dump", "/cooperative_lifting") == 0
    dump = capsys.readouterr().out
    assert dump.startswith("cooperative_lifting:\n  ros__parameters:\n")
    path = tmp_path / "lifting.yaml"
    path.write_text(dump)
    assert hri_lab("param", "load", str(path)) == 0
    assert "Set parameter mu successful" in capsys.readouterr().out.splitlines()
    assert hri_lab("param", "load", str(tmp_path / "none.yaml")) == 1
    assert "none.yaml: no such file" in capsys.readouterr().err


def test_action_list_and_a_goal_to_its_end(hri_lab, capsys):
    assert hri_lab("action", "list") == 0
    listed = capsys.readouterr().out.splitlines()
    assert "/count" in listed
    assert listed == sorted(listed) and len(listed) > 2
    assert hri_lab("action", "list", "-c") == 0
    assert capsys.readouterr().out == f"{len(listed)}\n"
    assert hri_lab("action", "send_goal", "/count", "{count: 2}", "--feedback") == 0
    out = capsys.readouterr().out
    # ros2action's send_goal: each YAML after its heading, indented on its first line (its format string)
    head, _, rest = out.partition("Goal accepted with ID: ")
    assert head == "Waiting for an action server to become available...\nSending goal:\n     count: 2\n\n"
    goal_id, _, rest = rest.partition("\n\n")
    assert len(goal_id) == 32 and int(goal_id, 16) >= 0  # the goal's UUID in hex, as bytes(uuid).hex()
    assert rest == (
        "Feedback:\n    current_number: 1\n\nFeedback:\n    current_number: 2\n\n"
        "Result:\n    final_count: 2\n\nGoal finished with status: SUCCEEDED\n"
    )


def test_send_goal_reads_its_goal_from_stdin_and_prints_every_field(hri_lab, capsys, monkeypatch):
    """`--stdin` (ros2's collect_stdin) after the type; the goal printed as sent, the fields not given
    at their defaults in the Goal's order, a message of several lines indented on its first only."""
    import io

    monkeypatch.setattr("sys.stdin", io.StringIO("count: 1\n"))
    assert hri_lab("action", "send_goal", "/count", "hri_lab/action/Count", "--stdin") == 0
    assert "Sending goal:\n     count: 1\n\n" in capsys.readouterr().out
    monkeypatch.setattr("sys.stdin", io.StringIO("count: 1\n"))
    assert hri_lab("action", "send_goal", "/count", "hri_lab/action/Count", "{count: 2}", "--stdin") == 1
    assert "--stdin reads the goal from standard input" in capsys.readouterr().err
    assert hri_lab("action", "send_goal", "/run_experiment", "{trials: 0}") == 1  # refused: trials >= 1
    printed = capsys.readouterr()
    assert "Sending goal:\n     trials: 0\nparticipant: ''\nseed: 0\nplots: false\nset: ''\n\n" in printed.out
    assert "trials" in printed.err


def test_action_info_and_node_info_list_clients_and_servers_as_ros2_prints_them(hri_lab, client, capsys):
    """ros2action's info verb: the clients (as rclpy programs tell the lab: the `endpoints` op) and
    the server (the lab's node for its own action, the providing node for a node's), -t with the
    type, -c the numbers only, the name as given; an action nobody serves or uses has none. `node
    info`'s sections of service clients, action servers and action clients from the same."""
    with client.websocket_connect("/") as program:
        program.send_json({"op": "node", "name": "/demo/fibonacci_server"})
        program.send_json({"op": "advertise_action", "action": "/fibonacci",
                           "type": "action_tutorials_interfaces/action/Fibonacci"})  # fmt: skip
        program.send_json({"op": "endpoints", "kind": "action_client", "name": "/count",
                           "entities": [{"node": "/counter", "qos": {}}, {"node": "/demo/fibonacci_server", "qos": {}}]})  # fmt: skip
        program.send_json({"op": "endpoints", "kind": "client", "name": "/add_two_ints",
                           "entities": [{"node": "/demo/fibonacci_server", "qos": {}}]})  # fmt: skip
        program.send_json({"op": "call_service", "id": "sync", "service": "/rosapi/get_time", "args": {}})
        answer = within(program.receive_json, 30, "the sync answer")
        while answer.get("op") != "service_response":  # the advertise's report comes first
            answer = within(program.receive_json, 30, "the sync answer")
        assert hri_lab("action", "info", "/count") == 0
        assert capsys.readouterr().out == (
            "Action: /count\nAction clients: 2\n    /counter\n    /demo/fibonacci_server\nAction servers: 1\n    /hri_lab\n"
        )
        assert hri_lab("action", "info", "-t", "fibonacci") == 0
        assert capsys.readouterr().out == (
            "Action: fibonacci\nAction clients: 0\nAction servers: 1\n"
            "    /demo/fibonacci_server [action_tutorials_interfaces/action/Fibonacci]\n"
        )
        assert hri_lab("action", "info", "--count", "/count") == 0
        assert capsys.readouterr().out == "Action: /count\nAction clients: 2\nAction servers: 1\n"
        assert hri_lab("node", "info", "/demo/fibonacci_server") == 0
        assert capsys.readouterr().out.endswith(
            "  Service Clients:\n    /add_two_ints: hri_lab/srv/AddTwoInts\n"
            "  Action Servers:\n    /fibonacci: action_tutorials_interfaces/action/Fibonacci\n"
            "  Action Clients:\n    /count: hri_lab/action/Count\n"
        )
        assert hri_lab("node", "info", "/hri_lab") == 0
        assert "  Action Servers:\n    /compare_controllers: hri_lab/action/CompareControllers\n    /count: " in (
            capsys.readouterr().out
        )
    assert hri_lab("action", "info", "/no_such_action") == 0
    assert capsys.readouterr().out == "Action: /no_such_action\nAction clients: 0\nAction servers: 0\n"


def test_topic_and_action_type_and_find_as_ros2_prints_them(hri_lab, client, capsys):
    """ros2topic's and ros2action's `type` (the name compared as given: nothing printed and status 1
    for one the graph lacks) and `find TYPE [-c]` (the names of that type, sorted), a program's topic
    among the lab's."""
    with client.websocket_connect("/") as program:
        program.send_json({"op": "advertise", "topic": "/chatter", "type": "std_msgs/String"})
        program.send_json({"op": "call_service", "id": "sync", "service": "/rosapi/get_time", "args": {}})
        while within(program.receive_json, 30, "the sync answer").get("op") != "service_response":
            pass  # the connection's ops are handled in order: the advertise is taken once this is answered
        assert hri_lab("topic", "type", "/chatter") == 0
        assert capsys.readouterr().out == "std_msgs/msg/String\n"
        assert hri_lab("topic", "type", "/joint_states") == 0
        assert capsys.readouterr().out == "sensor_msgs/msg/JointState\n"
        assert hri_lab("topic", "type", "chatter") == 1  # as ros2: the name as given
        assert capsys.readouterr().out == ""
        assert hri_lab("topic", "find", "std_msgs/msg/String") == 0
        found = capsys.readouterr().out.splitlines()
        assert "/chatter" in found and found == sorted(found)
        assert hri_lab("topic", "find", "geometry_msgs/WrenchStamped", "-c") == 0
        assert int(capsys.readouterr().out) >= 1
    assert hri_lab("action", "type", "/count") == 0
    assert capsys.readouterr().out == "hri_lab/action/Count\n"
    assert hri_lab("action", "type", "/nothing") == 1
    assert hri_lab("action", "find", "hri_lab/action/Count") == 0
    assert capsys.readouterr().out == "/count\n"
    assert hri_lab("action", "find", "hri_lab/action/Count", "--count") == 0
    assert capsys.readouterr().out == "1\n"


def test_topic_pub_info_as_ros2_prints_them_to_a_listener(hri_lab, client, capsys):
    with client.websocket_connect("/") as listener:
        listener.send_json({"op": "subscribe", "id": "l", "topic": "/cli_chatter", "type": "std_msgs/String"})
        assert hri_lab("topic", "info", "/cli_chatter") == 0  # the listener's subscription made the topic
        assert capsys.readouterr().out == "Type: std_msgs/msg/String\nPublisher count: 0\nSubscription count: 1\n"
        assert hri_lab("topic", "list") == 0
        listed = capsys.readouterr().out.splitlines()
        assert "/cli_chatter" in listed and listed == sorted(listed)  # the lab's and the listener's
        assert hri_lab("topic", "list", "-c") == 0
        assert capsys.readouterr().out == f"{len(listed)}\n"
        assert hri_lab("topic", "pub", "/cli_chatter", "std_msgs/msg/String", "{data: hi}", "--once") == 0
        assert capsys.readouterr().out == "publisher: beginning loop\npublishing #1: std_msgs.msg.String(data='hi')\n\n"
        heard = within(listener.receive_json, 30, "the published message")
        assert heard["topic"] == "/cli_chatter" and heard["msg"] == {"data": "hi"}
        assert hri_lab("topic", "pub", "-t", "2", "-r", "50", "/cli_chatter", "std_msgs/String", "{data: two}") == 0
        assert capsys.readouterr().out.count("std_msgs.msg.String(data='two')") == 2
        for _ in range(2):
            assert within(listener.receive_json, 30, "one of two")["msg"] == {"data": "two"}
    assert hri_lab("topic", "pub", "-1", "/joint_states", "sensor_msgs/msg/JointState", "-w", "0") == 1
    assert "advertise: topic /joint_states is published by the lab" in capsys.readouterr().err
    assert hri_lab("topic", "pub", "/x", "std_msgs/msg/String", "{date: hi}") == 1
    assert "Failed to populate field: std_msgs/String has no field 'date'" in capsys.readouterr().err
    assert hri_lab("topic", "pub", "/x", "std_msgs/msg/Nothing") == 1
    assert "The passed message type is invalid" in capsys.readouterr().err
    assert hri_lab("topic", "info", "/no_such_topic") == 1
    assert "Unknown topic '/no_such_topic'" in capsys.readouterr().err


def test_topic_info_verbose_service_info_and_pub_stdin_as_ros2_prints_them(hri_lab, client, capsys, monkeypatch):
    """ros2cli's `topic info -v` (each endpoint's node, type and QoS as rclpy's TopicEndpointInfo prints
    it), `service info`'s clients (as rclpy programs tell the lab: the `endpoints` op) and
    `topic pub --stdin` (the message's YAML read from standard input)."""
    import io

    qos = {"reliability": "BEST_EFFORT", "durability": "TRANSIENT_LOCAL", "lifespan": 1_500_000_000, "deadline": 0,
           "liveliness": "MANUAL_BY_TOPIC", "liveliness_lease_duration": 0}  # fmt: skip
    with client.websocket_connect("/") as program, client.websocket_connect("/") as listener:
        program.send_json({"op": "node", "name": "/demo/talker"})
        program.send_json({"op": "advertise", "topic": "/qos_chatter", "type": "std_msgs/String"})
        program.send_json({"op": "endpoints", "kind": "publisher", "name": "/qos_chatter",
                           "entities": [{"node": "/demo/talker", "qos": qos}]})  # fmt: skip
        program.send_json({"op": "endpoints", "kind": "client", "name": "/add_two_ints",
                           "entities": [{"node": "/demo/talker", "qos": {}}, {"node": "/caller", "qos": {}}]})  # fmt: skip
        listener.send_json({"op": "node", "name": "/echo"})
        listener.send_json({"op": "subscribe", "id": "l", "topic": "/qos_chatter", "type": "std_msgs/String"})
        for session in (program, listener):  # each connection's ops are handled in order: all taken once answered
            session.send_json({"op": "call_service", "id": "sync", "service": "/rosapi/get_time", "args": {}})
            assert within(session.receive_json, 30, "the sync answer")["op"] == "service_response"
        assert hri_lab("topic", "info", "-v", "/qos_chatter") == 0
        assert capsys.readouterr().out == (
            "Type: std_msgs/msg/String\n\nPublisher count: 1\n\n"
            "Node name: talker\nNode namespace: /demo\nTopic type: std_msgs/msg/String\nEndpoint type: PUBLISHER\n"
            "QoS profile:\n  Reliability: BEST_EFFORT\n  History (Depth): UNKNOWN\n  Durability: TRANSIENT_LOCAL\n"
            "  Lifespan: 1500000000 nanoseconds\n  Deadline: Infinite\n  Liveliness: MANUAL_BY_TOPIC\n"
            "  Liveliness lease duration: Infinite\n\n"
            "Subscription count: 1\n\n"
            "Node name: echo\nNode namespace: /\nTopic type: std_msgs/msg/String\nEndpoint type: SUBSCRIPTION\n"
            "QoS profile:\n  Reliability: RELIABLE\n  History (Depth): UNKNOWN\n  Durability: VOLATILE\n"
            "  Lifespan: Infinite\n  Deadline: Infinite\n  Liveliness: AUTOMATIC\n"
            "  Liveliness lease duration: Infinite\n\n"
        )
        assert hri_lab("service", "info", "/add_two_ints") == 0
        assert capsys.readouterr().out == "Type: hri_lab/srv/AddTwoInts\nClients count: 2\nServices count: 1\n"
        monkeypatch.setattr("sys.stdin", io.StringIO("data: from stdin\n"))
        assert hri_lab("topic", "pub", "--stdin", "-1", "/qos_chatter", "std_msgs/msg/String") == 0
        assert "std_msgs.msg.String(data='from stdin')" in capsys.readouterr().out
        heard = within(listener.receive_json, 30, "the message read from stdin")
        while heard.get("op") != "publish":
            heard = within(listener.receive_json, 30, "the message read from stdin")
        assert heard["msg"] == {"data": "from stdin"}


def test_param_delete_asks_the_node_and_says_what_it_answered(hri_lab, capsys):
    assert hri_lab("param", "delete", "/cooperative_lifting", "mu") == 1  # statically typed: rclcpp's refusal
    assert capsys.readouterr().err == (
        "Deleting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, "
        "setting it to {not set} is not allowed.\n"
    )
    assert hri_lab("param", "delete", "/cooperative_lifting", "no_such") == 1
    assert (
        capsys.readouterr().err
        == "Deleting parameter failed: parameter 'no_such' cannot be set because it was not declared\n"
    )
    assert hri_lab("param", "delete", "/no_such_node", "mu") == 1
    assert capsys.readouterr().err == "Node not found\n"


def test_topic_hz_and_bw_report_as_ros2topic_computes_them():
    rate = Rate()
    assert rate.report() is None  # no interval yet
    for at_s in (10.0, 10.1, 10.2, 10.4):
        rate.arrived(at_s)
    assert rate.report() == "average rate: 7.500\n\tmin: 0.100s max: 0.200s std dev: 0.04714s window: 3"
    assert rate.report() is None  # nothing new since
    small = Bandwidth()
    for at_s, size in ((0.0, 100), (0.5, 300)):
        small.arrived(at_s, size)
    assert small.report(1.0) == "400 B/s from 2 messages\n\tMessage size mean: 200 B min: 100 B max: 300 B"
    big = Bandwidth(window=2)  # the first arrival leaves the window: 3 MB over the 2 s since the second
    for at_s in (0.0, 1.0, 2.0):
        big.arrived(at_s, 1_500_000)
    assert big.report(3.0) == "1.50 MB/s from 2 messages\n\tMessage size mean: 1.50 MB min: 1.50 MB max: 1.50 MB"
