"""The grader: the reference passes with full marks; each mutant loses exactly what tests its
mistake (or fails); the battery is drawn from the seed; reports in every format."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from sim.controllers.interface import LiftingParams
from sim.controllers.plugin import PluginError, PluginFactory
from sim.person.participants import PARTICIPANTS
from sim.procedures.experiment import plan
from sim.procedures.trial import Trial

from app.grading.battery import PROBE_PASS_MARK, new_report, trial_items
from app.grading.probe_stream import PROBES, Draw, graded, probe_items
from app.grading.report import Item, summary_csv
from tests.http_client import http
from tests.lab_zygote import run_command

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "controllers"))
import mutants
import template_filled

CONTROLLERS = Path(__file__).resolve().parents[1] / "controllers"
REFERENCE = str(CONTROLLERS / "reference_sp.py")
ALL_PROBES = {name for name, _ in PROBES}
CONE = {
    "beyond the cone: follow against f_t",
    "beyond the cone: raise the grip toward f_n_max",
    "inside the cone margin: no tangential motion",
    "between the margin alpha mu f_n and the cone mu f_n: follow",
}
MOMENTS = {"a moment in the plate's plane: comply", "a moment about the plate's normal: comply"}


def failed(factory, seed: int = 0) -> dict[str, str]:
    return {i.name: i.detail for i in probe_items(factory, seed) if i.points < i.max_points}


def test_reference_sp_plugin_gets_full_marks(tmp_path):
    """The one full battery: sandboxed, every format, exit 0 only with the report written. The file
    is the lab's own SP (not a submission: 0 by default, tests/e2e/test_attack_grading.py), graded
    here with --reference flag: its items as any file's, and one more, not counted, flagging it."""
    out = tmp_path / "reports"
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "app.cli",
            "grade",
            REFERENCE,
            "--out",
            str(out),
            "--format",
            "gradescope",
            "--jobs",
            "2",
            "--quiet",
            "--reference",
            "flag",
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    report = json.loads((out / "reference_sp.json").read_text())
    flag = report["items"].pop(0)  # first: what an instructor reads first
    assert flag["max_points"] == 0
    assert "FLAGGED" in flag["detail"]
    assert "imports sim.controllers.sp" in flag["detail"]
    # 13 probes x 5 + 9 trials x 5 (all three participants count) + 2 robustness x 10 = 130, every
    # trial carried AND its stream within the SP law (app/grading/law_checks.py)
    assert report["points"] == report["max_points"] == 130.0, (out / "reference_sp.txt").read_text()
    assert "not SP" not in (out / "reference_sp.txt").read_text()
    assert report["passed"] is True
    # the hasty trials count (at the default margin the reference SP carries them) and are carried
    hasty = [i for i in report["items"] if "hasty" in i["name"]]
    assert len(hasty) == 3
    assert all(i["max_points"] == i["points"] == 5.0 and i["mark"] == "ok" for i in hasty)
    assert (out / "reference_sp.txt").read_text().count("not counted") == 1  # the flag alone
    results = json.loads(run.stdout)
    assert results == json.loads((out / "results.json").read_text())
    assert results["score"] == 130.0
    assert len(results["tests"]) == len(report["items"]) + 1 == 13 + 9 + 2 + 1
    assert set(results["tests"][0]) == {"name", "score", "max_score", "output"}
    assert (out / "summary.csv").read_text().splitlines()[1].startswith(f"{REFERENCE},130,130,100.0,yes")


@pytest.mark.parametrize(
    ("cls", "lost"),
    [
        (mutants.EEFrame, {"below the band: press along +n", "below the band at another pose: +n in the base frame"}),
        (
            mutants.TangentialFlipped,
            {"beyond the cone: follow against f_t", "between the margin alpha mu f_n and the cone mu f_n: follow"},
        ),
        (mutants.NoGripRaise, {"beyond the cone: raise the grip toward f_n_max"}),
        (
            mutants.BandTooWide,
            {"start and stop set the band [force, force + 5] and running", "the band's upper end is f_n_min + 5 N"},
        ),
        (mutants.StartStopNoBand, {"start and stop set the band [force, force + 5] and running"}),
        (mutants.MomentsHeld, MOMENTS),
    ],
)
def test_each_mutant_loses_the_probes_of_its_mistake(cls, lost):
    lost_now = failed(cls)
    if cls is mutants.EEFrame:  # every probe that moves is in the wrong frame: it falls below the mark
        assert lost <= set(lost_now)
        assert "(base frame)" in lost_now["below the band: press along +n"]
        assert len(lost_now) > len(PROBES) * (1 - PROBE_PASS_MARK / 100)
    elif cls is mutants.BandTooWide:
        assert lost <= set(lost_now) <= lost | {"above the band: release along -n"}
    elif cls is mutants.StartStopNoBand:
        # the probe stream starts lifting with the controller's own start(), as a trial does: its band
        # stays [0, 5] N, and a friction probe drawn at f_n below contact (1 N) sees no follow
        assert (
            lost
            <= set(lost_now)
            <= lost
            | {"beyond the cone: follow against f_t", "between the margin alpha mu f_n and the cone mu f_n: follow"}
        )
    else:
        assert set(lost_now) == lost, lost_now


