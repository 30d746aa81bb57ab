"""app/cli/grade_wall.py without a trial run: what the arguments expand to, no file (status 2), a
file that cannot be read reported with its reason before any world starts (the trials themselves:
tests/e2e/test_grade_wall.py)."""

import json
from pathlib import Path

from app.cli.grade_wall import expand, run
from app.cli.main import build_parser


def grade_wall(*argv: str) -> int:
    return run(build_parser().parse_args(["grade-wall", "--quiet", "--jobs", "1", *argv]))


def test_a_folder_is_its_py_files_sorted(tmp_path):
    for name in ("b.py", "a.py", "README.md"):
        (tmp_path / name).write_text("")
    assert expand([str(tmp_path), "x.py"]) == [tmp_path / "a.py", tmp_path / "b.py", Path("x.py")]


def test_no_file_is_status_2(tmp_path, capsys):
    assert grade_wall(str(tmp_path)) == 2
    assert "hri-lab grade-wall: no .py file to grade" in capsys.readouterr().err


def test_a_file_that_cannot_be_read_is_reported_without_a_trial(tmp_path, capsys):
    out = tmp_path / "out"
    assert grade_wall(str(tmp_path / "gone.py"), "--out", str(out), "--seed", "4") == 1
    report = json.loads((out / "gone.json").read_text())
    assert report["error"].startswith(f"cannot read {tmp_path / 'gone.py'}: No such file or directory")
    assert report["points"] == 0
    assert report["seed"] == 4
    assert report["kind"] == "wall following"
