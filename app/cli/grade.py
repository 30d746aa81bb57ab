"""`hri-lab grade FILES_OR_DIRS...`: one file or a batch, sandboxed, all items over the cores or a
Dask cluster (docs/course-scale.md).

Every file is first loaded once where it will be graded (a file that cannot be loaded gets a
report saying why), then its battery's jobs (app/grading/battery.py) run with every other
file's: here, in `--jobs` processes, or one task per job on the cluster at `--scheduler` (or
$HRI_LAB_SCHEDULER). With --out, a file's report is written as soon as its last item is in, and
a file whose report there is for the same seed and the same file (its sha256) is skipped
(--force grades it again): a batch cut off resumes where it stopped.

A file that imports, subclasses or copies the lab's own controllers (the sandbox sees it load them:
docs/sandbox.md) is not a submission: its report says so and it scores 0 (`--reference flag`
grades it, with an item that flags it). With --out, `similarity.csv` and `similarity.html` compare
every pair of the batch's files and each against the lab's controllers (app/grading/similarity.py).

Exit status: 0 all passed, 1 some failed (or could not be loaded), 2 refused (no sandbox, no
file); never 0 before every report is written.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from dataclasses import replace
from pathlib import Path

from tqdm import tqdm

from sim.controllers.plugin import PluginError, PluginFactory, split_spec
from sim.controllers.sandbox import sandbox_unavailable
from sim.procedures.runner import Job, run_jobs

from app.cli.outputs import trial_outputs
from app.cli.reports import emit, report_stem, write_report
from app.grading.battery import LOST, Items, Loaded, battery, load_check, new_report, reference_items
from app.grading.report import Item, Report


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


def file_sha256(spec: str) -> str:
    """sha256 of the controller file's bytes ("" when it cannot be read)."""
    try:
        return hashlib.sha256(split_spec(spec)[0].read_bytes()).hexdigest()
    except OSError:
        return ""


SECTION_OF = {"probe": "probe", "trial": "experiment", "robustness": "robustness"}  # --only -> the items' section


def up_to_date(report: Report, out: Path | None, sections: tuple[str, ...]) -> Report | None:
    """The report written in `out` for the same file, seed, file bytes and parts of the battery,
    if any (and no item lost in it to a worker that died)."""
    if out is None or not report.sha256:
        return None
    try:
        old = Report.from_dict(json.loads((out / f"{report_stem(report)}.json").read_text(encoding="utf-8")))
    except (OSError, ValueError, KeyError, TypeError):
        return None
    same = (old.subject, old.kind, old.seed, old.sha256) == (report.subject, report.kind, report.seed, report.sha256)
    parts = {i.section for i in old.items}
    same = same and (old.error != "" or parts == {SECTION_OF[s] for s in sections})
    return old if same and not any(i.detail.startswith(LOST) for i in old.items) else None