def test_admittance_follower_and_do_nothing_controllers_fail():
    for cls in (mutants.Admittance, mutants.ZeroTwist):
        report = new_report(cls.__name__, 0)
        report.items = probe_items(cls)
        lost = {i.name for i in report.items if i.points == 0}
        assert report.score_of("probe") < PROBE_PASS_MARK and not report.passed, lost
    assert {"inside the cone margin: no tangential motion", "inside the band: hold still"} | MOMENTS <= {
        i.name for i in probe_items(mutants.Admittance) if i.points == 0
    }


def test_the_untouched_template_fails(tmp_path):
    template = tmp_path / "cooperative_lifting.py"
    template.write_text(
        subprocess.run([sys.executable, "-m", "app.cli", "template"], capture_output=True, text=True, check=True).stdout
    )
    import importlib.util

    spec = importlib.util.spec_from_file_location("template_as_written", template)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    items = probe_items(module.CooperativeLifting)  # in-process here (the sandbox has tests of its own)
    assert not any("error" in i.detail for i in items)  # it runs: the robot just does not move
    assert {i.name for i in items if i.points == i.max_points} <= {
        "stopped: zero twist",
        "inside the band: hold still",
        "inside the cone margin: no tangential motion",
    }


def test_the_flipped_tangential_sign_loses_the_box():
    """Moving with f_t pushes the friction further out of the cone: at alpha 0.8 the box is
    dropped once the person lets go; at the default margin (0.5) the robot already moves with the
    friction during the approach, while the person still grasps the box (11 N of friction at 18 N
    at 1 s), slides the plate off the box (no contact at 2 s) and never gets a grip (both measured
    with this seed)."""
    result = Trial(PARTICIPANTS["average"], 3, mutants.TangentialFlipped(), params=LiftingParams(alpha=0.8)).run()
    assert not result.success
    assert result.reason.startswith("dropped")
    result = Trial(PARTICIPANTS["average"], 3, mutants.TangentialFlipped()).run()
    assert not result.success
    assert result.reason.startswith("no grip")


def test_probe_values_come_from_the_seed():
    assert [Draw(7, i).unit_in_plane().tolist() for i in range(3)] == [
        Draw(7, i).unit_in_plane().tolist() for i in range(3)
    ]
    assert Draw(7, 0).force != Draw(8, 0).force
    assert probe_items(mutants.NoGripRaise, seed=12345) == probe_items(mutants.NoGripRaise, seed=12345)


def test_not_counted_items_and_the_summary():
    report = new_report("a.py", 0)
    report.items = [Item("experiment", "trial 7: hasty #1", 0.0, 0.0, "dropped"), Item("probe", "p", 5.0, 5.0)]
    assert "trial 7: hasty #1 — not counted: dropped" in report.text()
    broken = new_report("b.py", 0)
    broken.error = "importing b.py failed: SyntaxError"
    assert summary_csv([report, broken]).splitlines() == [
        "subject,points,max_points,score,passed,error,seed,public_seed",
        "a.py,5,5,100.0,yes,,0,yes",
        "b.py,0,130,0.0,no,importing b.py failed: SyntaxError,0,yes",  # 0 of the full points, not 0/0
    ]


NO_HANDLERS = """
from sim.controllers.sp import SPController


class CooperativeLifting:  # the SP law, and no start()/stop() of its own
    def __init__(self):
        self.sp = SPController()

    def reset(self):
        self.sp.reset()

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return self.sp.step(wrench_ee, transform_ee_to_base, params, dt)
"""


def test_a_file_without_start_and_stop_scores_no_more_than_the_templates_todo_ones(tmp_path):
    """The lab's own handlers stand in for missing ones in the live lab (the robot lifts there), but
    a grade asks for the student's: a file without them is graded as one whose start()/stop() do
    nothing, as the template's TODO ones (the same items lost, a trial never started)."""
    path = tmp_path / "no_handlers.py"
    path.write_text(NO_HANDLERS)
    lost = failed(PluginFactory(str(path)))
    assert "no start() and no stop()" in lost["start and stop set the band [force, force + 5] and running"]
    todo = tmp_path / "todo.py"
    todo.write_text(
        NO_HANDLERS
        + "\n    def start(self, params, force):\n        return 'TODO'\n\n    def stop(self, params):\n        return 'TODO'\n"
    )
    assert set(lost) == set(failed(PluginFactory(str(todo))))
    assert len(lost) > 1
    (index, person, attempt, seed), *_ = plan(1, seed=0)
    (trial,) = trial_items(index, person, attempt, seed, graded(PluginFactory(str(path))))
    assert trial.points == 0 and trial.detail.startswith("no grip"), trial.detail
    live = PluginFactory(str(path))()  # the live lab: the lab's handlers stand in
    try:
        params = LiftingParams()
        live.start(params, 10.0)
        assert params.running
        assert params.f_n_min == 10.0
    finally:
        live.close()


