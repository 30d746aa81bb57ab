"""`hri-lab` command line."""
from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import signal
import sys
from dataclasses import replace
from pathlib import Path

import httpx
from tqdm import tqdm

from app.cli import client as client_cli
from app.cli.grade import emit, grade_files
from app.cli.grade_services import grade_services
from app.cli.outputs import add_output_options, summary_figure, trial_outputs
from app.lab import overrides
from app.ros.params import ParameterRefused
from sim.controllers import template as student_template
from sim.controllers.plugin import PluginError, PluginFactory, controller_factory
from sim.person.human import PARTICIPANTS
from sim.procedures.experiment import (
    format_comparison,
    format_sweep,
    format_table,
    plan,
    run_comparison,
    run_experiment,
    run_sweep,
    summary,
    sweep_json,
)


def _controller_factory(spec: str | None, sandboxed: bool = True):
    """sp, patch or a plug-in file's factory (loaded once here, in its sandbox, so that a broken
    file fails now)."""
    factory = controller_factory(spec, sandboxed)
    getattr(factory(), "close", lambda: None)()
    return factory


def _overrides(args: argparse.Namespace) -> list:
    """--params FILE.yaml, then --set NAME=VALUE (validated as the parameter server does)."""

    found = []
    if args.params:
        found, ignored = overrides.parse_file(Path(args.params).read_text(encoding="utf-8"))
        if ignored and not args.quiet:
            print(f"hri-lab: {args.params}: not applicable to a headless trial, ignored: {', '.join(ignored)}", file=sys.stderr)
    return found + overrides.parse_set(args.set or [])


def _progress_bar(args: argparse.Namespace, total: int):

    return tqdm(total=total, desc="trials", unit="trial", file=sys.stderr, disable=args.quiet)


def _experiment(args: argparse.Namespace) -> int:

    try:
        found = _overrides(args)
        axes = overrides.parse_sweep(args.sweep) if args.sweep else None
    except (OSError, ParameterRefused) as exc:
        print(f"hri-lab: {exc}", file=sys.stderr)
        return 2
    title, changed = overrides.describe(found), overrides.changed(found)
    if args.compare:
        if axes:
            print("hri-lab: --sweep runs one controller (pick it with --controller), not --compare", file=sys.stderr)
            return 2
        return _compare(args, overrides.setup_of(found), title, changed)
    factory = _controller_factory(args.controller)
    trials = len(plan(args.trials, args.participant, args.seed))
    points = overrides.sweep_points(axes, found) if axes else None
    with _progress_bar(args, trials * len(points or [None])) as bar:

        def progress(result) -> None:
            bar.set_postfix_str(f"{result.participant} #{result.attempt}: {'ok' if result.success else 'FAILED'}")
            bar.update(1)

        if points:
            rows = run_sweep(points, args.trials, args.participant, args.seed, factory, progress, args.jobs)
        else:
            results = run_experiment(args.trials, args.participant, args.seed, controller_factory=factory,
                                     on_result=progress, jobs=args.jobs, setup=overrides.setup_of(found),
                                     outputs=trial_outputs(args))
    controller = args.controller or "sp"
    if not points:
        summary_figure(args, {controller: results})
    if points and args.json:
        print(json.dumps({"controller": controller, "seed": args.seed, "set": changed, **sweep_json(rows)}, indent=2))
    elif points:
        swept = " x ".join(p.name for p, _ in axes)
        print(format_sweep(rows, f"sweep of {swept}, controller {controller}, seed {args.seed}; {title}"))
    elif args.json:
        print(json.dumps({"controller": controller, "seed": args.seed, "set": changed, "summary": summary(results),
                          "trials": [r.as_dict() for r in results]}, indent=2))
    else:
        print(format_table(results, f"controller {controller}, seed {args.seed}; {title}"))
    return 0


