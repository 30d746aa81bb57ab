"""The instructors' pages run as written (tests/e2e/docs_commands.py): docs/instructors.md and
docs/course-scale.md, every command in order against a real lab."""

import json
import subprocess
import sys
import zipfile

from tests.e2e.docs_commands import run_page


def test_the_instructors_page(tmp_path):
    run = run_page("instructors.md", tmp_path / "instructors")
    said = "\n".join(run.transcript)
    assert "seed 2024, a private seed" in said
    folder = run.folder
    report = json.loads((folder / "reports" / "cooperative_lifting.json").read_text())
    assert (report["points"], report["max_points"], report["seed"], report["public_seed"]) == (15.0, 130.0, 2024, False)
    assert (folder / "reports" / "ada.json").exists()
    assert (folder / "reports" / "results.json").exists()
    services = json.loads((folder / "services" / "services.json").read_text())
    assert (services["points"], services["max_points"]) == (1.0, 15.0)
    # the students' zip: no tests/, and the lab in it runs on its own (here: its template command)
    with zipfile.ZipFile(folder / "hri-lab-students.zip") as z:
        assert not [n for n in z.namelist() if n.startswith(("hri-lab/tests/", "hri-lab/bench/"))]
        z.extractall(tmp_path / "student")
    printed = subprocess.run(
        [sys.executable, "-m", "app.cli", "template", "services"],
        cwd=tmp_path / "student" / "hri-lab",
        capture_output=True,
        text=True,
        timeout=120,
        env={"PATH": "/usr/bin:/bin", "PYTHONSAFEPATH": ""},
    )
    assert printed.returncode == 0 and "import rospy" in printed.stdout, printed.stderr
    where = subprocess.run(
        [sys.executable, "-c", "import app, sim; print(app.__file__, sim.__file__)"],
        cwd=tmp_path / "student" / "hri-lab",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert where.stdout.count(str(tmp_path / "student" / "hri-lab")) == 2, (
        where.stdout
    )  # the zip's, not this checkout's


def test_the_course_scale_page(tmp_path):
    run = run_page("course-scale.md", tmp_path / "course")
    said = "\n".join(run.transcript)
    assert "skipped 1 up to date" in said
    assert "seed 0 is the public default" in said
    with zipfile.ZipFile(run.folder / "autograder.zip") as bundle:
        config = json.loads(bundle.read("hri-lab-autograder.json"))
    assert (config["seed"], config["services"], config["hide_until_due"]) == (2024, True, True)
    assert (run.folder / "trial.zip").exists()  # the public seed, on purpose
