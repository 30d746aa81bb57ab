"""Grading reports (app/grading/report.py): what an instructor can defend in every format — a
file that cannot be graded is 0 of the full points, a fault's traceback is written once with the
items it cost, and every report says its seed and whether it is the public default."""

import csv
import io
import json

from app.grading.battery import battery_points, new_report
from app.grading.report import PUBLIC_SEED, Item, Report, summary_csv

TRACE = 'Traceback (most recent call last):\n  File "ada.py", line 9, in step\n    1 / 0\nZeroDivisionError: division by zero\n'
FAULT = "Ada.step raised ZeroDivisionError: division by zero\n" + TRACE


def test_the_battery_is_worth_130_points_and_its_parts_theirs():
    assert battery_points() == 13 * 5 + 9 * 5 + 2 * 10 == 130
    assert battery_points(("probe",)) == 65
    assert battery_points(("trial",), trials=3) == 15


def test_a_file_that_cannot_be_graded_is_0_of_the_full_points_everywhere():
    report = new_report("syntax.py", 2024)
    report.error = "importing syntax.py failed: SyntaxError: invalid syntax"
    assert (report.points, report.max_points, report.passed) == (0, 130, False)
    assert "score: 0/130: FAIL" in report.text()
    data = report.as_dict()
    assert (data["points"], data["max_points"]) == (0, 130)
    gradescope = report.gradescope()
    assert gradescope["score"] == 0.0
    assert [(t["score"], t["max_score"]) for t in gradescope["tests"]] == [(0.0, 130.0)]
    row = next(csv.DictReader(io.StringIO(summary_csv([report]))))
    assert (row["points"], row["max_points"], row["passed"]) == ("0", "130", "no")
    assert Report.from_dict(json.loads(report.json())).max_points == 130


def test_a_fault_is_written_once_with_the_items_it_cost():
    report = new_report("ada.py", 2024)
    report.items = [
        Item("probe", "stopped: zero twist", 0.0, 5.0, FAULT),
        Item("probe", "inside the band: hold still", 5.0, 5.0),
        Item("experiment", "trial 1: calm #1", 0.0, 5.0, "controller error: " + FAULT),
    ]
    text = report.text()
    assert text.count("Traceback (most recent call last)") == 1
    assert text.count("(traceback below)") == 2
    assert "A fault cost 2 item(s): probe: stopped: zero twist, experiment: trial 1: calm #1" in text
    assert text.index("A fault cost") > text.index("score:")  # below the items and the verdict
    faults = report.as_dict()["faults"]
    assert faults == [{"traceback": TRACE, "items": ["probe: stopped: zero twist", "experiment: trial 1: calm #1"]}]
    gradescope = report.gradescope()
    assert gradescope["output"].count("Traceback") == 1
    assert all("Traceback" not in t["output"] for t in gradescope["tests"])
    assert report.items[0].detail == FAULT  # the item keeps its whole detail (JSON): only the text is shortened


def test_every_report_says_its_seed_and_whether_it_is_the_public_default():
    public, private = new_report("a.py", PUBLIC_SEED), new_report("a.py", 2024)
    assert "seed 0, the public default" in public.text()
    assert "seed 2024, a private seed" in private.text()
    assert public.as_dict()["public_seed"] is True
    assert private.as_dict()["public_seed"] is False
    assert "seed 2024, a private seed" in private.gradescope()["output"]
    rows = list(csv.DictReader(io.StringIO(summary_csv([public, private]))))
    assert [(r["seed"], r["public_seed"]) for r in rows] == [("0", "yes"), ("2024", "no")]
