"""app/grading/gradescope.py in this process: which file of a submission is graded, and results.json's
visibility (the bundle run as Gradescope runs it: tests/e2e/test_gradescope.py)."""

from app.grading.gradescope import results_json, submission_file
from app.grading.report import Item, Report


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
