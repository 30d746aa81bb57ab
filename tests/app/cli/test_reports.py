"""app/cli/reports.py: a report's file names, its files written whole (text, JSON, Gradescope's
results.json alone or per file in a batch), summary.csv, what is printed and the exit status."""

import json
from argparse import Namespace

from app.cli.reports import emit, report_stem, write_report
from app.grading.report import Item, Report


def report(subject="students/ada.py:Mine", kind="controller", points=10.0, error="") -> Report:
    return Report(subject, kind, 7, [Item("probe", "band", points, 10.0, "")], marks={"": 60.0}, error=error)


def args(**given) -> Namespace:
    return Namespace(**({"out": None, "json": None, "format": "text"} | given))


def test_a_report_is_named_after_its_file_or_its_kind():
    assert report_stem(report()) == "ada"  # the file's stem, without folder or :Class
    assert report_stem(report("http://127.0.0.1:8000", "services")) == "services"
    assert report_stem(report("follower.py", "wall following")) == "follower"


def test_a_report_is_written_whole_in_every_format(tmp_path):
    write_report(report(), tmp_path, gradescope=True, single=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ada.json", "ada.txt", "results.json"]  # no .part left
    assert json.loads((tmp_path / "ada.json").read_text())["points"] == 10.0
    assert json.loads((tmp_path / "results.json").read_text())["score"] == 10.0
    assert "score: 10/10" in (tmp_path / "ada.txt").read_text()
    batch = tmp_path / "batch"
    write_report(report(), batch, gradescope=True, single=False)  # in a batch: one results.json per file
    assert sorted(p.name for p in batch.iterdir()) == ["ada.json", "ada.results.json", "ada.txt"]


def test_one_report_is_printed_in_its_format_and_the_status_says_whether_it_passed(tmp_path, capsys):
    assert emit([report()], args()) == 0
    assert "score: 10/10" in capsys.readouterr().out
    assert emit([report(points=5.0)], args(format="json", json=str(tmp_path / "r.json"))) == 1  # 50 % < 60 %
    printed = json.loads(capsys.readouterr().out)
    assert printed["points"] == 5.0
    assert json.loads((tmp_path / "r.json").read_text()) == printed
    assert emit([report(error="SyntaxError")], args(format="gradescope")) == 1
    assert json.loads(capsys.readouterr().out)["tests"][0]["name"] == "controller: not graded"


def test_a_batch_prints_and_writes_its_summary(tmp_path, capsys):
    reports = [report("a.py"), report("b.py", points=0.0)]
    assert emit(reports, args(out=str(tmp_path))) == 1
    printed = capsys.readouterr().out
    assert printed.splitlines()[0].startswith("subject,points,max_points")
    assert printed == (tmp_path / "summary.csv").read_bytes().decode()  # the same CSV, its line ends too
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "a.txt", "b.json", "b.txt", "summary.csv"]
    written = tmp_path / "written"  # the reports are there already (hri-lab grade): only summary.csv is added
    written.mkdir()
    emit(reports, args(out=str(written)), written=True)
    assert [p.name for p in written.iterdir()] == ["summary.csv"]
