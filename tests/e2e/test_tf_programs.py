"""tf like ROS against a real lab: a program's static and dynamic frames (tests/ros_programs/
frame_broadcaster_rclpy.py, tf2_ros' broadcasters) join the lab's tree — an rclpy listener
(tf2_ros Buffer/TransformListener) and a rospy one (ROS 1's tf) look them up through the lab's
frames, roslibpy's /republish_tfs and the tf2_web_republisher action (roslibpy's ROS 1 ActionClient,
as roslibjs' TFClient uses it) resolve them, /tf_static carries them latched — and a program that
sends one of the lab's own frames is refused with the reason while its other frames are taken."""

import math

import httpx
import numpy as np
import roslibpy
from roslibpy.ros1.actionlib import ActionClient, Goal, GoalStatus

from tests.e2e.serving import served_lab
from tests.ros_running import run
from tests.waiting import wait_for

lab = served_lab()

MARKER_OFFSET_M = 0.05  # plate_marker on the plate's +z (the broadcaster's static transform)
CARROT_RADIUS_M = 0.1


def _republished(ros, sources: list[str], target: str) -> dict[str, dict]:
    """The transforms /republish_tfs sends for `sources` in `target` (the first message with all)."""
    answer = roslibpy.Service(ros, "/republish_tfs", "tf2_web_republisher/RepublishTFs").call(
        roslibpy.ServiceRequest({"source_frames": sources, "target_frame": target, "rate": 10.0}), timeout=30
    )
    got: dict[str, dict] = {}
    topic = roslibpy.Topic(ros, answer["topic_name"], "tf2_web_republisher/TFArray")
    topic.subscribe(lambda m: got.update({t["child_frame_id"]: t["transform"] for t in m["transforms"]}))
    try:
        wait_for(lambda: set(sources) <= set(got))
    finally:
        topic.unsubscribe()
    return got


def _from_the_action(ros, sources: list[str], target: str) -> dict[str, dict]:
    """The transforms a goal of the tf2_web_republisher action gets as feedback (the first with all);
    the goal, cancelled, ends PREEMPTED."""
    client = ActionClient(ros, "/tf2_web_republisher", "tf2_web_republisher/TFSubscriptionAction")
    thresholds = {"angular_thres": 0.01, "trans_thres": 0.01}  # roslibjs' example's
    goal = Goal(
        client, roslibpy.Message({"source_frames": sources, "target_frame": target, "rate": 10.0, **thresholds})
    )
    got: dict[str, dict] = {}
    goal.on("feedback", lambda f: got.update({t["child_frame_id"]: t["transform"] for t in f["transforms"]}))
    goal.send()
    try:
        wait_for(lambda: {s.strip("/") for s in sources} <= set(got))  # as tf2 names them: no leading slash
    finally:
        goal.cancel()
    try:
        wait_for(lambda: goal.is_finished)
        assert goal.status["status"] == GoalStatus.PREEMPTED
    finally:
        client.dispose()
    return got


def _vector(translation: dict) -> np.ndarray:
    return np.array([translation["x"], translation["y"], translation["z"]])


def _printed(program, prefix: str) -> list[float]:
    line = program.wait_for_line(prefix)
    return [float(v) for v in line.split(":", 1)[1].split()]


