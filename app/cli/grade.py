"""`hri-lab grade FILES_OR_DIRS...`: one file or a batch, sandboxed, all items over the cores.

Exit status: 0 all passed, 1 some failed (or could not be loaded), 2 refused (no sandbox, no
file); never 0 before every report is written.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from tqdm import tqdm

from sim.controllers.plugin import PluginError, PluginFactory, split_spec
from sim.controllers.sandbox import sandbox_unavailable
from sim.procedures.grading import battery, job_items, new_report, run_items

from app.cli.outputs import trial_outputs
from app.cli.reports import emit


def expand(specs: list[str]) -> list[str]:
    """Folders -> their .py files (sorted); files (with an optional :Class) as given."""
    found = []
    for spec in specs:
        path = Path(spec)
        if path.is_dir():
            found += [str(p) for p in sorted(path.glob("*.py"))]
        else:
            found.append(spec)
    return found


def run(args: argparse.Namespace) -> int:
    """Grade every file, write and print the reports; the exit status (module docstring)."""
    sandboxed = not args.unsandboxed
    if sandboxed and (reason := sandbox_unavailable()):
        print(
            f"hri-lab grade: refusing to run students' code without a sandbox: {reason}\n"
            "(--unsandboxed runs it in processes of their own but with your privileges)",
            file=sys.stderr,
        )
        return 2
    specs = expand(args.controllers)
    if not specs:
        print("hri-lab grade: no .py file to grade", file=sys.stderr)
        return 2
    reports, jobs, owners = [], [], []
    for spec in specs:
        report = new_report(spec, args.seed)
        reports.append(report)
        factory = PluginFactory(spec, sandboxed=sandboxed)
        try:
            factory().close()  # loads in the sandbox: a file that cannot be loaded is reported, not graded
        except PluginError as exc:
            report.error = str(exc)
            continue
        outputs = trial_outputs(args)  # recordings and figures of this file's trials, named after it
        if outputs is not None:
            outputs = replace(outputs, prefix=f"{split_spec(spec)[0].stem}_")
        for job in battery(factory, args.seed, outputs=outputs):
            jobs.append(job)
            owners += [report] * job_items(job)
    with tqdm(total=len(owners), desc="grading", unit="item", file=sys.stderr, disable=args.quiet) as bar:

        def progress(item) -> None:
            bar.set_postfix_str(f"{item.name[:40]}: {item.mark}")
            bar.update(1)

        items = run_items(jobs, args.jobs, progress)
    for report, item in zip(owners, items):
        report.items.append(item)
    return emit(reports, args)