def _compare(args: argparse.Namespace, setup, title: str, changed: dict) -> int:
    """The same participants and seeds with each controller, side by side."""
    names = [n.strip() for n in args.compare.split(",") if n.strip()]
    factories = {name: _controller_factory(name) for name in names}
    people = [args.participant] if args.participant else None
    results = run_comparison(names, args.trials, people, args.seed, controller_factory=factories.__getitem__, jobs=args.jobs,
                             setup=setup, outputs=trial_outputs(args))
    summary_figure(args, {name: [r for rs in by.values() for r in rs] for name, by in results.items()})
    if args.json:
        print(json.dumps({"seed": args.seed, "set": changed,
                          "results": {n: {p: [r.as_dict() for r in rs] for p, rs in by.items()} for n, by in results.items()}},
                         indent=2))
    else:
        print(format_comparison(results, f"seed {args.seed}; {title}"))
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
    exp.add_argument("--set", action="append", metavar="NAME=VALUE",
                     help="a parameter for every trial, e.g. --set alpha=0.5 --set k_t=0.2 (checked like `param set`)")
    exp.add_argument("--params", metavar="FILE.yaml", help="parameters for every trial, a `param dump` file (--set wins)")
    exp.add_argument("--sweep", action="append", metavar="NAME=V1,V2,...",
                     help="run the same trials at each value (twice: a grid of two parameters); one table")
    exp.add_argument("--quiet", action="store_true", help="no progress bar")
    add_output_options(exp)
    exp.set_defaults(func=_experiment)

    srv = sub.add_parser("serve", help="start the lab's server (HTTP API on 127.0.0.1)")
    srv.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    srv.add_argument("--port", type=int, default=8000)
    srv.add_argument("--params", metavar="FILE.yaml", help="parameters to load at start (a `param dump` file)")
    srv.add_argument("--view", choices=("full", "light", "none"), default=os.environ.get("HRI_LAB_VIEW", "full"),
                     help="3D view: full meshes, light (collision meshes, no shadows: software-rendered browsers) or none")
    srv.add_argument("--view-port", type=int, default=8080, help="port of the 3D view (viser moves to the next free one)")
    srv.add_argument("--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)")
    srv.add_argument("--output-dir", default=".", metavar="DIR",
                     help="where live recordings (DIR/recordings) and the actions' figures (DIR/figures) go")
    srv.add_argument("--token", default=os.environ.get("HRI_LAB_TOKEN"),
                     help="token that changes must carry (required to bind other than 127.0.0.1; default $HRI_LAB_TOKEN)")
    srv.add_argument("--exercises", action="store_true",
                     help="leave the handout's exercise services to the students' nodes (rosbridge): "
                          "each answers 'not provided yet' until a node advertises it")
    srv.set_defaults(func=_serve)

    tpl = sub.add_parser("template", help="print a starting file: the controller (default), a services node or the lifting node")
    tpl.add_argument("kind", nargs="?", choices=("controller", "services", "node"), default="controller",
                     help="controller: cooperative_lifting.py (plug-in); services: a roslibpy node with the handout's "
                          "servers; node: the lifting application as a roslibpy node")
    tpl.set_defaults(func=_template)

    grd = sub.add_parser("grade", help="grade students' controller files (probes, the nine trials, robustness), sandboxed")
    grd.add_argument("controllers", nargs="+", metavar="FILE.py[:Class]|DIR", help="files, or folders of .py files (a batch)")
    _report_options(grd, "probe values and trials")
    grd.add_argument("--jobs", type=_positive_int, default=os.cpu_count() or 1, help="items in parallel processes")
    grd.add_argument("--unsandboxed", action="store_true",
                     help="run the files without bubblewrap (still in processes of their own) where bwrap cannot run")
    grd.add_argument("--quiet", action="store_true", help="no progress bar")
    add_output_options(grd)
    grd.set_defaults(func=_grade)

    gsv = sub.add_parser("grade-services", help="grade the handout's exercise services a student's node provides "
                         "(a lab started with serve --exercises), over its HTTP API")
    gsv.add_argument("--url", default=os.environ.get("HRI_LAB_URL", client_cli.DEFAULT_URL),
                     help="the lab (default $HRI_LAB_URL or %(default)s); changes carry $HRI_LAB_TOKEN")
    _report_options(gsv, "cases")
    gsv.add_argument("--quiet", action="store_true", help="no progress lines")
    gsv.set_defaults(func=_grade_services)

    client_cli.add_parsers(sub)
    from app.cli import bag

    bag.add_parsers(sub)
    return parser


def _serve(args: argparse.Namespace) -> int:
    from app.cli.serve import serve

    factory = _controller_factory(args.controller)
    if isinstance(factory, PluginFactory):  # started in the simulation process, at its first step
        factory = replace(factory, eager=False)
    return serve(args.host, args.port, args.params, args.view, args.view_port, factory(), args.token,
                 exercises=args.exercises, output_dir=args.output_dir)


def _report_options(parser: argparse.ArgumentParser, drawn: str) -> None:
    """The grading report's options (the same for controllers and services)."""
    parser.add_argument("--out", metavar="DIR", help="write NAME.txt, NAME.json (and NAME.results.json with --format "
                        "gradescope) per report and summary.csv")
    parser.add_argument("--format", choices=("text", "json", "gradescope"), default="text",
                        help="what a single report prints (gradescope: its results.json); with --out, also written")
    parser.add_argument("--json", metavar="OUT.json", help="also write a single report as JSON")
    parser.add_argument("--seed", type=int, default=os.environ.get("HRI_LAB_GRADE_SEED", "0"), help=f"seed of the {drawn} "
                        "(default $HRI_LAB_GRADE_SEED or 0; a course's private seed gives numbers students never saw)")


def _grade(args: argparse.Namespace) -> int:
    return grade_files(args)


def _grade_services(args: argparse.Namespace) -> int:
    def progress(item) -> None:
        if not args.quiet:
            print(f"{item.mark:>6}  {item.name}", file=sys.stderr, flush=True)

    try:
        report = grade_services(args.url, args.seed, os.environ.get("HRI_LAB_TOKEN"), progress)
    except httpx.HTTPError as exc:
        print(f"hri-lab grade-services: cannot reach the lab at {args.url}: {exc}", file=sys.stderr)
        return 2
    return emit([report], args)


def _template(args: argparse.Namespace) -> int:
    if args.kind == "controller":
        path = Path(student_template.__file__)
    else:
        path = Path(__file__).parent / "templates" / {"services": "services_node.py", "node": "lifting_node.py"}[args.kind]
    print(path.read_text(encoding="utf-8"), end="")
    return 0


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be >= 1")
    return value


def _stop_with_workers(signum, frame) -> None:
    """SIGTERM/SIGHUP: the trial workers (experiment, grade --jobs) go with this process."""

    for child in multiprocessing.active_children():
        child.kill()
    os._exit(128 + signum)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.command in ("experiment", "grade"):
        for signum in (signal.SIGTERM, signal.SIGHUP):
            signal.signal(signum, _stop_with_workers)
    try:
        return client_cli.run(args.func, args)
    except PluginError as exc:
        print(f"hri-lab: controller: {exc}", file=sys.stderr)
        return 2


