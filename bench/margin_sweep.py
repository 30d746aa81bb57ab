"""The friction margin and the gains, measured (issue #17): the Table 1 trials at several values of
alpha (SP and patch: both keep the friction within alpha of their limit, the cone for SP, the
limit surface for patch) and of k_t, k_n, f_n_band and filter_hz (SP, around their defaults),
three participants x 3 tries (each try its own seed, the same seeds at every value). One table per
sweep, printed by the same functions as `hri-lab experiment --sweep NAME=V1,V2,...` (run_sweep,
format_sweep), and the machine it ran on.

A second, small measurement says what a smaller margin costs while the person is still: one
trial of the average participant per alpha and controller, observed step by step (the same
trial as the sweep's first average try): how far the commanded EE moves while the person stands
still (the settling and final holding phases, mm), and how often the controller switches
between holding and following (switches per second of carrying: chatter), and the share of the
carry it spends following.

    .venv/bin/python -m bench.margin_sweep [--jobs 2] [--tries 3] [--seed 0] [--only alpha,k_t,...]

The whole script is 172 trials, 568 s of CPU: about 5 min with --jobs 2 on two idle cores; it
took 17 min (1010 s) on the lab's 2-core machine shared with other jobs (load 4-15). Each sweep reproduces
alone with the CLI, e.g. `hri-lab experiment --sweep alpha=0.3,0.4,0.5,0.65,0.8 --controller patch`.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import sys
import time
from collections.abc import Iterator

import numpy as np

from sim.controllers.interface import LiftingParams
from sim.controllers.plugin import controller_factory
from sim.procedures.experiment import SweepRow, plan, run_sweep
from sim.procedures.runner import worker_pool
from sim.procedures.tables import format_sweep
from sim.procedures.trial import make_trial

from app.lab import overrides

DEFAULTS = LiftingParams()


def _around(value: float, low: float, high: float) -> str:
    return ",".join(f"{v:g}" for v in (low, value, high))


# (controller, sweep) - the values bracket the defaults inside the parameters' ranges (app/lab/params.py)
SWEEPS = [
    ("sp", "alpha=0.3,0.4,0.5,0.65,0.8"),
    ("patch", "alpha=0.3,0.4,0.5,0.65,0.8"),
    ("sp", f"k_t={_around(DEFAULTS.k_t, DEFAULTS.k_t / 2, DEFAULTS.k_t * 3)}"),
    ("sp", f"k_n={_around(DEFAULTS.k_n, DEFAULTS.k_n / 2, DEFAULTS.k_n * 2)}"),
    ("sp", f"f_n_band={_around(DEFAULTS.f_n_band, DEFAULTS.f_n_band / 2, DEFAULTS.f_n_band * 2)}"),
    ("sp", f"filter_hz={_around(DEFAULTS.filter_hz, DEFAULTS.filter_hz / 2, DEFAULTS.filter_hz * 3)}"),
]
STILL_PHASES = ("settling", "holding")  # the person does not move the box


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            cpu = next(line.split(":", 1)[1].strip() for line in info if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    return (
        f"machine: {cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}, "
        f"Python {platform.python_version()}; load average {load}"
    )


def run_sweeps(
    sweeps: list[tuple[str, str]], tries: int, seed: int, jobs: int
) -> Iterator[tuple[str, str, list[SweepRow]]]:
    """Each controller's points in one pool; a point shared by two sweeps (the defaults) runs once.
    Yields (controller, sweep, rows) as each controller's pool ends."""
    trials = 3 * tries
    for controller in dict.fromkeys(c for c, _ in sweeps):
        mine = [
            (spec, overrides.sweep_points(overrides.parse_sweep([spec]), [])) for c, spec in sweeps if c == controller
        ]
        unique: dict[str, tuple] = {}
        for _, points in mine:
            for values, setup in points:
                unique.setdefault(repr(setup), (values, setup))
        keys = list(unique)
        rows = run_sweep([unique[k] for k in keys], trials, None, seed, controller_factory(controller), jobs=jobs)
        by_key = dict(zip(keys, rows))
        for spec, points in mine:
            yield controller, spec, [SweepRow(values, by_key[repr(setup)].results) for values, setup in points]


