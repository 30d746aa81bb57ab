import ctypes
import os
import signal
import sys
import time
from multiprocessing import resource_tracker
from pathlib import Path

import pytest

PR_SET_CHILD_SUBREAPER = 36


def _children() -> list[int]:
    """Live child processes of this test run (orphans of its descendants come back to it), but
    this run's own multiprocessing resource tracker (it lives as long as the run)."""
    from multiprocessing import resource_tracker

    own = {getattr(resource_tracker._resource_tracker, "_pid", None)}
    pids = []
    for tid in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{tid}/children") as handle:
                pids += [int(p) for p in handle.read().split() if int(p) not in own]
        except OSError:
            pass
    return pids


def _reap() -> None:
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def _describe(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as handle:
            return f"{pid}: " + handle.read().replace(b"\0", b" ").decode(errors="replace")[:120]
    except OSError:
        return f"{pid}: (gone)"


TREE_OUTPUTS = [Path(__file__).resolve().parent.parent / name for name in ("recordings", "figures")]


def _tree_outputs() -> set[Path]:
    return {f for folder in TREE_OUTPUTS if folder.is_dir() for f in folder.iterdir()}


TESTS = Path(__file__).resolve().parent

# `make test` runs three workers and hands out whole files in collection order (--dist loadfile
# --no-loadscope-reorder): the longest files go first (as measured: `-p bench.suite_time`, tests/README.md), so that
# the run never ends with one worker still on a long file while the others have nothing left
# (longest processing time first). Paths from tests/. The wall trials go first of all: two minutes of
# trials in real time that need little CPU, run beside the heavy files so that both cores stay busy
# (where their length put them, the run's middle left a third of the cores idle: 2026-12-07, 454 s -> 424 s).
LONG_FILES_FIRST = (
    "e2e/test_grade_wall.py",
    "e2e/test_gradescope.py",
    "e2e/test_docs_student_pages.py",
    "e2e/browser/test_page.py",
    "e2e/browser/test_jupyterhub.py",
    "e2e/test_docs_instructor_pages.py",
    "e2e/test_ros_programs.py",
    "e2e/test_ros1_oracle.py",
    "e2e/test_bags.py",
    "e2e/test_autograder.py",
    "e2e/test_grading.py",
    "e2e/test_course_scale.py",
    "e2e/test_camera.py",
    "e2e/test_cli_server.py",
    "e2e/test_rclpy_programs.py",
    "e2e/test_lifting_node.py",
    "e2e/test_attack_grading.py",
    "e2e/test_tf_programs.py",
    "e2e/test_mobile_world.py",
    "e2e/browser/test_mobile_page.py",  # a wall-following circuit in real time (23 s of trial)
    "e2e/test_law_checks.py",
    "e2e/test_sandbox.py",
    "e2e/test_rosbridge_roslibpy.py",
    "e2e/test_fuzz.py",
    "e2e/test_limits.py",
    "e2e/browser/test_urdf_view_page.py",
    "e2e/test_experiment_actions.py",
    "e2e/test_examples.py",
    "e2e/browser/test_replay.py",
    "app/api/test_actions.py",
)
# ... and this one last of all: a rospy program's lifting law in real time (F_ext at 1 kHz into its
# callback, ~half a core), which drops the box when starved; mid-run, beside the browsers, the labs and
# two busy loops, it was (2 of 4 fresh runs, 2026-12-07); at the end the other workers run short files
LAST_FILES = ("e2e/test_ros_lifting_node.py",)


# Markers by folder (`make test-fast` runs neither; tests/README.md): `e2e`, the files under tests/e2e/
# (and tests/exercises/, the instructors' suite) that run other programs: real servers, nodes, students'
# programs, sandboxed controllers, the CLI; `browser`, the files under tests/e2e/browser/ that drive Chromium.
E2E_FOLDERS = ("e2e", "exercises")
BROWSER_FOLDER = ("e2e", "browser")


def pytest_collection_modifyitems(items) -> None:
    rank = {name: i for i, name in enumerate(LONG_FILES_FIRST)} | {
        name: len(LONG_FILES_FIRST) + 1 for name in LAST_FILES
    }

    def where(item) -> str:
        return item.path.resolve().relative_to(TESTS).as_posix()

    items.sort(key=lambda item: rank.get(where(item), len(LONG_FILES_FIRST)))  # stable: each file's order stays
    for item in items:
        parts = item.path.resolve().relative_to(TESTS).parts
        if parts[0] in E2E_FOLDERS:
            item.add_marker(pytest.mark.e2e)
        if parts[:2] == BROWSER_FOLDER:
            item.add_marker(pytest.mark.browser)


@pytest.fixture(scope="session", autouse=True)
def no_file_left_in_the_tree():
    """Fails the run when a test writes a recording or a figure into the working tree's default
    output folders (`make run` writes there; tests use temporary folders)."""
    before = _tree_outputs()
    yield
    added = sorted(str(f) for f in _tree_outputs() - before)
    if added:
        pytest.fail("files left in the working tree by the tests:\n" + "\n".join(added[:10]))


@pytest.fixture(scope="session", autouse=True)
def ros_logs_in_a_temporary_folder(tmp_path_factory):
    """The launches' logs (rosclient/launch.py's log_dir: ~/.ros/log by default, as ROS keeps them)
    below this run's temporary folder, for every program the tests start."""
    os.environ["ROS_LOG_DIR"] = str(tmp_path_factory.mktemp("ros_log"))


@pytest.fixture(scope="session", autouse=True)
def no_process_left_behind():
    """Fails the run when a test leaves a process behind. This run is made the subreaper of its
    descendants, so a worker orphaned by its parent comes back to it and is seen here."""
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    yield
    if "tests.lab_zygote" in sys.modules:  # the labs' zygote, if this process started one (tests/e2e/serving.py)
        sys.modules["tests.lab_zygote"].close()
    deadline = time.monotonic() + 15.0  # processes told to stop may take a moment
    own_tracker = resource_tracker._resource_tracker._pid  # this run's own helper (ends with it), if started
    while True:
        _reap()
        left = [pid for pid in _children() if pid != own_tracker]
        if not left or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    if left:
        described = [_describe(pid) for pid in left]
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        _reap()
        pytest.fail("processes left behind by the tests:\n" + "\n".join(described))


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    """The real app with its live 1 kHz loop, driven over HTTP (httpx via the TestClient); its
    recordings and figures go to a temporary folder, never into the working tree."""
    from fastapi.testclient import TestClient

    from app.serving.compose import create_app

    with TestClient(create_app()) as c:
        output = tmp_path_factory.mktemp("lab")
        c.app.state.lab.recordings_dir, c.app.state.lab.figures_dir = output / "recordings", output / "figures"
        yield c


@pytest.fixture
def lab(client):
    return client.app.state.lab
