"""`hri-lab grade-wall`: the reference wall followers (rclpy, rospy) pass; one that drives straight, one that spins
in place and one that follows the arena's wall fail, each with its reason and figures; a batch
writes every report (Gradescope's too) and the summary; a program runs jailed, reaches nothing but its own
trial (no port of the host, not the arena, the ground truth, the monitor or the lab's services) and is held
by one set of limits with all it starts. One batch (two at a time) serves every test but the silent one's."""

import json
import socket
import subprocess
import sys

import pytest

from sim.controllers.sandbox.cgroup import cgroup_kind

from tests.ros_running import PROGRAMS

FOLLOWERS = {
    "wall_follower_rclpy": "circuit: at ",
    "wall_follower_rospy": "circuit: at ",
    "drive_straight_rclpy": "collision: at ",
    "spin_in_place_rospy": "stall: at ",
    "arena_wall_follower_rclpy": "band: at ",
}


PROBES = ("jail_probe", "reach_probe", "limits_probe")  # hostile programs: each prints what it met, then ends


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """The followers and the probes graded in one batch, two trials at a time, while a server of the
    host's (a Dask scheduler, another lab) listens on its loopback: the reports' folder."""
    folder = tmp_path_factory.mktemp("grade-wall")  # the grader's working folder: where a recording would land
    out = folder / "reports"
    silent = folder / "silent.py"
    silent.write_text("print('I only print')\n")
    files = [str(PROGRAMS / f"{name}.py") for name in (*FOLLOWERS, *PROBES)] + [str(silent)]
    with socket.create_server(("127.0.0.1", 0)) as host_server:
        host_server.setblocking(False)
        done = subprocess.run(
            [sys.executable, "-m", "app.cli", "grade-wall", *files, "--trials", "1", "--jobs", "2", "--quiet"]
            + ["--out", str(out), "--format", "gradescope"],
            capture_output=True,
            text=True,
            timeout=900,
            cwd=folder,
        )
    assert done.returncode == 1, done.stdout + done.stderr  # some failed
    return out


def trial(out, name: str) -> dict:
    (item,) = json.loads((out / f"{name}.json").read_text())["items"]
    return item


def test_the_reference_passes_and_the_wrong_followers_fail_with_their_reasons(batch):
    out = batch
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0].startswith("subject,points")
    for name, reason in FOLLOWERS.items():
        report = json.loads((out / f"{name}.json").read_text())
        (item,) = report["items"]
        assert item["detail"].startswith(reason), item
        assert report["passed"] == name.startswith("wall_follower"), item
        assert "cylinder" in item["name"] or "box" in item["name"]  # the public seed's arena, described
        gradescope = json.loads((out / f"{name}.results.json").read_text())
        assert gradescope["score"] == report["points"]
        assert gradescope["tests"][0]["output"].endswith(item["detail"])
    straight = trial(out, "drive_straight_rclpy")["detail"]
    assert "touched the obstacle" in straight
    spin = trial(out, "spin_in_place_rospy")["detail"]
    assert "moved less than 0.05 m in 10 s" in spin
    band = trial(out, "arena_wall_follower_rclpy")["detail"]
    assert "outside the 0.20-0.70 m band for more than 20 s" in band


def test_a_graded_program_reaches_only_its_own_trial(batch):
    """Its network namespace holds nothing of the host's (the other trial's lab, the server listening
    beside the batch); the lab refuses it the arena, recording and driving over HTTP, and the ground
    truth, the monitor and the recording service over rosbridge, while the followers beside it drive."""
    detail = trial(batch, "reach_probe")["detail"]
    assert "host ports listed: 0; reached: 0" in detail, detail
    assert "arena: 403; start_recording: 401; drive: 401" in detail, detail
    assert "ground truth messages: 0; monitor messages: 0" in detail, detail
    assert "start_recording over rosbridge: refused: call_service /start_recording: the lab's own services" in detail
    assert not list(batch.parent.glob("**/*.mcap"))  # nothing recorded into the grader's folder


def test_a_graded_programs_limits_hold_it_and_all_it_starts_together(batch):
    """Three children of 700 MiB each and 300 processes: one cgroup per trial holds their sum (or, where
    the machine makes none, the report names the weaker limits it ran under)."""
    detail = trial(batch, "limits_probe")["detail"]
    kind, why = cgroup_kind()  # what this machine allows, as the grader found it
    if kind is None:
        assert f"[limits: per process only (no cgroup: {why})" in detail, detail
        return
    assert f"processes and threads, 1 CPU for the program and all it starts ({kind}, one group per trial)]" in detail
    assert "children holding 700 MiB at once: 0 of 3" in detail or "children holding 700 MiB at once: 1 of 3" in detail
    assert "memory cap: " in detail and "process(es) killed" in detail, detail
    started = int(detail.split("processes started: ")[1].split(" of ")[0])
    assert started < 128, detail
    assert "process cap: " in detail, detail


def test_a_program_runs_jailed(batch):
    detail = trial(batch, "jail_probe")["detail"]
    for attempt in ("host file", "checkout's tests", "own folder write", "tmp 100 MB"):
        assert f"{attempt}: denied" in detail, detail


def test_a_program_that_never_drives_is_reported(batch):
    detail = trial(batch, "silent")["detail"]
    assert detail.startswith("program: before its first /cmd_vel the program ended (exit status 0)")
    assert "I only print" in detail
