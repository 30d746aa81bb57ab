"""Bags as the handouts teach them, against real servers: `hri-lab bag record` records a program's
own topic (its definition carried into the bag), `hri-lab bag play` plays it back, looped and at 2x,
to a subscriber program; the camera recorded once, then the detection node developed on the bag in a
lab that publishes nothing (`serve --replay`); a ROS 1 .bag made with rosbags' writer plays into
the lab; a live lab's own topics are not played over (a warning); hostile bags are refused with
their reason within the stated memory bound."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import roslibpy
from rosbags.rosbag1 import Writer as Rosbag1Writer
from rosbags.typesys import Stores, get_typestore

from sim.recording import bounded

from app.recording import bags
from tests import hostile_bags
from tests.e2e.serving import running_server
from tests.http_client import http
from tests.ros_running import run
from tests.waiting import wait_for

ROOT = Path(__file__).parent.parent.parent
DETECTED = "detected_target_position"
TOLERANCE_PX = 5


@pytest.fixture(scope="module")
def lab():
    with running_server("--view", "none") as server:
        yield server


def hri_lab(*args: str, timeout: float = 120.0, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args], capture_output=True, text=True, timeout=timeout, cwd=cwd
    )


def start(*args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "app.cli", *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT
    )


def stop(process: subprocess.Popen) -> str:
    if process.poll() is None:
        process.terminate()
    out, _ = process.communicate(timeout=60)
    return out


def test_a_programs_topic_is_recorded_and_played_back_looped_at_2x(lab, tmp_path):
    publisher = run(lab.url, "student_info_publisher_rospy.py")
    try:
        publisher.wait_for_line("publisher ready")
        # from a folder with no .msg files: the definition is the one the program carried
        recorded = hri_lab(
            "bag", "record", "--url", lab.url, "/student_info", "-O", "info", "--duration", "4", cwd=tmp_path
        )
    finally:
        publisher.interrupt()
    assert recorded.returncode == 0, recorded.stderr
    info = hri_lab("bag", "info", str(tmp_path / "info"))
    assert "Topic: /student_info | Type: student_pkg/msg/StudentInfo" in info.stdout, info.stdout
    bag = bags.open_bag(tmp_path / "info")
    ages = [m.data["age"] for m in bag.messages()]
    assert len(ages) >= 3
    assert ages == sorted(ages)
    assert bag.definitions["student_pkg/msg/StudentInfo"] == "string name\nint32 age\nfloat64[] marks\n"

    listener = run(lab.url, "student_info_listener_rclpy.py")
    try:
        listener.wait_for_line("listener ready")
        player = start("bag", "play", "--url", lab.url, str(tmp_path / "info"), "-l", "-r", "2")
        try:
            wanted = [f"heard ada age {age} " for age in ages]

            def heard_twice() -> bool:
                lines = [line for line in listener.lines if line.startswith("heard ada")]
                firsts = [i for i, line in enumerate(lines) if line.startswith(wanted[0])]
                if len(firsts) < 2:
                    return False
                first_loop = lines[firsts[0] : firsts[0] + len(wanted)]
                return all(line.startswith(w) for line, w in zip(first_loop, wanted, strict=True))

            wait_for(heard_twice, timeout=120)
        finally:
            output = stop(player)
    finally:
        listener.interrupt()
    assert "at 2x" in output and "looping" in output, output
    assert "messages published" in output  # SIGTERM ends a playback as Ctrl+C does
    marks = next(line for line in listener.lines if line.startswith(wanted[1]))
    assert marks.endswith(f"marks [1.5, {ages[1] / 2.0}]")


def test_the_lab_s_own_topics_are_not_played_over_a_live_lab(lab, tmp_path):
    writer = bags.BagWriter(tmp_path / "joints", max_bytes=1 << 20)
    writer.add_topic("/joint_states", "sensor_msgs/JointState", None)
    writer.write("/joint_states", 1, {"name": ["panda_joint1"], "position": [0.5]})
    writer.close()
    played = hri_lab("bag", "play", "--url", lab.url, str(tmp_path / "joints"))
    assert played.returncode == 1
    assert "/joint_states is published by the lab's simulation: not played" in played.stderr
    assert "hri-lab serve --replay" in played.stderr
    assert "nothing to play" in played.stderr


def test_a_ros1_bag_made_with_rosbags_plays_into_the_lab(lab, ros, tmp_path):
    store = get_typestore(Stores.ROS1_NOETIC)
    String = store.types["std_msgs/msg/String"]
    with Rosbag1Writer(tmp_path / "real.bag") as writer:
        connection = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        for i in range(5):
            writer.write(
                connection,
                1_000_000_000 + i * 50_000_000,
                store.serialize_ros1(String(data=f"hello {i}"), connection.msgtype),
            )
    heard: list[str] = []
    clock: list[dict] = []
    topic = roslibpy.Topic(ros, "/chatter", "std_msgs/String", queue_length=100)
    topic.subscribe(lambda message: heard.append(message["data"]))
    clock_topic = roslibpy.Topic(ros, "/clock", "rosgraph_msgs/Clock", queue_length=100)
    clock_topic.subscribe(lambda message: clock.append(message["clock"]))
    try:
        player = start("bag", "play", "--url", lab.url, str(tmp_path / "real.bag"), "-l", "--clock")
        try:
            wait_for(lambda: sum(1 for h in heard if h == "hello 4") >= 1, timeout=120)
        finally:
            stop(player)
    finally:
        topic.unsubscribe()
        clock_topic.unsubscribe()
    assert {"sec": 1, "nanosec": 200_000_000} in clock  # the bag's time of its last message
    first = heard.index("hello 0")
    assert heard[first : first + 5] == [f"hello {i}" for i in range(5)]


def test_the_camera_recorded_once_then_the_detector_runs_on_the_bag(lab, ros, tmp_path):
    """The handout's use case: record the camera, then develop the detection node on the recording
    with no simulation publishing (a lab started with --replay)."""
    answer = http.post(f"{lab.url}/services/get_target_position", json={"get": True}, timeout=30).json()
    truth = np.array([answer["x"], answer["y"]])
    images: list[dict] = []  # the camera renders while somebody looks: its first image before recording
    watch = roslibpy.Topic(ros, "/image_raw", "sensor_msgs/Image", throttle_rate=1000)
    watch.subscribe(images.append)
    try:
        wait_for(lambda: images, timeout=120)
        recorded = hri_lab(
            "bag",
            "record",
            "--url",
            lab.url,
            "/image_raw",
            "/camera_info",
            "-O",
            str(tmp_path / "cam"),
            "--duration",
            "5",
        )
    finally:
        watch.unsubscribe()
    assert recorded.returncode == 0, recorded.stderr
    bag = bags.open_bag(tmp_path / "cam")
    assert {t.name: t.count for t in bag.info().topics}["/image_raw"] >= 1
    with running_server("--view", "none", "--replay") as replay:
        topics = http.get(f"{replay.url}/health", timeout=30)
        assert topics.status_code == 200
        detector = run(replay.url, "object_detector_rospy.py", f"get_target_position:={DETECTED}")
        try:
            detector.wait_for_line("detector ready")
            player = start("bag", "play", "--url", replay.url, str(tmp_path / "cam"), "-l")
            try:

                def detected():
                    got = http.post(f"{replay.url}/services/{DETECTED}", json={"get": True}, timeout=30)
                    if got.status_code != 200:
                        return None
                    pixel = (got.json()["x"], got.json()["y"])
                    return pixel if any(pixel) else None

                pixel = np.array(wait_for(detected, timeout=120))
            finally:
                output = stop(player)
        finally:
            detector.interrupt()
    assert np.linalg.norm(pixel - truth) <= TOLERANCE_PX, (pixel, truth)
    assert "not played" not in output  # the replay lab publishes none of them itself


@pytest.mark.parametrize("command", [("bag", "info"), ("bag", "play", "--url", "http://127.0.0.1:9"), ("play",)])
@pytest.mark.parametrize("make", [hostile_bags.bomb, hostile_bags.lz4_liar, hostile_bags.rosbag1_bomb])
def test_a_bomb_is_refused_with_its_reason_within_the_memory_bound(tmp_path, command, make):
    path = make(tmp_path / ("bomb.bag" if make is hostile_bags.rosbag1_bomb else "bomb.mcap"))
    done = subprocess.run(
        [sys.executable, "-c", hostile_bags.MEASURE, *command, str(path)],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert done.returncode == 1, done.stderr
    if command == ("play",) and make is hostile_bags.rosbag1_bomb:  # the 3D replay reads the lab's MCAP only
        assert "not an MCAP recording" in done.stderr, done.stderr
    else:
        assert "uncompressed" in done.stderr and "refused" in done.stderr, done.stderr
    rss = int(done.stderr.split("maxrss_kib")[1].split()[0]) * 1024
    assert rss < BASELINE_BYTES + bounded.MEMORY_BOUND_BYTES, f"{rss / 2**20:.0f} MiB"


BASELINE_BYTES = 384 << 20  # the command's own (Python, numpy, viser, uvicorn, rosbags) before reading


def _fixed_array(tmp_path: Path) -> Path:
    return hostile_bags.rosbag1_with_definition(tmp_path / "evil.bag", "evil/msg/Big", hostile_bags.FIXED_ARRAY)


@pytest.mark.parametrize(
    ("make", "command", "reason"),
    [
        (_fixed_array, ("bag", "convert"), "a fixed-size array of 100000000 items, over the cap of 65536"),
        (_fixed_array, ("bag", "play", "--url", "http://127.0.0.1:9"), "a fixed-size array of 100000000 items"),
        (lambda tmp: hostile_bags.billion_laughs(tmp / "laughs"), ("bag", "info"), "YAML aliases (*a0) are not read"),
        (lambda tmp: hostile_bags.sqlite_view(tmp / "view"), ("bag", "info"), "'messages' is a view, not a table"),
    ],
)
def test_a_hostile_definition_metadata_or_database_is_refused_within_the_memory_bound(tmp_path, make, command, reason):
    path = make(tmp_path)
    extra = [str(tmp_path / "out.bag")] if command == ("bag", "convert") else []
    done = subprocess.run(
        [sys.executable, "-c", hostile_bags.MEASURE, *command, str(path), *extra],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert done.returncode == 1, done.stderr
    assert reason in done.stderr, done.stderr
    rss = int(done.stderr.split("maxrss_kib")[1].split()[0]) * 1024
    assert rss < BASELINE_BYTES + bounded.MEMORY_BOUND_BYTES, f"{rss / 2**20:.0f} MiB"


def test_json_of_the_bag_info_names_the_storage(tmp_path):
    writer = bags.BagWriter(tmp_path / "b", max_bytes=1 << 20)
    writer.add_topic("/chatter", "std_msgs/String", None)
    writer.write("/chatter", 5, {"data": "x"})
    writer.close()
    info = json.loads(hri_lab("bag", "info", "--json", str(tmp_path / "b")).stdout)
    assert info["storage"] == "mcap"
    assert info["messages"] == 1
