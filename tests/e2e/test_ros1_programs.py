"""ROS 1 programs written as rospy's and actionlib's tutorials write them, run unchanged with `hri-lab
run` / `hri-lab launch` (tests/ros_programs/): genpy's star imports, a Header's seq, names in a
launch file's namespace, actionlib's server reached over its ROS 1 topics (roslibpy's ActionClient)
and by a rospy client, a ROS 1 cancel of its id alone relayed whole, and the program's node name
where the lab shows nodes."""

import threading

import roslibpy
import roslibpy.ros1.actionlib as ros1_actionlib

from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.ros_running import PROGRAMS, Program, run
from tests.waiting import wait_for

lab = served_lab()


def rosapi(ros, name: str, args: dict | None = None) -> dict:
    return roslibpy.Service(ros, f"/rosapi/{name}", "rosapi/X").call(roslibpy.ServiceRequest(args or {}), timeout=30)


def test_a_star_import_server_answers_under_its_node_name_and_a_second_service_raises(lab, ros):
    server = run(lab.url, "add_two_ints_server_star_rospy.py")
    try:
        server.wait_for_line("Ready to add two ints.")
        assert "Second service refused: service [/add_two_ints] already registered" in server.output
        answer = http.post(f"{lab.url}/services/add_two_ints", json={"a": 2, "b": 3}, timeout=30)
        assert answer.json() == {"sum": 5}, answer.text
        server.wait_for_line("Returning [2 + 3 = 5]")
        assert http.get(f"{lab.url}/services/add_two_ints").json()["node"] == "/add_two_ints_server"
        assert "/add_two_ints_server" in rosapi(ros, "nodes")["nodes"]
        assert "/add_two_ints" in rosapi(ros, "node_details", {"node": "/add_two_ints_server"})["services"]
        # roscpp's logger services, which rospy's init_node advertises for every node
        get_loggers = roslibpy.Service(ros, "/add_two_ints_server/get_loggers", "roscpp/GetLoggers")
        set_level = roslibpy.Service(ros, "/add_two_ints_server/set_logger_level", "roscpp/SetLoggerLevel")

        def levels() -> dict[str, str]:
            loggers = get_loggers.call(roslibpy.ServiceRequest({}), timeout=30)["loggers"]
            return {logger["name"]: logger["level"] for logger in loggers}

        assert levels()["rosout"] == "INFO"
        set_level.call(roslibpy.ServiceRequest({"logger": "rosout", "level": "warn"}), timeout=30)
        assert levels()["rosout"] == "WARN"
        again = run(lab.url, "add_two_ints_server_star_rospy.py")  # another node of the same name
        assert again.wait() == 1, again.output
        assert "rospy.service.ServiceException: service [/add_two_ints] cannot be provided" in again.output
        assert "already provided by node /add_two_ints_server" in again.output
    finally:
        assert server.interrupt() == 0, server.output


def test_a_header_publisher_with_none_and_a_listener_reading_seq(lab):
    listener = run(lab.url, "header_listener_rospy.py")
    talker = None
    try:
        listener.wait_for_line("listening")
        talker = run(lab.url, "header_talker_rospy.py")
        first = int(listener.wait_for_line("I heard seq ").split()[3].rstrip(":"))
        wait_for(lambda: sum("I heard seq" in line for line in listener.lines) >= 3, timeout=60)
        seqs = [int(line.split()[3].rstrip(":")) for line in listener.lines if "I heard seq" in line]
        assert first >= 1
        assert seqs == list(range(first, first + len(seqs)))
    finally:
        if talker is not None:
            talker.interrupt()
        listener.interrupt()


def test_a_namespaced_launch_resolves_relative_private_and_searched_names(lab, ros):
    launch = Program(lab.url, "launch", str(PROGRAMS / "namespaced.launch"), terminal=True)
    try:
        launch.wait_for_line("resolve_name:", timeout=120)
        out = launch.output
        assert "name /foo/param_talker namespace /foo/" in out
        assert "utterance: Hello World from foo" in out
        assert "global_example: global value" in out
        assert "topic_name: chatter" in out
        assert "search_param: /searched = found at the root" in out
        assert "resolve_name: /foo/chatter /foo/param_talker/private" in out
        assert wait_for(lambda: "/foo/chatter" in rosapi(ros, "topics")["topics"])
    finally:
        launch.interrupt()


