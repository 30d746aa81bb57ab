"""app/cli/grade.py without running a battery: what a folder expands to, a file's sha256, which
report in --out is still up to date (same file bytes, seed and parts, no item lost), and a batch
whose files cannot be controllers reported without a sandbox started (the batteries:
tests/e2e/test_grading.py)."""

import json

import pytest

from app.cli.grade import SECTION_OF, expand, file_sha256, run, up_to_date
from app.cli.main import build_parser
from app.cli.reports import write_report
from app.grading.battery import LOST, new_report
from app.grading.report import Item

ALL = ("probe", "trial", "robustness")


def test_a_folder_is_its_py_files_sorted_and_a_file_is_kept_with_its_class(tmp_path):
    for name in ("b.py", "a.py", "notes.txt"):
        (tmp_path / name).write_text("")
    assert expand([str(tmp_path), "x.py:Mine"]) == [str(tmp_path / "a.py"), str(tmp_path / "b.py"), "x.py:Mine"]


def test_the_sha256_is_of_the_files_bytes(tmp_path):
    (tmp_path / "a.py").write_bytes(b"abc")
    assert (
        file_sha256(f"{tmp_path / 'a.py'}:Mine") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    )
    assert file_sha256(str(tmp_path / "missing.py")) == ""


def graded(path, seed=5, sha="f" * 64, sections=ALL, lost=False):
    report = new_report(str(path), seed, sections)
    report.sha256 = sha
    report.items = [Item(SECTION_OF[s], "x", 1.0, 1.0, LOST + "killed" if lost else "") for s in sections]
    return report


def test_a_report_in_out_is_kept_only_for_the_same_file_seed_and_parts(tmp_path):
    out = tmp_path / "out"
    write_report(graded(tmp_path / "a.py"), out, gradescope=False, single=True)
    assert up_to_date(graded(tmp_path / "a.py"), out, ("probe",)) is None  # other parts of the battery
    fresh = new_report(str(tmp_path / "a.py"), 5, ("probe",))
    fresh.sha256 = "f" * 64
    write_report(graded(tmp_path / "a.py", sections=("probe",)), out, gradescope=False, single=True)
    kept = up_to_date(fresh, out, ("probe",))
    assert kept is not None
    assert kept.items[0].name == "x"
    fresh.seed = 6
    assert up_to_date(fresh, out, ("probe",)) is None  # another seed
    fresh.seed, fresh.sha256 = 5, "e" * 64
    assert up_to_date(fresh, out, ("probe",)) is None  # the file changed
    fresh.sha256 = "f" * 64
    write_report(graded(tmp_path / "a.py", sections=("probe",), lost=True), out, gradescope=False, single=True)
    assert up_to_date(fresh, out, ("probe",)) is None  # an item lost to a dead worker: graded again
    assert up_to_date(fresh, None, ("probe",)) is None  # no --out


def grade(*argv: str) -> int:
    return run(build_parser().parse_args(["grade", "--unsandboxed", "--quiet", "--jobs", "1", *argv]))


def test_no_file_to_grade_is_status_2(tmp_path, capsys):
    assert grade(str(tmp_path)) == 2  # an empty folder
    assert "hri-lab grade: no .py file to grade" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("name", "content", "said"),
    [("missing.py", None, "missing.py"), ("notes.py", b"\x00\xff binary", "notes.py")],
)
def test_a_file_that_cannot_be_a_controller_gets_a_report_saying_why(tmp_path, capsys, name, content, said):
    if content is not None:
        (tmp_path / name).write_bytes(content)
    out = tmp_path / "out"
    assert grade(str(tmp_path / name), "--seed", "5", "--out", str(out)) == 1
    written = json.loads((out / f"{name[:-3]}.json").read_text())
    assert written["points"] == 0
    assert written["max_points"] == 130
    assert said in written["error"]
    assert (out / "summary.csv").read_text().splitlines()[1].startswith(str(tmp_path / name))
