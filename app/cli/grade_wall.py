"""`hri-lab grade-wall FOLLOWER.py|DIR...`: the EE-381 lab's wall following, graded (docs/mobile-lab.md).

Every file gets the same trials, drawn from the seed (app/grading/wall.py: the
obstacle's shape, size and place, the start pose, the noise); each trial runs the program against
its own mobile world (app/grading/wall_trial.py) and is judged from the world's true state. The trials
of every file are the job runner's jobs (sim/procedures/runner.py): here, in `--jobs` processes, or
on the Dask cluster at `--scheduler`, as `hri-lab grade` runs its items. With --out, a file's report
is written as soon as its last trial is in.

Exit status: 0 all passed, 1 some failed, 2 no file.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from functools import partial
from pathlib import Path

from tqdm import tqdm

from sim.controllers.sandbox import sandbox_unavailable
from sim.procedures.runner import Job, run_jobs

from app.cli.reports import emit, write_report
from app.grading.report import Item, Report
from app.grading.wall import TRIALS, lost_item, new_wall_report, trial_configs


def expand(specs: list[str]) -> list[Path]:
    found: list[Path] = []
    for spec in specs:
        path = Path(spec)
        found += sorted(path.glob("*.py")) if path.is_dir() else [path]
    return found


def run(args: argparse.Namespace) -> int:
    from app.grading.wall_trial import run_trial  # the server's modules only when a grade runs

    jailed = not args.unsandboxed
    if jailed and not args.scheduler and (reason := sandbox_unavailable()):  # a cluster checks its own
        print(
            f"hri-lab grade-wall: refusing to run students' programs without a sandbox: {reason}\n"
            "(--unsandboxed runs them in processes of their own but with your privileges)",
            file=sys.stderr,
        )
        return 2
    paths = expand(args.programs)
    if not paths:
        print("hri-lab grade-wall: no .py file to grade", file=sys.stderr)
        return 2
    configs = trial_configs(args.seed, args.trials or TRIALS)
    reports: list[Report] = []
    jobs: list[Job[Item]] = []
    for path in paths:
        report = new_wall_report(str(path), args.seed)
        reports.append(report)
        try:
            data = path.read_bytes()
        except OSError as exc:
            report.error = f"cannot read {path}: {exc.strerror}"
            continue
        report.sha256 = hashlib.sha256(data).hexdigest()
        text = data.decode("utf-8", errors="replace")
        for index, config in enumerate(configs):
            jobs.append(
                Job(
                    report,
                    run_trial,
                    (path.name, text, config, index, args.seed, jailed),
                    lost=partial(lost_item, index, config, args.seed),
                )
            )
    out = Path(args.out) if args.out else None
    results: dict[int, Item] = {}
    left = {id(r): sum(1 for j in jobs if j.key is r) for r in reports}
    for report in reports:
        if out is not None and report.error:
            write_report(report, out, args.format == "gradescope", len(reports) == 1)
    with tqdm(total=len(jobs), desc="trials", unit="trial", file=sys.stderr, disable=args.quiet) as bar:

        def done(job: Job[Item], item: Item) -> None:
            results[id(job)] = item
            bar.set_postfix_str(f"{Path(str(job.key.subject)).name}: {item.mark}")  # type: ignore[attr-defined]
            bar.update(1)
            report: Report = job.key  # type: ignore[assignment]
            left[id(report)] -= 1
            if left[id(report)] == 0:
                report.items = [results[id(j)] for j in jobs if j.key is report]
                if out is not None:
                    write_report(report, out, args.format == "gradescope", len(reports) == 1)

        run_jobs(jobs, args.jobs, done, scheduler=args.scheduler or None)
    return emit(reports, args, written=out is not None)