def run(args: argparse.Namespace) -> int:
    """Grade every file, write and print the reports; the exit status (module docstring)."""
    sandboxed = not args.unsandboxed
    scheduler = args.scheduler or None
    if sandboxed and not scheduler and (reason := sandbox_unavailable()):
        return _refuse(reason)
    specs = expand(args.controllers)
    if not specs:
        print("hri-lab grade: no .py file to grade", file=sys.stderr)
        return 2
    out = Path(args.out) if args.out else None
    sections = tuple(s for s in SECTION_OF if s in (args.only or SECTION_OF))
    reports: list[Report] = []
    to_load, kept = [], []  # kept: the reports up to date in --out
    for spec in specs:
        report = new_report(spec, args.seed, sections)
        report.sha256 = file_sha256(spec)
        if not args.force and (old := up_to_date(report, out, sections)) is not None:
            reports.append(old)
            kept.append(old)
            continue
        reports.append(report)
        try:  # the file's text goes with the jobs: a worker elsewhere has no copy of it
            factory = PluginFactory(spec, sandboxed=sandboxed).carrying()
        except PluginError as exc:
            report.error = str(exc)
            continue
        to_load.append((report, factory))
    if kept:
        print(f"hri-lab grade: skipped {len(kept)} up to date (--force grades them again)", file=sys.stderr)
    checks = [
        Job(report, load_check, (factory, sandboxed), lost=lambda why: Loaded(error=f"{LOST}{why}"))
        for report, factory in to_load
    ]
    loaded = run_jobs(checks, args.jobs, scheduler=scheduler)
    jobs: list[Items] = []
    for (report, factory), check in zip(to_load, loaded):
        assert check is not None
        if check.refused:
            return _refuse(check.refused)
        if check.error:
            report.error = check.error
            continue
        if check.reference and args.reference == "zero":  # the lab's own controller: not graded, 0 points
            report.error = check.reference
            continue
        if check.reference:  # --reference flag: graded, and an item (not counted, the report's first) says so
            jobs.append(Job(report, reference_items, (check.reference,)))
        outputs = trial_outputs(args)  # recordings and figures of this file's trials, named after it
        if outputs is not None:
            outputs = replace(outputs, prefix=f"{split_spec(report.subject)[0].stem}_")
        jobs += battery(factory, args.seed, sections, outputs=outputs, key=report)
    for report in reports:
        if out is not None and report.error and not any(report is k for k in kept):
            write_report(report, out, args.format == "gradescope", len(reports) == 1)
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    _grade(jobs, reports, args, out, scheduler)
    if out is not None:
        _similarity(reports, out, args.similarity)
    return emit(reports, args, written=True)


def _similarity(reports: list[Report], out: Path, threshold: float | None) -> None:
    """The batch's similarity report beside its reports (app/grading/similarity.py); the flagged pairs said."""
    from app.grading.similarity import THRESHOLD, compare

    threshold = threshold or THRESHOLD
    files = sorted({path for r in reports if _text_file(path := split_spec(r.subject)[0])})
    try:
        pairs = compare(files, out, threshold)
    except Exception as exc:  # noqa: BLE001 - the reports are written: a failed comparison costs only itself
        print(f"hri-lab grade: no similarity report: {type(exc).__name__}: {exc}", file=sys.stderr)
        return
    flagged = [p for p in pairs if p.flagged]
    print(
        f"hri-lab grade: similarity of {len(files)} file(s), each pair and each against the lab's own controllers: "
        f"{len(flagged)} pair(s) at or above {threshold:g} ({out / 'similarity.csv'}, {out / 'similarity.html'})",
        file=sys.stderr,
    )
    for pair in flagged:
        print(
            f"  {pair.file}: {pair.share_of_file:.0%} in {pair.other}"
            + (" (the lab's own)" if pair.other_is_reference else f", {pair.share_of_other:.0%} of it"),
            file=sys.stderr,
        )


def _grade(jobs: list[Items], reports: list[Report], args: argparse.Namespace, out: Path | None, scheduler) -> None:
    """Run the jobs; each report gets its items in battery order and is written once complete."""
    results: dict[int, list[Item]] = {}
    left: dict[int, int] = {}
    for job in jobs:
        left[id(job.key)] = left.get(id(job.key), 0) + 1
    with tqdm(
        total=sum(job.size for job in jobs), desc="grading", unit="item", file=sys.stderr, disable=args.quiet
    ) as bar:

        def done(job: Items, items: list[Item]) -> None:
            results[id(job)] = items
            if items:
                bar.set_postfix_str(f"{items[-1].name[:40]}: {items[-1].mark}")
            bar.update(len(items))
            left[id(job.key)] -= 1
            if left[id(job.key)] == 0:
                report: Report = job.key  # type: ignore[assignment]
                report.items = [i for j in jobs if j.key is report for i in results[id(j)]]
                if out is not None:
                    write_report(report, out, args.format == "gradescope", len(reports) == 1)

        run_jobs(jobs, args.jobs, done, scheduler=scheduler)


def _text_file(path: Path) -> bool:
    """A file of UTF-8 text (what the similarity report can read)."""
    try:
        path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return False
    return True


def _refuse(reason: str) -> int:
    print(
        f"hri-lab grade: refusing to run students' code without a sandbox: {reason}\n"
        "(--unsandboxed runs it in processes of their own but with your privileges)",
        file=sys.stderr,
    )
    return 2