def test_a_programs_frames_join_the_tree_for_listeners_and_republish_tfs(ros, lab):
    broadcaster = run(lab.url, "frame_broadcaster_rclpy.py")
    try:
        broadcaster.wait_for_line("frames ready")
        listener = run(lab.url, "frame_listener_rclpy.py")
        ros1_listener = run(lab.url, "frame_listener_rospy.py")
        try:
            marker = np.array(_printed(listener, "plate_marker in panda_link0:"))
            radius = _printed(listener, "carrot radius:")[0]
            ros1_marker = np.array(_printed(ros1_listener, "plate_marker in panda_link0:"))
            ros1_radius = _printed(ros1_listener, "carrot radius:")[0]
        finally:
            listener.interrupt()
            ros1_listener.interrupt()
        # the lab's own composition of the same chain: the plate's pose (the robot stands still) and the marker's
        lab_frames = _republished(ros, ["plate", "plate_marker", "carrot"], "panda_link0")
        plate, lab_marker = (
            _vector(lab_frames["plate"]["translation"]),
            _vector(lab_frames["plate_marker"]["translation"]),
        )
        assert math.isclose(float(np.linalg.norm(lab_marker - plate)), MARKER_OFFSET_M, abs_tol=1e-6)
        assert np.allclose(marker, lab_marker, atol=1e-3)
        assert np.allclose(ros1_marker, lab_marker, atol=1e-3)
        assert math.isclose(radius, CARROT_RADIUS_M, abs_tol=1e-3)
        assert math.isclose(ros1_radius, CARROT_RADIUS_M, abs_tol=1e-3)
        carrot_from_marker = np.linalg.norm(_vector(lab_frames["carrot"]["translation"]) - lab_marker)
        assert math.isclose(float(carrot_from_marker), CARROT_RADIUS_M, abs_tol=1e-3)
        # the tf2_web_republisher action resolves the same frames (the still ones: the carrot turns)
        action_frames = _from_the_action(ros, ["/plate", "plate_marker", "carrot"], "panda_link0")
        for name in ("plate", "plate_marker"):
            assert np.allclose(
                _vector(action_frames[name]["translation"]), _vector(lab_frames[name]["translation"]), atol=1e-6
            )
        # /tf_static carries the program's static frame with the lab's (latched: a new subscriber gets it)
        static: list[dict] = []
        topic = roslibpy.Topic(ros, "/tf_static", "tf2_msgs/TFMessage")
        topic.subscribe(static.append)
        try:
            wait_for(lambda: static)
        finally:
            topic.unsubscribe()
        edges = {(t["header"]["frame_id"], t["child_frame_id"]) for t in static[0]["transforms"]}
        assert ("plate", "plate_marker") in edges
        assert ("panda_link8", "plate") in edges
        # and HTTP's /topics/tf_static (what `hri-lab topic echo /tf_static` prints) is the same topic
        served = httpx.get(f"{lab.url}/topics/tf_static", timeout=30).json()
        assert {(t["header"]["frame_id"], t["child_frame_id"]) for t in served["transforms"]} >= edges
    finally:
        broadcaster.interrupt()
    # the program gone, its frames go with it
    wait_for(lambda: _republish_refused(ros, "plate_marker"))


def _republish_refused(ros, frame: str) -> bool:
    try:
        roslibpy.Service(ros, "/republish_tfs", "tf2_web_republisher/RepublishTFs").call(
            roslibpy.ServiceRequest({"source_frames": [frame], "target_frame": "world", "rate": 10.0}), timeout=30
        )
    except Exception as exc:  # noqa: BLE001 - roslibpy's failed call
        return "does not exist" in str(exc)
    return False


def test_a_program_cannot_move_the_labs_frames(ros, lab):
    thief = run(lab.url, "frame_broadcaster_rclpy.py", "--ros-args", "-p", "steal:=true")
    try:
        line = thief.wait_for_line("refused")
        assert "frame box is the lab's" in line
        carrot = _republished(ros, ["carrot", "box"], "panda_link0")  # its own frame taken; the box still the lab's
        assert "carrot" in carrot
        moving: list[dict] = []
        topic = roslibpy.Topic(ros, "/tf", "tf2_msgs/TFMessage")
        topic.subscribe(moving.append)
        try:
            wait_for(lambda: len(moving) >= 3)
        finally:
            topic.unsubscribe()
        parents = [(t["header"]["frame_id"]) for m in moving for t in m["transforms"] if t["child_frame_id"] == "box"]
        assert parents
        assert set(parents) == {"panda_link0"}
        assert all(
            _vector(t["transform"]["translation"]).any()
            for m in moving
            for t in m["transforms"]
            if t["child_frame_id"] == "box"
        )  # the lab's box (on the table), not the program's identity transform
    finally:
        thief.interrupt()
