"""The grader: the reference passes with full marks, each broken controller loses what it should."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from sim.procedures.grading import PROBES, grade, probe_items
from sim.controllers.plugin import PluginError, PluginFactory

CONTROLLERS = Path(__file__).parent / "controllers"
REFERENCE = str(CONTROLLERS / "reference_sp.py")
BROKEN = str(CONTROLLERS / "broken.py")


def failed_probes(spec: str) -> dict[str, str]:
    return {i.name: i.detail for i in probe_items(PluginFactory(spec)) if i.points < i.max_points}


def test_reference_sp_plugin_gets_full_marks(tmp_path):
    out = tmp_path / "report.json"
    run = subprocess.run([sys.executable, "-m", "app.cli", "grade", REFERENCE, "--json", str(out), "--jobs", "2"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    report = json.loads(out.read_text())
    assert report["points"] == report["max_points"] == 95.0, run.stdout
    assert report["score"] == 100.0 and report["passed"] is True
    assert "score: 95/95 = 100.0 %" in run.stdout
    # the hasty trials are reported with 0 points, never counted against it
    assert any("hasty" in i["name"] and i["max_points"] == 0 for i in report["items"])


def test_template_runs_and_scores_low(tmp_path):
    template = tmp_path / "cooperative_lifting.py"
    template.write_text(subprocess.run([sys.executable, "-m", "app.cli", "template"], capture_output=True, text=True,
                                       check=True).stdout)
    report = grade(PluginFactory(str(template)), "template", jobs=2)
    assert report.score < 30 and not report.passed
    # it runs: no controller error anywhere, the robot just does not move
    assert not any("controller error" in i.detail for i in report.items)
    assert {i.name for i in report.items if i.points == i.max_points and i.max_points > 0} <= {
        "stopped: zero twist", "inside the band: hold still", "friction inside the cone: no tangential motion"}


def test_flipped_normal_loses_the_band_probes():
    failed = failed_probes(f"{BROKEN}:FlippedNormal")
    assert "below the band: press along +n" in failed and "expected along +n" in failed["below the band: press along +n"]
    assert "above the band: release along -n" in failed
    assert "a moment at the plate: comply" not in failed


def test_twist_left_in_the_ee_frame_loses_the_frame_probes():
    failed = failed_probes(f"{BROKEN}:EEFrameTwist")
    assert "below the band at a turned pose: +n in the base frame" in failed
    assert "(base frame)" in failed["below the band at a turned pose: +n in the base frame"]
    assert "the person lifts (friction beyond the cone): follow up" in failed


def test_no_tangential_following_loses_the_lift_probe_and_trials():
    report = grade(PluginFactory(f"{BROKEN}:NoTangential"), "no tangential", jobs=2)
    failed = {i.name: i.detail for i in report.items if i.points < i.max_points}
    assert "the person lifts (friction beyond the cone): follow up" in failed
    lost_trials = [d for n, d in failed.items() if n.startswith("trial")]
    assert len(lost_trials) >= 4 and all(d.startswith("dropped") for d in lost_trials)
    assert not report.passed


@pytest.mark.parametrize("name, reason", [
    ("Raising", "raised ZeroDivisionError: oops, a bug in step"),
    ("ReturnsNaN", "returned a non-finite twist"),
    ("TooSlow", "ms in one step"),
])
def test_faulty_controllers_lose_every_probe_with_the_reason(name, reason):
    items = probe_items(PluginFactory(f"{BROKEN}:{name}"))
    lost = [i for i in items if i.points == 0]
    assert len(lost) >= len(PROBES) - 1  # start/stop (inherited, correct) may still pass
    assert all(reason in i.detail for i in lost if i.name != "start and stop set the band [force, force + 5] and running")


def test_plugin_loading_errors(tmp_path):
    with pytest.raises(PluginError, match="no controller file"):
        PluginFactory(str(tmp_path / "missing.py"))()
    bad = tmp_path / "bad.py"
    bad.write_text("import does_not_exist\n")
    with pytest.raises(PluginError, match="importing .* failed: ModuleNotFoundError"):
        PluginFactory(str(bad))()
    with pytest.raises(PluginError, match="has no class Nope"):
        PluginFactory(f"{REFERENCE}:Nope")()
    run = subprocess.run([sys.executable, "-m", "app.cli", "grade", str(bad)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "importing" in run.stderr


def test_a_raising_plugin_in_the_live_server_stops_the_robot_not_the_server():
    import time

    import httpx

    from app.cli.launch import running_server

    with running_server("--view", "none", "--controller", f"{BROKEN}:Raising") as server:
        url = server.url
        assert httpx.post(f"{url}/services/start_cooperative_lifting", json={"force": 10}).status_code == 200
        time.sleep(0.3)
        error = httpx.get(f"{url}/topics/lifting_state").json()["error"]
        assert "controller error: Raising.step raised ZeroDivisionError: oops, a bug in step" in error
        assert "Traceback" in error and "broken.py" in error
        command = httpx.get(f"{url}/topics/cartesian_velocity_controller/command").json()
        assert all(v == 0.0 for v in command["linear"].values())
        assert httpx.get(f"{url}/health").json()["loop_alive"] is True