def test_a_simple_action_server_is_reached_over_its_topics_and_by_a_rospy_client(lab, ros):
    server = run(lab.url, "fibonacci_server_actionlib.py")
    try:
        server.wait_for_line("fibonacci server ready")
        assert "/fibonacci" in [a["name"] for a in http.get(f"{lab.url}/actions").json()]  # the lab lists it
        # roslibpy's ROS 1 ActionClient: /fibonacci/goal, cancel, status, feedback, result
        client = ros1_actionlib.ActionClient(ros, "/fibonacci", "actionlib_tutorials/FibonacciAction")
        feedback: list = []
        goal = ros1_actionlib.Goal(client, roslibpy.Message({"order": 5}))
        goal.on("feedback", feedback.append)
        goal.send()
        result = goal.wait(60)
        assert result == {"sequence": [0, 1, 1, 2, 3, 5]}
        wait_for(lambda: goal.status["status"] == ros1_actionlib.GoalStatus.SUCCEEDED)
        assert feedback
        assert feedback[-1] == {"sequence": [0, 1, 1, 2, 3, 5]}
        # a cancel over the topic preempts a long goal
        long_goal = ros1_actionlib.Goal(client, roslibpy.Message({"order": 400}))
        started = threading.Event()
        long_goal.on("feedback", lambda fb: started.set())
        long_goal.send()
        assert started.wait(60)
        long_goal.cancel()
        assert len(long_goal.wait(60)["sequence"]) < 400
        wait_for(lambda: long_goal.status["status"] == ros1_actionlib.GoalStatus.PREEMPTED)  # the status list's next
        client.dispose()
        # actionlib's own client, from another program
        rospy_client = run(lab.url, "fibonacci_client_actionlib.py", "6")
        assert rospy_client.wait(timeout=120) == 0, rospy_client.output
        assert "Result: 0, 1, 1, 2, 3, 5, 8" in rospy_client.output
    finally:
        server.interrupt()


def test_a_subscribe_listener_hears_of_each_peer(lab, ros):
    program = run(lab.url, "subscribe_notify_rospy.py")
    heard: list = []
    topic = roslibpy.Topic(ros, "/chatter_peers", "std_msgs/String")
    try:
        program.wait_for_line("publishing")
        topic.subscribe(heard.append)
        program.wait_for_line("a peer subscribed to topic [/chatter_peers]")
        assert wait_for(lambda: heard) == [{"data": "greetings. welcome to topic /chatter_peers"}]
        assert len(rosapi(ros, "subscribers", {"topic": "/chatter_peers"})["subscribers"]) == 1  # roslibpy
        topic.unsubscribe()
        program.wait_for_line("a peer unsubscribed from topic [/chatter_peers], 0 left")
        assert rosapi(ros, "publishers", {"topic": "/chatter_peers"})["publishers"] == ["/talker_callback"]
    finally:
        program.interrupt()


def test_a_ros1_cancel_of_its_id_alone_reaches_a_program_and_a_client_with_its_stamp(lab, ros):
    program = run(lab.url, "cancel_listener_rospy.py")
    heard: list = []
    listener = roslibpy.Topic(ros, "/test_action/cancel", "actionlib_msgs/GoalID")
    cancel = roslibpy.Topic(ros, "/test_action/cancel", "actionlib_msgs/GoalID")
    try:
        program.wait_for_line("listening")
        listener.subscribe(heard.append)
        cancel.advertise()

        def relayed() -> bool:  # roslibpy's advertise does not wait: sent again until it is heard
            if not heard:
                cancel.publish(roslibpy.Message({"id": "goal_7"}))  # as roslibpy's ROS 1 Goal.cancel sends it
            return bool(heard)

        wait_for(relayed, timeout=60)
        assert heard[0] == {"stamp": {"sec": 0, "nanosec": 0, "secs": 0, "nsecs": 0}, "id": "goal_7"}
        program.wait_for_line("cancel goal_7 stamp 0.000000000")
    finally:
        listener.unsubscribe()
        cancel.unadvertise()
        program.interrupt()


def test_a_listener_reads_the_talkers_connection_header(lab):
    listener = run(lab.url, "snack_listener_rospy.py")
    talker = None
    try:
        listener.wait_for_line("a message built here has a connection header: False")  # as in rospy
        talker = run(lab.url, "snack_talker_rospy.py")
        line = listener.wait_for_line("offers")
        string_md5 = "992ce8a1687cec8c8bd883ec73ca41d1"  # genpy's std_msgs/String._md5sum
        assert (
            line
            == f"/snack_talker on /snacks (std_msgs/String, md5 {string_md5}, latching 1) offers pretzels from shelf 3 with tea"
        )
    finally:
        if talker is not None:
            talker.interrupt()
        listener.interrupt()


def test_a_server_reads_the_callers_header_and_the_client_the_servers(lab):
    server = run(lab.url, "ticket_server_rospy.py")
    try:
        server.wait_for_line("Ready to add with tickets.")
        client = run(lab.url, "ticket_client_rospy.py")
        assert client.wait() == 0, client.output
        assert "sum 42" in client.output
        add_two_ints_md5 = "6a2e34150c00229791cc89ff309fff21"  # genpy's AddTwoInts._md5sum
        assert (
            f"answered by /ticket_server for /ticketed_add (example_interfaces/AddTwoInts, md5 {add_two_ints_md5})"
            in client.output
        )
        server.wait_for_line("call from /ticket_client with ticket A-113")
        answer = http.post(f"{lab.url}/services/ticketed_add", json={"a": 1, "b": 2}, timeout=30)  # the lab calls
        assert answer.json() == {"sum": 3}, answer.text
        server.wait_for_line("call from /hri_lab with ticket none")
    finally:
        assert server.interrupt() == 0, server.output
