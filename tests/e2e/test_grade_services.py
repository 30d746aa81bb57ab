"""`hri-lab grade-services`: a lab started with --exercises, the student's node from the services
template (tests/nodes/services_solution.py, right and with mistakes), graded over HTTP with the
controller grader's report formats. (The lab's own answers, the reference: tests/exercises.)"""

import json
import os

import pytest

from app.grading.services import grade_services
from tests.e2e.serving import served_lab
from tests.lab_zygote import run_command
from tests.waiting import start_node, stop_node

TORQUES = "/compute_torques: tau = J(q)^T F of the Panda at the lab's q (Exercise 8)"


lab = served_lab("--exercises")  # the lab with its exercise services


def grade(lab, *args, seed="5"):
    env = {k: v for k, v in os.environ.items() if k not in ("HRI_LAB_URL", "HRI_LAB_GRADE_SEED")}
    return run_command("grade-services", "--url", lab.url, "--seed", seed, *args, timeout=120, env=env)


def test_the_solution_node_passes_with_full_marks_in_every_format(lab, tmp_path):
    node = start_node(lab, "services_solution.py")
    try:
        result = grade(lab, "--format", "gradescope", "--out", str(tmp_path))
    finally:
        stop_node(node)
    assert result.returncode == 0, result.stdout + result.stderr
    gradescope = json.loads(result.stdout)
    assert gradescope["score"] == 15
    assert len(gradescope["tests"]) == 10
    assert all(t["score"] == t["max_score"] > 0 for t in gradescope["tests"])
    assert {p.name for p in tmp_path.iterdir()} == {"services.txt", "services.json", "results.json", "summary.csv"}
    assert "PASS" in (tmp_path / "services.txt").read_text()
    assert "    ok  /compute_wrench" in result.stderr  # progress, one line per item


@pytest.mark.parametrize("mistake", ["--wrong-torques", "--torques-as-force"])
def test_wrong_torques_lose_exactly_the_torque_item(lab, mistake):
    node = start_node(lab, "services_solution.py", mistake)
    try:
        report = grade_services(lab.url, seed=5)
    finally:
        stop_node(node)
    failed = {item.name: item.detail for item in report.items if item.points < item.max_points}
    assert set(failed) == {TORQUES}, failed
    assert "expected" in failed[TORQUES]  # the case and the independent answer


def test_the_untouched_template_fails_and_the_seed_draws_the_cases(lab):
    node = start_node(lab, "../../app/cli/templates/services_node.py")
    try:
        first, again, other = (grade_services(lab.url, seed) for seed in (5, 5, 6))
    finally:
        stop_node(node)
    assert first.passed is False
    assert first.points == 1
    assert first.json() == again.json()  # the same seed, the same report
    details = [{i.name: i.detail for i in r.items}[TORQUES] for r in (first, other)]
    assert details[0] != details[1]  # another seed, other wrenches


def test_no_node_every_exercise_is_not_provided(lab):
    result = grade(lab)
    assert result.returncode == 1
    assert result.stdout.count("not provided yet") == 10
    assert "score: 0/15" in result.stdout


def test_a_lab_that_cannot_be_reached_is_said_so():
    result = run_command("grade-services", "--url", "http://127.0.0.1:9", timeout=60)
    assert result.returncode == 2
    assert "cannot reach the lab at http://127.0.0.1:9" in result.stderr


STOP = "/stop_cooperative_lifting: f_n_min = 0, stopped (Exercises 11-14)"
STOP_NODE = """import sys

from app.cli.templates import services_node as node

MESSAGE = sys.argv.pop()  # the last argument: the stop message


def stop(request, response):
    response["message"] = MESSAGE
    return True


node.main({"/stop_cooperative_lifting": ("hri_lab/StopCooperativeLifting", stop)})
"""


@pytest.mark.parametrize(
    ("message", "passes"),
    [
        ("Cooperative Lifting was stopped! The force limit was set back to 12.5 N", True),  # the handout's own
        ("Cooperative Lifting stopped.", True),
        ("Stop.", True),
        ("Cooperative Lifting ended.", False),
        ("TODO", False),
    ],
)
def test_stop_is_judged_by_the_labs_state_and_the_messages_sense(lab, tmp_path, message, passes):
    """The lab applies a node's stop (not started, f_n_min 0); the message must say it stopped and
    need state no number (the handout's own stop states the force limit it set back)."""
    script = tmp_path / "stop_node.py"
    script.write_text(STOP_NODE)
    node = start_node(lab, str(script), message)
    try:
        report = grade_services(lab.url, seed=5)
    finally:
        stop_node(node)
    item = next(i for i in report.items if i.name == STOP)
    assert (item.points == item.max_points) is passes, item.detail
    if not passes:
        assert item.detail == f"message {message!r} does not say that lifting stopped"