RAISES = """
import numpy as np


def helper(x):
    return x / 0.0 if x > 1e9 else 1 // int(x * 0)


class CooperativeLifting:
    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.zeros(6) * helper(float(wrench_ee[2]))
"""


def test_a_crash_shows_the_students_frames_once_with_the_items_it_cost(tmp_path):
    path = tmp_path / "raises.py"
    path.write_text(RAISES)
    report = new_report(str(path), 0, ("probe",))
    report.items = probe_items(PluginFactory(str(path)))
    text = report.text()
    assert text.count("Traceback (most recent call last)") == 1, text
    trace = text[text.index("Traceback") :]
    assert f'File "{path}", line 14, in step' in trace
    assert f'File "{path}", line 6, in helper' in trace
    assert "ZeroDivisionError: integer division or modulo by zero" in trace
    assert "sandbox" not in trace
    assert "child.py" not in trace
    assert "sim/" not in trace
    cost = [line for line in text.splitlines() if line.startswith("A fault cost")]
    assert len(cost) == 1 and "12 item(s)" in cost[0], cost  # every probe that steps it (start/stop do not)


def test_plugin_loading_errors(tmp_path):
    with pytest.raises(PluginError, match="no controller file"):
        PluginFactory(str(tmp_path / "missing.py"))()
    bad = tmp_path / "bad.py"
    bad.write_text("import does_not_exist\n")
    with pytest.raises(PluginError, match=r"importing .* failed: ModuleNotFoundError"):
        PluginFactory(str(bad))()
    with pytest.raises(PluginError, match="has no class Nope"):
        PluginFactory(f"{REFERENCE}:Nope")()


def test_a_batch_reports_every_file_even_those_that_cannot_load(tmp_path):
    folder = tmp_path / "submissions"
    folder.mkdir()
    (folder / "exits.py").write_text((CONTROLLERS / "exits_at_import.py").read_text())
    (folder / "syntax.py").write_text("class CooperativeLifting(:\n")
    out = tmp_path / "reports"
    run = run_command("grade", str(folder), "--out", str(out), "--quiet", timeout=300)
    assert run.returncode == 1, run.stderr
    assert "failed: SystemExit: 0" in (out / "exits.txt").read_text()
    assert "SyntaxError" in json.loads((out / "syntax.json").read_text())["error"]
    assert len((out / "summary.csv").read_text().splitlines()) == 3


def test_a_raising_plugin_in_the_live_server_stops_the_robot_not_the_server():
    import time

    from tests.e2e.serving import running_server

    with running_server("--view", "none", "--controller", f"{CONTROLLERS / 'broken.py'}:Raising") as server:
        url = server.url
        assert http.post(f"{url}/services/start_cooperative_lifting", json={"force": 10}, timeout=30).status_code == 200
        deadline = time.monotonic() + 30
        while not (error := http.get(f"{url}/topics/lifting_state").json()["error"]) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert "controller error: Raising.step raised ZeroDivisionError: oops, a bug in step" in error
        assert "Traceback" in error
        assert "broken.py" in error
        command = http.get(f"{url}/topics/cartesian_velocity_controller/command").json()
        assert all(v == 0.0 for v in command["linear"].values())
        assert http.get(f"{url}/health").json()["loop_alive"] is True


def test_the_template_filled_in_as_its_hints_say_passes():
    """Issue 3b: tests/controllers/template_filled.py is the template with every TODO done from its
    hints and the README (step 0's low-pass included). Its probes all pass and its twist is the
    built-in SP's to the last bits, so its trials are the reference's (full marks, above): a
    trial of each with the same seed ends the same way."""
    assert failed(template_filled.CooperativeLifting) == {}
    filled = Trial(PARTICIPANTS["average"], 4, template_filled.CooperativeLifting()).run()
    reference = Trial(PARTICIPANTS["average"], 4).run()
    assert filled.success
    assert reference.success
    assert filled.steps == reference.steps
    assert (filled.duration, filled.f_n_min, filled.f_n_max, filled.slip) == pytest.approx(
        (reference.duration, reference.f_n_min, reference.f_n_max, reference.slip), rel=1e-6
    )
