"""`hri-lab serve --world mobile`: the base driven over rosbridge (/cmd_vel), its sensors as ROS has
them (/scan, /odom, /tf, /joint_states, /robot_description), the watchdog, and the handout's
keys-to-twist node driving it with `hri-lab param set` changing its speed; its frames through
/republish_tfs (tf2_web_republisher, as a TFClient reads them); `hri-lab record`, `bag info` and `play` of it."""

import itertools
import math
import subprocess
import sys
import threading
import time

import httpx
import roslibpy

from app.serving.launch import free_port
from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.ros_running import Program, run
from tests.waiting import wait_for

lab = served_lab("--world", "mobile")


def latest(lab, topic: str) -> dict:
    return http.get(f"{lab.url}/topics/{topic}").json()


def stamp(message: dict) -> float:
    return message["header"]["stamp"]["sec"] + message["header"]["stamp"]["nanosec"] * 1e-9


def test_the_topics_are_turtlebot3s(lab):
    topics = {t["name"]: t["type"] for t in http.get(f"{lab.url}/topics").json()}
    assert topics["/scan"] == "sensor_msgs/LaserScan"
    assert topics["/odom"] == "nav_msgs/Odometry"
    assert topics["/cmd_vel_followed"] == "geometry_msgs/Twist"
    assert "/cmd_vel" not in topics  # the nodes' topic: the lab follows it, never publishes it
    assert topics["/joint_states"] == "sensor_msgs/JointState"
    scan = latest(lab, "scan")
    assert len(scan["ranges"]) == 360
    assert scan["range_min"] == 0.12
    assert scan["range_max"] == 3.5
    assert scan["header"]["frame_id"] == "base_scan"
    assert scan["scan_time"] == 0.2
    static = {(t["header"]["frame_id"], t["child_frame_id"]) for t in latest(lab, "tf_static")["transforms"]}
    assert ("base_footprint", "base_link") in static
    assert ("base_link", "base_scan") in static
    (moving,) = latest(lab, "tf")["transforms"]
    assert (moving["header"]["frame_id"], moving["child_frame_id"]) == ("odom", "base_footprint")
    assert latest(lab, "joint_states")["name"] == ["wheel_left_joint", "wheel_right_joint"]
    assert '<robot name="turtlebot3_burger">' in latest(lab, "robot_description")["data"]


def test_cmd_vel_drives_the_base_and_the_watchdog_stops_it(lab, ros):
    scans: list[dict] = []
    listener = roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan")
    listener.subscribe(scans.append)
    param = roslibpy.Param(ros, "/robot_description")
    assert "wheel_left_joint" in param.get(timeout=10)
    publisher = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist")
    publisher.advertise()
    start = latest(lab, "odom")["pose"]["pose"]["position"]
    stop = threading.Event()

    def publish_at_10_hz():  # as a node's timer does, whatever the test's own reads cost
        while not stop.wait(0.1):
            publisher.publish(roslibpy.Message({"linear": {"x": 0.0}, "angular": {"z": 0.8}}))

    thread = threading.Thread(target=publish_at_10_hz, daemon=True)
    thread.start()
    try:
        wait_for(lambda: latest(lab, "joint_states")["velocity"] == [-0.8 * 0.08 / 0.033, 0.8 * 0.08 / 0.033], 60)
        position = latest(lab, "odom")["pose"]["pose"]["position"]
        assert math.isclose(position["x"], start["x"], abs_tol=1e-9)  # turning on the spot
        assert math.isclose(position["y"], start["y"], abs_tol=1e-9)
    finally:
        stop.set()
        thread.join()
        listener.unsubscribe()
    # nobody commands: the base stops after the watchdog's 0.5 s (and its deceleration)
    wait_for(lambda: latest(lab, "odom")["twist"]["twist"]["angular"]["z"] == 0.0, 60)
    assert latest(lab, "cmd_vel_followed")["angular"]["z"] == 0.0
    stamps = [stamp(s) for s in scans]
    assert len(stamps) >= 2
    assert all(b - a >= 0.2 - 1e-6 for a, b in itertools.pairwise(stamps))
    assert all(round((t - stamps[0]) / 0.2, 6).is_integer() for t in stamps)  # taken at 5 Hz of simulated time
    assert all(len(s["ranges"]) == 360 for s in scans)


def test_a_twist_with_a_bad_field_is_refused(lab, ros):
    publisher = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist")
    publisher.advertise()
    publisher.publish(roslibpy.Message({"linear": {"x": "fast"}}))
    publisher.publish(roslibpy.Message({"linear": {"x": 0.1}, "angular": {"z": 1e400}}))
    time.sleep(0.3)
    assert latest(lab, "cmd_vel_followed")["linear"]["x"] == 0.0
    assert http.get(f"{lab.url}/health").json()["loop_alive"]