def observe(controller: str, spec: str, seed: int) -> dict:
    """One average trial (the sweep's first average try) at `spec` (NAME=VALUE), observed step by step."""
    _, setup = overrides.sweep_points(overrides.parse_sweep([spec]), [])[0]
    index, person, attempt, trial_seed = next(item for item in plan(9, None, seed) if item[1].name == "average")
    trial = make_trial(
        index, person, attempt, trial_seed, controller_factory=controller_factory(controller), setup=setup
    )
    dt = trial.world.config.dt
    still_path = 0.0  # m the commanded EE moved while the person was still
    switches = carry_steps = following = 0
    was = False
    while trial.step():
        phase = trial.world.human.phase
        speed = float(np.linalg.norm(trial.world.twist_command[:3]))
        if phase in STILL_PHASES:
            still_path += speed * dt
        if phase == "carrying":
            carry_steps += 1
            following += trial.controller.slipping
            switches += trial.controller.slipping != was
        was = trial.controller.slipping
    result = trial.result()
    carry_s = carry_steps * dt
    return {
        "controller": controller,
        "spec": spec,
        "success": result.success,
        "still_mm": still_path * 1000,
        "switches_per_s": switches / carry_s if carry_s else float("nan"),
        "following": following / carry_steps if carry_steps else float("nan"),
        "slip_mm": result.slip * 1000,
    }


def run_observed(specs: list[tuple[str, str]], seed: int, jobs: int) -> list[dict]:
    with worker_pool(jobs) as pool:
        return list(pool.map(observe, [c for c, _ in specs], [s for _, s in specs], [seed] * len(specs)))


def format_observed(rows: list[dict]) -> str:
    header = f"{'controller':<10} {'value':<12} {'ok':>3} {'EE moved while still mm':>24} {'switches/s carrying':>20} {'following % of carry':>21} {'slip mm':>8}"
    lines = [header, "-" * len(header)]
    for r in rows:
        lines.append(
            f"{r['controller']:<10} {r['spec']:<12} {'yes' if r['success'] else 'NO':>3} {r['still_mm']:>24.2f} "
            f"{r['switches_per_s']:>20.1f} {r['following'] * 100:>21.0f} {r['slip_mm']:>8.1f}"
        )
    lines.append("-" * len(header))
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2: the machine is shared)")
    parser.add_argument("--tries", type=int, default=3, help="tries per participant (each its own seed)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", help="comma-separated parameter names (default: all sweeps)")
    parser.add_argument("--no-observed", action="store_true", help="skip the step-by-step cost measurement")
    args = parser.parse_args()
    wanted = set(args.only.split(",")) if args.only else None
    sweeps = [(c, s) for c, s in SWEEPS if wanted is None or s.split("=")[0] in wanted]
    print(machine(), flush=True)
    started = time.perf_counter()
    for controller, spec, rows in run_sweeps(sweeps, args.tries, args.seed, args.jobs):
        name = spec.split("=")[0]
        print()
        print(
            format_sweep(
                rows,
                f"sweep of {name}, controller {controller}, seed {args.seed}, {args.tries} tries per "
                f"participant; other parameters the defaults"
                f"  (hri-lab experiment --sweep {spec} --controller {controller} --trials {3 * args.tries})",
            ),
            flush=True,
        )
    if not args.no_observed and (wanted is None or "alpha" in wanted):
        alphas = next(s for _, s in SWEEPS if s.startswith("alpha=")).split("=")[1].split(",")
        observed = run_observed([(c, f"alpha={a}") for c in ("sp", "patch") for a in alphas], args.seed, args.jobs)
        print("\nwhat the margin costs, one average trial per value (the sweep's first average try):")
        print(format_observed(observed))
    cpu = sum(
        getattr(resource.getrusage(who), f)
        for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
        for f in ("ru_utime", "ru_stime")
    )
    print(
        f"\nwall time {time.perf_counter() - started:.0f} s with --jobs {args.jobs}, CPU time {cpu:.0f} s "
        f"(this process and its workers); load average now {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
        flush=True,
    )


if __name__ == "__main__":
    sys.exit(main())
