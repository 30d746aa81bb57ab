"""`hri-lab experiment`: the Table 1 trials headless, a comparison of controllers, a sweep."""

from __future__ import annotations

import argparse
import json
import sys

from tqdm import tqdm

from sim.controllers.plugin import PluginFactory
from sim.procedures.experiment import plan, run_comparison, run_experiment, run_sweep
from sim.procedures.tables import format_comparison, format_sweep, format_table, summary, sweep_json

from app.cli.controllers import loaded_factory
from app.cli.outputs import summary_figure, trial_outputs
from app.lab import overrides
from app.ros.params import ParameterRefused, read_parameter_file


def _overrides(args: argparse.Namespace) -> list:
    """--params FILE.yaml, then --set NAME=VALUE (validated as the parameter server does)."""
    found: list = []
    if args.params:
        try:
            found, ignored = overrides.parse_file(read_parameter_file(args.params))
        except ParameterRefused as exc:
            raise ParameterRefused(f"{args.params}: {exc}") from None
        if ignored and not args.quiet:
            print(
                f"hri-lab: {args.params}: not applicable to a headless trial, ignored: {', '.join(ignored)}",
                file=sys.stderr,
            )
    return found + overrides.parse_set(args.set or [])


def _factory(args: argparse.Namespace, spec: str | None):
    """--controller's factory; a student's file read here and carried along to a cluster's
    workers (they have no copy of it)."""
    factory = loaded_factory(spec)
    return factory.carrying() if args.scheduler and isinstance(factory, PluginFactory) else factory


def _progress_bar(args: argparse.Namespace, total: int):
    return tqdm(total=total, desc="trials", unit="trial", file=sys.stderr, disable=args.quiet)


def run(args: argparse.Namespace) -> int:
    """The trials (or the comparison, or the sweep) and their table; 2 for a refused parameter."""
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
    factory = _factory(args, args.controller)
    trials = len(plan(args.trials, args.participant, args.seed))
    points = overrides.sweep_points(axes, found) if axes else None
    with _progress_bar(args, trials * len(points or [None])) as bar:

        def progress(result) -> None:
            bar.set_postfix_str(f"{result.participant} #{result.attempt}: {'ok' if result.success else 'FAILED'}")
            bar.update(1)

        if points:
            rows = run_sweep(
                points, args.trials, args.participant, args.seed, factory, progress, args.jobs, scheduler=args.scheduler
            )
        else:
            results = run_experiment(
                args.trials,
                args.participant,
                args.seed,
                controller_factory=factory,
                on_result=progress,
                jobs=args.jobs,
                setup=overrides.setup_of(found),
                outputs=trial_outputs(args),
                scheduler=args.scheduler,
            )
    controller = args.controller or "sp"
    if not points:
        summary_figure(args, {controller: results})
    if points and args.json:
        print(json.dumps({"controller": controller, "seed": args.seed, "set": changed, **sweep_json(rows)}, indent=2))
    elif points:
        swept = " x ".join(p.name for p, _ in axes or [])
        print(format_sweep(rows, f"sweep of {swept}, controller {controller}, seed {args.seed}; {title}"))
    elif args.json:
        print(
            json.dumps(
                {
                    "controller": controller,
                    "seed": args.seed,
                    "set": changed,
                    "summary": summary(results),
                    "trials": [r.as_dict() for r in results],
                },
                indent=2,
            )
        )
    else:
        print(format_table(results, f"controller {controller}, seed {args.seed}; {title}"))
    return 0


def _compare(args: argparse.Namespace, setup, title: str, changed: dict) -> int:
    """The same participants and seeds with each controller, side by side."""
    names = [n.strip() for n in args.compare.split(",") if n.strip()]
    factories = {name: _factory(args, name) for name in names}
    people = [args.participant] if args.participant else None
    results = run_comparison(
        names,
        args.trials,
        people,
        args.seed,
        controller_factory=factories.__getitem__,
        jobs=args.jobs,
        setup=setup,
        outputs=trial_outputs(args),
        scheduler=args.scheduler,
    )
    summary_figure(args, {name: [r for rs in by.values() for r in rs] for name, by in results.items()})
    if args.json:
        print(
            json.dumps(
                {
                    "seed": args.seed,
                    "set": changed,
                    "results": {n: {p: [r.as_dict() for r in rs] for p, rs in by.items()} for n, by in results.items()},
                },
                indent=2,
            )
        )
    else:
        print(format_comparison(results, f"seed {args.seed}; {title}"))
    return 0
