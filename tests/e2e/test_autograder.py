"""The Gradescope bundle (app/cli/autograder.py): unzipped into a folder laid out like
Gradescope's /autograder, its run_autograder (with this checkout's Python) grades failing
submissions and writes a results.json in Gradescope's format; where bubblewrap cannot run, it
grades with the child-process limits and says so. A passing submission (the lab's SP, flagged)
is graded through the bundle's own install: tests/e2e/test_gradescope.py."""

import json
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from tests.lab_zygote import run_command

CONTROLLERS = Path(__file__).resolve().parents[1] / "controllers"
VISIBILITY = {"hidden", "after_due_date", "after_published", "visible"}


def build_bundle(out: Path, *args: str) -> Path:
    run = run_command("autograder", "-o", str(out), "--seed", "5", *args, timeout=120)
    assert run.returncode == 0, run.stderr
    return out


@pytest.fixture(scope="module")
def bundle(tmp_path_factory) -> Path:
    """The course flags a file built on the lab's own SP (--reference flag)."""
    return build_bundle(tmp_path_factory.mktemp("bundle") / "autograder.zip", "--hide-until-due", "--reference", "flag")


def gradescope(
    tmp_path: Path, bundle: Path, submission: str, env: dict | None = None, files: dict[str, str] | None = None
) -> dict:
    """/autograder as Gradescope lays it out (source, run_autograder, submission/), then run_autograder."""
    root = tmp_path / "autograder"
    with zipfile.ZipFile(bundle) as z:
        z.extractall(root / "source")
    shutil.copy(root / "source" / "run_autograder", root / "run_autograder")
    (root / "submission").mkdir()
    (root / "submission" / "cooperative_lifting.py").write_text(submission)
    for name, text in (files or {}).items():
        (root / "submission" / name).write_text(text)
    run = subprocess.run(
        [shutil.which("bash") or "/bin/bash", str(root / "run_autograder")],
        capture_output=True,
        text=True,
        timeout=900,
        env={**os.environ, "HRI_LAB_GRADESCOPE_ROOT": str(root), "HRI_LAB_PYTHON": sys.executable, **(env or {})},
    )
    assert run.returncode == 0, run.stdout + run.stderr
    return json.loads((root / "results" / "results.json").read_text())


def valid(results: dict) -> None:
    """Gradescope's results.json: a score, tests with name, score, max_score, output, visibility."""
    assert isinstance(results["score"], float)
    assert isinstance(results["output"], str)
    for test in results["tests"]:
        assert set(test) == {"name", "score", "max_score", "output", "visibility"}
        assert isinstance(test["name"], str)
        assert test["visibility"] in VISIBILITY
        assert 0 <= test["score"] <= test["max_score"]
    assert results["score"] == sum(t["score"] for t in results["tests"])


def test_the_bundle_holds_what_gradescope_runs(bundle):
    with zipfile.ZipFile(bundle) as z:
        names = set(z.namelist())
        config = json.loads(z.read("hri-lab-autograder.json"))
        setup = z.read("setup.sh").decode()
        assert z.getinfo("run_autograder").external_attr >> 16 & 0o111
    assert {"setup.sh", "run_autograder", "hri-lab/pyproject.toml", "hri-lab/app/grading/battery.py"} <= names
    assert config["seed"] == 5
    assert config["hide_until_due"] is True
    assert "bubblewrap" in setup
    assert '/uv" pip install --quiet --compile-bytecode' in setup  # uv installs the lab
    assert '--editable "$ROOT/source/hri-lab"' in setup
    snippets = re.findall(r'python"? -c "([^"]+)"', setup)
    assert snippets == ["from sim.warm_up import warm_up; warm_up()"]
    for snippet in snippets:  # what setup.sh runs in the lab's Python
        done = subprocess.run([sys.executable, "-c", snippet], capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, (snippet, done.stderr[-2000:])


def test_the_labs_own_controller_scores_zero_by_default(tmp_path):
    """The issue's three lines (`class CooperativeLifting(SPController): pass`) scored 130/130 PASS;
    a course's bundle without --reference gives 0 of the full points, saying why, and grades nothing."""
    plain = build_bundle(tmp_path / "plain.zip")
    results = gradescope(tmp_path, plain, (CONTROLLERS / "reference_sp.py").read_text())
    valid(results)
    assert results["score"] == 0.0
    assert [(t["name"], t["score"], t["max_score"]) for t in results["tests"]] == [
        ("controller: not graded", 0.0, 130.0)
    ]
    assert "is the lab's reference controller, not a submission: it imports sim.controllers.sp" in results["output"]


def test_a_failing_submission_where_bubblewrap_cannot_run(tmp_path, bundle):
    # no bwrap on the PATH: as in a container where it cannot create namespaces
    results = gradescope(tmp_path, bundle, "class CooperativeLifting(:\n", {"PATH": "/nonexistent"})
    valid(results)
    # not graded: one test, 0 of the full 130 points (a gradebook reads 0/130, not 0/0)
    assert results["score"] == 0.0
    assert [(t["score"], t["max_score"]) for t in results["tests"]] == [(0.0, 130.0)]
    assert "bubblewrap cannot run in this container" in results["output"]
    assert "SyntaxError" in results["output"]
    assert "seed 5, a private seed" in results["output"]


def test_the_services_exercises_with_services_even_when_the_node_says_ready_early(tmp_path):
    """--services: the submission's services node against a lab started in the container. A
    roslibpy node's "node ready" can come before the lab has what it advertised (roslibpy's
    advertise does not wait): here the line comes a second early. Its services are graded once the
    lab has them, not counted as missing."""
    out = tmp_path / "services.zip"
    made = run_command("autograder", "-o", str(out), "--services", "--public-seed", timeout=120)
    assert made.returncode == 0, made.stderr
    node = (Path(__file__).resolve().parents[1] / "nodes" / "services_solution.py").read_text()
    early = 'import time\nprint("node ready (too early)", flush=True)\ntime.sleep(1.0)\n' + node
    root = tmp_path / "gs"
    root.mkdir()
    results = gradescope(root, out, "class CooperativeLifting(:\n", files={"services_node.py": early})
    services = [t for t in results["tests"] if t["name"].startswith("services")]
    assert len(services) == 10 and all(t["score"] == t["max_score"] > 0 for t in services), services
    valid(results)
    assert results["score"] == 15.0
    assert "SyntaxError" in results["output"]
