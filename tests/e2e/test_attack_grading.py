"""The attack suite's graded files (docs/operations.md): `hri-lab grade` of a file that is the lab's
own controller, or that sleeps through its steps, ends with a report that says why (never a
silent PASS, never a grade that does not end)."""

import json
import subprocess
from pathlib import Path

from tests.lab_zygote import run_command

CONTROLLERS = Path(__file__).resolve().parents[1] / "controllers"


def grade(out: Path, *args: str) -> subprocess.CompletedProcess:
    return run_command("grade", *args, "--out", str(out), "--jobs", "2", "--quiet", timeout=900)


def test_the_labs_own_controller_and_a_copy_of_it_score_zero_saying_why(tmp_path):
    """The issue's three lines scored 130/130 PASS; a copy of sp.py's text run as the file's own too."""
    run = grade(tmp_path, str(CONTROLLERS / "reference_sp.py"), str(CONTROLLERS / "copies_reference.py"))
    assert run.returncode == 1, run.stdout + run.stderr
    for name, reach in (("reference_sp", "imports sim.controllers.sp"), ("copies_reference", "controllers/sp.py")):
        report = json.loads((tmp_path / f"{name}.json").read_text())
        assert report["points"] == 0
        assert report["passed"] is False
        assert report["items"] == []
        assert "is the lab's reference controller, not a submission" in report["error"]
        assert reach in report["error"]


def test_a_sleeper_is_stopped_with_the_wall_time_it_took_and_its_file_budget_ends_it(tmp_path):
    """Sleeping 2 s on 10 of every 250 steps: an item stops at its second sleep (2 s of grace plus
    its simulated time) with the wall time it took; once the file's items have slept 10 s in a
    worker, its later items there are not run. Every item scores 0 saying why; the grade ends."""
    run = grade(tmp_path, str(CONTROLLERS / "sleeper.py"))
    assert run.returncode == 1, run.stdout + run.stderr
    report = json.loads((tmp_path / "sleeper.json").read_text())
    assert report["points"] == 0
    assert report["items"]
    sleeps = ("(sleeping?)", "sleeps or blocks")  # the wall time it slept, or the count of its sleeps
    assert all(any(s in i["detail"] for s in sleeps) for i in report["items"] if i["max_points"]), report["items"]
    details = " ".join(i["detail"] for i in report["items"])
    assert "your step() took" in details
    assert "beyond the file's budget of 10 s" in details
