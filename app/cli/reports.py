"""The grading reports as `hri-lab grade` and `hri-lab grade-services` write and print them:
text, JSON, Gradescope's results.json, and with --out DIR a file per report and summary.csv."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from sim.controllers.plugin import split_spec
from sim.procedures.report import Report, summary_csv


def report_stem(report: Report) -> str:
    """A report's file name stem: the controller file's, or "services"."""
    return split_spec(report.subject)[0].stem if report.kind == "controller" else report.kind


def write_outputs(reports: list[Report], out: Path, gradescope: bool) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for report in reports:
        stem = report_stem(report)
        (out / f"{stem}.txt").write_text(report.text() + "\n", encoding="utf-8")
        (out / f"{stem}.json").write_text(report.json(), encoding="utf-8")
        if gradescope:
            name = "results.json" if len(reports) == 1 else f"{stem}.results.json"
            (out / name).write_text(json.dumps(report.gradescope(), indent=2), encoding="utf-8")
    (out / "summary.csv").write_text(summary_csv(reports), encoding="utf-8")


def emit(reports: list[Report], args: argparse.Namespace) -> int:
    """The reports written (--out, --json) and printed (--format); the exit status: 0 all passed."""
    if args.out:
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
