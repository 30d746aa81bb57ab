"""The experiment actions over HTTP against the real app: each goal runs its trials in a pool of
worker processes started afresh (spawn), so these run other programs and take a while; the live
robot is left alone meanwhile. (The actions' protocol, refusals and quick goals: tests/app/api/test_actions.py.)"""

import pytest

from sim.controllers.interface import LiftingParams
from sim.procedures.experiment import run_comparison
from sim.procedures.tables import format_comparison
from sim.procedures.trial import Setup

from tests.waiting import wait_sim, wait_terminal


def test_run_experiment_action_leaves_the_live_robot_alone(client, lab):
    client.post("/services/stop_cooperative_lifting")
    client.post("/services/reset_simulation")
    wait_sim(lab.snapshot, 0.2)
    q_before = lab.snapshot().q.copy()
    sim_before = lab.snapshot().time
    goal = {"trials": 1, "participant": "hasty", "seed": 3, "set": "alpha=0.9 k_t=0.2"}
    goal_id = client.post("/actions/run_experiment/goals", json=goal).json()["goal_id"]
    view = wait_terminal(client, "run_experiment", goal_id, timeout=120)
    assert view["status"] == "succeeded", view
    assert view["result"]["trials"] == 1
    assert "hasty" in view["result"]["table"]
    defaults = LiftingParams()
    assert view["result"]["table"].splitlines()[0] == (
        f"parameters: alpha = 0.9 (default {defaults.alpha:g}), k_t = 0.2 (default {defaults.k_t:g})"
    )
    assert view["feedback"][0]["trial"] == 1
    assert view["feedback"][0]["of"] == 1
    assert lab.snapshot().q == pytest.approx(q_before, abs=1e-6)
    assert lab.snapshot().time > sim_before + 0.5  # and the live loop kept running meanwhile


def test_compare_controllers_action_runs_the_same_trials_with_each_controller(client):
    """The action's figures are the headless comparison's (same participants, same seeds)."""
    # short trials: at the wider margin alpha 0.8 the hasty participant's box is dropped at ~3 s
    goal = {"controllers": "sp,patch", "trials": 1, "participants": "hasty", "seed": 3, "set": "alpha=0.8"}
    goal_id = client.post("/actions/compare_controllers/goals", json=goal).json()["goal_id"]
    view = wait_terminal(client, "compare_controllers", goal_id, timeout=180)
    assert view["status"] == "succeeded", view
    result = view["result"]
    assert result["controllers"] == ["sp", "patch"]
    assert result["trials"] == [1, 1]
    assert [(f["controller"], f["participant"], f["trial"], f["of"]) for f in view["feedback"]] == [
        ("sp", "hasty", 1, 2),
        ("patch", "hasty", 2, 2),
    ]
    direct = run_comparison(["sp", "patch"], 1, ["hasty"], seed=3, setup=Setup(params=LiftingParams(alpha=0.8)))
    assert result["successes"] == [int(direct[name]["hasty"][0].success) for name in ("sp", "patch")]
    assert [f["duration"] for f in view["feedback"]] == [direct[name]["hasty"][0].duration for name in ("sp", "patch")]
    assert result["table"] == format_comparison(direct, f"parameters: alpha = 0.8 (default {LiftingParams().alpha:g})")


def test_experiment_action_returns_figure_urls(client, lab, tmp_path):
    lab.figures_dir = tmp_path
    goal = client.post(
        "/actions/run_experiment/goals", json={"trials": 1, "participant": "hasty", "plots": True, "set": "alpha=0.8"}
    )  # the short trial: at the wider margin alpha 0.8 the hasty participant's box drops at ~3 s
    view = wait_terminal(client, "run_experiment", goal.json()["goal_id"], timeout=120)
    assert view["status"] == "succeeded"
    figures = view["result"]["figures"]
    run = goal.json()["goal_id"]
    assert figures == [f"/figures/{run}/summary.png", f"/figures/{run}/trial01_hasty_1.png"]
    for url in figures:
        png = client.get(url)
        assert png.status_code == 200
        assert png.headers["content-type"] == "image/png"
        assert png.content[:4] == b"\x89PNG"
    assert client.get(f"/figures/{run}/trial01_hasty_1.svg").headers["content-type"].startswith("image/svg+xml")
