"""--record DIR and --plots DIR, shared by `hri-lab experiment` and `hri-lab grade`: an MCAP
recording and a figure of every trial."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from sim.recording.trial import TrialOutputs


def trial_outputs(args: argparse.Namespace):
    """--record DIR / --plots DIR: an MCAP recording and a figure of every trial."""
    if not (getattr(args, "record", None) or getattr(args, "plots", None)):
        return None
    for folder in (args.record, args.plots):
        try:
            if folder:
                Path(folder).mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise SystemExit(f"hri-lab: cannot write to {folder}: {exc}") from None
    return TrialOutputs(args.record, args.plots)


def summary_figure(args: argparse.Namespace, results: dict) -> None:
    if args.record:
        print(f"recordings: {args.record}/*.mcap (open them in Foxglove or with `hri-lab play`)", file=sys.stderr)
    if args.plots:
        from sim.recording.figures import save_summary_figure

        paths = save_summary_figure(results, args.plots)
        print(f"figures: {args.plots}/*.png, *.svg (summary: {paths['png']})", file=sys.stderr)
