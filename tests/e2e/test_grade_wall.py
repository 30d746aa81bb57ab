"""`hri-lab grade-wall`: the reference wall followers (rclpy, rospy) pass; one that drives straight, one that spins
in place and one that follows the arena's wall fail, each with its reason and figures; a batch
writes every report (Gradescope's too) and the summary; a program runs jailed."""

import json
import subprocess
import sys

from tests.ros_running import PROGRAMS

FOLLOWERS = {
    "wall_follower_rclpy": "circuit: at ",
    "wall_follower_rospy": "circuit: at ",
    "drive_straight_rclpy": "collision: at ",
    "spin_in_place_rospy": "stall: at ",
    "arena_wall_follower_rclpy": "band: at ",
}


def test_the_reference_passes_and_the_wrong_followers_fail_with_their_reasons(tmp_path):
    out = tmp_path / "reports"
    files = [str(PROGRAMS / f"{name}.py") for name in FOLLOWERS]
    done = subprocess.run(
        [sys.executable, "-m", "app.cli", "grade-wall", *files, "--trials", "1", "--jobs", "2", "--quiet"]
        + ["--out", str(out), "--format", "gradescope"],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 1, done.stdout + done.stderr  # some failed
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0].startswith("subject,points")
    for name, reason in FOLLOWERS.items():
        report = json.loads((out / f"{name}.json").read_text())
        (item,) = report["items"]
        assert item["detail"].startswith(reason), item
        assert report["passed"] == name.startswith("wall_follower"), item
        assert "cylinder" in item["name"] or "box" in item["name"]
        gradescope = json.loads((out / f"{name}.results.json").read_text())
        assert gradescope["score"] == report["points"]
        assert gradescope["tests"][0]["output"].endswith(item["detail"])
    straight = json.loads((out / "drive_straight_rclpy.json").read_text())["items"][0]["detail"]
    assert "touched the obstacle" in straight
    spin = json.loads((out / "spin_in_place_rospy.json").read_text())["items"][0]["detail"]
    assert "moved less than 0.05 m in 10 s" in spin
    band = json.loads((out / "arena_wall_follower_rclpy.json").read_text())["items"][0]["detail"]
    assert "outside the 0.20-0.70 m band for more than 20 s" in band


def test_a_program_that_never_drives_is_reported(tmp_path):
    silent = tmp_path / "silent.py"
    silent.write_text("print('I only print')\n")
    done = subprocess.run(
        [sys.executable, "-m", "app.cli", "grade-wall", str(silent), "--trials", "1", "--jobs", "1", "--quiet"]
        + ["--format", "json"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    (item,) = json.loads(done.stdout)["items"]
    assert item["detail"].startswith("program: before its first /cmd_vel the program ended (exit status 0)")
    assert "I only print" in item["detail"]


def test_a_program_runs_jailed(tmp_path):
    out = tmp_path / "reports"
    done = subprocess.run(
        [sys.executable, "-m", "app.cli", "grade-wall", str(PROGRAMS / "jail_probe.py"), "--trials", "1", "--quiet"]
        + ["--out", str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    (item,) = json.loads((out / "jail_probe.json").read_text())["items"]
    for attempt in ("host file", "checkout's tests", "own folder write", "tmp 100 MB"):
        assert f"{attempt}: denied" in item["detail"], item["detail"]
