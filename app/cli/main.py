"""`hri-lab` command line."""
from __future__ import annotations

import argparse
import json
import os
import sys
from dataclasses import replace
from pathlib import Path

from sim.procedures.experiment import (
    format_comparison,
    format_table,
    plan,
    run_comparison,
    run_experiment,
    summary,
)
from sim.person.human import PARTICIPANTS
from sim.controllers.plugin import PluginError, PluginFactory, controller_factory

from app.cli import client as client_cli


def _controller_factory(spec: str | None, sandboxed: bool = True):
    """sp, patch or a plug-in file's factory (loaded once here, in its sandbox, so that a broken
    file fails now)."""
    factory = controller_factory(spec, sandboxed)
    getattr(factory(), "close", lambda: None)()
    return factory


def _experiment(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    if args.compare:
        return _compare(args)
    factory = _controller_factory(args.controller)
    total = len(plan(args.trials, args.participant, args.seed))
    with tqdm(total=total, desc="trials", unit="trial", file=sys.stderr, disable=args.quiet) as bar:

        def progress(result) -> None:
            bar.set_postfix_str(f"{result.participant} #{result.attempt}: {'ok' if result.success else 'FAILED'}")
            bar.update(1)

        results = run_experiment(args.trials, args.participant, args.seed, controller_factory=factory,
                                 on_result=progress, jobs=args.jobs)
    if args.json:
        print(json.dumps({"summary": summary(results), "trials": [r.as_dict() for r in results]}, indent=2))
    else:
        print(format_table(results))
    return 0


def _compare(args: argparse.Namespace) -> int:
    """The same participants and seeds with each controller, side by side."""
    names = [n.strip() for n in args.compare.split(",") if n.strip()]
    factories = {name: _controller_factory(name) for name in names}
    people = [args.participant] if args.participant else None
    results = run_comparison(names, args.trials, people, args.seed, controller_factory=factories.__getitem__, jobs=args.jobs)
    if args.json:
        print(json.dumps({n: {p: [r.as_dict() for r in rs] for p, rs in by.items()} for n, by in results.items()}, indent=2))
    else:
        print(format_comparison(results))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hri-lab", description="The simulated cooperative-lifting lab.")
    sub = parser.add_subparsers(dest="command", required=True)
    exp = sub.add_parser("experiment", help="run the lab's Table 1 trials headless (faster than real time)")
    exp.add_argument("--trials", type=_positive_int, default=9, help="number of trials (default 9 = 3 participants x 3 tries)")
    exp.add_argument("--participant", choices=sorted(PARTICIPANTS), help="only this participant")
    exp.add_argument("--seed", type=int, default=0, help="random seed (same seed, same table)")
    exp.add_argument("--jobs", type=_positive_int, default=os.cpu_count() or 1,
                     help="trials run in this many processes (default: one per core; same results)")
    exp.add_argument("--json", action="store_true", help="print JSON instead of the table")
    exp.add_argument("--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)")
    exp.add_argument("--compare", metavar="sp,patch", help="run the same participants and seeds with each controller, side by side")
    exp.add_argument("--quiet", action="store_true", help="no progress bar")
    exp.set_defaults(func=_experiment)

    srv = sub.add_parser("serve", help="start the lab's server (HTTP API on 127.0.0.1)")
    srv.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    srv.add_argument("--port", type=int, default=8000)
    srv.add_argument("--params", metavar="FILE.yaml", help="parameters to load at start (a `param dump` file)")
    srv.add_argument("--view", choices=("full", "light", "none"), default=os.environ.get("HRI_LAB_VIEW", "full"),
                     help="3D view: full meshes, light (collision meshes, no shadows: software-rendered browsers) or none")
    srv.add_argument("--view-port", type=int, default=8080, help="port of the 3D view (viser moves to the next free one)")
    srv.add_argument("--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)")
    srv.add_argument("--token", default=os.environ.get("HRI_LAB_TOKEN"),
                     help="token that changes must carry (required to bind other than 127.0.0.1; default $HRI_LAB_TOKEN)")
    srv.set_defaults(func=_serve)

    tpl = sub.add_parser("template", help="print the student's starting file (hri-lab template > cooperative_lifting.py)")
    tpl.set_defaults(func=_template)

    grd = sub.add_parser("grade", help="grade students' controller files (probes, the nine trials, robustness), sandboxed")
    grd.add_argument("controllers", nargs="+", metavar="FILE.py[:Class]|DIR", help="files, or folders of .py files (a batch)")
    grd.add_argument("--out", metavar="DIR", help="write NAME.txt, NAME.json (and NAME.results.json with --format gradescope) "
                     "per file and summary.csv")
    grd.add_argument("--format", choices=("text", "json", "gradescope"), default="text",
                     help="what a single file's report prints (gradescope: its results.json); with --out, also written")
    grd.add_argument("--json", metavar="OUT.json", help="also write a single file's report as JSON")
    grd.add_argument("--seed", type=int, default=_env_seed(), help="seed of the probe values and trials "
                     "(default $HRI_LAB_GRADE_SEED or 0; a course's private seed gives numbers students never saw)")
    grd.add_argument("--jobs", type=_positive_int, default=os.cpu_count() or 1, help="items in parallel processes")
    grd.add_argument("--unsandboxed", action="store_true",
                     help="run the files without bubblewrap (still in processes of their own) where bwrap cannot run")
    grd.add_argument("--quiet", action="store_true", help="no progress bar")
    grd.set_defaults(func=_grade)

    client_cli.add_parsers(sub)
    return parser


def _serve(args: argparse.Namespace) -> int:
    from app.cli.serve import serve

    factory = _controller_factory(args.controller)
    if isinstance(factory, PluginFactory):  # started in the simulation process, at its first step
        factory = replace(factory, eager=False)
    return serve(args.host, args.port, args.params, args.view, args.view_port, factory(), args.token)


def _env_seed() -> int:
    try:
        return int(os.environ.get("HRI_LAB_GRADE_SEED", "0"))
    except ValueError:
        return 0


def _grade(args: argparse.Namespace) -> int:
    from app.cli.grade import grade_files

    return grade_files(args)


def _template(args: argparse.Namespace) -> int:
    from sim.controllers import template as student_template

    print(Path(student_template.__file__).read_text(encoding="utf-8"), end="")
    return 0


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be >= 1")
    return value


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return client_cli.run(args.func, args)
    except PluginError as exc:
        print(f"hri-lab: controller: {exc}", file=sys.stderr)
        return 2


