"""app/cli/bag.py without a lab: `bag info` (text and JSON) and `bag convert` of a recording made
here, and what each refuses before reaching a lab or writing a file (record, play and the ROS
graph's bag record/play against a lab: tests/e2e/test_bags.py, tests/e2e/test_recording.py)."""

import json

import pytest

from sim.recording.writer import Recording
from sim.world import World

from app.cli.main import main


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """0.05 s of the lab's topics and scene (the lab's recorder's MCAP)."""
    path = tmp_path_factory.mktemp("bag") / "lab.mcap"
    world = World()
    with Recording(path, world.config, model=world.model) as rec:
        for _ in range(51):
            rec.add(world.snapshot())
            world.step()
    return path


def test_bag_info_prints_ros2_bag_infos_layout_or_json(recording, capsys):
    assert main(["bag", "info", str(recording)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("Files:             lab.mcap\n")
    assert "Duration:          0.050s" in text  # the topics at 0, 10, ..., 50 ms
    assert main(["bag", "info", "--json", str(recording)]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["complete"]
    assert info["duration"] == pytest.approx(0.05)
    assert {t["name"]: t["count"] for t in info["topics"]}["/joint_states"] == 6


def test_bag_info_of_what_is_not_a_bag_says_why(tmp_path, capsys):
    (tmp_path / "notes.mcap").write_text("hello")
    assert main(["bag", "info", str(tmp_path / "notes.mcap")]) == 1
    assert "not an MCAP recording (a text file;" in capsys.readouterr().err


def test_bag_convert_writes_a_ros1_bag_and_refuses_another_name(recording, tmp_path, capsys):
    assert main(["bag", "convert", str(recording), str(tmp_path / "out.mcap")]) == 1
    assert "a ROS 1 bag's name ends in .bag" in capsys.readouterr().err
    assert not (tmp_path / "out.mcap").exists()
    assert main(["bag", "convert", str(recording), str(tmp_path / "out.bag")]) == 0
    assert capsys.readouterr().out.strip() == str(tmp_path / "out.bag")
    assert main(["bag", "info", "--json", str(tmp_path / "out.bag")]) == 0
    converted = json.loads(capsys.readouterr().out)
    assert converted["storage"] == "rosbag1"
    assert {t["name"]: t["count"] for t in converted["topics"]}["/joint_states"] == 6


def test_record_refuses_to_overwrite_before_reaching_the_lab(recording, capsys):
    url = "http://127.0.0.1:9"  # never asked: the refusal comes first
    assert main(["record", "--url", url, "-o", str(recording)]) == 1
    assert f"{recording} exists: choose another name with -o" in capsys.readouterr().err


def test_play_of_what_is_not_a_recording_says_why(tmp_path, capsys):
    assert main(["play", str(tmp_path / "missing.mcap")]) == 1
    assert "no such file" in capsys.readouterr().err
