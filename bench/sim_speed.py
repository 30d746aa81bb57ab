"""Simulation speed: microseconds per 1 kHz step of the full loop (robot + contacts + box +
human + controller + sensor), the real-time factor, the nine-trial experiment's wall time, and a
profile of where a step's time goes; also the step with the controller in Python (what a plug-in
or a node's command takes: compiled sense, Python control, compiled robot and rest;
docs/simulation-compiled.md).

    .venv/bin/python -m bench.sim_speed [--repeats 5] [--steps 5000] [--no-experiment]
"""

from __future__ import annotations

import argparse
import cProfile
import io
import pstats
import statistics
import time

from sim.controllers.sp import SPController
from sim.person.participants import PARTICIPANTS
from sim.procedures.experiment import run_experiment
from sim.world import World


def carrying_world() -> World:
    """A world in the middle of a calm trial (robot pressing, box carried): the costly state."""
    world = World()
    world.reset(PARTICIPANTS["calm"], seed=1)
    world.start_lifting(10.0)
    while world.human.phase != "carrying":
        world.step()
    world.run(1.0)
    return world


class SPInPython(SPController):
    """The SP law run by its Python class (a subclass with its own twist_ee is never compiled)."""

    def twist_ee(self, wrench_ee, params):
        return super().twist_ee(wrench_ee, params)


def time_steps(world: World, steps: int) -> float:
    start = time.perf_counter()
    for _ in range(steps):
        world.step()
    return (time.perf_counter() - start) / steps


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--no-experiment", action="store_true")
    args = parser.parse_args()

    world = carrying_world()
    per_step = [time_steps(world, args.steps) for _ in range(args.repeats)]
    median = statistics.median(per_step)
    print(
        f"full step: median {median * 1e6:.1f} us  (min {min(per_step) * 1e6:.1f}, max {max(per_step) * 1e6:.1f}, "
        f"{args.repeats} x {args.steps} steps)"
    )
    print(f"real-time factor at 1 kHz: {1e-3 / median:.1f}x  (target >= 20x, <= 50 us/step)")
    world.set_controller(SPInPython())
    split = statistics.median(time_steps(world, args.steps) for _ in range(args.repeats))
    print(f"step with the controller in Python (SP's class): median {split * 1e6:.1f} us")
    world.set_controller(SPController())

    profiler = cProfile.Profile()
    profiler.enable()
    time_steps(world, 2000)
    profiler.disable()
    text = io.StringIO()
    pstats.Stats(profiler, stream=text).sort_stats("tottime").print_stats(12)
    print("where the time goes (cProfile, 2000 steps, sorted by own time):")
    print("\n".join(line for line in text.getvalue().splitlines() if line.strip())[:3000])

    if not args.no_experiment:
        walls = {}
        for jobs in (1, 2):
            start = time.perf_counter()
            results = run_experiment(9, seed=0, jobs=jobs)
            walls[jobs] = time.perf_counter() - start
            simulated = sum(r.duration for r in results)
            print(
                f"nine-trial experiment, {jobs} process(es): wall {walls[jobs]:.1f} s for {simulated:.1f} s simulated "
                f"({simulated / walls[jobs]:.1f}x real time), {sum(r.success for r in results)}/9 successes (target < 30 s)"
            )
        print(f"parallel speedup with 2 processes: {walls[1] / walls[2]:.2f}x")


if __name__ == "__main__":
    main()