def test_the_keys_to_twist_node_drives_the_base_and_param_set_changes_its_speed(lab):
    # each key held for two of the node's 0.2 s ticks: at the base's acceleration limits (sim/mobile/base.py)
    # a speed below reaches 1.5 rad/s or 0.22 m/s from rest in more than one tick
    node = run(lab.url, "keys_to_twist_rclpy.py", "wwaa", "--ros-args", "-r", "key_twist:=cmd_vel")

    def param_set(name: str, value: str) -> None:
        changed = subprocess.run(
            [sys.executable, "-m", "app.cli", "param", "set", "/keytwist_param", name, value, "--url", lab.url],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert changed.returncode == 0, changed.stdout + changed.stderr

    def twist():
        t = latest(lab, "odom")["twist"]["twist"]
        return t["linear"]["x"], t["angular"]["z"]

    try:
        node.wait_for_line("key a: linear.x=0 angular.z=0.5")
        wait_for(lambda: twist() == (0.1, 0.0), timeout=60)  # the defaults: key w at 0.1 m/s
        wait_for(lambda: twist() == (0.0, 0.5), timeout=60)  # key a at 0.5 rad/s
        param_set("linear_speed", "0.3")  # the handout's change: above the Burger's 0.22 m/s
        node.wait_for_line("key w: linear.x=0.3")
        wait_for(lambda: twist() == (0.22, 0.0), timeout=60)  # held to the base's top speed
        param_set("angular_speed", "1.5")
        wait_for(lambda: twist() == (0.0, 1.5), timeout=60)
    finally:
        node.interrupt()


def test_republish_tfs_serves_the_mobile_worlds_frames(lab, ros):
    still = {"x": 0.0, "y": 0.0, "z": 0.0}
    wait_for(lambda: latest(lab, "odom")["twist"]["twist"] == {"linear": still, "angular": still}, timeout=60)
    answer = roslibpy.Service(ros, "/republish_tfs", "tf2_web_republisher/RepublishTFs").call(
        roslibpy.ServiceRequest({"source_frames": ["base_footprint", "base_scan"], "target_frame": "odom"}), timeout=30
    )
    got: dict[str, dict] = {}
    topic = roslibpy.Topic(ros, answer["topic_name"], "tf2_web_republisher/TFArray")
    topic.subscribe(lambda m: got.update({t["child_frame_id"]: t["transform"] for t in m["transforms"]}))
    try:
        wait_for(lambda: {"base_footprint", "base_scan"} <= set(got))
    finally:
        topic.unsubscribe()
    pose = latest(lab, "odom")["pose"]["pose"]  # the base stands still: odom -> base_footprint is /odom's pose
    footprint = got["base_footprint"]
    assert math.isclose(footprint["translation"]["x"], pose["position"]["x"], abs_tol=1e-9)
    for axis in "zw":  # the quaternion as /odom's (tf2 composes the broadcast one: its sign too)
        assert math.isclose(footprint["rotation"][axis], pose["orientation"][axis], abs_tol=1e-9)
    assert got["base_scan"]["translation"]["z"] > 0.1  # the lidar above the floor (base_link, then its mount)


def test_the_world_publishes_its_clock(lab, ros):
    ticks: list[dict] = []
    clock = roslibpy.Topic(ros, "/clock", "rosgraph_msgs/Clock")
    clock.subscribe(ticks.append)
    try:
        wait_for(lambda: len(ticks) >= 3)
    finally:
        clock.unsubscribe()
    seconds = [t["clock"]["sec"] + t["clock"]["nanosec"] * 1e-9 for t in ticks]
    assert seconds == sorted(seconds)
    assert seconds[-1] > seconds[0]


def test_record_then_play_the_mobile_world(lab, tmp_path):
    out = tmp_path / "drive.mcap"
    recorded = subprocess.run(
        [sys.executable, "-m", "app.cli", "record", "-o", str(out), "--duration", "2", "--url", lab.url],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert recorded.returncode == 0, recorded.stdout + recorded.stderr
    info = subprocess.run(
        [sys.executable, "-m", "app.cli", "bag", "info", str(out)], capture_output=True, text=True, timeout=60
    ).stdout
    assert "Topic: /scan" in info
    assert "foxglove.LaserScan" in info
    assert "foxglove.SceneUpdate" in info
    port = free_port()
    play = Program(None, "play", str(out), "--port", str(port), "--view", "light")
    try:
        play.wait_for_line("Press Ctrl+C")  # printed before its server binds the port: wait for that too

        def listed():
            try:
                return http.get(f"http://127.0.0.1:{port}/topics").json()
            except httpx.ConnectError:
                return None

        topics = {t["name"]: t["type"] for t in wait_for(listed, 60)}
        assert topics["/scan"] == "foxglove.LaserScan"
        assert topics["/odom"] == "nav_msgs/Odometry"
        scan = http.get(f"http://127.0.0.1:{port}/topics/scan").json()
        assert scan["frame_id"] == "base_scan"
        assert len(scan["ranges"]) == 360
    finally:
        play.interrupt()
