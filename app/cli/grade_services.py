"""`hri-lab grade-services --url URL`: grade the handout's exercise services over the lab's HTTP API
(the items and their checks: app/grading/services.py). Every case's numbers are drawn
from the seed (`--seed`, default $HRI_LAB_GRADE_SEED); reports: the controller grader's formats
(text, JSON, Gradescope's results.json).
"""

from __future__ import annotations

import argparse
import os
import sys

import httpx

from app.cli.reports import emit
from app.grading.services import grade_services


def run(args: argparse.Namespace) -> int:
    """`hri-lab grade-services`: one line per item as it is graded, then the report; 2 when the
    lab cannot be reached."""

    def progress(item) -> None:
        if not args.quiet:
            print(f"{item.mark:>6}  {item.name}", file=sys.stderr, flush=True)

    try:
        report = grade_services(args.url, args.seed, os.environ.get("HRI_LAB_TOKEN"), progress)
    except httpx.HTTPError as exc:
        print(f"hri-lab grade-services: cannot reach the lab at {args.url}: {exc}", file=sys.stderr)
        return 2
    return emit([report], args)
