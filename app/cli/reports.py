"""The grading reports as `hri-lab grade` and `hri-lab grade-services` write and print them:
text, JSON, Gradescope's results.json, and with --out DIR a file per report and summary.csv."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from sim.controllers.plugin import split_spec

from app.grading.report import Report, summary_csv

FILE_KINDS = ("controller", "wall following")  # reports of a file (named after it), not of a lab


def report_stem(report: Report) -> str:
    """A report's file name stem: the controller file's, or "services"."""
    return split_spec(report.subject)[0].stem if report.kind in FILE_KINDS else report.kind


def write_report(report: Report, out: Path, gradescope: bool, single: bool) -> None:
    """NAME.txt, NAME.json (and Gradescope's results.json: NAME.results.json in a batch) in `out`;
    the JSON last, each file whole (written aside, then renamed): a batch cut off mid-write
    leaves no report that looks complete."""
    out.mkdir(parents=True, exist_ok=True)
    stem = report_stem(report)
    if gradescope:
        _write(out / ("results.json" if single else f"{stem}.results.json"), json.dumps(report.gradescope(), indent=2))
    _write(out / f"{stem}.txt", report.text() + "\n")
    _write(out / f"{stem}.json", report.json())


def _write(path: Path, text: str) -> None:
    part = path.with_name(path.name + ".part")
    part.write_text(text, encoding="utf-8")
    part.replace(path)


def write_outputs(reports: list[Report], out: Path, gradescope: bool) -> None:
    for report in reports:
        write_report(report, out, gradescope, len(reports) == 1)
    out.mkdir(parents=True, exist_ok=True)
    _write(out / "summary.csv", summary_csv(reports))


def emit(reports: list[Report], args: argparse.Namespace, written: bool = False) -> int:
    """The reports written (--out, --json; written: the reports are in --out already, only
    summary.csv is left) and printed (--format); the exit status: 0 all passed."""
    if args.out and written:
        _write(Path(args.out) / "summary.csv", summary_csv(reports))
    elif args.out:
        write_outputs(reports, Path(args.out), args.format == "gradescope")
    if len(reports) == 1:
        report = reports[0]
        if args.json:
            Path(args.json).write_text(report.json(), encoding="utf-8")
        if args.format == "json":
            print(report.json())
        elif args.format == "gradescope":
            print(json.dumps(report.gradescope(), indent=2))
        else:
            print(report.text())
    else:
        print(summary_csv(reports), end="")
    sys.stdout.flush()
    return 0 if all(r.passed for r in reports) else 1
