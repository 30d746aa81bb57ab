"""app/cli/autograder.py in this process: the bundle's files and config, the public seed refused,
which file of a submission is graded, and results.json's visibility (the bundle run as Gradescope
runs it: tests/e2e/test_gradescope.py; its CLI: tests/e2e/test_autograder.py)."""

import json
import zipfile

from app.cli.autograder import CONFIG, SOURCE, build, results_json, submission_file
from app.cli.main import build_parser
from grading.report import PUBLIC_SEED, Item, Report


def bundle_args(tmp_path, *argv: str):
    return build_parser().parse_args(["autograder", "-o", str(tmp_path / "autograder.zip"), *argv])


def test_the_bundle_holds_the_scripts_executable_the_config_and_the_labs_source(tmp_path, capsys):
    assert build(bundle_args(tmp_path, "--seed", "31", "--services", "--hide-until-due")) == 0
    with zipfile.ZipFile(tmp_path / "autograder.zip") as z:
        names = set(z.namelist())
        for script in ("setup.sh", "run_autograder"):
            assert z.getinfo(script).external_attr >> 16 == 0o100755
        config = json.loads(z.read(CONFIG))
        setup = z.read("setup.sh").decode()
    assert {f"{SOURCE}/pyproject.toml", f"{SOURCE}/sim/world.py", f"{SOURCE}/app/cli/autograder.py"} <= names
    assert config["seed"] == 31
    assert config["services"]
    assert config["hide_until_due"]
    assert config["reference"] == "zero"
    assert f'"$ROOT/source/{SOURCE}[nodes]"' in setup  # --services: roslibpy installed for the nodes
    assert "seed 31" in capsys.readouterr().out


def test_the_public_seed_is_refused_unless_asked_for(tmp_path, capsys, monkeypatch):
    """Seed 0 is what every student grades with at home: a bundle with it would grade with numbers
    the students know. Refused (exit 2, saying why) unless --public-seed; $HRI_LAB_GRADE_SEED is
    the course's seed when --seed is not given."""
    monkeypatch.delenv("HRI_LAB_GRADE_SEED", raising=False)
    assert build(bundle_args(tmp_path)) == 2
    err = capsys.readouterr().err
    assert f"seed {PUBLIC_SEED} is the public default" in err
    assert "--public-seed" in err
    assert not (tmp_path / "autograder.zip").exists()
    assert build(bundle_args(tmp_path, "--public-seed")) == 0
    assert f"seed {PUBLIC_SEED}, the public default" in capsys.readouterr().out
    with zipfile.ZipFile(tmp_path / "autograder.zip") as z:
        assert "[nodes]" not in z.read("setup.sh").decode()  # no --services: no roslibpy
    monkeypatch.setenv("HRI_LAB_GRADE_SEED", "77")
    assert build(bundle_args(tmp_path)) == 0
    assert "seed 77, a private seed" in capsys.readouterr().out


def test_the_graded_file_is_the_templates_name_or_the_only_py_file(tmp_path):
    (tmp_path / "sub").mkdir()
    assert submission_file(tmp_path) is None  # nothing submitted
    (tmp_path / "sub" / "mine.py").write_text("")
    assert submission_file(tmp_path) == tmp_path / "sub" / "mine.py"  # the only one, in a folder too
    (tmp_path / "helper.py").write_text("")
    assert submission_file(tmp_path) is None  # two, neither named as the template
    (tmp_path / "cooperative_lifting.py").write_text("")
    assert submission_file(tmp_path) == tmp_path / "cooperative_lifting.py"


def test_results_json_adds_the_reports_and_hides_the_tests_until_due():
    a = Report("a.py", "controller", 3, [Item("probe", "p", 2.0, 4.0)])
    b = Report("lab", "services", 3, [Item("services", "s", 1.0, 1.0)])
    results = results_json([a, b], ["a note"], hide_until_due=True)
    assert results["score"] == 3.0
    assert [t["name"] for t in results["tests"]] == ["probe: p", "services: s"]
    assert {t["visibility"] for t in results["tests"]} == {"after_due_date"}
    assert results["visibility"] == "visible"
    assert results["stdout_visibility"] == "hidden"
    assert results["output"].splitlines()[0] == "a note"
    assert {t["visibility"] for t in results_json([a], [], hide_until_due=False)["tests"]} == {"visible"}
