"""A course's grading throughput: submissions per hour with `hri-lab grade --jobs 2` and with a
Dask LocalCluster of one and of two workers (`--scheduler`: the scaling), and the cluster's own cost per task (a trivial
task's round trip, against the local pool's). docs/course-scale.md holds the figures.

    .venv/bin/python -m bench.course_scale [--submissions 2] [--tasks 200] [--only probe]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from sim.procedures.runner import Job, run_jobs

REFERENCE = Path(__file__).resolve().parent.parent / "tests" / "controllers" / "reference_sp.py"


def nothing(x: int) -> int:
    return x


def grade_wall(folder: Path, extra: list[str], only: list[str]) -> float:
    """s of wall time of one `hri-lab grade` of the folder."""
    started = time.perf_counter()
    run = subprocess.run(
        # the reference SP is the lab's own (0 points by default): graded as a file, flagged
        [sys.executable, "-m", "app.cli", "grade", str(folder), "--quiet", "--reference", "flag", *only, *extra],
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - started
    if run.returncode != 0:
        raise SystemExit(f"grade failed ({run.returncode}): {run.stderr[-2000:]}")
    return wall


def per_task(tasks: int, **where) -> float:
    """s per trivial task, the batch's wall time over its tasks."""
    work = [Job(i, nothing, (i,)) for i in range(tasks)]
    started = time.perf_counter()
    run_jobs(work, **where)
    return (time.perf_counter() - started) / tasks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--submissions", type=int, default=2, help="copies of the reference SP file graded")
    parser.add_argument("--tasks", type=int, default=200, help="trivial tasks for the per-task cost")
    parser.add_argument("--only", choices=("probe", "trial", "robustness"), help="a part of the battery (quicker)")
    args = parser.parse_args()
    only = ["--only", args.only] if args.only else []

    from distributed import LocalCluster

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "submissions"
        folder.mkdir()
        for i in range(args.submissions):
            shutil.copy(REFERENCE, folder / f"student{i:03d}.py")
        print(
            f"{args.submissions} submissions (the reference SP), {'--only ' + args.only if args.only else 'the whole battery'}"
        )
        local = grade_wall(folder, ["--jobs", "2"], only)
        print(f"--jobs 2:            {local:7.1f} s  = {3600 * args.submissions / local:6.1f} submissions/h")
        pool = per_task(args.tasks, jobs=2)
        with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            alone = grade_wall(folder, ["--scheduler", cluster.scheduler_address], only)
            print(f"1-worker cluster:    {alone:7.1f} s  = {3600 * args.submissions / alone:6.1f} submissions/h")
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            remote = grade_wall(folder, ["--scheduler", cluster.scheduler_address], only)
            print(f"2-worker cluster:    {remote:7.1f} s  = {3600 * args.submissions / remote:6.1f} submissions/h")
            print(f"scaling, 1 -> 2 workers: {alone / remote:.2f}x (2 cores)")
            per_task(10, scheduler=cluster.scheduler_address)  # the workers warm (imports)
            dask = per_task(args.tasks, scheduler=cluster.scheduler_address)
        print(f"a trivial task ({args.tasks}): local pool {pool * 1e3:.2f} ms, cluster {dask * 1e3:.2f} ms each")
    print(f"load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())} ({os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
